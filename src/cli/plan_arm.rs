//! `freefloat plan` for an arm of another number of links than the paper's two (docs/spec.md
//! §1, §3): the same flags, `n + 1` angles in `--from`/`--to`, the minimum-effort planner.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use freefloat::model::arm::Arm;
use freefloat::plan::Method;
use freefloat::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::report::arm::{ArmReport, arm_csv};
use freefloat::report::io::write_atomic;
use freefloat::report::numbers::{error_number, number, scientific};
use freefloat::report::plot::arm_animation_gif;

use freefloat::plan::ros::Encoding;

use super::args::{CostArg, Format, PlanArgs, ProblemArgs, TransformArg};
use super::ros::OutKind;

/// Runs `plan` for `arm`: exit 0 with a certified plan, 2 for bad input (e.g. a flag the
/// n-joint planner does not take), 3 without a certified plan. `out` is the checked `--out`
/// file (`true` for JSON). `--gif` is checked before planning, as for the 2-link robot, and
/// written after `--out`, before anything is printed.
pub fn run(
    args: &PlanArgs,
    arm: &Arm,
    out: Option<(&PathBuf, OutKind)>,
    base_out: Option<(&PathBuf, Encoding)>,
) -> anyhow::Result<ExitCode> {
    let p = &args.problem;
    refuse_two_link_flags(args)?;
    let gif = super::checked_gif(args)?;
    let method = args.method.map(Method::from).unwrap_or(Method::Optimal);
    let problem = problem(p, arm)?;
    let request = ArmRequest {
        problem: problem.clone(),
        samples: super::config::samples(p.samples)?,
        tolerance: super::config::tolerance(p.tolerance)?,
        torques: p.torques,
        ecsa: super::ecsa_options(p)?,
        cost: Default::default(),
        smooth_ends: false,
    };
    let planned = plan_arm(arm, method, &request)?;
    let report = |with_trajectory| ArmReport::new(&planned, &problem.start, &problem.goal, with_trajectory);
    let mut text = match args.format {
        Format::Table => table(&planned, &report(false)),
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
    super::emit(&text)?;
    planned.certified()?;
    Ok(ExitCode::SUCCESS)
}

/// The flags of the 2-link pipeline that an n-link arm cannot take: bad input, not ignored
/// (docs/spec.md §3 has the table of every flag: honoured or refused). `--harmonics` and
/// `--window` with another method than the ECSA are the library's refusal ([`plan_arm`]).
fn refuse_two_link_flags(args: &PlanArgs) -> anyhow::Result<()> {
    let p = &args.problem;
    let given = [
        (p.to_ee.is_some(), "--to-ee (task-space goals are for 2-link arms)"),
        (p.elbow.is_some(), "--elbow (it chooses the inverse kinematics of --to-ee, a 2-link goal)"),
        (p.transform != TransformArg::Auto, "--transform (the NFA's feedback transformations are the 2-link robot's)"),
        (p.max_velocity.is_some(), "--max-velocity"),
        (p.smooth_ends, "--smooth-ends"),
        (p.cost != CostArg::Effort, "--cost energy"),
    ];
    for (given, flag) in given {
        if given {
            bail!("{flag} is not available for an arm of another number of links than 2 (docs/spec.md §3)");
        }
    }
    Ok(())
}

/// The problem of the flags for an `n`-link arm: `--from`/`--to` with `n + 1` angles
/// `PHI,TH1,..,THn` in degrees, `--from-velocity` with `n` (or the default `0,0`: at rest).
fn problem(p: &ProblemArgs, arm: &Arm) -> anyhow::Result<ChainProblem> {
    let n = arm.joints();
    let angles = |flag: &str, text: &str, count: usize| -> anyhow::Result<Vec<f64>> {
        let values = list(flag, text)?;
        if values.len() != count {
            bail!(
                "{flag} takes {count} comma-separated angles for this {n}-link arm (PHI,TH1,..,TH{n} in deg), got {}{}",
                values.len(),
                if count == n + 1 { "; the default is the 2-link paper's problem" } else { "" }
            );
        }
        if let Some(&x) = values.iter().find(|x| x.abs() > super::config::max_angle_deg()) {
            return Err(freefloat::Error::from(freefloat::model::InputError::InvalidParameter {
                name: flag.into(),
                value: x,
                expected: "angles with |angle| <= 572957 deg (1e4 rad, docs/spec.md §2)",
            })
            .into());
        }
        Ok(values.iter().map(|x| x.to_radians()).collect())
    };
    let start = angles("--from", &p.ends.from, n + 1)?;
    let goal = angles("--to", &p.ends.to, n + 1)?;
    // The default `0,0` is rest for any arm; any other text gives one velocity per joint.
    let initial_velocity = match list("--from-velocity", &p.from_velocity)? {
        v if v.len() == n => v.iter().map(|x| x.to_radians()).collect(),
        v if v.len() == 2 && v.iter().all(|x| *x == 0.0) => vec![0.0; n],
        v => bail!("--from-velocity takes {n} joint velocities DTH1,..,DTH{n} in deg/s for this arm, got {}", v.len()),
    };
    // Checked here, naming the flags; the planner checks again under its own names.
    let horizon = super::config::time(p.ends.time)?;
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
fn table(planned: &ArmPlanned, r: &ArmReport) -> String {
    let deg = |q: &[f64]| {
        let parts: Vec<String> = q.iter().map(|x| number(x.to_degrees())).collect();
        format!("({})", parts.join(", "))
    };
    let list = |v: &[f64]| v.iter().map(|x| number(*x)).collect::<Vec<_>>().join(", ");
    let verdict = |ok: bool| if ok { "CERTIFIED" } else { "NOT CERTIFIED" };
    let v = planned.verification();
    let mut s = String::new();
    let method = match (&r.optimal, &r.ecsa) {
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
    if let Some(o) = &r.optimal {
        s += &format!(
            "  optimality               KKT residual {}, holonomy residual {} rad, {} spline spans\n",
            scientific(o.kkt_residual, 1),
            scientific(o.holonomy_residual, 1),
            o.spans
        );
    }
    if let Some(e) = &r.ecsa {
        s += &format!(
            "  iteration                residual {} rad (tolerance {}), {}, {} x {} quadrature nodes\n",
            scientific(e.iteration.residual, 1),
            number(e.iteration.tolerance),
            e.iteration.termination,
            e.quadrature_pieces,
            e.quadrature_nodes
        );
    }
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
    s
}
