//! `freefloat compare` for an arm of another number of links than the paper's two (docs/spec.md
//! §3): the minimum-effort planner and the ECSA side by side, the NFA listed as refused.

use std::process::ExitCode;

use anyhow::Context;
use freefloat::model::arm::Arm;
use freefloat::plan::Method;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::report::io::PlanReport;
use freefloat::report::numbers::{error_number, number, rounded, significant};

use super::args::{CompareArgs, CompareFormat, ProblemArgs};
use super::plan_arm::{Planning, plan_problem, problem, refuse_flags};

/// Runs `compare` for `arm`: the optimal planner and the ECSA on the same problem, the NFA listed
/// as refused with its reason. Exit 0 when both plans are certified, 3 when one has no certified
/// plan (the other still shown), 2 for bad input.
pub fn compare(args: &CompareArgs, arm: &Arm) -> anyhow::Result<ExitCode> {
    let p = &args.problem;
    refuse_flags(p, arm)?;
    let (arm, geometry_notes) = super::geometry::arm_with_flags(arm, &p.robot, &p.geometry)?;
    let arm = &arm;
    let mut results: Vec<(Method, Result<Planning, freefloat::Error>)> = Vec::new();
    for method in [Method::Optimal, Method::Nfa, Method::Ecsa] {
        let result = if method == Method::Nfa {
            let problem = problem(p, arm)?;
            plan_arm(arm, method, &ArmRequest::new(problem.clone())).map(|planned| Planning {
                planned,
                problem,
                notes: vec![],
                to_ee: None,
            })
        } else {
            plan_problem(p, arm, method)?
        };
        match result {
            Err(e) if e.is_bad_input() && method != Method::Nfa => return Err(e.into()),
            result => results.push((method, result)),
        }
    }
    let reports: Vec<(Method, Result<PlanReport, String>)> = results
        .iter()
        .map(|(m, r)| {
            let report = r.as_ref().map_err(|e| e.to_string()).map(|plan| {
                let mut r = PlanReport::from_arm(&plan.planned, &plan.problem.start, &plan.problem.goal, false);
                r.notes = plan.notes.clone();
                r.notes.extend(geometry_notes.iter().cloned());
                r.to_ee = plan.to_ee.clone();
                r
            });
            (*m, report)
        })
        .collect();
    if args.format == CompareFormat::Json {
        let mut object = serde_json::Map::new();
        let mut errors = serde_json::Map::new();
        for (method, r) in &reports {
            let value = match r {
                Ok(report) => serde_json::to_value(report)?,
                Err(message) => {
                    errors.insert(method.name().into(), message.clone().into());
                    serde_json::Value::Null
                }
            };
            object.insert(method.name().into(), value);
        }
        object.insert("errors".into(), errors.into());
        super::emit(&format!("{}\n", serde_json::to_string_pretty(&serde_json::Value::from(object))?))?;
    } else {
        super::emit(&compare_table(arm, p, &reports))?;
    }
    for (method, result) in results.into_iter().filter(|(m, _)| *m != Method::Nfa) {
        let failed = |what: &str| format!("compare: {} {what} (the other method is in the table)", method.name());
        result
            .with_context(|| failed("has no plan"))?
            .planned
            .certified()
            .with_context(|| failed("is not certified"))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The side-by-side table of an arm's `compare`.
fn compare_table(arm: &Arm, p: &ProblemArgs, reports: &[(Method, Result<PlanReport, String>)]) -> String {
    type Row = (&'static str, fn(&PlanReport) -> String);
    let rows: [Row; 10] = [
        ("effort [rad^2/s]", |r| number(r.effort)),
        ("verified final error [rad]", |r| error_number(r.final_error)),
        ("certified", |r| if r.certified { "yes".into() } else { "NO".into() }),
        ("iterations", |r| r.iterations.map_or("-".into(), |i| i.to_string())),
        ("max |u_k| [rad/s]", |r| r.max_abs_u.iter().map(|x| rounded(*x, 4)).collect::<Vec<_>>().join(", ")),
        ("max |tau_k| [N m]", |r| match &r.max_abs_torque {
            Some(t) => t.iter().map(|x| rounded(*x, 4)).collect::<Vec<_>>().join(", "),
            None => "- (--torques)".into(),
        }),
        ("torque final error [rad]", |r| r.torque_final_error.map(error_number).unwrap_or("- (--torques)".into())),
        ("horizon [s]", |r| number(r.time)),
        ("time: plan [ms]", |r| significant(r.seconds.plan * 1e3, 4)),
        ("time: torques [ms]", |r| r.seconds.torques.map_or("- (--torques)".into(), |t| significant(t * 1e3, 4))),
    ];
    let mut s = format!(
        "freefloat compare: {}-link arm, mount (a, b) = ({}, {}) m, {} -> {} deg, T = {} s\n",
        arm.joints(),
        number(arm.mount.a),
        number(arm.mount.b),
        p.ends.from,
        p.to_ee.as_ref().map_or(p.ends.to.clone(), |pose| format!("pose {pose}")),
        number(p.ends.time)
    );
    let width = reports
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok())
        .flat_map(|r| rows.iter().map(move |(_, cell)| cell(r).len()))
        .fold(26, usize::max)
        + 2;
    let mut head = format!("  {:<31}", "");
    for (method, r) in reports {
        let name = match (method, r) {
            (Method::Ecsa, Ok(r)) => r
                .ecsa
                .as_ref()
                .map_or("ECSA".to_string(), |e| format!("ECSA (H = {}, window {})", e.harmonics(), e.window().name())),
            (Method::Optimal, _) => "optimal".to_string(),
            (m, _) => m.name().to_uppercase(),
        };
        head += &format!("{name:<width$}");
    }
    s += head.trim_end();
    s += "\n";
    for (label, cell) in rows {
        s += &format!("  {label:<31}");
        for (method, r) in reports {
            let text = match r {
                Ok(r) => cell(r),
                Err(_) if *method == Method::Nfa => "(refused)".into(),
                Err(_) => "(no plan)".into(),
            };
            s += &format!("{text:<width$}");
        }
        s = s.trim_end().to_string();
        s += "\n";
    }
    for (method, r) in reports {
        if let Err(message) = r {
            s += &format!("  {}: {message}\n", method.name());
        }
    }
    s
}
