//! Criterion bench of `freefloat check` (issue 23): a 1001-point ROS 2 JointTrajectory of the
//! SPART-like 4-link arm (`examples/robots/four_link.toml`), exported from freefloat's own plan,
//! checked: the samples matched to the joints, the quintic interpolation, the base's attitude
//! integrated at 1e-12 and the inverse-dynamics torques at every point. A second bench adds
//! reading the message from its YAML text.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::analysis::check::{CheckOptions, check, samples_from_message};
use freefloat::model::arm::Arm;
use freefloat::model::arm::file::default_joint_names;
use freefloat::plan::Method;
use freefloat::plan::ros::{Encoding, JointTrajectory, from_text, to_text};
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::report::ros::{MotionRows, joint_trajectory};
use std::hint::black_box;

fn bench_check(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots/four_link.toml");
    let arm = Arm::load(&path).expect("the example arm");
    let deg = |v: &[f64]| v.iter().map(|x: &f64| x.to_radians()).collect::<Vec<_>>();
    let problem =
        ChainProblem::rest_to_rest(deg(&[0.0, 30.0, -20.0, 40.0, -30.0]), deg(&[10.0, 60.0, 20.0, -10.0, 30.0]), 10.0);
    let request = ArmRequest {
        problem: problem.clone(),
        samples: 1001,
        tolerance: 1e-9,
        torques: false,
        ecsa: Default::default(),
        cost: Default::default(),
        smooth_ends: false,
        shortest_horizon: false,
    };
    let planned = plan_arm(&arm, Method::Optimal, &request).expect("a certified plan");
    let names = default_joint_names(4);
    let message = joint_trajectory(&MotionRows::from_arm(&planned), &names).expect("a message");
    let yaml = to_text(&message, Encoding::Yaml).expect("YAML");
    let samples = samples_from_message(&message, &names, &path).expect("valid");
    let options = CheckOptions::default();
    c.bench_function("check/4link_1001_points", |bench| {
        bench.iter(|| {
            black_box(check(&arm, &names, black_box(&samples), 0.0, Some(&problem.goal), &options).expect("checks"))
        })
    });
    c.bench_function("check/4link_1001_points_from_yaml", |bench| {
        bench.iter(|| {
            let message: JointTrajectory = from_text(black_box(&yaml), Encoding::Yaml, "bench").expect("parses");
            let samples = samples_from_message(&message, &names, &path).expect("valid");
            black_box(check(&arm, &names, &samples, 0.0, Some(&problem.goal), &options).expect("checks"))
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench_check
}
criterion_main!(benches);
