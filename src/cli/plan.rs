//! `freefloat plan` and `freefloat compare`.

use std::process::ExitCode;

use anyhow::bail;
use freefloat::dynamics::{TorqueOptions, TorqueReport, torque_plan};
use freefloat::io::{PlanReport, trajectory_csv, write_atomic};
use freefloat::plan::{Method, Motion};
use freefloat::{NormalFormPlanner, Plan};

use super::args::{CompareArgs, Format, MethodArg, PlanArgs};

/// Runs `plan`: exit 0 with a certified plan, 3 (numbers on stderr) otherwise.
pub fn run(args: &PlanArgs) -> anyhow::Result<ExitCode> {
    let problem = super::problem(&args.problem)?;
    let options = super::nfa_options(&args.problem);
    let (mut plan, motion): (Plan, Box<dyn Motion>) = match args.method {
        MethodArg::Nfa => {
            let (plan, motion) = NormalFormPlanner::new(options).plan_with_motion(&problem)?;
            (plan, Box::new(motion))
        }
        MethodArg::Ecsa => bail!("--method ecsa is not available yet"),
    };
    // The torque level (SPEC §2): inverse dynamics at the samples, forward-dynamics certificate.
    let torques = if args.problem.torques { Some(add_torques(&mut plan, motion.as_ref())?) } else { None };
    let report_of = |with_trajectory| {
        let report = PlanReport::new(&plan, with_trajectory);
        match &torques {
            Some(t) => report.with_torques(t),
            None => report,
        }
    };
    let report = report_of(false);
    match args.format {
        Format::Table => print!("{}", table(&plan, &report)),
        Format::Json => println!("{}", serde_json::to_string_pretty(&report)?),
        Format::Csv => print!("{}", String::from_utf8(trajectory_csv(&plan.trajectory)?)?),
    }
    if let Some(path) = &args.out {
        let bytes = match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => trajectory_csv(&plan.trajectory)?,
            Some("json") => serde_json::to_vec_pretty(&report_of(true))?,
            _ => bail!("--out {}: the file name must end in .json or .csv", path.display()),
        };
        write_atomic(path, &bytes)?;
    }
    plan.certified()?;
    if let Some(t) = &torques {
        t.check()?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The torque level of `plan` (SPEC §2): torques at its samples into the trajectory's `tau`,
/// their wall time into `seconds.torques`, and the forward-dynamics certificate (tolerance
/// 1e-6 rad).
fn add_torques(plan: &mut Plan, motion: &dyn Motion) -> Result<TorqueReport, freefloat::Error> {
    let tp = torque_plan(motion, &plan.problem, &plan.trajectory.t, &TorqueOptions::default())?;
    plan.trajectory.tau = Some(tp.tau);
    plan.seconds.torques = Some(tp.report.seconds.torques);
    Ok(tp.report)
}

/// Runs `compare`.
pub fn compare(_args: &CompareArgs) -> anyhow::Result<ExitCode> {
    bail!("`compare` needs the ECSA planner, which is not available yet")
}

fn deg(q: [f64; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4})", q[0].to_degrees(), q[1].to_degrees(), q[2].to_degrees())
}

fn vec3(z: Option<[f64; 3]>) -> String {
    z.map(|z| format!("({:.6}, {:.6}, {:.6})", z[0], z[1], z[2])).unwrap_or_else(|| "-".into())
}

/// The human-readable report.
pub fn table(plan: &Plan, r: &PlanReport) -> String {
    let method = match plan.method {
        Method::Nfa => format!("NFA, transform {}", r.transform.map(|t| t.name()).unwrap_or("-")),
        Method::Ecsa => format!("ECSA, {} iterations", r.iterations.unwrap_or(0)),
    };
    let status = if r.certified { "CERTIFIED" } else { "NOT CERTIFIED" };
    let mut s = String::new();
    s += &format!("freefloat plan: {method}, mount (a, b) = ({}, {}) m\n", r.mount[0], r.mount[1]);
    s += &format!("  start q0 [deg]           {}\n", deg(r.start));
    s += &format!("  goal  qd [deg]           {}\n", deg(r.goal));
    s += &format!("  horizon                  {} s, {} samples\n", r.time, r.samples);
    s += &format!("  z0, zd                   {}  ->  {}\n", vec3(r.z0), vec3(r.zd));
    s += &format!("  reached q(T) [deg]       {}\n", deg(r.reached));
    s += &format!("  verified final error     {:.3e} rad (tolerance {:.1e})  {status}\n", r.final_error, r.tolerance);
    s +=
        &format!("  max deviation from plan  {:.3e} rad ({} integrator steps)\n", r.max_path_deviation, r.verify_steps);
    s += &format!("  max |u1|, |u2|           {:.6}, {:.6} rad/s\n", r.max_abs_u[0], r.max_abs_u[1]);
    s += &format!("  min |sigma|, |P|         {:.6}, {:.6}\n", r.min_abs_sigma, r.min_abs_p);
    if let Some(t) = &r.torque_certificate {
        let c = &t.certificate;
        let status = if c.certified { "CERTIFIED" } else { "NOT CERTIFIED" };
        s += &format!("  max |tau1|, |tau2|       {:.6}, {:.6} N m\n", t.max_abs_torque[0], t.max_abs_torque[1]);
        s += &format!(
            "  torque final error       {:.3e} rad (tolerance {:.1e})  {status}\n",
            c.final_error, c.tolerance
        );
        s += &format!(
            "  torque path deviation    {:.3e} rad ({} integrator steps)\n",
            c.max_path_deviation, c.stats.accepted
        );
        s += &format!("  max |angular momentum|   {:.3e} kg m^2/s\n", c.max_abs_momentum);
        s += &format!("  max |base row of (6)|    {:.3e} N m\n", t.max_abs_base_residual);
    }
    let torques = r.seconds.torques.map(|t| format!(", torques {:.3} ms", t * 1e3)).unwrap_or_default();
    let torque_verify = r
        .torque_certificate
        .map(|t| format!(", torque certificate {:.3} ms", t.seconds.verify * 1e3))
        .unwrap_or_default();
    s += &format!(
        "  time                     plan {:.3} ms{torques}, verify {:.3} ms{torque_verify}\n",
        r.seconds.plan * 1e3,
        r.seconds.verify * 1e3
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use freefloat::{NfaOptions, PlanningProblem, RobotParams};

    /// `--torques` fills `max_abs_torque`, `torque_final_error`, `seconds.torques`, the CSV's
    /// tau columns and the table; a failed torque certificate exits with code 3 and its numbers.
    #[test]
    fn torques_fill_report_csv_and_table() {
        let problem = PlanningProblem::paper(RobotParams::src());
        let options = NfaOptions { samples: 101, accelerations: true, ..Default::default() };
        let (mut plan, motion) = NormalFormPlanner::new(options).plan_with_motion(&problem).unwrap();
        let torques = add_torques(&mut plan, &motion).unwrap();
        let report = PlanReport::new(&plan, false).with_torques(&torques);
        let json: serde_json::Value = serde_json::to_value(&report).unwrap();
        assert!(json["max_abs_torque"].as_array().is_some_and(|a| a.len() == 2));
        assert!(json["torque_final_error"].as_f64().is_some_and(|e| e <= 1e-6));
        assert!(json["seconds"]["torques"].as_f64().is_some());
        assert_eq!(json["certified"], serde_json::Value::Bool(true));
        let csv = String::from_utf8(trajectory_csv(&plan.trajectory).unwrap()).unwrap();
        let row = csv.lines().nth(50).unwrap();
        assert!(row.split(',').skip(13).all(|cell| cell.parse::<f64>().is_ok()), "{row}");
        let text = table(&plan, &report);
        assert!(text.contains("max |tau1|, |tau2|") && text.contains("torque final error"), "{text}");

        let failed = freefloat::Error::NotCertified { final_error: 2e-6, tolerance: 1e-6, level: "torque" };
        let message = failed.to_string();
        assert!(message.contains("2.000e-6") && message.contains("torque"), "{message}");
        assert_eq!(crate::cli::exit_code(&anyhow::Error::from(failed)), 3);
    }
}
