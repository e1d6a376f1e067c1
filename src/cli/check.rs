//! `freefloat check` (docs/spec.md §3): what a joint trajectory made by any other tool does to
//! the free-floating robot of the flags.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use freefloat::analysis::check::{CheckOptions, CheckReport, check, read_trajectory};
use freefloat::model::arm::Arm;
use freefloat::model::arm::file::default_joint_names;
use freefloat::model::wrap_angle;
use freefloat::report::io::write_atomic;
use freefloat::report::numbers::{error_number, number, scientific};

use super::args::{CheckArgs, DomainFormat, RobotArgs};

/// Largest difference between `--from`'s joints and the trajectory's first point \[rad\]
/// (degrees typed with a few digits).
const START_MATCH: f64 = 1e-6;

/// The robot of the flags as an arm (the `src` preset and 2-link files as the 2-link arm), with
/// its joint names (a URDF's, else `joint1..jointN`).
fn robot(args: &RobotArgs) -> anyhow::Result<(Arm, Vec<String>)> {
    let arm = match super::any_robot(args)? {
        super::Robot::Arm(arm) => arm,
        super::Robot::TwoLink => Arm::from_params(&super::robot(args)?),
    };
    let names = match args.urdf.as_ref().or(args.robot.as_ref()) {
        Some(path) => Arm::load_named(path)?.1,
        None => default_joint_names(arm.joints()),
    };
    Ok((arm, names))
}

/// Angles in degrees from a flag, each within `--from`/`--to`'s bound, in radians.
fn angles(flag: &str, text: &str) -> anyhow::Result<Vec<f64>> {
    let values = super::parse_numbers(flag, text)?;
    if let Some(x) = values.iter().find(|x| x.abs() > super::config::max_angle_deg()) {
        bail!("{flag}: {x} deg is out of range: angles with |angle| <= 572957 deg (1e4 rad, docs/spec.md §2)");
    }
    Ok(values.iter().map(|x| x.to_radians()).collect())
}

/// Runs `check`: exit 0 when the trajectory reaches `--to` within `--tolerance` (or no goal is
/// given), keeps the clearance (the robot file's shapes, `--obstacle`, `--clearance`) and stays
/// inside every declared limit (the file's and `--limit`'s), 3 with the numbers when it does
/// not, 2 for bad input. `--out` is checked before the
/// work and written before anything is printed.
pub fn run(args: &CheckArgs) -> anyhow::Result<ExitCode> {
    let out = match &args.out {
        Some(path) => {
            let json = match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
                Some("json") => true,
                Some("csv") => false,
                _ => bail!("--out {}: the file name must end in .json or .csv", path.display()),
            };
            freefloat::report::io::check_writable(path)?;
            super::config::outputs_apart_from_inputs(&[("--out", Some(path))], &[("--trajectory", &args.trajectory)])?;
            Some((path, json))
        }
        None => None,
    };
    let tolerance = super::config::tolerance(args.tolerance)?;
    let (arm, names) = robot(&args.robot)?;
    let (arm, _notes) = super::geometry::arm_with_flags(&arm, &args.robot, &args.geometry)?;
    let n = arm.joints();
    let input = read_trajectory(&args.trajectory, &names)?;
    let first = &input.samples.positions[0];
    let base_start = match &args.from {
        Some(text) => {
            let from = angles("--from", text)?;
            if from.len() != 1 && from.len() != n + 1 {
                bail!(
                    "--from takes PHI or {} angles PHI,TH1,..,TH{n} in deg for this {n}-joint robot, got {}",
                    n + 1,
                    from.len()
                );
            }
            for (k, (given, point)) in from.iter().skip(1).zip(first).enumerate() {
                if wrap_angle(given - point).abs() > START_MATCH {
                    bail!(
                        "--from: joint `{}` is {} deg, the trajectory's first point has {} deg (they must agree within 1e-6 rad)",
                        names[k],
                        number(given.to_degrees()),
                        number(point.to_degrees())
                    );
                }
            }
            from[0]
        }
        None => input.base_start.unwrap_or(0.0),
    };
    let goal = match &args.to {
        Some(text) => {
            let goal = angles("--to", text)?;
            if goal.len() != n + 1 {
                bail!(
                    "--to takes {} angles PHI,TH1,..,TH{n} in deg for this {n}-joint robot, got {}",
                    n + 1,
                    goal.len()
                );
            }
            Some(goal)
        }
        None => None,
    };
    let options = CheckOptions { tolerance, ..CheckOptions::default() };
    let report = check(&arm, &names, &input.samples, base_start, goal.as_deref(), &options)?;
    let text = match args.format {
        DomainFormat::Table => table(&args.trajectory, &arm, &report),
        DomainFormat::Json => format!("{}\n", serde_json::to_string_pretty(&report)?),
    };
    if let Some((path, json)) = out {
        let bytes = if json { serde_json::to_vec_pretty(&report)? } else { csv(&report, &input.samples.positions)? };
        write_atomic(path, &bytes)?;
    }
    super::emit(&text)?;
    report.holds()?;
    Ok(ExitCode::SUCCESS)
}

/// One row per point: `t, phi, xb, yb` and the joints' angles under their names (SI, radians).
fn csv(report: &CheckReport, positions: &[Vec<f64>]) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["t".to_string(), "phi".into(), "xb".into(), "yb".into()];
    header.extend(report.joint_names.iter().cloned());
    w.write_record(&header)?;
    let b = &report.base;
    for (i, p) in positions.iter().enumerate() {
        let mut row = vec![b.t[i], b.phi[i], b.position[i][0], b.position[i][1]];
        row.extend(p);
        w.write_record(row.iter().map(|x| format!("{x:.17e}")))?;
    }
    Ok(w.into_inner()?)
}

/// The human-readable report.
fn table(path: &std::path::Path, arm: &Arm, r: &CheckReport) -> String {
    let deg = |q: &[f64]| format!("({})", q.iter().map(|x| number(x.to_degrees())).collect::<Vec<_>>().join(", "));
    let list = |v: &[f64]| v.iter().map(|x| number(*x)).collect::<Vec<_>>().join(", ");
    let mut s = String::new();
    s += &format!(
        "freefloat check: {}, {} points over {} s, {} interpolation\n",
        PathBuf::from(path).display(),
        r.points,
        number(r.time),
        r.interpolation.name()
    );
    s += &format!(
        "  robot                    {}-link arm, mount (a, b) = ({}, {}) m, joints {}\n",
        r.joints,
        number(arm.mount.a),
        number(arm.mount.b),
        r.joint_names.join(", ")
    );
    s += &format!("  start q0 [deg]           {}\n", deg(&r.start));
    s += &format!("  reached q(T) [deg]       {}  (base integrated at zero momentum, Eq. 7)\n", deg(&r.reached));
    if let (Some(goal), Some(errors), Some(e), Some(worst)) = (&r.goal, &r.final_errors, r.final_error, &r.worst) {
        s += &format!("  goal  qd [deg]           {}\n", deg(goal));
        s += &format!(
            "  final errors [rad]       {}  (base phi first)\n",
            errors.iter().map(|e| scientific(*e, 2)).collect::<Vec<_>>().join(", ")
        );
        let verdict = if r.holds { "HOLDS" } else { "MISSED" };
        s += &format!(
            "  final error              {} rad at {worst} (tolerance {})  {verdict}\n",
            error_number(e),
            number(r.tolerance)
        );
    }
    let phi = &r.base.phi;
    let (lo, hi) = phi.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    s += &format!(
        "  base phi [deg]           {} -> {} (range {} to {})\n",
        number(r.start[0].to_degrees()),
        number(r.reached[0].to_degrees()),
        number(lo.to_degrees()),
        number(hi.to_degrees())
    );
    let (p0, p1) = (r.base.position[0], r.base.position[r.base.position.len() - 1]);
    let travel = r.base.position.iter().map(|p| (p[0] - p0[0]).hypot(p[1] - p0[1])).fold(0.0, f64::max);
    s += &format!(
        "  base position [m]        ({}, {}) -> ({}, {}), at most {} from the start\n",
        number(p0[0]),
        number(p0[1]),
        number(p1[0]),
        number(p1[1]),
        number(travel)
    );
    s += &format!("  max |theta_k'| [rad/s]   {}\n", list(&r.max_abs_velocity));
    s += &format!("  max |tau_k| [N m]        {}  (inverse dynamics at the points, Eq. 6)\n", list(&r.max_abs_torque));
    s += &format!("  max |base row of (6)|    {} N m\n", scientific(r.max_abs_base_residual, 2));
    s += &format!("  max |angular momentum|   {} kg m^2/s\n", scientific(r.max_abs_momentum, 2));
    if let Some(limits) = &r.limits {
        s += &super::limits::table_line(limits);
    }
    s += &super::geometry::table_line(r.clearance.as_ref());
    if r.limits.is_none() && r.clearance.is_none() {
        s += "  limits, clearance        none to check: the robot declares no limits and has no shapes\n";
    }
    s +=
        &format!("  time                     {} ms ({} integrator steps)\n", number(r.seconds * 1e3), r.stats.accepted);
    s
}
