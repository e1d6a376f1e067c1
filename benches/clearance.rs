//! Criterion benches of the minimum-effort planner keeping a clearance (issue 21): the SPART-like
//! 4-link plan (0, 30, -60, 45, -30) -> (30, 60, -30, 20, -60) deg in 10 s with the base's box and
//! the links' spheres of `tests/fixtures/spart_like_4dof_geometry.urdf` and a clearance of
//! 0.02 m (target <= 60 ms), and the 3-link example with 4 cm wide links reaching around a
//! circular obstacle that its unconstrained plan crosses (target <= 30 ms). Both are the cases of
//! `tests/it/geometry.rs`; each plan is checked to be certified and clear before timing.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::model::arm::Arm;
use freefloat::model::arm::collision::Body;
use freefloat::model::geometry::Shape;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::hint::black_box;
use std::path::Path;

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// The SPART-like fixture with its own limits, base box and link spheres, keeping 0.02 m.
fn spart() -> (Arm, ChainProblem) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/spart_like_4dof_geometry.urdf");
    let text = std::fs::read_to_string(&path).expect("the fixture");
    let mut arm = Arm::from_urdf_str(&text, &path).expect("the URDF");
    arm.geometry.clearance = 0.02;
    let problem =
        ChainProblem::rest_to_rest(deg(&[0.0, 30.0, -60.0, 45.0, -30.0]), deg(&[30.0, 60.0, -30.0, 20.0, -60.0]), 10.0);
    (arm, problem)
}

/// The 3-link example with 4 cm wide links (links 1 and 3 not checked against each other) and a
/// 5 cm obstacle at (-0.4, 0.1) m on its unconstrained plan's path.
fn three_link_obstacle() -> (Arm, ChainProblem) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots/three_link.toml");
    let text = std::fs::read_to_string(&path)
        .expect("the example")
        .lines()
        .map(|l| if l.starts_with("inertia") { format!("{l}\nwidth = 0.04") } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let mut arm = Arm::from_toml(&text, &path).expect("the TOML");
    arm.geometry.obstacles.push(Shape::circle([-0.4, 0.1], 0.05).expect("a circle"));
    arm.geometry.excluded.push((Body::Link(1), Body::Link(3)));
    let problem = ChainProblem::rest_to_rest(deg(&[0.0, 0.0, 30.0, 30.0]), deg(&[20.0, 90.0, 30.0, -30.0]), 8.0);
    (arm, problem)
}

fn bench_clearance(c: &mut Criterion) {
    for (name, (arm, problem)) in [("4link_spart_base", spart()), ("3link_obstacle", three_link_obstacle())] {
        let planner = ChainPlanner::new(arm, ChainOptions::default());
        let plan = planner.plan(&problem).expect("plans");
        let report = plan.verification.clearance.expect("a clearance report");
        assert!(plan.verification.certified && report.holds(), "{name}: certified and clear");
        c.bench_function(&format!("clearance_plan_certified/{name}"), |bench| {
            bench.iter(|| black_box(planner.plan(black_box(&problem)).expect("plans")))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(std::time::Duration::from_secs(5));
    targets = bench_clearance
}
criterion_main!(benches);
