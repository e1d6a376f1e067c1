//! Criterion benches of the minimum-effort planner with the robot's limits (issue 20): a
//! certified plan inside binding limits of the 3-link example (velocity: target <= 15 ms; with
//! torque limits too: <= 40 ms; the targets name a position range too, which the planner
//! does not yet plan reliably on this problem), of the paper's 2-link robot as an arm with
//! binding velocity limits (<= 5 ms), of the SPART-like 4-link example with its own limits
//! (<= 40 ms), and `--time auto`'s shortest horizon on the 3-link example (<= 10 times one plan).
//! Each limit is set below the unconstrained plan's use so that it binds (checked before timing).

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::model::arm::{Arm, JointLimits, Limits};
use freefloat::planners::chain::horizon::uses;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::hint::black_box;
use std::path::Path;

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// `arm` with every joint's velocity (and with `torque` its torque) at `fraction` of the
/// unconstrained plan's peak, and joint `range`'s position range (if any) cut to `[lo, hi]` rad.
fn binding(arm: &Arm, problem: &ChainProblem, fraction: f64, torque: bool, range: Option<(usize, [f64; 2])>) -> Arm {
    let free = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(problem).expect("the free plan");
    let n = arm.joints();
    let mut peak = vec![[0.0_f64; 2]; n];
    for p in free.sample(2001) {
        let tau = freefloat::dynamics::arm::inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
        for j in 0..n {
            peak[j] = [peak[j][0].max(p.rate[j].abs()), peak[j][1].max(tau[j].abs())];
        }
    }
    let joints = (0..n)
        .map(|j| JointLimits {
            velocity: Some(fraction * peak[j][0]),
            torque: torque.then(|| fraction * peak[j][1]),
            position: range.filter(|(k, _)| *k == j).map(|(_, r)| r),
            acceleration: None,
        })
        .collect();
    let limited = arm.clone().with_limits(Limits { joints, base: None }).expect("valid limits");
    let (most, _) = uses(&ChainPlanner::new(limited.clone(), ChainOptions::default()), &free);
    assert!(most.expect("limits").used > 1.0, "the free plan breaks a limit");
    limited
}

fn example(name: &str) -> Arm {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots").join(name);
    let text = std::fs::read_to_string(&path).expect("the example");
    if name.ends_with(".urdf") {
        Arm::from_urdf_str(&text, &path).expect("the URDF")
    } else {
        Arm::from_toml(&text, &path).expect("the TOML")
    }
}

fn bench_limits(c: &mut Criterion) {
    let three = example("three_link.toml").with_limits(Limits::default()).expect("no limits");
    let problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0]), 10.0)
    };
    let src = Arm::from_params(&freefloat::RobotParams::src());
    let (q0, qd, horizon) = freefloat::model::paper_problem();
    let paper = ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon);
    let mut spart = example("spart_like_4dof.urdf");
    spart.geometry = Default::default();
    let spart_problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 20.0, -30.0, 40.0, 10.0]), deg(&[30.0, 60.0, 30.0, -20.0, 40.0]), 30.0)
    };
    let cases = [
        ("3link_velocity", binding(&three, &problem, 0.8, false, None), problem.clone()),
        ("3link_velocity_torque", binding(&three, &problem, 0.8, true, None), problem.clone()),
        ("2link_src_velocity", binding(&src, &paper, 0.8, false, None), paper),
        ("4link_spart_own_limits", spart, spart_problem),
    ];
    for (name, arm, problem) in cases {
        let planner = ChainPlanner::new(arm, ChainOptions::default());
        c.bench_function(&format!("limits_plan_certified/{name}"), |bench| {
            bench.iter(|| black_box(planner.plan(black_box(&problem)).expect("plans")))
        });
    }
    let planner = ChainPlanner::new(binding(&three, &problem, 0.8, false, None), ChainOptions::default());
    c.bench_function("limits_shortest_horizon/3link_velocity", |bench| {
        bench.iter(|| black_box(planner.shortest_horizon(black_box(&problem)).expect("a horizon")))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(std::time::Duration::from_secs(5));
    targets = bench_limits
}
criterion_main!(benches);
