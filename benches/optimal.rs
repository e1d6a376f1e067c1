//! Criterion benches of the optimal planner (issue 11): the exact motion (seeds, SQP, refinement)
//! plus the 1001-sample trajectory on the paper's problem, targets <= 2 ms (paper's mounts) and
//! <= 10 ms (a = 1, b = -1). The verification is timed apart and does not count.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::plan::{Motion, verify};
use freefloat::planners::optimal::OptimalPlanner;
use freefloat::{Mount, PlanningProblem, RobotParams};
use std::hint::black_box;

fn problem(a: f64, b: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid"))
}

fn bench_optimal(c: &mut Criterion) {
    let planner = OptimalPlanner::default();
    for (name, a, b) in
        [("a0", 0.0, 0.0), ("a0.1", 0.1, 0.1), ("a0.2", 0.2, 0.2), ("a0.3", 0.3, 0.3), ("a1_b-1", 1.0, -1.0)]
    {
        let p = problem(a, b);
        c.bench_function(&format!("optimal_plan_1001/{name}"), |bench| {
            bench.iter(|| {
                let motion = planner.motion(black_box(&p)).expect("plans");
                black_box(motion.trajectory(&p, 1001).expect("samples"))
            })
        });
        let motion = planner.motion(&p).expect("plans");
        c.bench_function(&format!("optimal_verify/{name}"), |bench| {
            bench.iter(|| black_box(verify(&motion as &dyn Motion, &p, &Default::default(), 1e-9).expect("verify")))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(std::time::Duration::from_secs(3));
    targets = bench_optimal
}
criterion_main!(benches);
