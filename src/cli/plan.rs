//! `freefloat plan` and `freefloat compare`.

use std::process::ExitCode;

use anyhow::bail;
use freefloat::io::{PlanReport, trajectory_csv, write_atomic};
use freefloat::plan::Method;
use freefloat::{NormalFormPlanner, Plan, Planner};

use super::args::{CompareArgs, Format, MethodArg, PlanArgs};

/// Runs `plan`: exit 0 with a certified plan, 3 (numbers on stderr) otherwise.
pub fn run(args: &PlanArgs) -> anyhow::Result<ExitCode> {
    let problem = super::problem(&args.problem)?;
    let options = super::nfa_options(&args.problem);
    let plan = match args.method {
        MethodArg::Nfa => NormalFormPlanner::new(options).plan(&problem)?,
        MethodArg::Ecsa => bail!("--method ecsa is not available yet"),
    };
    if args.problem.torques {
        bail!("--torques is not available yet");
    }
    let report = PlanReport::new(&plan, false);
    match args.format {
        Format::Table => print!("{}", table(&plan, &report)),
        Format::Json => println!("{}", serde_json::to_string_pretty(&report)?),
        Format::Csv => print!("{}", String::from_utf8(trajectory_csv(&plan.trajectory)?)?),
    }
    if let Some(path) = &args.out {
        let bytes = match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => trajectory_csv(&plan.trajectory)?,
            Some("json") => serde_json::to_vec_pretty(&PlanReport::new(&plan, true))?,
            _ => bail!("--out {}: the file name must end in .json or .csv", path.display()),
        };
        write_atomic(path, &bytes)?;
    }
    plan.certified()?;
    Ok(ExitCode::SUCCESS)
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
    if let (Some(tau), Some(e)) = (r.max_abs_torque, r.torque_final_error) {
        s += &format!("  max |tau1|, |tau2|       {:.6}, {:.6} N m\n", tau[0], tau[1]);
        s += &format!("  torque final error       {e:.3e} rad\n");
    }
    let torques = r.seconds.torques.map(|t| format!(", torques {:.3} ms", t * 1e3)).unwrap_or_default();
    s += &format!(
        "  time                     plan {:.3} ms{torques}, verify {:.3} ms\n",
        r.seconds.plan * 1e3,
        r.seconds.verify * 1e3
    );
    s
}
