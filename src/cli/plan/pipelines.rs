//! How `plan` and `compare` obtain a plan: [`arm`] for every robot's minimum-effort and ECSA
//! plans, the paper's robot as its 2-link arm (through [`plan_problem`]: `n + 1` angles in
//! `--from`/`--to`, `n` in `--from-velocity`, `--to-ee` by the inverse kinematics of `n` links),
//! and [`two_link`] for the NFA, the paper's 2-link model's (through [`plan_with`]; docs/spec.md
//! §1, §3).

use std::path::PathBuf;

use anyhow::bail;
use freefloat::model::InputError;
use freefloat::model::arm::Arm;
use freefloat::model::kinematics::Elbow;
use freefloat::plan::{Method, PlanningProblem, TorqueOptions};
use freefloat::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::optimal::Cost;
use freefloat::planners::to_pose::plan_arm_to_pose;
use freefloat::planners::{Planned, PlannerOptions, plan_to_pose, planner};
use freefloat::report::arm::PoseGoal;
use freefloat::report::numbers::{number, rounded};
use freefloat::report::plot::{GifOptions, PictureFormat};
use freefloat::track::{arm_closed_loop_certificate, closed_loop_certificate};

use super::Obtained;
use crate::cli::args::{CostArg, ElbowArg, PlanArgs, ProblemArgs, RobotArgs, TransformArg};

/// The checked `--gif` file and its options.
type Gif<'a> = Option<(&'a PathBuf, GifOptions)>;

/// The planner options of the flags.
fn planner_options(args: &ProblemArgs) -> anyhow::Result<PlannerOptions> {
    Ok(PlannerOptions {
        nfa: crate::cli::nfa_options(args)?,
        ecsa: crate::cli::ecsa_options(args)?,
        optimal: crate::cli::optimal_options(args)?,
    })
}

/// Plans with `method`; with `--max-velocity`, plans again with the horizon stretched when the
/// velocity plan's peak |u| exceeds the cap (decided on the velocity plan alone, whatever the
/// torque level gives); then, with `--torques`, adds the torque level (docs/spec.md, Sec. 2) to
/// the plan kept: inverse dynamics at the samples, and the forward-dynamics certificate. Bad
/// flags are the outer error, a problem without a plan the inner one.
pub(in crate::cli) fn plan_with(
    method: Method,
    args: &ProblemArgs,
    problem: &PlanningProblem,
) -> anyhow::Result<Result<Planned, freefloat::Error>> {
    if args.elbow.is_some() && args.to_ee.is_none() {
        bail!("{ELBOW_WITHOUT_POSE}");
    }
    let planner = planner(method, &planner_options(args)?);
    let pose = match &args.to_ee {
        Some(text) => {
            let [x, y, psi] = crate::cli::parse_list::<3>("--to-ee", text)?;
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
    let cap = crate::cli::config::max_velocity(args.max_velocity)?;
    let velocity_plan = match (cap, plan_velocity(problem)) {
        (Some(cap), Ok(first)) if first.plan.max_abs_u[0].max(first.plan.max_abs_u[1]) > cap => {
            // Each method's path is fixed in the time scaled by T (the optimal one too: effort and
            // energy scale as 1/T, the holonomy not at all), so velocities scale as 1/T.
            let peak = first.plan.max_abs_u[0].max(first.plan.max_abs_u[1]);
            let stretched = PlanningProblem { horizon: problem.horizon * peak / cap, ..*problem };
            freefloat::plan::check_horizon("the horizon stretched by --max-velocity", stretched.horizon)?;
            crate::cli::note(&format!(
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

/// `--elbow` without `--to-ee`: bad input for every robot.
const ELBOW_WITHOUT_POSE: &str =
    "--elbow chooses the inverse-kinematics solution of --to-ee: give --to-ee X,Y,PSI, or drop --elbow";

/// The NFA's plan of the paper's 2-link model (for the paper's robot, or for a 2-link arm with
/// limits, `limited`): the plan of [`plan_with`], its clearance and limits checked, with torques
/// its closed-loop certificate; with the checked `--gif`. `--plot` is refused (it draws a
/// minimum-effort or ECSA plan).
pub(super) fn two_link(args: &PlanArgs, limited: Option<Arm>) -> anyhow::Result<(Obtained, Gif<'_>)> {
    if args.plot.is_some() {
        bail!(
            "--plot draws a minimum-effort or ECSA plan (--method optimal or ecsa): the NFA's plan of the paper's \
             2-link model has no such figure; drop --plot, or see its pictures with --gif"
        );
    }
    let gif = crate::cli::checked_gif(args)?;
    let problem = crate::cli::problem(&args.problem)?;
    let (geometry, _) = crate::cli::geometry::two_link(&args.problem.robot, &args.problem.geometry)?;
    let mut planned = plan_with(super::method(args, None)?, &args.problem, &problem)??;
    // The clearance and the limits in one pass.
    let limits = crate::cli::limits::two_link_checks(limited.as_ref(), geometry.clone(), &mut planned)?;
    // With torques, the closed-loop certificate too: executable with feedback?
    let closed_loop = match args.problem.torques {
        true => Some(closed_loop_certificate(&planned.plan.problem, planned.motion.as_ref())?),
        false => None,
    };
    let tool = tool_note(&args.problem.robot, &Arm::from_params(&planned.plan.problem.robot))?;
    Ok((Obtained::TwoLink { planned, geometry, limited, limits, closed_loop, tool }, gif))
}

/// Every arm, the paper's robot too: the plan of [`plan_problem`], with the checked `--gif` (and
/// `--plot`). A flag the arm cannot take is bad input.
pub(super) fn arm<'a>(args: &'a PlanArgs, arm: &Arm) -> anyhow::Result<(Obtained, Gif<'a>)> {
    let p = &args.problem;
    refuse_flags(p, arm)?;
    let (arm, geometry_notes) = crate::cli::geometry::arm_with_flags(arm, &p.robot, &p.geometry)?;
    let arm = &arm;
    let gif = crate::cli::checked_gif(args)?;
    let plot = match &args.plot {
        Some(path) => {
            let format = PictureFormat::from_path(path)?;
            freefloat::report::io::check_writable(path)?;
            Some((path.clone(), format))
        }
        None => None,
    };
    let method = super::method(args, Some(arm))?;
    let mut planning = plan_problem(p, arm, method)?.map_err(|e| name_flag(e, p))?;
    planning.notes.extend(geometry_notes);
    let file = p.robot.robot.as_ref().or(p.robot.urdf.as_ref()).map_or("the robot".into(), |f| f.display().to_string());
    // With torques, the closed-loop certificate too, as for the 2-link robot: the plan tracked on
    // the nominal arm with computed torque at 1 kHz.
    let closed_loop = match p.torques {
        true => Some(arm_closed_loop_certificate(&planning.planned.arm, &planning.problem, &planning.planned.plan)?),
        false => None,
    };
    Ok((Obtained::Arm { planning, plot, file, closed_loop }, gif))
}

/// An arm's plan with what the report says about it.
pub(in crate::cli) struct Planning {
    pub(in crate::cli) planned: ArmPlanned,
    /// The problem planned (the goal of `--to-ee`'s kept branch, the horizon of `--max-velocity`).
    pub(in crate::cli) problem: ChainProblem,
    /// The report's notes.
    pub(in crate::cli) notes: Vec<String>,
    /// The report's `to_ee`.
    pub(in crate::cli) to_ee: Option<PoseGoal>,
}

/// Plans the flags' problem for `arm` with `method`: the goal of `--to`, or of every branch of
/// the inverse kinematics of `--to-ee` (the certified plan of least effort kept); then, with
/// `--max-velocity`, again with the horizon stretched when the plan's peak joint velocity exceeds
/// the cap (velocities scale as 1/T along the same path, as for the 2-link robot). The re-plan,
/// and `--time auto`'s search, hold the cap as a velocity limit of every joint
/// ([`with_velocity_cap`]): where the robot's own limits shaped the first plan the stretched
/// optimum is not that plan scaled, and the certificate then checks the cap like any limit. Bad
/// flags are the outer error, a problem without a plan the inner one.
pub(in crate::cli) fn plan_problem(
    p: &ProblemArgs,
    arm: &Arm,
    method: Method,
) -> anyhow::Result<Result<Planning, freefloat::Error>> {
    let mut problem = arm_problem(p, arm)?;
    let cap = crate::cli::config::max_velocity(p.max_velocity)?;
    let capped = cap.map(|cap| with_velocity_cap(arm, cap)).transpose()?;
    let first_arm = match (auto_horizon(p), &capped) {
        (true, Some(capped)) => capped,
        _ => arm,
    };
    let optimal = method == Method::Optimal;
    let request = |problem: &ChainProblem| ArmRequest {
        problem: problem.clone(),
        samples: crate::cli::config::samples(p.samples).unwrap_or(1001),
        tolerance: crate::cli::config::tolerance(p.tolerance).unwrap_or(1e-9),
        torques: p.torques,
        ecsa: if method == Method::Ecsa { crate::cli::ecsa_options(p).unwrap_or_default() } else { Default::default() },
        cost: match p.cost {
            CostArg::Energy if optimal => Cost::Energy,
            _ => Cost::Effort,
        },
        smooth_ends: p.smooth_ends && optimal,
        shortest_horizon: auto_horizon(p),
    };
    // Checked here so that the closure above cannot fail.
    crate::cli::config::samples(p.samples)?;
    crate::cli::config::tolerance(p.tolerance)?;
    if method == Method::Ecsa {
        crate::cli::ecsa_options(p)?;
    }
    let mut notes = vec![tool_note(&p.robot, arm)?];
    let mut to_ee = None;
    let _spinner = crate::cli::output::Spinner::start(if auto_horizon(p) {
        "searching the shortest horizon inside the limits (--time auto)"
    } else {
        "planning"
    });
    let first = match &p.to_ee {
        None => plan_arm(first_arm, method, &request(&problem)),
        Some(text) => {
            let [x, y, psi] = crate::cli::parse_list::<3>("--to-ee", text)?;
            let branch = match (p.elbow, arm.joints()) {
                (None, _) => None,
                (Some(e), 2) => Some(if e == ElbowArg::Up { "up" } else { "down" }),
                (Some(_), n) => bail!(
                    "--elbow chooses between the two inverse-kinematics solutions of a 2-link arm; this arm has {n} \
                     links: drop --elbow (every branch is tried and the certified plan of least effort kept)"
                ),
            };
            match plan_arm_to_pose(first_arm, method, &request(&problem), (x, y, psi.to_radians()), branch) {
                Ok((goal, planned)) => {
                    if let Some(kept) = goal.kept() {
                        problem.goal = kept.solution.q.clone();
                    }
                    notes.push(goal.note());
                    to_ee = Some(goal);
                    Ok(planned)
                }
                Err(freefloat::Error::Input(InputError::PoseBranch { branch: Some(b), reaching, .. })) => bail!(
                    "--to-ee {}: --elbow {b}: no inverse-kinematics branch of that name reaches the pose (those that \
                     do: {}); drop --elbow to plan them all",
                    crate::cli::config::quote(text),
                    reaching.join(", ")
                ),
                Err(freefloat::Error::Input(e @ InputError::PoseBranch { .. })) => {
                    bail!("--to-ee {}: {e}", crate::cli::config::quote(text))
                }
                Err(e) => Err(e),
            }
        }
    };
    let planned = match (cap, &capped, first) {
        (Some(cap), Some(capped), Ok(first)) if !auto_horizon(p) && peak_velocity(&first) > cap => {
            let peak = peak_velocity(&first);
            let start = problem.initial_velocity.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if start > cap {
                bail!(
                    "--max-velocity {}: the start velocity (--from-velocity) has |theta_k'| = {} rad/s already; \
                     raise the cap or slow the start",
                    number(cap),
                    rounded(start, 4)
                );
            }
            // 0.01 % beyond the sampled peak's ratio: the continuous peak of a plan that is the
            // first one scaled (the ECSA's, which does not plan with limits) stays under the cap
            // between the samples (1001 samples of the 3-link example's ECSA plan miss its peak
            // by 3.5e-6 relative, and its certificate then refused it at 1e-6).
            let stretched = problem.horizon * peak / cap * (1.0 + 1e-4);
            freefloat::plan::check_horizon("the horizon stretched by --max-velocity", stretched)?;
            let note = format!(
                "peak |theta_k'| = {} rad/s exceeds --max-velocity {}: horizon stretched from {} s to {} s, the cap \
                 held as every joint's velocity limit",
                rounded(peak, 4),
                number(cap),
                number(problem.horizon),
                number(stretched)
            );
            crate::cli::note(&format!("note: {note}\n"));
            notes.push(note);
            problem.horizon = stretched;
            plan_arm(capped, method, &request(&problem))
        }
        (_, _, result) => result,
    };
    if let (Some(cap), true) = (cap, auto_horizon(p)) {
        notes.push(format!("--max-velocity {} rad/s held as every joint's velocity limit", number(cap)));
    }
    Ok(planned.map(|planned| {
        // The horizon `--time auto` found.
        problem.horizon = planned.plan.horizon();
        Planning { planned, problem, notes, to_ee }
    }))
}

/// `arm` with `--max-velocity`'s cap \[rad/s\] as every joint's velocity limit (the lower of it
/// and the robot's own).
fn with_velocity_cap(arm: &Arm, cap: f64) -> anyhow::Result<Arm> {
    let mut limits = arm.limits.clone();
    limits.joints.resize(arm.joints(), Default::default());
    for joint in &mut limits.joints {
        joint.velocity = Some(joint.velocity.map_or(cap, |v| v.min(cap)));
    }
    Ok(arm.clone().with_limits(limits)?)
}

/// A refusal of `smooth_ends`/`cost` by the library (e.g. with the ECSA) under the flag's name.
fn name_flag(e: freefloat::Error, p: &ProblemArgs) -> anyhow::Error {
    let text = e.to_string();
    let flag = match () {
        _ if p.smooth_ends && text.contains("`smooth_ends`") => "--smooth-ends",
        _ if p.cost != CostArg::Effort && text.contains("`cost`") => "--cost energy",
        _ => return e.into(),
    };
    anyhow::Error::from(e).context(format!("{flag} cannot be honoured here"))
}

/// The largest `|theta_k'|` of a plan \[rad/s\]: its peak rates (refined between the samples),
/// or the minimum-effort planner's (sampled finely), whichever is larger.
fn peak_velocity(planned: &ArmPlanned) -> f64 {
    let peak = planned.peak_rates.iter().fold(0.0_f64, |m, r| m.max(*r));
    peak.max(planned.stats().map_or(0.0, |s| s.peak_velocity))
}

/// The plan's note on the tool frame: for a URDF the frame that ends the last link
/// ([`Arm::load_tool_frame`]), for a robot file the tip of the last link.
fn tool_note(robot: &RobotArgs, arm: &Arm) -> anyhow::Result<String> {
    let n = arm.joints();
    let length = number(arm.links[n - 1].length);
    let urdf = crate::cli::robot_file(robot)?
        .filter(|path| path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("urdf")));
    let Some(path) = urdf else {
        return Ok(format!("end effector: the tip of link {n}, {length} m from joint {n}"));
    };
    Ok(match Arm::load_tool_frame(path)? {
        Some(frame) => format!("end effector: frame `{frame}`, {length} m along link {n} (the URDF's tool frame)"),
        None => format!(
            "end effector: the centre of mass of link {n}, {length} m along it (the URDF has no fixed frame beyond \
             the last joint)"
        ),
    })
}

/// The flags that an arm cannot take: bad input, not ignored (docs/spec.md §3 has the table of
/// every flag). `--harmonics` and `--window` with another method than the ECSA are the
/// library's refusal ([`plan_arm`]).
pub(in crate::cli) fn refuse_flags(p: &ProblemArgs, arm: &Arm) -> anyhow::Result<()> {
    if p.elbow.is_some() && p.to_ee.is_none() {
        bail!("{ELBOW_WITHOUT_POSE}");
    }
    if p.transform != TransformArg::Auto {
        bail!(
            "--transform: the NFA's feedback transformations are the 2-link robot's (its normal form is for two \
             joints), and this arm has {} links (docs/spec.md §3)",
            arm.joints()
        );
    }
    Ok(())
}

/// Whether `--time auto` was given (kept as `+inf` by the parser).
fn auto_horizon(p: &ProblemArgs) -> bool {
    p.ends.time.is_infinite() && p.ends.time > 0.0
}

/// The problem of the flags for an `n`-link arm: `--from`/`--to` with `n + 1` angles
/// `PHI,TH1,..,THn` in degrees, `--from-velocity` with `n` (or the default `0,0`: at rest).
pub(in crate::cli) fn arm_problem(p: &ProblemArgs, arm: &Arm) -> anyhow::Result<ChainProblem> {
    let n = arm.joints();
    let angles = crate::cli::config::arm_angles;
    let start = angles("--from", &p.ends.from, n + 1)?;
    // With --to-ee the goal is the inverse kinematics' (`--to` conflicts with it and is unread).
    let goal = if p.to_ee.is_some() { start.clone() } else { angles("--to", &p.ends.to, n + 1)? };
    // The default `0,0` is rest for any arm; any other text gives one velocity per joint.
    let initial_velocity = match crate::cli::parse_numbers("--from-velocity", &p.from_velocity)? {
        v if v.len() == n => v.iter().map(|x| x.to_radians()).collect(),
        v if v.len() == 2 && v.iter().all(|x| *x == 0.0) => vec![0.0; n],
        v => bail!("--from-velocity takes {n} joint velocities DTH1,..,DTH{n} in deg/s for this arm, got {}", v.len()),
    };
    // Checked here, naming the flags; the planner checks again under its own names.
    // `--time auto`: the search's first probe is the default horizon.
    let horizon = if auto_horizon(p) { 10.0 } else { crate::cli::config::time(p.ends.time)? };
    Ok(ChainProblem { start, goal, horizon, initial_velocity, wrap: !p.no_wrap })
}
