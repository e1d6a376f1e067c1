//! Runs a velocity plan repeatedly (for profiling with callgrind or perf):
//! `profile_plan N A B TRANSFORM`.
use freefloat::{Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams, Transform};

fn main() -> Result<(), freefloat::Error> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let a: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.1);
    let b: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.1);
    let transform = match args.get(4).map(String::as_str) {
        Some("global") => Transform::Global,
        _ => Transform::Eq14,
    };
    let p = PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b)?)?);
    let planner = NormalFormPlanner::new(NfaOptions { transform: Some(transform), ..Default::default() });
    let start = std::time::Instant::now();
    for _ in 0..n {
        let m = planner.motion(&p)?;
        std::hint::black_box(m.trajectory(&p, false)?);
    }
    println!("{:.3} ms per plan", start.elapsed().as_secs_f64() * 1e3 / n as f64);
    Ok(())
}
