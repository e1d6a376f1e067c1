//! Issue 19, item 2: the minimum-effort plan at n = 2 against the exhaustive
//! [`reference`](super::reference) search on 50 random mounts and on the issue's table; the 300
//! recorded problems (tests/fixtures/two_link_300.csv, read here) against both of yesterday's
//! planners are the one planner's test, `chain::tests_recorded`.

use rayon::prelude::*;

use super::reference::reference_effort;
use super::*;
use crate::model::{Configuration, Mount, RobotParams};

/// A recorded problem: its index, the problem, the 2-joint planner's certified effort before
/// issue 19, the better of both planners' certified efforts (infinite where none certified), and
/// the 2-joint planner's recorded wall time \[ms\].
pub(crate) type Recorded = (usize, PlanningProblem, f64, f64, f64);

/// The fixture's problems and their recorded efforts.
pub(crate) fn fixture() -> Vec<Recorded> {
    let text = include_str!("../../../tests/fixtures/two_link_300.csv");
    let mut out = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("i,")) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 15, "a fixture row has 15 fields: {line}");
        let x: Vec<f64> = f[1..].iter().map(|s| s.parse::<f64>().unwrap_or(f64::NAN)).collect();
        let robot = RobotParams::src().with_mount(Mount::new(x[0], x[1]).unwrap()).unwrap();
        let start = Configuration { phi: x[2], theta1: x[3], theta2: x[4] };
        let goal = Configuration { phi: x[5], theta1: x[6], theta2: x[7] };
        let problem = PlanningProblem::new(robot, start, goal, 10.0).unwrap();
        let effort = |value: f64, certified: &str| if certified == "true" { value } else { f64::INFINITY };
        let two = effort(x[8], f[10]);
        out.push((f[0].parse().unwrap(), problem, two, two.min(effort(x[11], f[13])), x[10]));
    }
    assert_eq!(out.len(), 300);
    out
}

/// Issue 19's table, the paper's problem at four mounts: the n-joint planner's efforts there
/// (6.516 at (0, -1) and 57.940 at (1, 1), where the 2-joint planner gave 10.805 and 76.393) are
/// now the 2-joint plan's too, and the equal rows stay.
#[test]
fn issue_19_table_every_row_at_least_the_better_column() {
    for (a, b, better) in [(0.0, -1.0, 6.516), (1.0, 1.0, 57.940), (0.1, 0.1, 0.22013), (-0.5, -0.5, 5.552)] {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
        let plan = OptimalPlanner::default().plan(&PlanningProblem::paper(robot)).unwrap().plan;
        assert!(plan.verification.certified, "({a}, {b}) certified");
        // The table's efforts are rounded to 5 significant digits.
        assert!(plan.effort <= better * (1.0 + 1e-4), "({a}, {b}): {} > {better}", plan.effort);
    }
}

/// Issue 19: on 50 random mounts of the paper's problem the plan's effort is within 1 % of the
/// exhaustive reference search's on at least 49 (the misses are printed).
///
/// Measured: 23 misses with the two-joint planner's search and with the one planner's at first
/// (by up to 2.2 times), 6 once two-joint arms tried joint goals two turns further, 2 with the
/// centred loop and the one-turn coil beside the loops (a = 1.4457, b = -1.4166: plan 445.14,
/// reference 429.10; a = 1.2544, b = -1.2358: 179.13 against 169.03), none once lines of more
/// than a turn were solved on a basis of 8 spans per turn too (`chain::LINE_SPANS_PER_TURN`:
/// 349.54, below that reference's 429.10, and 169.33). The reference, given that basis at twice
/// the resolution too, then found one (a = -1.4004, b = 1.2127: plan 80.499, reference 76.124,
/// from a loop of the other orientation on 35 spans). About a minute on two cores.
#[test]
fn within_one_percent_of_the_reference_on_49_of_50_mounts() {
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
            let plan = OptimalPlanner::default().plan(&problem).unwrap().plan;
            let effort = if plan.verification.certified { plan.effort } else { f64::INFINITY };
            let reference = reference_effort(&problem).map_or(f64::INFINITY, |r| r.0);
            (a, b, effort, reference)
        })
        .collect();
    let misses: Vec<_> = rows.iter().filter(|r| !(r.2 <= 1.01 * r.3)).collect();
    for (a, b, effort, reference) in &misses {
        eprintln!("miss at a = {a:?}, b = {b:?}: plan {effort:.6}, reference {reference:.6}");
    }
    let better = rows.iter().filter(|r| r.2 < r.3 * (1.0 - 1e-6)).count();
    eprintln!("plan below the reference on {better} of 50 mounts");
    assert!(misses.len() <= 1, "{} misses (a, b, plan, reference): {misses:?}", misses.len());
}
