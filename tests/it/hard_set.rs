//! Issue 22's slow test: `adaptive` on five problems of the hard set
//! (`tests/fixtures/hard_set.csv`, made by `examples/hard_set.rs`), 50 perturbed trials each,
//! ends at least 95 % of them within 1e-3 rad of the goal. The five are those that the loop of
//! 50 rad/s left below 95 % under 1 % torque noise (problems 0, 3, 9, 10 and 18); the
//! disturbances are the example's: 5 % parameters, 1 cm mount, 1 % torque noise, 1e-5 rad and
//! 1e-5 rad/s sensor noise, 1 kHz, default gains and re-planning, seed 1.

use freefloat::model::arm::Arm;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::track::{Controller, Disturbances, MonteCarloOptions, Perturbation, TrackOptions, monte_carlo};
use freefloat::{Method, Mount, RobotParams};

const PROBLEMS: [usize; 5] = [0, 3, 9, 10, 18];
const TRIALS: usize = 50;

#[test]
fn adaptive_ends_95_percent_of_the_hard_set_trials() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/hard_set.csv")).unwrap();
    let options = TrackOptions {
        controller: Controller::Adaptive,
        disturbances: Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() },
        ..Default::default()
    };
    let mc = MonteCarloOptions {
        trials: TRIALS,
        seed: 1,
        perturbation: Perturbation { relative: 0.05, mount: 0.01 },
        controllers: vec![Controller::Adaptive],
        ..Default::default()
    };
    let mut rows = 0;
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with('i')) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        if !PROBLEMS.contains(&(v[0] as usize)) {
            continue;
        }
        rows += 1;
        let model = Arm { mount: Mount { a: v[1], b: v[2] }, ..Arm::from_params(&RobotParams::src()) };
        let problem = ChainProblem::rest_to_rest(v[3..6].to_vec(), v[6..9].to_vec(), 10.0);
        let planned = plan_arm(&model, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
        let (_, summary) = monte_carlo(&model, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
        let s = &summary[0];
        assert!(
            s.success_rate >= 0.95,
            "problem {}: {:.1} % of {TRIALS} within 1e-3 rad (median {:?}, max {:?})",
            v[0],
            100.0 * s.success_rate,
            s.median_error,
            s.max_error
        );
    }
    assert_eq!(rows, PROBLEMS.len(), "the fixture lacks a problem");
}
