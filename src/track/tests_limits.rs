//! The plant at the robot's declared limits (issue 20 item 6): per-joint torque saturation
//! combined with the user's cap, position and velocity limits as trial failures, and nothing
//! changed for an arm without limits.

use super::*;
use crate::Method;
use crate::model::arm::{Arm, JointLimits, Limits};
use crate::model::{Mount, RobotParams};
use crate::plan::PlanningProblem;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;

/// The paper's robot at a = b = 0.1, its problem and its minimum-effort plan.
fn paper() -> (Arm, ChainProblem, ArmPlanned) {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let (arm, problem) = two_link(&PlanningProblem::paper(robot));
    let planned = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    (arm, problem, planned)
}

fn with_joints(arm: &Arm, joints: Vec<JointLimits>) -> Arm {
    arm.clone().with_limits(Limits { joints, base: None }).unwrap()
}

/// Per-joint declared torque limits saturate the plant exactly (the applied torque is the clamp
/// of the command at each joint's own limit, no noise, no bias), and the user's cap
/// `torque_limit` combines with them: the smaller wins, joint by joint.
#[test]
fn a_plant_at_its_per_joint_torque_limit_saturates_exactly() {
    let (arm, _, _) = paper();
    let torque = |t: f64| JointLimits { torque: Some(t), ..Default::default() };
    let limited = with_joints(&arm, vec![torque(0.3), torque(2.0)]);
    for (cap, limits) in [(f64::INFINITY, [0.3, 2.0]), (1.0, [0.3, 1.0]), (0.1, [0.1, 0.1])] {
        let disturbances = Disturbances { torque_limit: cap, ..Default::default() };
        let mut plant = plant::Plant::new(&limited, &[0.0, 0.5, -0.3], disturbances, 0);
        assert_eq!(vec![plant.torque_limit(0), plant.torque_limit(1)], limits.to_vec());
        for command in [[0.5, -5.0], [0.05, 0.09], [-1e9, 1e9], [0.3, -2.0]] {
            let applied = plant.step(&command, 1e-3, 1);
            let clamp = [command[0].clamp(-limits[0], limits[0]), command[1].clamp(-limits[1], limits[1])];
            assert_eq!(applied.tau, clamp, "cap {cap}, command {command:?}");
            assert_eq!(applied.saturated, command.iter().zip(&limits).any(|(t, l)| t.abs() > *l));
            assert_eq!(applied.broken, None);
        }
    }
    // A closed loop under the declared limits never applies more than them.
    let (_, problem, planned) = paper();
    let options = TrackOptions { controller: Controller::Ct, rate: 200.0, ..Default::default() };
    let run = track(&limited, &problem, &planned.plan, &limited, &options, 0).unwrap();
    assert!(run.saturated_fraction > 0.0, "the plan needs more than 0.3 N m on joint 1");
    assert!(run.peak_torque[0] <= 0.3 && run.peak_torque[1] <= 2.0, "{:?}", run.peak_torque);
}

/// A trial whose true motion leaves a joint's position range, or exceeds a joint's velocity
/// limit, fails with that reason (checked at every integrator step, so even within one tick),
/// counts as failed in the Monte Carlo summary and writes its reason in the trials file.
#[test]
fn a_trial_that_breaks_a_position_or_velocity_limit_is_a_failure() {
    let (arm, problem, planned) = paper();
    // The plan takes theta1 from problem.start[1] to problem.goal[1]: a range that ends
    // half-way is left during the motion.
    let (from, to) = (problem.start[1], problem.goal[1]);
    let (lo, hi) = if from < to { (from - 0.1, 0.5 * (from + to)) } else { (0.5 * (from + to), from + 0.1) };
    let position = JointLimits { position: Some([lo, hi]), ..Default::default() };
    let by_position = with_joints(&arm, vec![position, JointLimits::default()]);
    // The true robot has the range, the model does not: a goal outside a declared range is
    // refused as bad input (ChainProblem::validate), so the range lives only in the plant.
    let options = TrackOptions { controller: Controller::Ct, rate: 200.0, ..Default::default() };
    let run = track(&arm, &problem, &planned.plan, &by_position, &options, 0).unwrap();
    let failure = run.failure.expect("the motion leaves the range");
    assert_eq!(failure.reason, "position_limit");
    assert!(failure.t > 0.0 && failure.t < problem.horizon);
    assert!(run.final_error.is_infinite() && run.diverged_at.is_none());

    // A plant started faster than its velocity limit breaks it on the first step.
    let velocity = JointLimits { velocity: Some(0.1), ..Default::default() };
    let by_velocity = with_joints(&arm, vec![JointLimits::default(), velocity]);
    let mut plant = plant::Plant::new(&by_velocity, &problem.start, Disturbances::default(), 0).moving(&[0.0, 0.2]);
    assert_eq!(plant.step(&[0.0, 0.0], 1e-3, 4).broken, Some("velocity_limit"));

    let mc = MonteCarloOptions {
        trials: 2,
        controllers: vec![Controller::Ct],
        truth: Some(by_position.clone()),
        ..Default::default()
    };
    let (trials, summaries) = monte_carlo(&arm, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
    assert!(trials.iter().all(|t| t.failure == Some("position_limit") && t.final_error.is_infinite()));
    assert_eq!((summaries[0].failed, summaries[0].limit_failures, summaries[0].successes), (2, 2, 0));
    let run_words = trials_file::run_description(&by_position, &problem, &options, &mc, "optimal");
    assert!(run_words.contains("/limits:"), "limits change the rows, so the run: {run_words}");
    let bytes = trials_file::write(&run_words, mc.shard, &trials).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(text.contains("\n0,ct,,position_limit,"), "{text}");
    let back = trials_file::read(&bytes, std::path::Path::new("t.csv")).unwrap();
    let read: Vec<Trial> = back.rows.iter().map(Trial::from).collect();
    assert_eq!(read[0].failure, Some("position_limit"));
    assert_eq!(summarise(&mc.controllers, &read, mc.success_tolerance), summaries);
}

/// Limits the motion never reaches change nothing: the run is bit for bit the run without
/// limits (the same applied torques, the same end state), and an arm without limits keeps the
/// trials file's `# run:` words of earlier versions.
#[test]
fn limits_never_reached_change_nothing() {
    let (arm, problem, planned) = paper();
    let wide = JointLimits {
        position: Some([-100.0, 100.0]),
        velocity: Some(1e3),
        torque: Some(1e6),
        acceleration: Some(1e6),
    };
    let limited = with_joints(&arm, vec![wide; 2]);
    let options = TrackOptions { controller: Controller::Adaptive, rate: 200.0, ..Default::default() };
    let free = track(&arm, &problem, &planned.plan, &arm, &options, 3).unwrap();
    let bounded = track(&limited, &problem, &planned.plan, &limited, &options, 3).unwrap();
    assert_eq!(free.failure, None);
    assert_eq!(
        (bounded.failure, bounded.final_errors.clone(), bounded.peak_torque.clone()),
        (None, free.final_errors, free.peak_torque)
    );
    let mc = MonteCarloOptions::default();
    let words = trials_file::run_description(&arm, &problem, &options, &mc, "optimal");
    assert!(!words.contains("limits"), "{words}");
}
