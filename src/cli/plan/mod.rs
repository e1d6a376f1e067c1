//! `freefloat plan` for every robot (docs/spec.md §3): only how the plan is obtained depends on
//! the method ([`pipelines`]: every robot's minimum-effort and ECSA plans through
//! [`plan_problem`], the NFA's of the paper's 2-link model through [`plan_with`]); the table ([`table`]), the JSON, the CSV, the ROS messages, the files and
//! the exit codes are written once, by [`run`].

mod pipelines;
mod table;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::bail;
use freefloat::model::arm::Arm;
use freefloat::plan::Method;
use freefloat::plan::limit_use::LimitReport;
use freefloat::planners::Planned;
use freefloat::report::arm::arm_csv;
use freefloat::report::arm_plan_figure;
use freefloat::report::io::{PlanReport, trajectory_csv, write_atomic};
pub use freefloat::report::numbers::{error_number, number, scientific};
use freefloat::report::plot::{GifOptions, PictureFormat, arm_animation_gif, plan_picture, two_link_animation_gif};
use freefloat::report::ros::MotionRows;
use freefloat::track::ClosedLoopCertificate;

pub(super) use pipelines::{Planning, arm_problem as problem, plan_problem, plan_with, refuse_flags};
pub use table::{degrees, table};

use super::args::{CostArg, Format, PlanArgs, TransformArg, WindowArg};
use super::ros::OutKind;

/// The method of `plan`: `--method`, else the NFA when `--transform` names a transformation, else
/// the optimal planner. A method-specific flag given to another method is bad input (exit 2). For
/// an arm other than the paper's robot (`arm`), a moving start is the planner's to refuse (the
/// `n`-joint ECSA plans from rest), and `--transform` was refused before ([`refuse_flags`]).
fn method(args: &PlanArgs, arm: Option<&Arm>) -> anyhow::Result<Method> {
    let p = &args.problem;
    let transform = p.transform != TransformArg::Auto;
    let method = match args.method {
        Some(m) => Method::from(m),
        None if transform => Method::Nfa,
        None => Method::Optimal,
    };
    let ecsa = p.harmonics != 1 || p.window != WindowArg::None;
    let moving =
        arm.is_none() && super::parse_list::<2>("--from-velocity", &p.from_velocity)?.iter().any(|v| v.abs() > 0.0);
    let optimal = p.smooth_ends || p.no_wrap || p.cost != CostArg::Effort || moving;
    let optimal_flags =
        if arm.is_some() { "--smooth-ends/--cost/--no-wrap" } else { "--from-velocity/--smooth-ends/--cost/--no-wrap" };
    let misplaced = [
        (transform, Method::Nfa, "--transform"),
        (ecsa, Method::Ecsa, "--harmonics/--window"),
        (optimal, Method::Optimal, optimal_flags),
    ];
    for (given, owner, flags) in misplaced {
        if given && method != owner {
            bail!("{flags} apply to --method {}, not to --method {}", owner.name(), method.name());
        }
    }
    Ok(method)
}

/// A plan as one robot's pipeline obtained it, with what the outputs need beside it.
#[allow(clippy::large_enum_variant, reason = "one value per run, moved once")]
enum Obtained {
    /// The NFA's plan of the paper's 2-link model.
    TwoLink {
        planned: Planned,
        geometry: freefloat::model::arm::collision::Geometry,
        /// A 2-link arm with limits planned by the NFA: its limits, checked along the plan.
        limited: Option<Arm>,
        limits: Option<LimitReport>,
        /// With `--torques`: executable with feedback?
        closed_loop: Option<ClosedLoopCertificate>,
        /// The note on the tool frame.
        tool: String,
    },
    /// Every arm's, the paper's robot's too (the minimum-effort planner and the ECSA).
    Arm {
        planning: Planning,
        plot: Option<(PathBuf, PictureFormat)>,
        file: String,
        /// With `--torques`: executable with feedback?
        closed_loop: Option<ClosedLoopCertificate>,
    },
}

impl Obtained {
    /// The JSON report, with the trajectory when `with_trajectory`.
    fn report(&self, with_trajectory: bool) -> PlanReport {
        match self {
            Self::TwoLink { planned, limited, limits, closed_loop, tool, .. } => {
                let mut r = PlanReport::new(planned, with_trajectory);
                if let Some(arm) = limited {
                    r.robot = arm.clone();
                }
                r.set_limits(limits.clone());
                r.notes.push(tool.clone());
                match closed_loop {
                    Some(c) => r.with_closed_loop(c.clone()),
                    None => r,
                }
            }
            Self::Arm { planning: Planning { planned, problem, notes, to_ee }, closed_loop, .. } => {
                let mut r = PlanReport::from_arm(planned, &problem.start, &problem.goal, with_trajectory);
                r.notes = notes.clone();
                r.to_ee = to_ee.clone();
                match closed_loop {
                    Some(c) => r.with_closed_loop(c.clone()),
                    None => r,
                }
            }
        }
    }

    /// The largest residual of the base row of Eq. (6) \[N m\] (with torques).
    fn base_residual(&self) -> Option<f64> {
        match self {
            Self::TwoLink { planned, .. } => planned.torques.as_ref().map(|t| t.max_abs_base_residual),
            Self::Arm { planning, .. } => planning.planned.torques.as_ref().map(|t| t.max_abs_base_residual),
        }
    }

    /// The trajectory's CSV.
    fn csv(&self) -> anyhow::Result<Vec<u8>> {
        Ok(match self {
            Self::TwoLink { planned, .. } => trajectory_csv(&planned.plan.trajectory)?,
            Self::Arm { planning, .. } => arm_csv(&planning.planned)?,
        })
    }

    /// The number of joints and the rows of the ROS messages.
    fn motion_rows(&self) -> (usize, MotionRows) {
        match self {
            Self::TwoLink { planned, .. } => (2, MotionRows::from_plan(&planned.plan)),
            Self::Arm { planning, .. } => (planning.planned.arm.joints(), MotionRows::from_arm(&planning.planned)),
        }
    }

    /// The `--gif` animation, written to `path`.
    fn write_gif(&self, path: &Path, options: &GifOptions, r: &PlanReport) -> anyhow::Result<()> {
        let bytes = match self {
            Self::TwoLink { planned, geometry, .. } => {
                let plan = &planned.plan;
                let title = format!("freefloat plan: {}, T = {} s", plan.method.name(), number(plan.problem.horizon));
                two_link_animation_gif(plan, geometry, r.clearance, &title, options, path)?
            }
            Self::Arm { planning, .. } => arm_animation_gif(&planning.planned, &arm_title(planning), options, path)?,
        };
        Ok(write_atomic(path, &bytes)?)
    }

    /// The `--plot` picture (an arm's plan only: the 2-link pipeline refuses `--plot`).
    fn write_plot(&self) -> anyhow::Result<()> {
        if let Self::Arm { planning, plot: Some((path, format)), file, .. } = self {
            let figure = arm_plan_figure(&planning.planned, arm_title(planning), file);
            write_atomic(path, &plan_picture(&figure, *format, path)?)?;
        }
        Ok(())
    }

    /// Exit 3 without a certified plan (every level, the limits).
    fn check(&self) -> anyhow::Result<()> {
        match self {
            Self::TwoLink { planned, limits, .. } => {
                planned.certified()?;
                limits.as_ref().map_or(Ok(()), |r| r.check())?;
            }
            Self::Arm { planning, .. } => planning.planned.certified()?,
        }
        Ok(())
    }
}

/// The title of an arm's pictures.
fn arm_title(planning: &Planning) -> String {
    let planned = &planning.planned;
    format!(
        "freefloat plan: {}, {}-link arm, T = {} s",
        planned.method.name(),
        planned.arm.joints(),
        number(planning.problem.horizon)
    )
}

/// Runs `plan`: exit 0 with a certified plan, 2 for bad input (e.g. a flag the robot cannot
/// take), 3 (numbers on stderr) without a certified plan. The output files are checked before
/// planning and written before anything is printed, so that stdout never shows a result of a run
/// that then fails.
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
    // only), whose plan is checked against the limits.
    let (obtained, gif) = match super::any_robot(&args.problem.robot)? {
        super::Robot::Arm(arm) if !(arm.joints() == 2 && method(args, None)? == Method::Nfa) => {
            pipelines::arm(args, &arm)?
        }
        super::Robot::Arm(arm) => pipelines::two_link(args, Some(arm))?,
        super::Robot::TwoLink if method(args, None)? != Method::Nfa => {
            pipelines::arm(args, &Arm::from_params(&super::robot(&args.problem.robot)?))?
        }
        super::Robot::TwoLink => pipelines::two_link(args, None)?,
    };
    let r = obtained.report(false);
    let mut text = match args.format {
        Format::Table => table(&r, obtained.base_residual()) + &super::geometry::table_line(r.clearance.as_ref()),
        Format::Json => format!("{}\n", serde_json::to_string_pretty(&r)?),
        Format::Csv => String::from_utf8(obtained.csv()?)?,
        Format::JointTrajectory => String::new(),
    };
    match out {
        Some((path, OutKind::Report)) => write_atomic(path, &serde_json::to_vec_pretty(&obtained.report(true))?)?,
        Some((path, OutKind::Csv)) => write_atomic(path, &obtained.csv()?)?,
        _ => {}
    }
    if super::ros::wanted(args.format, out, base_out) {
        let (joints, rows) = obtained.motion_rows();
        let names = super::ros::joint_names(&args.problem.robot, joints)?;
        if let Some(yaml) = super::ros::messages(&rows, &names, args.format, out, base_out)? {
            text = yaml;
        }
    }
    if let Some((path, options)) = gif {
        obtained.write_gif(path, &options, &r)?;
    }
    obtained.write_plot()?;
    if let Some(limits) = &r.limits
        && args.format == Format::Table
    {
        text += &super::limits::table_line(limits);
    }
    super::emit(&text)?;
    obtained.check()?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use freefloat::RobotParams;
    use freefloat::plan::{PlanningProblem, TorqueOptions};
    use freefloat::planners::{PlannerOptions, planner};

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
        let text = table(&report, planned.torques.as_ref().map(|t| t.max_abs_base_residual));
        assert!(text.contains("max |tau1|, |tau2|") && text.contains("torque final error"), "{text}");

        let failed = freefloat::Error::NotCertified { final_error: 2e-6, tolerance: 1e-6, level: "torque" };
        let message = failed.to_string();
        assert!(message.contains("2.000e-6") && message.contains("torque"), "{message}");
        assert_eq!(crate::cli::exit_code(&anyhow::Error::from(failed)), 3);
    }
}
