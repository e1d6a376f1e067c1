//! Criterion benches of the chain planner (issue 14): a certified minimum-effort plan (search,
//! SQP, refinement and the velocity-level certificate) of a 3-link arm (target <= 5 ms) and a
//! 7-link arm (target <= 50 ms), rest to rest in T = 10 s.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::Mount;
use freefloat::model::arm::{Arm, Base, Link};
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::hint::black_box;

/// Slender-rod links `(length, mass)`, centre of mass at half length.
fn links(spec: &[(f64, f64)]) -> Vec<Link> {
    spec.iter().map(|&(l, m)| Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 }).collect()
}

fn bench_chain(c: &mut Criterion) {
    let three = Arm {
        base: Base { mass: 15.0, inertia: 0.5 },
        mount: Mount { a: 0.2, b: 0.0 },
        links: links(&[(0.4, 2.0), (0.35, 1.5), (0.25, 0.8)]),
    };
    let seven_spec: Vec<(f64, f64)> = (0..7).map(|i| (0.3 - 0.025 * i as f64, 1.5 - 0.2 * i as f64)).collect();
    let seven =
        Arm { base: Base { mass: 20.0, inertia: 0.8 }, mount: Mount { a: 0.2, b: 0.1 }, links: links(&seven_spec) };
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
        c.bench_function(&format!("chain_plan_certified/{name}"), |bench| {
            bench.iter(|| black_box(planner.plan(black_box(&problem)).expect("plans")))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(std::time::Duration::from_secs(3));
    targets = bench_chain
}
criterion_main!(benches);
