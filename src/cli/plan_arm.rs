//! `freefloat plan` and `freefloat compare` for an arm of another number of links than the
//! paper's two (docs/spec.md §1, §3): the same flags but the NFA's, `n + 1` angles in
//! `--from`/`--to`, `n` in `--from-velocity`, `--to-ee` by the inverse kinematics of `n` links.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use freefloat::model::InputError;
use freefloat::model::arm::Arm;
use freefloat::plan::Method;
use freefloat::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::optimal::Cost;
use freefloat::planners::to_pose::plan_arm_to_pose;
use freefloat::report::arm::{PoseGoal, arm_csv};
use freefloat::report::arm_plan_figure;
use freefloat::report::io::PlanReport;
use freefloat::report::io::write_atomic;
use freefloat::report::numbers::{error_number, number, rounded, scientific};
use freefloat::report::plot::{PictureFormat, arm_animation_gif, plan_picture};

use freefloat::plan::ros::Encoding;

use super::args::{CostArg, ElbowArg, Format, PlanArgs, ProblemArgs, RobotArgs, TransformArg, WindowArg};
use super::ros::OutKind;

/// Runs `plan` for `arm`: exit 0 with a certified plan, 2 for bad input (e.g. a flag the
/// arm cannot take), 3 without a certified plan. `out` is the checked `--out` file. `--gif` is
/// checked before planning, as for the 2-link robot, and written after `--out`, before anything
/// is printed.
pub fn run(
    args: &PlanArgs,
    arm: &Arm,
    out: Option<(&PathBuf, OutKind)>,
    base_out: Option<(&PathBuf, Encoding)>,
) -> anyhow::Result<ExitCode> {
    let p = &args.problem;
    refuse_flags(p, arm)?;
    let (arm, geometry_notes) = super::geometry::arm_with_flags(arm, &p.robot, &p.geometry)?;
    let arm = &arm;
    let gif = super::checked_gif(args)?;
    let plot = match &args.plot {
        Some(path) => {
            let format = PictureFormat::from_path(path)?;
            freefloat::report::io::check_writable(path)?;
            Some((path, format))
        }
        None => None,
    };
    let method = args.method.map(Method::from).unwrap_or(Method::Optimal);
    if method == Method::Ecsa && (p.smooth_ends || p.cost != CostArg::Effort || p.no_wrap) {
        bail!("--smooth-ends/--cost/--no-wrap apply to --method optimal, not to --method ecsa");
    }
    if method != Method::Ecsa && (p.harmonics != 1 || p.window != WindowArg::None) {
        bail!("--harmonics/--window apply to --method ecsa, not to --method {}", method.name());
    }
    let Planning { planned, problem, mut notes, to_ee } = plan_problem(p, arm, method)?.map_err(|e| name_flag(e, p))?;
    notes.extend(geometry_notes);
    let report = |with_trajectory| {
        let mut r = PlanReport::from_arm(&planned, &problem.start, &problem.goal, with_trajectory);
        r.notes = notes.clone();
        r.to_ee = to_ee.clone();
        r
    };
    let mut text = match args.format {
        Format::Table => {
            table(&planned, &report(false)) + &super::geometry::table_line(planned.verification().clearance.as_ref())
        }
        Format::Json => format!("{}\n", serde_json::to_string_pretty(&report(false))?),
        Format::Csv => String::from_utf8(arm_csv(&planned)?)?,
        Format::JointTrajectory => String::new(),
    };
    match out {
        Some((path, OutKind::Report)) => write_atomic(path, &serde_json::to_vec_pretty(&report(true))?)?,
        Some((path, OutKind::Csv)) => write_atomic(path, &arm_csv(&planned)?)?,
        _ => {}
    }
    if super::ros::wanted(args.format, out, base_out) {
        let names = super::ros::joint_names(&args.problem.robot, arm.joints())?;
        let rows = freefloat::report::ros::MotionRows::from_arm(&planned);
        if let Some(yaml) = super::ros::messages(&rows, &names, args.format, out, base_out)? {
            text = yaml;
        }
    }
    if let Some((path, options)) = gif {
        let title = format!(
            "freefloat plan: {}, {}-link arm, T = {} s",
            planned.method.name(),
            arm.joints(),
            number(problem.horizon)
        );
        write_atomic(path, &arm_animation_gif(&planned, &title, &options, path)?)?;
    }
    if let Some((path, format)) = plot {
        let title = format!(
            "freefloat plan: {}, {}-link arm, T = {} s",
            planned.method.name(),
            arm.joints(),
            number(problem.horizon)
        );
        let file =
            p.robot.robot.as_ref().or(p.robot.urdf.as_ref()).map_or("the robot".into(), |f| f.display().to_string());
        write_atomic(path, &plan_picture(&arm_plan_figure(&planned, title, &file), format, path)?)?;
    }
    super::emit(&text)?;
    planned.certified()?;
    Ok(ExitCode::SUCCESS)
}

/// An arm's plan with what the report says about it.
pub(super) struct Planning {
    pub(super) planned: ArmPlanned,
    /// The problem planned (the goal of `--to-ee`'s kept branch, the horizon of `--max-velocity`).
    pub(super) problem: ChainProblem,
    /// The report's notes.
    pub(super) notes: Vec<String>,
    /// The report's `to_ee`.
    pub(super) to_ee: Option<PoseGoal>,
}

/// Plans the flags' problem for `arm` with `method`: the goal of `--to`, or of every branch of
/// the inverse kinematics of `--to-ee` (the certified plan of least effort kept); then, with
/// `--max-velocity`, again with the horizon stretched when the plan's peak joint velocity exceeds
/// the cap (velocities scale as 1/T along the same path, as for the 2-link robot). Bad flags are
/// the outer error, a problem without a plan the inner one.
pub(super) fn plan_problem(
    p: &ProblemArgs,
    arm: &Arm,
    method: Method,
) -> anyhow::Result<Result<Planning, freefloat::Error>> {
    let mut problem = problem(p, arm)?;
    let cap = super::config::max_velocity(p.max_velocity)?;
    let optimal = method == Method::Optimal;
    let request = |problem: &ChainProblem| ArmRequest {
        problem: problem.clone(),
        samples: super::config::samples(p.samples).unwrap_or(1001),
        tolerance: super::config::tolerance(p.tolerance).unwrap_or(1e-9),
        torques: p.torques,
        ecsa: if method == Method::Ecsa { super::ecsa_options(p).unwrap_or_default() } else { Default::default() },
        cost: match p.cost {
            CostArg::Energy if optimal => Cost::Energy,
            _ => Cost::Effort,
        },
        smooth_ends: p.smooth_ends && optimal,
        shortest_horizon: auto_horizon(p),
    };
    // Checked here so that the closure above cannot fail.
    super::config::samples(p.samples)?;
    super::config::tolerance(p.tolerance)?;
    if method == Method::Ecsa {
        super::ecsa_options(p)?;
    }
    let mut notes = vec![tool_note(&p.robot, arm)?];
    let mut to_ee = None;
    let first = match &p.to_ee {
        None => plan_arm(arm, method, &request(&problem)),
        Some(text) => {
            let [x, y, psi] = super::parse_list::<3>("--to-ee", text)?;
            let branch = match (p.elbow, arm.joints()) {
                (None, _) => None,
                (Some(e), 2) => Some(if e == ElbowArg::Up { "up" } else { "down" }),
                (Some(_), n) => bail!(
                    "--elbow chooses between the two inverse-kinematics solutions of a 2-link arm; this arm has {n} \
                     links: drop --elbow (every branch is tried and the certified plan of least effort kept)"
                ),
            };
            match plan_arm_to_pose(arm, method, &request(&problem), (x, y, psi.to_radians()), branch) {
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
                    super::config::quote(text),
                    reaching.join(", ")
                ),
                Err(freefloat::Error::Input(e @ InputError::PoseBranch { .. })) => {
                    bail!("--to-ee {}: {e}", super::config::quote(text))
                }
                Err(e) => Err(e),
            }
        }
    };
    let planned = match (cap, first) {
        (Some(cap), Ok(first)) if peak_velocity(&first) > cap => {
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
            let stretched = problem.horizon * peak / cap;
            freefloat::plan::check_horizon("the horizon stretched by --max-velocity", stretched)?;
            let note = format!(
                "peak |theta_k'| = {} rad/s exceeds --max-velocity {}: horizon stretched from {} s to {} s",
                rounded(peak, 4),
                number(cap),
                number(problem.horizon),
                number(stretched)
            );
            super::note(&format!("note: {note}\n"));
            notes.push(note);
            problem.horizon = stretched;
            plan_arm(arm, method, &request(&problem))
        }
        (_, result) => result,
    };
    Ok(planned.map(|planned| {
        // The horizon `--time auto` found.
        problem.horizon = planned.plan.horizon();
        Planning { planned, problem, notes, to_ee }
    }))
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

/// The largest `|theta_k'|` of a plan \[rad/s\]: the samples', or the minimum-effort planner's
/// (sampled finely), whichever is larger.
fn peak_velocity(planned: &ArmPlanned) -> f64 {
    let sampled = planned.trajectory.iter().flat_map(|p| p.rate.iter()).fold(0.0_f64, |m, r| m.max(r.abs()));
    sampled.max(planned.stats().map_or(0.0, |s| s.peak_velocity))
}

/// The plan's note on the tool frame: for a URDF the frame that ends the last link
/// ([`Arm::load_tool_frame`]), for a robot file the tip of the last link.
pub(super) fn tool_note(robot: &RobotArgs, arm: &Arm) -> anyhow::Result<String> {
    let n = arm.joints();
    let length = number(arm.links[n - 1].length);
    let urdf = super::robot_file(robot)?
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
pub(super) fn refuse_flags(p: &ProblemArgs, arm: &Arm) -> anyhow::Result<()> {
    if p.elbow.is_some() && p.to_ee.is_none() {
        bail!("--elbow chooses the inverse-kinematics solution of --to-ee: give --to-ee X,Y,PSI, or drop --elbow");
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
pub(super) fn problem(p: &ProblemArgs, arm: &Arm) -> anyhow::Result<ChainProblem> {
    let n = arm.joints();
    let angles = super::config::arm_angles;
    let start = angles("--from", &p.ends.from, n + 1)?;
    // With --to-ee the goal is the inverse kinematics' (`--to` conflicts with it and is unread).
    let goal = if p.to_ee.is_some() { start.clone() } else { angles("--to", &p.ends.to, n + 1)? };
    // The default `0,0` is rest for any arm; any other text gives one velocity per joint.
    let initial_velocity = match list("--from-velocity", &p.from_velocity)? {
        v if v.len() == n => v.iter().map(|x| x.to_radians()).collect(),
        v if v.len() == 2 && v.iter().all(|x| *x == 0.0) => vec![0.0; n],
        v => bail!("--from-velocity takes {n} joint velocities DTH1,..,DTH{n} in deg/s for this arm, got {}", v.len()),
    };
    // Checked here, naming the flags; the planner checks again under its own names.
    // `--time auto`: the search's first probe is the default horizon.
    let horizon = if auto_horizon(p) { 10.0 } else { super::config::time(p.ends.time)? };
    Ok(ChainProblem { start, goal, horizon, initial_velocity, wrap: !p.no_wrap })
}

/// A comma-separated list of finite numbers (at most 64), naming the flag on error.
pub(super) fn list(flag: &str, text: &str) -> anyhow::Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() > 64 {
        bail!("{flag} takes at most 64 numbers, got {}", parts.len());
    }
    parts
        .iter()
        .map(|part| {
            let x: f64 = part
                .parse()
                .map_err(|_| anyhow::anyhow!("{flag}: `{}` is not a number", super::config::quote(part)))?;
            if !x.is_finite() {
                bail!("{flag}: `{}` is not a finite number", super::config::quote(part));
            }
            Ok(x)
        })
        .collect()
}

/// The human-readable summary.
fn table(planned: &ArmPlanned, r: &PlanReport) -> String {
    let deg = |q: &[f64]| {
        let parts: Vec<String> = q.iter().map(|x| number(x.to_degrees())).collect();
        format!("({})", parts.join(", "))
    };
    let list = |v: &[f64]| v.iter().map(|x| number(*x)).collect::<Vec<_>>().join(", ");
    let verdict = |ok: bool| if ok { "CERTIFIED" } else { "NOT CERTIFIED" };
    let v = planned.verification();
    let mut s = String::new();
    let method = match (planned.stats(), planned.ecsa()) {
        (Some(o), _) => format!("optimal (minimum effort), {}-link arm, {} SQP iterations", r.joints, o.iterations),
        (None, Some(e)) => format!(
            "ecsa ({} harmonic(s), window {}, {}), {}-link arm, {} iterations in {} continuation steps",
            e.harmonics,
            e.window.name(),
            e.solver.name(),
            r.joints,
            e.iteration.iterations,
            e.continuation_steps
        ),
        (None, None) => format!("{}, {}-link arm", r.method.name(), r.joints),
    };
    s += &format!(
        "freefloat plan: {method}, mount (a, b) = ({}, {}) m\n",
        number(r.robot.mount.a),
        number(r.robot.mount.b)
    );
    s += &format!("  start q0 [deg]           {}\n", deg(&r.start));
    s += &format!("  goal  qd [deg]           {}\n", deg(&r.goal));
    s += &format!("  horizon                  {} s, {} samples\n", number(r.time), r.samples);
    s += &format!("  reached q(T) [deg]       {}\n", deg(&r.reached));
    s += &format!(
        "  verified final error     {} rad (tolerance {})  {}\n",
        error_number(v.final_error),
        number(v.tolerance),
        verdict(v.certified)
    );
    s += &format!("  max |angular momentum|   {} kg m^2/s\n", scientific(v.max_abs_momentum, 2));
    s += &format!("  effort                   {} rad^2/s (integral of |u|^2 dt)\n", number(r.effort));
    s += &format!("  max |u_k| [rad/s]        {}\n", list(&r.max_abs_u));
    if let Some(o) = planned.stats().filter(|o| !o.converged) {
        s += &format!(
            "  SQP                      stopped ({}) at KKT residual {}: a feasible plan, not proven the \
             least effort\n",
            o.termination.name(),
            scientific(o.kkt_residual, 1)
        );
    }
    if let Some(last) = planned.trajectory.last() {
        let q: Vec<f64> = std::iter::once(last.phi).chain(last.theta.iter().copied()).collect();
        let e = planned.arm.task_point(&q, &vec![0.0; q.len()]).end_effector;
        s += &format!(
            "  end effector at T        ({} m, {} m, {} deg)\n",
            rounded(e[0], 6),
            rounded(e[1], 6),
            rounded(e[2].to_degrees(), 4)
        );
    }
    if let Some(goal) = &r.to_ee {
        for b in &goal.branches {
            let outcome = match (b.effort, &b.error) {
                (Some(effort), _) => format!("effort {}{}", number(effort), if b.kept { "  (kept)" } else { "" }),
                (None, Some(e)) => e.clone(),
                (None, None) => "-".into(),
            };
            s += &format!(
                "  --to-ee branch           {}: residual {} m, {}\n",
                b.solution.branch,
                scientific(b.solution.residual, 1),
                outcome
            );
        }
    }
    if let Some(o) = planned.stats() {
        s += &format!(
            "  optimality               KKT residual {}, holonomy residual {} rad, {} spline spans\n",
            scientific(o.kkt_residual, 1),
            scientific(o.holonomy_residual, 1),
            o.spans
        );
    }
    if let Some(e) = planned.ecsa() {
        s += &format!(
            "  iteration                residual {} rad (tolerance {}), {}, {} x {} quadrature nodes\n",
            scientific(e.iteration.residual, 1),
            number(e.iteration.tolerance),
            e.iteration.termination,
            e.quadrature_pieces,
            e.quadrature_nodes
        );
    }
    s += &super::limits::table_line(&planned.limits);
    if let Some(t) = &planned.torques {
        let c = &t.certificate;
        s += &format!("  max |tau_k| [N m]        {}\n", list(&t.max_abs_torque));
        s += &format!(
            "  torque final error       {} rad (tolerance {})  {}\n",
            error_number(c.final_error),
            number(c.tolerance),
            verdict(c.certified)
        );
        s += &format!("  max |base row of (6)|    {} N m\n", scientific(t.max_abs_base_residual, 2));
    }
    s += &format!(
        "  time                     plan {} ms{}\n",
        number(r.seconds.plan * 1e3),
        planned.torques.as_ref().map_or(String::new(), |t| format!(", torques {} ms", number(t.seconds * 1e3)))
    );
    for note in &r.notes {
        s += &format!("  note: {note}\n");
    }
    s
}
