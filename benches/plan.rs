//! Criterion benches of the velocity-level NFA plan (docs/spec.md §5): eq14 with 1001 samples <= 1 ms,
//! with 101 samples <= 0.1 ms (issue 11),
//! eq11/eq12 <= 0.3 ms; the band-steered global plan <= 5 ms. Verification is benched
//! separately and does not count.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::plan::{Motion, verify};
use freefloat::{Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams, Transform};
use std::hint::black_box;

fn problem(a: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, a).expect("finite")).expect("valid"))
}

fn bench_plan(c: &mut Criterion) {
    for (name, a, transform) in [
        ("eq11", 0.0, Transform::Eq11),
        ("eq12", 0.0, Transform::Eq12),
        ("eq14_a0.1", 0.1, Transform::Eq14),
        ("eq14_a0.3", 0.3, Transform::Eq14),
    ] {
        let p = problem(a);
        let planner = NormalFormPlanner::new(NfaOptions { transform: Some(transform), ..Default::default() });
        c.bench_function(&format!("nfa_velocity_plan_1001/{name}"), |b| {
            b.iter(|| {
                let motion = planner.motion(black_box(&p)).expect("plan");
                black_box(motion.trajectory(&p, false).expect("trajectory"))
            })
        });
        let coarse =
            NormalFormPlanner::new(NfaOptions { transform: Some(transform), samples: 101, ..Default::default() });
        c.bench_function(&format!("nfa_velocity_plan_101/{name}"), |b| {
            b.iter(|| {
                let motion = coarse.motion(black_box(&p)).expect("plan");
                black_box(motion.trajectory(&p, false).expect("trajectory"))
            })
        });
        let motion = planner.motion(&p).expect("plan");
        c.bench_function(&format!("nfa_verify/{name}"), |b| {
            b.iter(|| black_box(verify(&motion as &dyn Motion, &p, &Default::default(), 1e-9).expect("verify")))
        });
    }
}

/// Beyond the paper: the global normal form's band-steered plan (issue: <= 5 ms), for the paper's
/// "impossible" mount a = 1, b = -1 and for a = b = 0.5.
fn bench_band(c: &mut Criterion) {
    for (name, a, b) in [("a1_b-1", 1.0, -1.0), ("a0.5_b0.5", 0.5, 0.5)] {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid");
        let p = PlanningProblem::paper(robot);
        let planner = NormalFormPlanner::new(NfaOptions { transform: Some(Transform::Global), ..Default::default() });
        c.bench_function(&format!("nfa_band_plan_1001/{name}"), |bench| {
            bench.iter(|| {
                let motion = planner.motion(black_box(&p)).expect("plan");
                black_box(motion.trajectory(&p, false).expect("trajectory"))
            })
        });
    }
}

criterion_group!(benches, bench_plan, bench_band);
criterion_main!(benches);
