//! Issue 19 item 2 for the chain planner at `n = 2`: against the 300 recorded problems of both
//! of yesterday's planners (tests/fixtures/two_link_300.csv) and against the exhaustive
//! [`reference`](crate::planners::optimal::reference) search.

use rayon::prelude::*;

use super::{ChainOptions, ChainPlanner, ChainProblem};
use crate::model::arm::Arm;
use crate::planners::optimal::comparison::{Recorded, fixture};
use crate::planners::optimal::reference::reference_effort;

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

/// On the recorded problems (one in three, those whose 2-joint plan took under 1 s when recorded)
/// every plan is certified and costs at most the 2-joint planner's recorded effort (+1e-6
/// relative). On all 300 it held too when measured (0 uncertified, 0 above the 2-joint planner,
/// 59 below both recorded planners, 28 above the n-joint planner's recorded effort), see
/// [`all_300_recorded_problems`].
#[test]
fn never_worse_than_the_recorded_two_joint_planner() {
    let above: Vec<(usize, f64, f64)> = fixture()
        .into_par_iter()
        .filter(|r| r.0 % 3 == 0 && r.4 < 1000.0)
        .map(|r| (r.0, chain_effort(&r), r.2))
        .filter(|(_, e, two)| !(*e <= two * (1.0 + 1e-6)))
        .collect();
    assert!(above.is_empty(), "uncertified or above the recorded 2-joint effort (index, effort, recorded): {above:?}");
}

/// [`never_worse_than_the_recorded_two_joint_planner`] on all 300, printing where the better
/// recorded planner is still below the plan.
#[test]
#[ignore = "slow: all 300 recorded problems (minutes in release)"]
fn all_300_recorded_problems() {
    let rows: Vec<(usize, f64, f64, f64)> =
        fixture().into_par_iter().map(|r| (r.0, chain_effort(&r), r.2, r.3)).collect();
    let above_both: Vec<_> = rows.iter().filter(|r| !(r.1 <= r.3 * (1.0 + 1e-6))).collect();
    eprintln!("above the better recorded planner on {}: {above_both:?}", above_both.len());
    let above_two: Vec<_> = rows.iter().filter(|r| !(r.1 <= r.2 * (1.0 + 1e-6))).collect();
    assert!(above_two.is_empty(), "above the recorded 2-joint effort: {above_two:?}");
}

/// The chain planner against the exhaustive reference search on 50 random mounts of the paper's
/// problem (the 2-joint planner's test, `within_one_percent_of_the_reference_on_49_of_50_mounts`):
/// prints the misses; the issue asks for at most 1.
#[test]
#[ignore = "measurement: the chain planner against the reference on 50 mounts (minutes)"]
fn chain_against_the_reference_on_50_mounts() {
    use crate::model::{Mount, RobotParams};
    use crate::plan::PlanningProblem;
    let mut rng = 0x19_5EED_u64;
    let mut next = move || {
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        (rng.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mounts: Vec<(f64, f64)> = (0..50).map(|_| (3.0 * next() - 1.5, 3.0 * next() - 1.5)).collect();
    let rows: Vec<(f64, f64, f64, f64)> = mounts
        .into_par_iter()
        .map(|(a, b)| {
            let problem = PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap());
            let effort = chain_effort(&(0, problem, 0.0, 0.0, 0.0));
            let reference = reference_effort(&problem).map_or(f64::INFINITY, |r| r.0);
            (a, b, effort, reference)
        })
        .collect();
    let misses: Vec<_> = rows.iter().filter(|r| !(r.2 <= 1.01 * r.3)).collect();
    for (a, b, effort, reference) in &misses {
        eprintln!("miss at a = {a:.4}, b = {b:.4}: chain {effort:.6}, reference {reference:.6}");
    }
    let better = rows.iter().filter(|r| r.2 < r.3 * (1.0 - 1e-6)).count();
    eprintln!("{} misses; chain below the reference on {better} of 50 mounts", misses.len());
}
