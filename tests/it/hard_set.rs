//! Issue 22's slow tests: `adaptive` ends at least 95 % of the perturbed trials of the hardest
//! problems of each hard set within 1e-3 rad of the goal. The sets are made by
//! `examples/hard_set.rs`; the disturbances are the example's: 5 % parameters, 1 cm mount, 1 %
//! torque noise, 1e-5 rad and 1e-5 rad/s sensor noise, 1 kHz, default gains and re-planning,
//! seed 1.
//! - `tests/fixtures/hard_set.csv` (the SRC robot): problems 0, 3, 9, 10 and 18, those that the
//!   loop of 50 rad/s left below 95 % under 1 % torque noise, 50 trials each.
//! - `tests/fixtures/hard_set_3link.csv` (`examples/robots/three_link.toml`): problems 13 and 19,
//!   the largest median and largest maximum final error of the example's 50-trial runs (every
//!   problem ended 50 of 50 trials), 25 trials each.
//! - `tests/fixtures/hard_set_4link.csv` (`examples/robots/four_link.toml`, SPART's numbers):
//!   problems 0, 11 and 18, 25 trials each: 11 the worst of the set (98 % of 50; the base drifts
//!   on the identified model's error after the final correction, which ended 80 % of 50 when it
//!   came 0.4 s before the end, the default before the final correction moved to `final_window`
//!   exactly), 0 and 18 the worst before.

use freefloat::model::arm::Arm;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::track::{
    Controller, Disturbances, MonteCarloOptions, Perturbation, ReplanOptions, TrackOptions, monte_carlo,
};
use freefloat::{Method, Mount, RobotParams};

/// Runs `trials` perturbed trials of each of `problems` of the set `file` (in `tests/fixtures`,
/// its arm that of its `# robot:` line, else the SRC robot) with no re-plan in the last
/// `final_window` seconds (default 0.25) and asserts >= 95 % successes.
fn holds_95_percent(file: &str, problems: &[usize], trials: usize, final_window: f64) {
    let root = env!("CARGO_MANIFEST_DIR");
    let text = std::fs::read_to_string(format!("{root}/tests/fixtures/{file}")).unwrap();
    let base = match text.lines().find_map(|l| l.strip_prefix("# robot: ")) {
        Some(path) => Arm::load(format!("{root}/{}", path.trim()).as_ref()).unwrap(),
        None => Arm::from_params(&RobotParams::src()),
    };
    let n = base.joints();
    let options = TrackOptions {
        controller: Controller::Adaptive,
        disturbances: Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() },
        ..Default::default()
    };
    let options = TrackOptions { replan: ReplanOptions { final_window, ..options.replan }, ..options };
    let mc = MonteCarloOptions {
        trials,
        seed: 1,
        perturbation: Perturbation { relative: 0.05, mount: 0.01 },
        controllers: vec![Controller::Adaptive],
        ..Default::default()
    };
    let mut rows = 0;
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with('i')) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v.len(), 2 * n + 6, "{file}: a row for {n} joints");
        if !problems.contains(&(v[0] as usize)) {
            continue;
        }
        rows += 1;
        let model = Arm { mount: Mount { a: v[1], b: v[2] }, ..base.clone() };
        let problem = ChainProblem::rest_to_rest(v[3..n + 4].to_vec(), v[n + 4..2 * n + 5].to_vec(), 10.0);
        let planned = plan_arm(&model, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
        let (_, summary) = monte_carlo(&model, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
        let s = &summary[0];
        assert!(
            s.success_rate >= 0.95,
            "{file} problem {}: {:.1} % of {trials} within 1e-3 rad (median {:?}, max {:?})",
            v[0],
            100.0 * s.success_rate,
            s.median_error,
            s.max_error
        );
    }
    assert_eq!(rows, problems.len(), "{file} lacks a problem");
}

#[test]
fn adaptive_ends_95_percent_of_the_hard_set_trials() {
    holds_95_percent("hard_set.csv", &[0, 3, 9, 10, 18], 50, 0.25);
}

#[test]
fn adaptive_ends_95_percent_of_the_3_link_hard_set_trials() {
    holds_95_percent("hard_set_3link.csv", &[13, 19], 25, 0.25);
}

#[test]
fn adaptive_ends_95_percent_of_the_4_link_hard_set_trials() {
    holds_95_percent("hard_set_4link.csv", &[0, 11, 18], 25, 0.25);
}
