//! Prints the paper's five NFA cases (Figs. 4-8): final error, peak controls, timing.
use freefloat::{Mount, NfaOptions, NormalFormPlanner, Planner, PlanningProblem, RobotParams, Transform};

fn main() -> Result<(), freefloat::Error> {
    for (a, transform) in [(0.0, Transform::Eq11), (0.0, Transform::Eq12), (0.1, Transform::Eq14), (0.2, Transform::Eq14), (0.3, Transform::Eq14), (1.0, Transform::Eq14)] {
        let b = if a == 1.0 { -1.0 } else { a };
        let robot = RobotParams::src().with_mount(Mount::new(a, b)?)?;
        let planner = NormalFormPlanner::new(NfaOptions { transform: Some(transform), ..Default::default() });
        match planner.plan(&PlanningProblem::paper(robot)) {
            Ok(plan) => println!(
                "a={a} b={b} {}: final_error {:.3e} dev {:.3e} max|u| {:?} min|sigma| {:.4} min|P| {:.4} steps {} plan {:.3} ms verify {:.3} ms",
                transform.name(),
                plan.verification.final_error,
                plan.verification.max_path_deviation,
                plan.max_abs_u,
                plan.min_abs_sigma,
                plan.min_abs_p,
                plan.verification.stats.accepted,
                plan.seconds.plan * 1e3,
                plan.seconds.verify * 1e3
            ),
            Err(e) => println!("a={a} b={b}: {e}"),
        }
    }
    Ok(())
}
