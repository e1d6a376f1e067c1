//! Criterion benches of the minimum-effort planner (issues 11, 14 and 19): the exact motion
//! (seeds, SQP, refinement) plus the 1001-sample trajectory on the paper's problem, targets
//! <= 1.5 ms at a = b = 0.1 and <= 10 ms at a = 1, b = -1 (the verification is timed apart and
//! does not count); and a certified plan (search, SQP, refinement and the velocity-level
//! certificate) of a 3-link arm (target <= 5 ms) and a 7-link arm (target <= 30 ms), rest to rest
//! in T = 10 s.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::model::arm::{Arm, Base, Link};
use freefloat::plan::{Motion, verify};
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
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

/// Slender-rod links `(length, mass)`, centre of mass at half length.
fn links(spec: &[(f64, f64)]) -> Vec<Link> {
    spec.iter().map(|&(l, m)| Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 }).collect()
}

fn bench_arms(c: &mut Criterion) {
    let three = Arm {
        base: Base { mass: 15.0, inertia: 0.5 },
        mount: Mount { a: 0.2, b: 0.0 },
        links: links(&[(0.4, 2.0), (0.35, 1.5), (0.25, 0.8)]),
        limits: Default::default(),
        geometry: Default::default(),
    };
    let seven_spec: Vec<(f64, f64)> = (0..7).map(|i| (0.3 - 0.025 * i as f64, 1.5 - 0.2 * i as f64)).collect();
    let seven = Arm {
        base: Base { mass: 20.0, inertia: 0.8 },
        mount: Mount { a: 0.2, b: 0.1 },
        links: links(&seven_spec),
        limits: Default::default(),
        geometry: Default::default(),
    };
    let cases = [
        ("3link", three, vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6]),
        (
            "7link",
            seven,
            vec![0.0, 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.6],
            vec![0.4, -0.3, 0.5, 0.1, 0.7, 0.2, -0.5, 0.0],
        ),
    ];
    for (name, arm, start, goal) in cases {
        let planner = ChainPlanner::new(arm, ChainOptions::default());
        let problem = ChainProblem::rest_to_rest(start, goal, 10.0);
        c.bench_function(&format!("optimal_plan_certified/{name}"), |bench| {
            bench.iter(|| black_box(planner.plan(black_box(&problem)).expect("plans")))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(std::time::Duration::from_secs(3));
    targets = bench_optimal, bench_arms
}
criterion_main!(benches);
