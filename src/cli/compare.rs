//! `freefloat compare` of the 2-link robot: the optimal planner, the NFA and the ECSA on the same
//! problem, side by side (docs/spec.md §3; an arm of another number of links: `compare_arm.rs`).

use std::process::ExitCode;

use anyhow::Context;
use freefloat::plan::{Method, PlanningProblem};
use freefloat::report::io::PlanReport;
use freefloat::report::numbers::{error_number, number, rounded, significant};

use super::args::{CompareArgs, CompareFormat, WindowArg};
use super::plan::{deg, plan_with};

/// Runs `compare`: the optimal planner, the NFA and the ECSA on the same problem, side by side.
/// Exit 0 when every plan is certified; 3 when one has no certified plan (the others are still
/// shown); 2 for bad input.
pub fn compare(args: &CompareArgs) -> anyhow::Result<ExitCode> {
    if let super::Robot::Arm(arm) = super::any_robot(&args.problem.robot)? {
        return super::compare_arm::compare(args, &arm);
    }
    let problem = super::problem(&args.problem)?;
    let (geometry, _) = super::geometry::two_link(&args.problem.robot, &args.problem.geometry)?;
    let mut results = Vec::new();
    for method in COMPARED {
        let result = plan_with(method, &args.problem, &problem)?.and_then(|mut planned| {
            planned.check_clearance(&geometry)?;
            Ok(planned)
        });
        if let Err(e) = result {
            if e.is_bad_input() {
                return Err(e.into());
            }
            results.push(Err(e));
        } else {
            results.push(result);
        }
    }
    let reports: Vec<Result<PlanReport, String>> = results
        .iter()
        .map(|r| match r {
            Ok(planned) => Ok(PlanReport::new(planned, false)),
            Err(e) => Err(e.to_string()),
        })
        .collect();
    if args.format == CompareFormat::Json {
        super::emit(&format!("{}\n", serde_json::to_string_pretty(&compare_json(&reports)?)?))?;
    } else {
        super::emit(&compare_table(&problem, &reports))?;
    }
    for (method, result) in COMPARED.iter().zip(results) {
        // The ECSA's plain series moves at t = 0: its torques cannot start from rest.
        let hint = match (method, args.problem.window) {
            (Method::Ecsa, WindowArg::None) if args.problem.torques => {
                "; its plain series does not start at rest, --window sin2 does"
            }
            _ => "",
        };
        let failed =
            |what: &str| format!("compare: {} {what} (the other methods are in the table{hint})", method.name());
        result.with_context(|| failed("has no plan"))?.certified().with_context(|| failed("is not certified"))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The methods of `compare`, in its columns' order.
const COMPARED: [Method; 3] = [Method::Optimal, Method::Nfa, Method::Ecsa];

/// The JSON object of `compare`: `{"optimal": report, "nfa": report, "ecsa": report}`, a method
/// without a plan as `null` with its message under `"errors"`.
fn compare_json(reports: &[Result<PlanReport, String>]) -> anyhow::Result<serde_json::Value> {
    let mut object = serde_json::Map::new();
    let mut errors = serde_json::Map::new();
    for (name, r) in COMPARED.iter().map(|m| m.name()).zip(reports) {
        let value = match r {
            Ok(report) => serde_json::to_value(report)?,
            Err(message) => {
                errors.insert(name.to_string(), message.clone().into());
                serde_json::Value::Null
            }
        };
        object.insert(name.to_string(), value);
    }
    if !errors.is_empty() {
        object.insert("errors".into(), errors.into());
    }
    Ok(object.into())
}

/// The side-by-side table of `compare`.
fn compare_table(problem: &PlanningProblem, reports: &[Result<PlanReport, String>]) -> String {
    type Row = (&'static str, fn(&PlanReport) -> String);
    let rows: [Row; 18] = [
        ("effort [rad^2/s]", |r| number(r.effort)),
        ("verified final error [rad]", |r| error_number(r.final_error)),
        ("certified", |r| if r.certified { "yes".into() } else { "NO".into() }),
        ("iterations", |r| r.iterations.map(|i| i.to_string()).unwrap_or_else(|| "- (closed form)".into())),
        ("iteration residual [rad]", |r| r.ecsa.as_ref().map(|x| error_number(x.residual())).unwrap_or("-".into())),
        ("max |u1| [rad/s]", |r| number(r.max_abs_u[0])),
        ("max |u2| [rad/s]", |r| number(r.max_abs_u[1])),
        ("u(0) [rad/s]", |r| pair(&r.controls_at_ends[0])),
        ("u(T) [rad/s]", |r| pair(&r.controls_at_ends[1])),
        // Filled by `--torques` (inverse dynamics, torque issue): peak |tau1|, |tau2|.
        ("max |tau1|, |tau2| [N m]", |r| r.max_abs_torque.as_deref().map(pair).unwrap_or("- (--torques)".into())),
        ("torque final error [rad]", |r| r.torque_final_error.map(error_number).unwrap_or("- (--torques)".into())),
        ("torque level certified", |r| match &r.torque_certificate {
            Some(t) if t.certified() => "yes".into(),
            Some(_) => "NO".into(),
            None => "- (--torques)".into(),
        }),
        ("min |sigma|, min |P|", |r| match (r.min_abs_sigma, r.min_abs_p) {
            (Some(sigma), Some(p)) => pair(&[sigma, p]),
            _ => "-".into(),
        }),
        ("max deviation from plan [rad]", |r| r.max_path_deviation.map(error_number).unwrap_or("-".into())),
        ("time: plan [ms]", |r| significant(r.seconds.plan * 1e3, 4)),
        ("time: torques [ms]", |r| r.seconds.torques.map(|t| significant(t * 1e3, 4)).unwrap_or("-".into())),
        ("time: verify [ms]", |r| r.seconds.verify.map(|t| significant(t * 1e3, 4)).unwrap_or("-".into())),
        ("time: total [ms]", |r| {
            let s = &r.seconds;
            significant((s.plan + s.verify.unwrap_or(0.0) + s.torques.unwrap_or(0.0)) * 1e3, 4)
        }),
    ];
    let header = |r: &Result<PlanReport, String>, name: &str| match r {
        Ok(r) => match (&r.transform, &r.ecsa, &r.optimal) {
            (Some(t), _, _) => format!("NFA ({})", t.name()),
            (None, Some(x), _) => format!("ECSA (H = {}, window {})", x.harmonics(), x.window().name()),
            (None, None, Some(_)) => "optimal".to_string(),
            _ => name.to_uppercase(),
        },
        Err(_) => name.to_uppercase(),
    };
    let mut s = String::new();
    let mount = problem.robot.mount;
    s += &format!(
        "freefloat compare: mount (a, b) = ({}, {}) m, {} -> {} deg, T = {} s\n",
        number(mount.a),
        number(mount.b),
        deg(&problem.start.to_array()),
        deg(&problem.goal.to_array()),
        number(problem.horizon)
    );
    let mut head = format!("  {:<31}", "");
    for (method, r) in COMPARED.iter().zip(reports) {
        head += &format!("{:<26}", header(r, method.name()));
    }
    s += head.trim_end();
    s += "\n";
    for (label, cell) in rows {
        s += &format!("  {label:<31}");
        for r in reports {
            let text = match r {
                Ok(r) => cell(r),
                Err(_) => "(no plan)".into(),
            };
            s += &format!("{text:<26}");
        }
        s = s.trim_end().to_string();
        s += "\n";
    }
    for (name, r) in COMPARED.iter().map(|m| m.name()).zip(reports) {
        if let Err(message) = r {
            s += &format!("  {name}: {message}\n");
        }
    }
    s
}

/// A pair rounded to 4 decimals (`0.1235, 0.0955`).
fn pair(x: &[f64]) -> String {
    format!("{}, {}", rounded(x[0], 4), rounded(x[1], 4))
}

#[cfg(test)]
mod tests {
    use super::*;
    use freefloat::planners::{PlannerOptions, planner};
    use freefloat::{Mount, RobotParams, Transform};

    fn reports(a: f64, transform: Option<Transform>) -> (PlanningProblem, Vec<Result<PlanReport, String>>) {
        let robot = RobotParams::src().with_mount(Mount::new(a, -a).expect("finite")).expect("valid");
        let problem = PlanningProblem::paper(robot);
        let options =
            PlannerOptions { nfa: freefloat::NfaOptions { transform, ..Default::default() }, ..Default::default() };
        let report = |method| {
            planner(method, &options).plan(&problem).map(|p| PlanReport::new(&p, false)).map_err(|e| e.to_string())
        };
        (problem, COMPARED.iter().map(|&m| report(m)).collect())
    }

    /// The paper's problem: both columns filled, JSON has both reports with docs/spec.md §3's keys.
    #[test]
    fn compare_default_problem() {
        let (problem, reports) = reports(0.0, None);
        let table = compare_table(&problem, &reports);
        assert!(table.contains("NFA (eq12)") && table.contains("ECSA (H = 1, window none)"), "{table}");
        assert!(!table.contains("(no plan)"), "{table}");
        let json = compare_json(&reports).unwrap();
        for method in ["optimal", "nfa", "ecsa"] {
            for key in ["final_error", "max_abs_u", "iterations", "seconds", "max_abs_torque", "transform"] {
                assert!(json[method].get(key).is_some(), "{method}.{key}");
            }
        }
        assert!(json["ecsa"]["iterations"].as_u64().is_some() && json["nfa"]["iterations"].is_null());
        assert!(json.get("errors").is_none());
    }

    /// Where the NFA has no plan (a = 1, b = -1: the path leaves the domain of Eq. 14) the
    /// ECSA still plans; the NFA column says so and the JSON carries the NFA's error.
    #[test]
    fn compare_when_the_nfa_fails() {
        let (problem, reports) = reports(1.0, Some(Transform::Eq14));
        assert!(reports[0].is_ok() && reports[1].is_err() && reports[2].is_ok());
        let table = compare_table(&problem, &reports);
        assert!(table.contains("(no plan)") && table.contains("  nfa: "), "{table}");
        let json = compare_json(&reports).unwrap();
        assert!(json["nfa"].is_null() && json["errors"]["nfa"].is_string() && json["ecsa"].is_object());
    }
}
