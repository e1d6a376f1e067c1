//! Tests of the spin goals ([`ChainPlanner::spin_goals`]): on a heavy base the cheap way to turn
//! the base far is whole turns of one joint, more than the other goal representatives have.

use std::f64::consts::TAU;

use super::*;
use crate::model::Mount;
use crate::model::arm::{Base, Link};

/// The paper's arm (two 0.6 m, 3 kg links, slender rods) on a 2000 kg, 400 kg m^2 base: one turn
/// of `theta1` turns the base by about 2.4 deg only.
fn heavy_base() -> Arm {
    let link = Link { length: 0.6, com: 0.3, mass: 3.0, inertia: 3.0 * 0.36 / 12.0 };
    Arm {
        base: Base { mass: 2000.0, inertia: 400.0 },
        mount: Mount { a: 0.0, b: 0.0 },
        links: vec![link; 2],
        limits: Default::default(),
        geometry: Default::default(),
    }
}

/// The base 90 deg round, the joints back where they started, in 10 s: the plan of the goal
/// modulo 2 pi is certified and costs no more than the least of the literal goals with theta1
/// `k` whole turns further, solved one by one (an independent reference: each is a problem of
/// its own, without the search; `k` from -44 to -30 holds the least, about -36 turns of theta1,
/// where the base turns 2.4 deg a turn). Before the spin goals the search's coils found 36275
/// rad^2/s, seven times the least (5130).
#[test]
fn a_heavy_base_is_turned_by_spinning_a_joint() {
    let arm = heavy_base();
    let (start, goal) = (vec![0.0, 0.5, 0.5], vec![TAU / 4.0, 0.5, 0.5]);
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let plan = planner.plan(&ChainProblem::rest_to_rest(start.clone(), goal.clone(), 10.0)).expect("a plan");
    assert!(plan.verification.certified, "{:?}", plan.verification);
    let literal = |k: i32| {
        let mut g = goal.clone();
        g[1] += TAU * f64::from(k);
        let problem = ChainProblem { wrap: false, ..ChainProblem::rest_to_rest(start.clone(), g, 10.0) };
        planner.plan(&problem).map(|p| p.effort()).unwrap_or(f64::INFINITY)
    };
    let (k, least) = (-44..=-30).map(|k| (k, literal(k))).min_by(|a, b| a.1.total_cmp(&b.1)).expect("a range");
    assert!(least.is_finite() && (-43..=-31).contains(&k), "the least literal goal inside the range: {k}, {least}");
    assert!(
        plan.effort() <= least * (1.0 + 1e-6),
        "wrapped {} against the literal goals' least {least} at k = {k}",
        plan.effort()
    );
}
