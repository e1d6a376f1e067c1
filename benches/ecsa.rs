//! Criterion benches of the ECSA (docs/spec.md §5): the pseudo-inverse iteration to a residual of
//! 1e-10 rad for a = b = 0.1 <= 20 ms (the paper: 1.5 s). Also the full velocity-level plan
//! (iteration + 1001 samples with accelerations) and the verification, which does not count.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::plan::{Motion, verify};
use freefloat::{EcsaOptions, EcsaPlanner, Mount, PlanningProblem, RobotParams, Window};
use std::hint::black_box;

fn problem(a: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, a).expect("finite")).expect("valid"))
}

fn bench_ecsa(c: &mut Criterion) {
    for (name, a, window) in
        [("a0.1", 0.1, Window::None), ("a0.3", 0.3, Window::None), ("a0.1_sin2", 0.1, Window::SinSquared)]
    {
        let p = problem(a);
        let planner = EcsaPlanner::new(EcsaOptions::default().with_window(window));
        c.bench_function(&format!("ecsa_solve_1e-10/{name}"), |b| {
            b.iter(|| black_box(planner.solve(black_box(&p)).expect("converges")))
        });
        c.bench_function(&format!("ecsa_velocity_plan_1001/{name}"), |b| {
            b.iter(|| {
                let solution = planner.solve(black_box(&p)).expect("converges");
                let motion = planner.motion(&p, &solution).expect("samples");
                black_box(motion.trajectory().expect("trajectory"))
            })
        });
        let motion = planner.motion(&p, &planner.solve(&p).expect("converges")).expect("samples");
        c.bench_function(&format!("ecsa_verify/{name}"), |b| {
            b.iter(|| black_box(verify(&motion as &dyn Motion, &p, &Default::default(), 1e-9).expect("verify")))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(std::time::Duration::from_secs(3));
    targets = bench_ecsa
}
criterion_main!(benches);
