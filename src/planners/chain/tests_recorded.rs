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

/// The recorded problems where the n-joint planner as recorded (before issue 19's seeds and
/// finalists) found a cheaper plan than the plan (effort ratio 1.17, 1.04, 1.12, 1.05, 1.06):
/// it refined an 8-span loop seed of many turns that cannot meet the constraint there, where the
/// planner now solves a coil on many spans instead.
const KNOWN_ABOVE_BOTH: [usize; 5] = [22, 31, 75, 256, 262];

/// Issue 19 item 2 at `n = 2`, on all 300 recorded problems (about a minute on two cores): every
/// plan is certified and costs at most (+1e-6 relative) the recorded 2-joint planner's effort and
/// today's 2-joint planner's, and at most the better recorded planner's but on
/// [`KNOWN_ABOVE_BOTH`]. Measured when written: 40 of 300 below both recorded planners.
#[test]
fn never_worse_than_either_two_link_planner_on_300_problems() {
    let today = two_joint_today();
    let rows: Vec<(usize, f64, f64, f64)> =
        fixture().into_par_iter().map(|r| (r.0, chain_effort(&r), r.2.min(today[r.0]), r.3)).collect();
    let above_two: Vec<_> = rows.iter().filter(|r| !(r.1 <= r.2 * (1.0 + 1e-6))).collect();
    assert!(above_two.is_empty(), "uncertified or above a 2-joint effort (index, effort, 2-joint): {above_two:?}");
    let above_both: Vec<_> = rows.iter().filter(|r| !(r.1 <= r.3 * (1.0 + 1e-6))).collect();
    let unexpected: Vec<_> = above_both.iter().filter(|r| !KNOWN_ABOVE_BOTH.contains(&r.0)).collect();
    assert!(unexpected.is_empty(), "above both recorded planners (index, effort, _, best): {unexpected:?}");
}
