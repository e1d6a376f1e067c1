//! Tests of the optimal planner.

use super::*;
use crate::model::{Mount, RobotParams};

fn paper(a: f64, b: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap())
}

#[test]
fn smoke_paper_cases() {
    for (a, b) in [(0.0, 0.0), (0.1, 0.1), (0.2, 0.2), (0.3, 0.3), (1.0, -1.0)] {
        let clock = std::time::Instant::now();
        let (plan, motion) = OptimalPlanner::default().plan_with_motion(&paper(a, b)).unwrap();
        eprintln!(
            "({a},{b}): {:?} err {:.2e} dev {:.2e} t {:.3} ms",
            motion.stats,
            plan.verification.final_error,
            plan.verification.max_path_deviation,
            clock.elapsed().as_secs_f64() * 1e3
        );
    }
}
