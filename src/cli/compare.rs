//! `freefloat compare`: the optimal planner, the NFA and the ECSA on the same problem, side by side
//! (docs/spec.md §3), for every robot: every arm, the paper's robot as its 2-link arm, through
//! one pipeline ([`arm`]); the NFA is the paper's model's, refused for another arm. The table,
//! the JSON, the exit codes and the messages are written once.

use std::process::ExitCode;

use freefloat::model::arm::Arm;
use freefloat::plan::Method;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::report::io::PlanReport;
use freefloat::report::numbers::{error_number, number, rounded, significant};

use super::args::{CompareArgs, CompareFormat, WindowArg};
use super::plan::{Planning, degrees, plan_problem, plan_with, problem, refuse_flags};

/// Runs `compare`: the optimal planner, the NFA and the ECSA on the same problem, side by side.
/// Exit 0 when every plan is certified; 3 when one has no certified plan (the others are still
/// shown); 2 for bad input (a method this robot cannot take, the NFA of an arm, is listed as
/// refused, not failed).
pub fn compare(args: &CompareArgs) -> anyhow::Result<ExitCode> {
    let compared = match super::any_robot(&args.problem.robot)? {
        super::Robot::Arm(robot) => arm(args, &robot)?,
        // The paper's robot is the 2-link arm of every method's one pipeline (issue 19), its NFA
        // the paper's model's ([`two_link_nfa`]).
        super::Robot::TwoLink => arm(args, &Arm::from_params(&super::robot(&args.problem.robot)?))?,
    };
    if args.format == CompareFormat::Json {
        super::emit(&format!("{}\n", serde_json::to_string_pretty(&compare_json(&compared.reports)?)?))?;
    } else {
        super::emit(&compare_table(&compared))?;
    }
    let Some(failure) = compared.failures.into_iter().next() else {
        return Ok(ExitCode::SUCCESS);
    };
    // The ECSA's plain series moves at t = 0: its torques cannot start from rest.
    let hint = match (failure.method, args.problem.window) {
        (Method::Ecsa, WindowArg::None) if args.problem.torques => {
            "; its plain series does not start at rest, --window sin2 does"
        }
        _ => "",
    };
    let others = match compared.reports.len() - compared.refused.len() - 1 {
        1 => "the other method is",
        _ => "the other methods are",
    };
    let context = format!("compare: {} {} ({others} in the table{hint})", failure.method.name(), failure.what);
    Err(anyhow::Error::from(failure.error).context(context))
}

/// The methods of `compare`, in its columns' order.
const COMPARED: [Method; 3] = [Method::Optimal, Method::Nfa, Method::Ecsa];

/// What one robot's pipeline planned for `compare`.
struct Compared {
    /// The table's first line.
    title: String,
    /// Each method's report, or the message of why it has none, in the columns' order.
    reports: Vec<(Method, Result<PlanReport, String>)>,
    /// The methods this robot cannot take: `(refused)` in the table, no failure.
    refused: Vec<Method>,
    /// The methods without a certified plan, in the columns' order: the first one is the exit's.
    failures: Vec<Failure>,
}

/// A method without a certified plan.
struct Failure {
    method: Method,
    /// `has no plan` or `is not certified`.
    what: &'static str,
    error: freefloat::Error,
}

impl Compared {
    /// An empty comparison under `title`.
    fn new(title: String) -> Self {
        Self { title, reports: Vec::new(), refused: Vec::new(), failures: Vec::new() }
    }

    /// Adds `method`'s plan (its report and certificate) or why it has none.
    fn add(&mut self, method: Method, planned: Outcome) {
        let (report, certified) = match planned {
            Ok((report, certified)) => (Ok(report), certified.map_err(|e| (e, "is not certified"))),
            Err(e) => (Err(e.to_string()), Err((e, "has no plan"))),
        };
        self.reports.push((method, report));
        if let Err((error, what)) = certified {
            self.failures.push(Failure { method, what, error });
        }
    }
}

/// The first line of the table: the robot (`n-link arm, ` for an arm), the mounting point [m],
/// the ends (angles in degrees) and the horizon [s] (`+inf`: `--time auto`'s, not yet found).
fn title(robot: &str, mount: freefloat::Mount, start: &[f64], goal: &str, horizon: f64) -> String {
    let horizon = match horizon.is_infinite() {
        true => "auto (the shortest inside the limits)".to_string(),
        false => format!("{} s", number(horizon)),
    };
    format!(
        "freefloat compare: {robot}mount (a, b) = ({}, {}) m, {} -> {goal} deg, T = {horizon}\n",
        number(mount.a),
        number(mount.b),
        degrees(start),
    )
}

/// Every arm, the paper's robot too (issue 19): the optimal planner and the ECSA through
/// [`plan_problem`]; the NFA of the paper's model checked against the arm ([`two_link_nfa`]),
/// else refused with [`plan_arm`]'s reason.
///
/// With `--time auto` the optimal planner (the first column) finds the shortest horizon inside
/// the limits, and the other methods plan at it; without it they have none and say so.
fn arm(args: &CompareArgs, arm: &Arm) -> anyhow::Result<Compared> {
    let mut p = args.problem.clone();
    let auto = p.ends.time.is_infinite();
    let p = &mut p;
    refuse_flags(p, arm)?;
    let (arm, geometry_notes) = super::geometry::arm_with_flags(arm, &p.robot, &p.geometry)?;
    let arm = &arm;
    let chain = problem(p, arm)?;
    let goal = p.to_ee.as_ref().map_or_else(|| degrees(&chain.goal), |pose| format!("pose {pose}"));
    let robot = format!("{}-link arm, ", arm.joints());
    let mut compared = Compared::new(title(&robot, arm.mount, &chain.start, &goal, p.ends.time));
    for method in COMPARED {
        if method == Method::Nfa
            && let Some(nfa) = two_link_nfa(p, arm)?
        {
            compared.add(method, nfa);
            continue;
        }
        if p.ends.time.is_infinite() && method != Method::Optimal {
            let why = "no horizon: the optimal planner's search of --time auto found none to plan at".to_string();
            compared.reports.push((method, Err(why)));
            compared.refused.push(method);
            continue;
        }
        let result = match method {
            Method::Nfa => plan_arm(arm, method, &ArmRequest::new(chain.clone())).map(|planned| Planning {
                planned,
                problem: chain.clone(),
                notes: vec![],
                to_ee: None,
            }),
            _ => plan_problem(p, arm, method)?,
        };
        if let (true, Ok(found)) = (auto && method == Method::Optimal, &result) {
            // The horizon of `--time auto`, for the title and the other methods.
            p.ends.time = found.problem.horizon;
            compared.title = title(&robot, arm.mount, &chain.start, &goal, p.ends.time)
                .replace(" s\n", " s (--time auto: the shortest inside the limits)\n");
        }
        match result {
            Err(e) if method == Method::Nfa => {
                compared.reports.push((method, Err(e.to_string())));
                compared.refused.push(method);
            }
            Err(e) if e.is_bad_input() => return Err(e.into()),
            result => compared.add(
                method,
                result.map(|plan| {
                    let mut r = PlanReport::from_arm(&plan.planned, &plan.problem.start, &plan.problem.goal, false);
                    r.notes = plan.notes;
                    r.notes.extend(geometry_notes.iter().cloned());
                    r.to_ee = plan.to_ee;
                    (r, plan.planned.certified())
                }),
            ),
        }
    }
    Ok(compared)
}

/// A method's report and certificate, or why it has no plan.
type Outcome = Result<(PlanReport, Result<(), freefloat::Error>), freefloat::Error>;

/// The NFA of a 2-link arm that is the paper's model (e.g. the preset with `--limit`), as
/// `plan --method nfa` plans it: the paper's model's plan, checked along its motion against the
/// arm's limits and shapes (a limit it breaks is a failure, exit 3); `None` for another arm (the
/// NFA refused with [`plan_arm`]'s reason).
fn two_link_nfa(p: &super::args::ProblemArgs, arm: &Arm) -> anyhow::Result<Option<Outcome>> {
    if arm.as_src().is_none() {
        return Ok(None);
    }
    let problem = super::problem(p)?;
    let (geometry, _) = super::geometry::two_link(&p.robot, &p.geometry)?;
    let mut planned = match plan_with(Method::Nfa, p, &problem)? {
        Ok(planned) => planned,
        Err(e) if e.is_bad_input() => return Err(e.into()),
        Err(e) => return Ok(Some(Err(e))),
    };
    let limits = super::limits::two_link_checks(Some(arm), geometry, &mut planned)?;
    let mut r = PlanReport::new(&planned, false);
    r.robot = arm.clone();
    r.set_limits(limits.clone());
    let certified = planned.certified().and_then(|()| limits.map_or(Ok(()), |l| l.check()));
    Ok(Some(Ok((r, certified))))
}

/// The JSON object of `compare`: `{"optimal": report, "nfa": report, "ecsa": report}`, a method
/// without a plan as `null` with its message under `"errors"`.
fn compare_json(reports: &[(Method, Result<PlanReport, String>)]) -> anyhow::Result<serde_json::Value> {
    let mut object = serde_json::Map::new();
    let mut errors = serde_json::Map::new();
    for (method, r) in reports {
        let value = match r {
            Ok(report) => serde_json::to_value(report)?,
            Err(message) => {
                errors.insert(method.name().into(), message.clone().into());
                serde_json::Value::Null
            }
        };
        object.insert(method.name().into(), value);
    }
    if !errors.is_empty() {
        object.insert("errors".into(), errors.into());
    }
    Ok(object.into())
}

/// A row of the table: its label and the cell of a report.
type Row = (String, Box<dyn Fn(&PlanReport) -> String>);

/// The rows of the table for plans of `joints` joints: one `max |u_k|` row per joint.
fn rows(joints: usize) -> Vec<Row> {
    fn row(label: &str, cell: impl Fn(&PlanReport) -> String + 'static) -> Row {
        (label.to_string(), Box::new(cell))
    }
    let mut rows = vec![
        row("effort [rad^2/s]", |r| number(r.effort)),
        row("verified final error [rad]", |r| error_number(r.final_error)),
        row("certified", |r| if r.certified { "yes".into() } else { "NO".into() }),
        row("iterations", |r| r.iterations.map(|i| i.to_string()).unwrap_or_else(|| "- (closed form)".into())),
        row("iteration residual [rad]", |r| r.ecsa.as_ref().map(|x| error_number(x.residual())).unwrap_or("-".into())),
    ];
    for k in 0..joints {
        rows.push(row(&format!("max |u{}| [rad/s]", k + 1), move |r| {
            r.max_abs_u.get(k).map_or("-".into(), |u| number(*u))
        }));
    }
    let taus = match joints {
        1 => "|tau1|".to_string(),
        2 => "|tau1|, |tau2|".to_string(),
        n => format!("|tau1|, .., |tau{n}|"),
    };
    rows.extend([
        row("u(0) [rad/s]", |r| list(&r.controls_at_ends[0])),
        row("u(T) [rad/s]", |r| list(&r.controls_at_ends[1])),
        // Filled by `--torques` (inverse dynamics, torque issue): the peak |tau_k|.
        row(&format!("max {taus} [N m]"), |r| r.max_abs_torque.as_deref().map(list).unwrap_or("- (--torques)".into())),
        row("torque final error [rad]", |r| r.torque_final_error.map(error_number).unwrap_or("- (--torques)".into())),
        row("torque level certified", |r| match &r.torque_certificate {
            Some(t) if t.certified() => "yes".into(),
            Some(_) => "NO".into(),
            None => "- (--torques)".into(),
        }),
        row("min |sigma|, min |P|", |r| match (r.min_abs_sigma, r.min_abs_p) {
            (Some(sigma), Some(p)) => list(&[sigma, p]),
            _ => "-".into(),
        }),
        row("max deviation from plan [rad]", |r| r.max_path_deviation.map(error_number).unwrap_or("-".into())),
        row("time: plan [ms]", |r| significant(r.seconds.plan * 1e3, 4)),
        row("time: torques [ms]", |r| r.seconds.torques.map(|t| significant(t * 1e3, 4)).unwrap_or("-".into())),
        row("time: verify [ms]", |r| r.seconds.verify.map(|t| significant(t * 1e3, 4)).unwrap_or("-".into())),
        row("time: total [ms]", |r| {
            let s = &r.seconds;
            significant((s.plan + s.verify.unwrap_or(0.0) + s.torques.unwrap_or(0.0)) * 1e3, 4)
        }),
    ]);
    rows
}

/// The side-by-side table of `compare`: columns 26 characters wide, or wider for a long cell (an
/// arm of many joints).
fn compare_table(compared: &Compared) -> String {
    let reports = &compared.reports;
    let joints = reports.iter().filter_map(|(_, r)| r.as_ref().ok()).map(|r| r.joints).max().unwrap_or(2);
    let rows = rows(joints);
    let width = reports
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok())
        .flat_map(|r| rows.iter().map(move |(_, cell)| cell(r).len() + 2))
        .fold(26, usize::max);
    let header = |method: &Method, r: &Result<PlanReport, String>| match r {
        Ok(r) => match (&r.transform, &r.ecsa, &r.optimal) {
            (Some(t), _, _) => format!("NFA ({})", t.name()),
            (None, Some(x), _) => format!("ECSA (H = {}, window {})", x.harmonics(), x.window().name()),
            (None, None, Some(_)) => "optimal".to_string(),
            _ => method.name().to_uppercase(),
        },
        Err(_) => method.name().to_uppercase(),
    };
    let mut s = compared.title.clone();
    let mut head = format!("  {:<31}", "");
    for (method, r) in reports {
        head += &format!("{:<width$}", header(method, r));
    }
    s += head.trim_end();
    s += "\n";
    for (label, cell) in &rows {
        let mut line = format!("  {label:<31}");
        for (method, r) in reports {
            let text = match r {
                Ok(r) => cell(r),
                Err(_) if compared.refused.contains(method) => "(refused)".into(),
                Err(_) => "(no plan)".into(),
            };
            line += &format!("{text:<width$}");
        }
        s += line.trim_end();
        s += "\n";
    }
    for (method, r) in reports {
        if let Err(message) = r {
            s += &format!("  {}: {message}\n", method.name());
        }
    }
    s
}

/// Numbers rounded to 4 decimals: `0.1235, 0.0955`.
fn list(x: &[f64]) -> String {
    x.iter().map(|x| rounded(*x, 4)).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use freefloat::planners::chain::ChainProblem;
    use freefloat::planners::{PlannerOptions, planner};
    use freefloat::{Mount, PlanningProblem, RobotParams, Transform};

    /// The paper's problem for the paper's robot mounted at `(a, -a)`, planned by the 2-link
    /// planners.
    fn two_link_compared(a: f64, transform: Option<Transform>) -> Compared {
        let robot = RobotParams::src().with_mount(Mount::new(a, -a).expect("finite")).expect("valid");
        let problem = PlanningProblem::paper(robot);
        let options =
            PlannerOptions { nfa: freefloat::NfaOptions { transform, ..Default::default() }, ..Default::default() };
        let (start, goal) = (problem.start.to_array(), degrees(&problem.goal.to_array()));
        let mut compared = Compared::new(title("", robot.mount, &start, &goal, problem.horizon));
        for method in COMPARED {
            let planned = planner(method, &options).plan(&problem);
            compared.add(method, planned.map(|p| (PlanReport::new(&p, false), p.certified())));
        }
        compared
    }

    /// The row labels of a table, in order (not its title, header or messages).
    fn labels(table: &str) -> Vec<String> {
        let message = |line: &str| COMPARED.iter().any(|m| line.starts_with(&format!("  {}: ", m.name())));
        let rows = table.lines().skip(2).take_while(|line| !message(line));
        rows.map(|line| line[2..33].trim_end().to_string()).collect()
    }

    /// The paper's problem: both columns filled, JSON has both reports with docs/spec.md §3's keys.
    #[test]
    fn compare_default_problem() {
        let compared = two_link_compared(0.0, None);
        let table = compare_table(&compared);
        assert!(table.contains("NFA (eq12)") && table.contains("ECSA (H = 1, window none)"), "{table}");
        assert!(!table.contains("(no plan)"), "{table}");
        let json = compare_json(&compared.reports).unwrap();
        for method in ["optimal", "nfa", "ecsa"] {
            for key in ["final_error", "max_abs_u", "iterations", "seconds", "max_abs_torque", "transform"] {
                assert!(json[method].get(key).is_some(), "{method}.{key}");
            }
        }
        assert!(json["ecsa"]["iterations"].as_u64().is_some() && json["nfa"]["iterations"].is_null());
        assert!(json.get("errors").is_none());
        assert!(compared.failures.is_empty());
    }

    /// Where the NFA has no plan (a = 1, b = -1: the path leaves the domain of Eq. 14) the
    /// ECSA still plans; the NFA column says so and the JSON carries the NFA's error.
    #[test]
    fn compare_when_the_nfa_fails() {
        let compared = two_link_compared(1.0, Some(Transform::Eq14));
        let r = &compared.reports;
        assert!(r[0].1.is_ok() && r[1].1.is_err() && r[2].1.is_ok());
        let table = compare_table(&compared);
        assert!(table.contains("(no plan)") && table.contains("  nfa: "), "{table}");
        let json = compare_json(r).unwrap();
        assert!(json["nfa"].is_null() && json["errors"]["nfa"].is_string() && json["ecsa"].is_object());
        assert!(matches!(&compared.failures[..], [Failure { method: Method::Nfa, what: "has no plan", .. }]));
    }

    /// One table for every robot: the paper's robot as a 2-link arm (the n-joint planners, the NFA
    /// refused) has the rows of the 2-link pipeline, in the same order, and the same columns.
    #[test]
    fn an_arm_has_the_two_link_rows() {
        let paper = two_link_compared(0.0, None);
        let arm = Arm::from_params(&RobotParams::src());
        let q = PlanningProblem::paper(RobotParams::src());
        let chain = ChainProblem {
            start: q.start.to_array().to_vec(),
            goal: q.goal.to_array().to_vec(),
            horizon: q.horizon,
            initial_velocity: vec![0.0; 2],
            wrap: true,
        };
        let mut compared =
            Compared::new(title("2-link arm, ", arm.mount, &chain.start, &degrees(&chain.goal), chain.horizon));
        for method in COMPARED {
            let planned = plan_arm(&arm, method, &ArmRequest::new(chain.clone()));
            if let (Method::Nfa, Err(e)) = (method, &planned) {
                compared.reports.push((method, Err(e.to_string())));
                compared.refused.push(method);
                continue;
            }
            let report = |p: freefloat::planners::arm::ArmPlanned| {
                (PlanReport::from_arm(&p, &chain.start, &chain.goal, false), p.certified())
            };
            compared.add(method, planned.map(report));
        }
        let (two_link, arm) = (compare_table(&paper), compare_table(&compared));
        assert_eq!(labels(&two_link), labels(&arm), "{two_link}\n{arm}");
        assert_eq!(labels(&arm).len(), 18, "{arm}");
        assert_eq!(
            two_link.lines().nth(1),
            arm.lines().nth(1).map(|h| h.replace("NFA       ", "NFA (eq12)")).as_deref()
        );
        assert!(arm.contains("(refused)") && !arm.contains("(no plan)") && compared.failures.is_empty(), "{arm}");
    }
}
