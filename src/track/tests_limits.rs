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

/// The 3-link example at its velocity limit (20 deg/s on every joint) in T = 21 s, its plan at
/// that limit over most of the motion, run on 5 % perturbed robots: with the limit margin the
/// plan and the re-plans keep headroom inside the limits, the plant still saturates at the true
/// ones, and the trials are judged at the true limits. More trials stay inside them and more
/// reach the goal than with the plan at the limits (margin 0), whose trials break them.
#[test]
fn the_limit_margin_keeps_trials_inside_the_true_limits() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml");
    let velocity = JointLimits { velocity: Some(20f64.to_radians()), ..Default::default() };
    let robot = with_joints(&Arm::load(std::path::Path::new(path)).unwrap(), vec![velocity; 3]);
    let goal = [30.0_f64, 60.0, -30.0, 20.0].map(f64::to_radians).to_vec();
    let problem = ChainProblem::rest_to_rest(vec![0.0; 4], goal, 21.0);
    let mc = MonteCarloOptions {
        trials: 8,
        perturbation: Perturbation { relative: 0.05, mount: 0.0 },
        controllers: vec![Controller::Adaptive],
        ..Default::default()
    };
    let run = |limit_margin: f64| {
        let mut options = TrackOptions::default();
        options.replan.limit_margin = limit_margin;
        let planned = options.replan.first_plan(&robot, &problem).unwrap();
        planned.certified().unwrap();
        assert_eq!(options.replan.limit_margin.to_bits(), limit_margin.to_bits(), "T = 21 s fits the whole margin");
        // The plan keeps the margin: its verified speed inside (1 - margin) of the limit.
        let planning = options.replan.planning_model(&robot, &problem);
        for (j, l) in planning.limits.joints.iter().enumerate() {
            assert!(
                (l.velocity.unwrap() - (1.0 - limit_margin) * robot.limits.joint(j).velocity.unwrap()).abs() < 1e-15
            );
        }
        let (_, summaries) = monte_carlo(&robot, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
        summaries[0]
    };
    let (bare, kept) = (run(0.0), run(ReplanOptions::default().limit_margin));
    assert!(bare.limit_failures > 0, "at the limits a perturbed robot breaks them: {bare:?}");
    assert!(kept.limit_failures < bare.limit_failures, "{kept:?} against {bare:?}");
    assert!(kept.successes > bare.successes, "{kept:?} against {bare:?}");
}

/// The limits of a plan with headroom ([`Limits::with_headroom`]): rates times `1 - F`, ranges
/// shrunk about their centre, widened to hold the ends and a measured speed but never beyond the
/// limits themselves; nothing changes at `F = 0` or without limits; a bad margin is refused.
#[test]
fn headroom_tightens_every_limit_and_admits_the_measured_state() {
    let joint =
        JointLimits { position: Some([-1.0, 3.0]), velocity: Some(2.0), torque: Some(10.0), acceleration: Some(4.0) };
    let limits = Limits { joints: vec![joint; 2], base: Some([-0.5, 0.5]) };
    assert_eq!(limits.with_headroom(0.0, &[], &[]), limits);
    assert_eq!(Limits::default().with_headroom(0.1, &[], &[]), Limits::default());
    let tight = limits.with_headroom(0.1, &[], &[]);
    let j = tight.joint(0);
    assert_eq!((j.velocity, j.torque, j.acceleration), (Some(1.8), Some(9.0), Some(3.6)));
    let [lo, hi] = j.position.unwrap();
    assert!((lo + 0.8).abs() < 1e-15 && (hi - 2.8).abs() < 1e-15, "{lo} {hi}");
    let [blo, bhi] = tight.base.unwrap();
    assert!((blo + 0.45).abs() < 1e-15 && (bhi - 0.45).abs() < 1e-15);
    // A measured state beyond the tightened limits (joint 1 at 2.9 rad moving at 1.9 rad/s, the
    // base at -0.49 rad), and one beyond the limits themselves (joint 2 at 2.5 rad/s).
    let admitted = limits.with_headroom(0.1, &[&[-0.49, 2.9, 0.0]], &[1.9, 2.5]);
    let (a, b) = (admitted.joint(0), admitted.joint(1));
    assert!(a.position.unwrap()[1] > 2.9 && a.position.unwrap()[1] <= 3.0);
    assert!(a.velocity.unwrap() > 1.9 && a.velocity.unwrap() <= 2.0);
    assert_eq!(b.velocity, Some(2.0), "never beyond the limit itself");
    assert!(admitted.base.unwrap()[0] < -0.49 && admitted.base.unwrap()[0] >= -0.5);
    assert_eq!(a.torque, Some(9.0));
    for bad in [-0.01, 1.0, f64::NAN, f64::INFINITY] {
        let o =
            TrackOptions { replan: ReplanOptions { limit_margin: bad, ..Default::default() }, ..Default::default() };
        assert!(o.validate().unwrap_err().to_string().contains("limit-margin"), "{bad}");
    }
    let (arm, _, _) = paper();
    let e = ReplanOptions::check_limit_margin(&arm, Some(0.05)).unwrap_err().to_string();
    assert!(e.contains("limit-margin") && e.contains("no limits"), "{e}");
    assert!(ReplanOptions::check_limit_margin(&arm, None).is_ok());
    // A margin of 0 is none: accepted for any robot (a script may pass it to every run).
    assert!(ReplanOptions::check_limit_margin(&arm, Some(0.0)).is_ok());
}
