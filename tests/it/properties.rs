//! Properties over random problems: the planners never panic, and never return a non-finite
//! number; a plan is either certified, or says it is not, or there is a typed error.

use freefloat::{
    Configuration, Mount, NfaOptions, NormalFormPlanner, Planned, Planner, PlanningProblem, RobotParams, Transform,
};
use proptest::prelude::*;

fn finite(plan: &freefloat::Plan) -> bool {
    let tr = &plan.trajectory;
    let columns = tr.q.iter().chain(&tr.dq).chain(tr.ddq.iter().flatten()).chain(tr.z.iter().flatten());
    columns.flatten().all(|x| x.is_finite())
        && plan.max_abs_u.iter().all(|x| x.is_finite())
        && plan.verification.final_error.is_finite()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_problems_plan_or_fail_cleanly(
        a in -1.0..1.0f64, b in -1.0..1.0f64,
        start in prop::array::uniform3(-3.2..3.2f64),
        step in prop::array::uniform3(-1.5..1.5f64),
        transform in prop_oneof![Just(None), Just(Some(Transform::Eq14)), Just(Some(Transform::Global))],
    ) {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid");
        let start = Configuration::from_array(start);
        let goal = Configuration::new(start.phi + step[0], start.theta1 + step[1], start.theta2 + step[2]);
        let problem = PlanningProblem::new(robot, start, goal, 10.0).expect("valid problem");
        let options = NfaOptions { transform, samples: 201, accelerations: true, ..Default::default() };
        match NormalFormPlanner::new(options).plan(&problem) {
            Ok(Planned { plan, .. }) => {
                prop_assert!(finite(&plan), "non-finite value in a plan");
                if plan.verification.certified {
                    prop_assert!(plan.verification.final_error <= 1e-9);
                }
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
