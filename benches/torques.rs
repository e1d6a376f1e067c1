//! Criterion benches of the torque level (docs/spec.md §5): inverse dynamics at the 1001 samples of an
//! eq14 plan (a = b = 0.1) <= 0.5 ms. The forward-dynamics certificate is benched separately
//! and does not count.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::model::arm::Arm;
use freefloat::plan::{TorqueOptions, certify_torques, torques_at};
use freefloat::{Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams, Transform};

fn problem(a: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, a).expect("finite")).expect("valid"))
}

fn bench_torques(c: &mut Criterion) {
    let mut group = c.benchmark_group("torques");
    group.measurement_time(Duration::from_secs(3));
    for (name, a, transform) in
        [("eq14_a0.1", 0.1, Transform::Eq14), ("eq14_a0.3", 0.3, Transform::Eq14), ("eq12", 0.0, Transform::Eq12)]
    {
        let p = problem(a);
        let planner = NormalFormPlanner::new(NfaOptions { transform: Some(transform), ..Default::default() });
        let (plan, motion) = planner.plan_with_motion(&p).expect("plan");
        let arm = Arm::from_params(&p.robot);
        let times = plan.trajectory.t.clone();
        group.bench_function(format!("inverse_dynamics_1001/{name}"), |b| {
            b.iter(|| black_box(torques_at(&arm, &motion, black_box(&times)).expect("torques")))
        });
        group.bench_function(format!("forward_certificate/{name}"), |b| {
            b.iter(|| black_box(certify_torques(&motion, &p, &TorqueOptions::default()).expect("certificate")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_torques);
criterion_main!(benches);
