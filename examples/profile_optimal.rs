//! Runs the bench path of `benches/optimal.rs` repeatedly (for profiling with callgrind):
//! `profile_optimal CASE N`, CASE `src0.1` (the paper's problem at a = b = 0.1) or `src1`
//! (a = 1, b = -1): the 2-link minimum-effort motion plus its 1001-sample trajectory.
use freefloat::planners::optimal::OptimalPlanner;
use freefloat::{Mount, PlanningProblem, RobotParams};

fn main() -> Result<(), freefloat::Error> {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("src0.1");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let (a, b) = if case == "src1" { (1.0, -1.0) } else { (0.1, 0.1) };
    let p = PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b)?)?);
    let planner = OptimalPlanner::default();
    let start = std::time::Instant::now();
    let mut last = (0.0, 0.0);
    for _ in 0..n {
        let motion = planner.motion(&p)?;
        let trajectory = motion.trajectory(&p, 1001)?;
        last = (motion.stats.effort, trajectory.q[trajectory.q.len() - 1][0]);
        std::hint::black_box(trajectory);
    }
    println!(
        "{case}: effort {:.12}, phi(T) {:.15}, {:.3} ms per plan",
        last.0,
        last.1,
        start.elapsed().as_secs_f64() * 1e3 / n as f64
    );
    Ok(())
}
