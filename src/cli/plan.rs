//! `freefloat plan` and `freefloat compare`.

use std::process::ExitCode;

use anyhow::bail;
use freefloat::model::arm::Arm;
use freefloat::model::kinematics::Elbow;
use freefloat::plan::{Method, Plan, PlanningProblem, TorqueOptions};
use freefloat::planners::{Planned, PlannerOptions, plan_to_pose, planner};
use freefloat::report::io::{PlanReport, trajectory_csv, write_atomic};
pub use freefloat::report::numbers::{error_number, number, rounded, scientific, significant};
use freefloat::report::plan_report::{EcsaAccount, OptimalAccount, TorqueAccount};
use freefloat::report::plot::two_link_animation_gif;
use freefloat::track::closed_loop_certificate;

use super::ros::OutKind;

use super::args::{CostArg, ElbowArg, Format, PlanArgs, ProblemArgs, TransformArg, WindowArg};

/// The planner options of the flags.
fn planner_options(args: &ProblemArgs) -> anyhow::Result<PlannerOptions> {
    Ok(PlannerOptions {
        nfa: super::nfa_options(args)?,
        ecsa: super::ecsa_options(args)?,
        optimal: super::optimal_options(args)?,
    })
}

/// Plans with `method`; with `--max-velocity`, plans again with the horizon stretched when the
/// velocity plan's peak |u| exceeds the cap (decided on the velocity plan alone, whatever the
/// torque level gives); then, with `--torques`, adds the torque level (docs/spec.md, Sec. 2) to
/// the plan kept: inverse dynamics at the samples, and the forward-dynamics certificate. Bad
/// flags are the outer error, a problem without a plan the inner one.
pub(super) fn plan_with(
    method: Method,
    args: &ProblemArgs,
    problem: &PlanningProblem,
) -> anyhow::Result<Result<Planned, freefloat::Error>> {
    if args.elbow.is_some() && args.to_ee.is_none() {
        bail!("--elbow chooses the inverse-kinematics solution of --to-ee: give --to-ee X,Y,PSI, or drop --elbow");
    }
    let planner = planner(method, &planner_options(args)?);
    let pose = match &args.to_ee {
        Some(text) => {
            let [x, y, psi] = super::parse_list::<3>("--to-ee", text)?;
            Some((x, y, psi.to_radians()))
        }
        None => None,
    };
    let elbow = args.elbow.map(|e| match e {
        ElbowArg::Up => Elbow::Up,
        ElbowArg::Down => Elbow::Down,
    });
    let plan_velocity = |problem: &PlanningProblem| -> Result<Planned, freefloat::Error> {
        match pose {
            Some(pose) => Ok(plan_to_pose(planner.as_ref(), problem, pose, elbow)?.1),
            None => planner.plan(problem),
        }
    };
    let cap = super::config::max_velocity(args.max_velocity)?;
    let velocity_plan = match (cap, plan_velocity(problem)) {
        (Some(cap), Ok(first)) if first.plan.max_abs_u[0].max(first.plan.max_abs_u[1]) > cap => {
            // Each method's path is fixed in the time scaled by T (the optimal one too: effort and
            // energy scale as 1/T, the holonomy not at all), so velocities scale as 1/T.
            let peak = first.plan.max_abs_u[0].max(first.plan.max_abs_u[1]);
            let stretched = PlanningProblem { horizon: problem.horizon * peak / cap, ..*problem };
            freefloat::plan::check_horizon("the horizon stretched by --max-velocity", stretched.horizon)?;
            super::note(&format!(
                "note: peak |u| = {} rad/s exceeds --max-velocity {}: horizon stretched from {} s to {} s\n",
                rounded(peak, 4),
                number(cap),
                number(problem.horizon),
                number(stretched.horizon)
            ));
            plan_velocity(&stretched)
        }
        (_, result) => result,
    };
    Ok(velocity_plan.and_then(|mut planned| {
        if args.torques {
            planned.add_torques(&TorqueOptions::default())?;
        }
        Ok(planned)
    }))
}

/// The method of `plan`: `--method`, else the NFA when `--transform` names a transformation, else
/// the optimal planner. A method-specific flag given to another method is bad input (exit 2).
fn method(args: &PlanArgs) -> anyhow::Result<Method> {
    let p = &args.problem;
    let transform = p.transform != TransformArg::Auto;
    let method = match args.method {
        Some(m) => Method::from(m),
        None if transform => Method::Nfa,
        None => Method::Optimal,
    };
    let ecsa = p.harmonics != 1 || p.window != WindowArg::None;
    let moving = super::parse_list::<2>("--from-velocity", &p.from_velocity)?.iter().any(|v| v.abs() > 0.0);
    let optimal = p.smooth_ends || p.no_wrap || p.cost != CostArg::Effort || moving;
    let misplaced = [
        (transform, Method::Nfa, "--transform"),
        (ecsa, Method::Ecsa, "--harmonics/--window"),
        (optimal, Method::Optimal, "--from-velocity/--smooth-ends/--cost/--no-wrap"),
    ];
    for (given, owner, flags) in misplaced {
        if given && method != owner {
            bail!("{flags} apply to --method {}, not to --method {}", owner.name(), method.name());
        }
    }
    Ok(method)
}

/// Runs `plan`: exit 0 with a certified plan, 3 (numbers on stderr) otherwise. The `--out` file
/// is checked before planning and written before anything is printed, so that stdout never
/// shows a result of a run that then fails.
pub fn run(args: &PlanArgs) -> anyhow::Result<ExitCode> {
    super::config::distinct_outputs(&[
        ("--out", args.out.as_deref()),
        ("--gif", args.gif.as_deref()),
        ("--plot", args.plot.as_deref()),
    ])?;
    let out = match &args.out {
        Some(path) => {
            let kind = super::ros::out_kind(path, args.format)?;
            freefloat::report::io::check_writable(path)?;
            Some((path, kind))
        }
        None => None,
    };
    let base_out = super::ros::checked_base_out(args)?;
    // Issue 20: a 2-link arm with limits takes the n-joint pipeline, but for the NFA (2-link
    // only), whose plan is checked against the limits below.
    let mut limited = None;
    if let super::Robot::Arm(arm) = super::any_robot(&args.problem.robot)? {
        if !(arm.joints() == 2 && method(args)? == Method::Nfa) {
            return super::plan_arm::run(args, &arm, out, base_out);
        }
        limited = Some(arm);
    }
    if args.plot.is_some() {
        bail!("--plot draws an arm's plan (--robot or --urdf, not --method nfa): not the 2-link NFA's");
    }
    let gif = super::checked_gif(args)?;
    let problem = super::problem(&args.problem)?;
    let (geometry, _) = super::geometry::two_link(&args.problem.robot, &args.problem.geometry)?;
    let mut planned = plan_with(method(args)?, &args.problem, &problem)??;
    // The clearance and the limits in one pass.
    let limits = super::limits::two_link_checks(limited.as_ref(), geometry.clone(), &mut planned)?;
    let plan = &planned.plan;
    // With torques, the closed-loop certificate too: executable with feedback?
    let closed_loop = match args.problem.torques {
        true => Some(closed_loop_certificate(&plan.problem, planned.motion.as_ref())?),
        false => None,
    };
    let tool = super::plan_arm::tool_note(&args.problem.robot, &Arm::from_params(&plan.problem.robot))?;
    let report = |with_trajectory| {
        let mut r = PlanReport::new(&planned, with_trajectory);
        if let Some(arm) = &limited {
            r.robot = arm.clone();
        }
        r.limits = limits.clone();
        r.notes.push(tool.clone());
        match &closed_loop {
            Some(c) => r.with_closed_loop(c.clone()),
            None => r,
        }
    };
    let r = report(false);
    let mut text = match args.format {
        Format::Table => table(plan, &r) + &super::geometry::table_line(r.clearance.as_ref()),
        Format::Json => format!("{}\n", serde_json::to_string_pretty(&r)?),
        Format::Csv => String::from_utf8(trajectory_csv(&plan.trajectory)?)?,
        Format::JointTrajectory => String::new(),
    };
    match out {
        Some((path, OutKind::Report)) => write_atomic(path, &serde_json::to_vec_pretty(&report(true))?)?,
        Some((path, OutKind::Csv)) => write_atomic(path, &trajectory_csv(&plan.trajectory)?)?,
        _ => {}
    }
    if super::ros::wanted(args.format, out, base_out) {
        let names = super::ros::joint_names(&args.problem.robot, 2)?;
        let rows = freefloat::report::ros::MotionRows::from_plan(plan);
        if let Some(yaml) = super::ros::messages(&rows, &names, args.format, out, base_out)? {
            text = yaml;
        }
    }
    if let Some((path, options)) = gif {
        let title = format!("freefloat plan: {}, T = {} s", plan.method.name(), number(plan.problem.horizon));
        write_atomic(path, &two_link_animation_gif(plan, &geometry, r.clearance, &title, &options, path)?)?;
    }
    if let Some(report) = &limits
        && args.format == Format::Table
    {
        text += &super::limits::table_line(report);
    }
    super::emit(&text)?;
    planned.certified()?;
    limits.map_or(Ok(()), |r| r.check())?;
    Ok(ExitCode::SUCCESS)
}

pub(super) fn deg(q: &[f64]) -> String {
    format!("({}, {}, {})", rounded(q[0].to_degrees(), 4), rounded(q[1].to_degrees(), 4), rounded(q[2].to_degrees(), 4))
}

fn vec3(z: Option<[f64; 3]>) -> String {
    z.map(|z| format!("({}, {}, {})", rounded(z[0], 6), rounded(z[1], 6), rounded(z[2], 6)))
        .unwrap_or_else(|| "-".into())
}

/// The human-readable report.
pub fn table(plan: &Plan, r: &PlanReport) -> String {
    let method = match plan.method {
        Method::Nfa => format!("NFA, transform {}", r.transform.map(|t| t.name()).unwrap_or("-")),
        Method::Ecsa => format!("ECSA, {} iterations", r.iterations.unwrap_or(0)),
        Method::Optimal => format!("optimal (minimum effort), {} SQP iterations", r.iterations.unwrap_or(0)),
    };
    // Each level's own verdict: a failed torque level does not mark the velocity level.
    let status = if plan.verification.certified { "CERTIFIED" } else { "NOT CERTIFIED" };
    let mut s = String::new();
    s += &format!("freefloat plan: {method}, mount (a, b) = ({}, {}) m\n", number(r.mount[0]), number(r.mount[1]));
    s += &format!("  start q0 [deg]           {}\n", deg(&r.start));
    s += &format!("  goal  qd [deg]           {}\n", deg(&r.goal));
    s += &format!("  horizon                  {} s, {} samples\n", number(r.time), r.samples);
    if r.z0.is_some() {
        s += &format!("  z0, zd                   {}  ->  {}\n", vec3(r.z0), vec3(r.zd));
    }
    s += &format!("  reached q(T) [deg]       {}\n", deg(&r.reached));
    s += &format!(
        "  verified final error     {} rad (tolerance {})  {status}\n",
        error_number(r.final_error),
        number(r.tolerance)
    );
    s += &format!(
        "  max deviation from plan  {} rad ({} integrator steps)\n",
        r.max_path_deviation.map_or("-".into(), error_number),
        r.verify_steps
    );
    s += &format!("  effort                   {} rad^2/s (integral of |u|^2 dt)\n", number(r.effort));
    s += &format!("  max |u1|, |u2|           {}, {} rad/s\n", number(r.max_abs_u[0]), number(r.max_abs_u[1]));
    if let Some(OptimalAccount::TwoLink(o)) = &r.optimal {
        s += &format!(
            "  optimality               KKT residual {}, holonomy residual {} rad, {} spline spans (degree {})\n",
            scientific(o.kkt_residual, 1),
            scientific(o.holonomy_residual, 1),
            o.spans,
            o.degree
        );
    }
    if let (Some(sigma), Some(p)) = (r.min_abs_sigma, r.min_abs_p) {
        s += &format!("  min |sigma|, |P|         {}, {}\n", rounded(sigma, 6), rounded(p, 6));
    }
    if let Some(EcsaAccount::TwoLink(x)) = &r.ecsa {
        let [u0, u1] = &r.controls_at_ends;
        s += &format!("  controls                 {} harmonic(s), window {}\n", x.harmonics, x.window.name());
        s += &format!(
            "  iteration residuals      {} rad ({})\n",
            x.residual_history.iter().map(|&r| scientific(r, 1)).collect::<Vec<_>>().join(", "),
            x.termination_name()
        );
        s += &format!(
            "  u(0), u(T)               ({}, {}), ({}, {}) rad/s{}\n",
            rounded(u0[0], 6),
            rounded(u0[1], 6),
            rounded(u1[0], 6),
            rounded(u1[1], 6),
            if x.window == freefloat::Window::None { "  (plain series: not at rest)" } else { "" }
        );
    }
    if let Some(b) = r.band {
        s += &format!(
            "  band steering            N = {} loops of amplitude A = {:.2} rad, eps = {:.3}, lambda in [{:.3}, {:.3}]\n",
            b.loops, b.amplitude, b.margin, b.lambda_range[0], b.lambda_range[1]
        );
    }
    s += &format!(
        "  joint travel [deg]       phi {:.1}, theta1 {:.1}, theta2 {:.1}\n",
        r.joint_travel[0].to_degrees(),
        r.joint_travel[1].to_degrees(),
        r.joint_travel[2].to_degrees()
    );
    if let Some(TorqueAccount::TwoLink(t)) = &r.torque_certificate {
        let c = &t.certificate;
        let status = if c.certified { "CERTIFIED" } else { "NOT CERTIFIED" };
        s += &format!(
            "  max |tau1|, |tau2|       {}, {} N m\n",
            number(t.max_abs_torque[0]),
            number(t.max_abs_torque[1])
        );
        s += &format!(
            "  torque final error       {} rad (tolerance {})  {status}\n",
            error_number(c.final_error),
            number(c.tolerance)
        );
        s += &format!(
            "  torque path deviation    {} rad ({} integrator steps)\n",
            error_number(c.max_path_deviation),
            c.stats.accepted
        );
        s += &format!("  max |angular momentum|   {} kg m^2/s\n", error_number(c.max_abs_momentum));
        s += &format!("  max |base row of (6)|    {} N m\n", error_number(t.max_abs_base_residual));
    }
    if let Some(c) = &r.closed_loop {
        let status = if c.certified { "CERTIFIED: executable with feedback" } else { "NOT CERTIFIED" };
        s += &format!(
            "  closed loop (ct, {} Hz)  final error {} rad (tolerance {})  {status}\n",
            number(c.rate),
            error_number(c.final_error),
            number(c.tolerance)
        );
    }
    let torques = r.seconds.torques.map(|t| format!(", torques {} ms", significant(t * 1e3, 4))).unwrap_or_default();
    let torque_verify = match &r.torque_certificate {
        Some(TorqueAccount::TwoLink(t)) => {
            format!(", torque certificate {} ms", significant(t.seconds.verify * 1e3, 4))
        }
        _ => String::new(),
    };
    s += &format!(
        "  time                     plan {} ms{torques}, verify {} ms{torque_verify}\n",
        significant(r.seconds.plan * 1e3, 4),
        significant(plan.seconds.verify * 1e3, 4)
    );
    for note in &r.notes {
        s += &format!("  note: {note}\n");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use freefloat::RobotParams;

    /// `--torques` fills `max_abs_torque`, `torque_final_error`, `seconds.torques`, the CSV's
    /// tau columns and the table; a failed torque certificate exits with code 3 and its numbers.
    #[test]
    fn torques_fill_report_csv_and_table() {
        let problem = PlanningProblem::paper(RobotParams::src());
        let nfa = freefloat::NfaOptions { samples: 101, accelerations: true, ..Default::default() };
        let options = PlannerOptions { nfa, ..Default::default() };
        let mut planned = planner(Method::Nfa, &options).plan(&problem).unwrap();
        planned.add_torques(&TorqueOptions::default()).unwrap();
        let plan = &planned.plan;
        let report = PlanReport::new(&planned, false);
        let json: serde_json::Value = serde_json::to_value(&report).unwrap();
        assert!(json["max_abs_torque"].as_array().is_some_and(|a| a.len() == 2));
        assert!(json["torque_final_error"].as_f64().is_some_and(|e| e <= 1e-6));
        assert!(json["seconds"]["torques"].as_f64().is_some());
        assert_eq!(json["certified"], serde_json::Value::Bool(true));
        let csv = String::from_utf8(trajectory_csv(&plan.trajectory).unwrap()).unwrap();
        let row = csv.lines().nth(50).unwrap();
        assert!(row.split(',').skip(13).all(|cell| cell.parse::<f64>().is_ok()), "{row}");
        let text = table(plan, &report);
        assert!(text.contains("max |tau1|, |tau2|") && text.contains("torque final error"), "{text}");

        let failed = freefloat::Error::NotCertified { final_error: 2e-6, tolerance: 1e-6, level: "torque" };
        let message = failed.to_string();
        assert!(message.contains("2.000e-6") && message.contains("torque"), "{message}");
        assert_eq!(crate::cli::exit_code(&anyhow::Error::from(failed)), 3);
    }
}
