//! Runs the eq14 velocity plan repeatedly (for profiling with callgrind or perf).
use freefloat::{Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams, Transform};

fn main() -> Result<(), freefloat::Error> {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let p = PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(0.1, 0.1)?)?);
    let planner = NormalFormPlanner::new(NfaOptions { transform: Some(Transform::Eq14), ..Default::default() });
    let start = std::time::Instant::now();
    for _ in 0..n {
        let m = planner.motion(&p)?;
        std::hint::black_box(m.trajectory(&p, false)?);
    }
    println!("{:.3} ms per plan", start.elapsed().as_secs_f64() * 1e3 / n as f64);
    Ok(())
}
