//! Issue 19 item 2, the one minimum-effort planner at `n = 2`: against the 300 recorded problems
//! of both of yesterday's planners (tests/fixtures/two_link_300.csv) and against the 2-joint
//! planner as it stood before the merge (tests/fixtures/two_link_300_two_joint.csv); the
//! comparison with the exhaustive reference search is `optimal::comparison`'s.

use rayon::prelude::*;

use super::{ChainOptions, ChainPlanner, ChainProblem};
use crate::model::arm::Arm;
use crate::planners::optimal::comparison::{Recorded, fixture};

/// The chain planner's certified effort on a recorded problem (infinite when it fails).
fn chain_effort(r: &Recorded) -> f64 {
    let problem = &r.1;
    let chain = ChainPlanner::new(Arm::from_params(&problem.robot), ChainOptions::default());
    let (q0, qd) = (problem.start.to_array().to_vec(), problem.goal.to_array().to_vec());
    match chain.plan(&ChainProblem::rest_to_rest(q0, qd, problem.horizon)) {
        Ok(p) if p.verification.certified => p.effort(),
        _ => f64::INFINITY,
    }
}

/// Today's 2-joint planner's certified effort on each recorded problem, by index
/// (tests/fixtures/two_link_300_two_joint.csv; infinite where it did not certify).
fn two_joint_today() -> Vec<f64> {
    let text = include_str!("../../../tests/fixtures/two_link_300_two_joint.csv");
    let rows: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("i,"))
        .enumerate()
        .map(|(i, l)| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f[0].parse::<usize>().ok(), Some(i), "rows in index order: {l}");
            if f[2] == "true" { f[1].parse().unwrap() } else { f64::INFINITY }
        })
        .collect();
    assert_eq!(rows.len(), 300);
    rows
}

/// Issue 19 item 2 at `n = 2`, on all 300 recorded problems (about a minute on two cores): every
/// plan is certified and costs at most (+1e-6 relative) the better of the two recorded planners'
/// efforts and today's 2-joint planner's. (Until stop 50 five problems were exempt from the
/// recorded n-joint planner's bound, at 1.04 to 1.17 times it; measured at stop 50 through
/// `freefloat plan` they stand at 0.56 to 0.90 times it: 22, 31, 75, 256, 262.)
#[test]
fn never_worse_than_either_two_link_planner_on_300_problems() {
    let today = two_joint_today();
    let rows: Vec<(usize, f64, f64)> =
        fixture().into_par_iter().map(|r| (r.0, chain_effort(&r), r.3.min(today[r.0]))).collect();
    let above: Vec<_> = rows.iter().filter(|r| !(r.1 <= r.2 * (1.0 + 1e-6))).collect();
    assert!(above.is_empty(), "uncertified or above a recorded planner's effort (index, effort, best): {above:?}");
}

/// The chain planner's effort and SQP iterations on each recorded problem, one line each
/// (`index effort iterations`), for comparing a change's efforts problem by problem:
/// `cargo test --release --lib recorded_efforts -- --ignored --nocapture`.
#[test]
#[ignore = "a measurement, not a check (about a minute on two cores)"]
fn recorded_efforts() {
    let rows: Vec<(usize, f64, usize)> = fixture()
        .into_par_iter()
        .map(|r| {
            let problem = &r.1;
            let chain = ChainPlanner::new(Arm::from_params(&problem.robot), ChainOptions::default());
            let (q0, qd) = (problem.start.to_array().to_vec(), problem.goal.to_array().to_vec());
            match chain.plan(&ChainProblem::rest_to_rest(q0, qd, problem.horizon)) {
                Ok(p) if p.verification.certified => (r.0, p.effort(), p.stats.iterations),
                _ => (r.0, f64::INFINITY, 0),
            }
        })
        .collect();
    for (i, effort, iterations) in &rows {
        println!("recorded {i} {effort:.12e} {iterations}");
    }
    println!("recorded total iterations {}", rows.iter().map(|r| r.2).sum::<usize>());
}
