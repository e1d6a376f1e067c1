//! Issue 22: the closed loop where it is hard. The common factor of the identified model from
//! the joint torques' work ([`super::energy`]), re-plans on the knots of their reference
//! ([`super::replan`]), and the hard set (`tests/fixtures/hard_set.csv`, made by
//! `examples/hard_set.rs`).

use super::*;
use crate::Method;
use crate::model::arm::Arm;
use crate::model::{Mount, RobotParams};
use crate::planners::arm::{ArmRequest, plan_arm};
use crate::planners::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainProblem};

/// The hard set's problems: `(arm, problem)` per row of the fixture.
fn hard_set() -> Vec<(Arm, ChainProblem)> {
    let text = include_str!("../../tests/fixtures/hard_set.csv");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('i'))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            let arm = Arm { mount: Mount { a: v[1], b: v[2] }, ..Arm::from_params(&RobotParams::src()) };
            (arm, ChainProblem::rest_to_rest(v[3..6].to_vec(), v[6..9].to_vec(), 10.0))
        })
        .collect()
}

/// The true arm, driven by a torque held over each tick, does work `tau . (theta(t + dt) -
/// theta(t))` that equals the change of its kinetic energy; the balance over the run gives the
/// factor between the true parameters and an estimate a common factor off them (to the plant's
/// Runge–Kutta error: oscillating torques keep the motion slow).
#[test]
fn the_work_of_the_joint_torques_gives_the_common_factor() {
    let nominal = Arm::from_params(&RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap());
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&nominal, 3).unwrap();
    let mut plant = plant::Plant::new(&truth, &[0.2, 0.5, -0.4], Disturbances::default(), 0);
    let mut balance = energy::EnergyBalance::new(2, 5.0);
    let dt = 1e-3;
    for i in 0..5000 {
        let t = i as f64 * dt;
        let tau = [0.8 * (2.1 * t).sin(), -0.4 * (3.3 * t + 0.3).cos()];
        balance.update(&plant.measure(), &tau, dt);
        plant.step(&tau, dt, 1);
    }
    let x = identify::parameters(&truth);
    for s in [0.8, 1.0, 1.07] {
        let estimate: Vec<f64> = x.iter().map(|v| v / s).collect();
        let factor = balance.factor(&estimate);
        assert!((factor - s).abs() < 1e-6 * s, "factor {factor} for {s}");
    }
}

/// On the public hard case with a 5 % model error, `adaptive` ends with the true
/// parameters themselves (the momentum gives them up to a factor, the work the factor), not a
/// multiple of them: the computed torque is then the true robot's.
#[test]
fn an_adaptive_run_identifies_the_parameters_and_their_factor() {
    let nominal = Arm::from_params(&RobotParams::src().with_mount(Mount::new(1.3, -0.9).unwrap()).unwrap());
    let rad = |v: [f64; 3]| v.map(f64::to_radians).to_vec();
    let problem = ChainProblem::rest_to_rest(rad([10.0, 40.0, -70.0]), rad([80.0, -30.0, 60.0]), 10.0);
    let planned = plan_arm(&nominal, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    let truth = Perturbation { relative: 0.05, mount: 0.0 }.apply(&nominal, 2).unwrap();
    let options = TrackOptions { controller: Controller::Adaptive, ..Default::default() };
    let run = track(&nominal, &problem, &planned.plan, &truth, &options, 2).unwrap();
    let id = run.identification.unwrap();
    let off = id.identified.iter().zip(&id.truth).map(|(i, t)| (i / t - 1.0).abs()).fold(0.0, f64::max);
    let nominal_off = id.nominal.iter().zip(&id.truth).map(|(i, t)| (i / t - 1.0).abs()).fold(0.0, f64::max);
    assert!(off < 1e-3, "identified parameters {off:.2e} off the truth (nominal {nominal_off:.2e})");
    assert!(run.final_error < 1e-4, "final error {:.2e}", run.final_error);
}

/// A re-plan from a state on its reference keeps the reference's knots after that time, so
/// that the reference's rest is a point of its basis (the warm start is exact, and feasible):
/// the re-plan is certified, costs no more than that rest (the rest competes in its search),
/// and takes a few iterations. (The reference has no thin end layer, which a re-plan drops:
/// see the next test.)
#[test]
fn a_replan_keeps_the_knots_of_its_reference() {
    let (arm, problem) = hard_set().swap_remove(1);
    let options = ChainOptions { grading: 0, ..Default::default() };
    let plan = ChainPlanner::new(arm.clone(), options).plan(&problem).unwrap();
    let reference = replan::Reference::Initial(&plan);
    let b = plan.basis().breakpoints();
    let k = b.len() / 3;
    let t = b[k] + 0.2 * (b[k + 1] - b[k]);
    let mut replanner = replan::Replanner::new(plan.q(10.0).unwrap(), ReplanOptions::default());
    let again = replanner.replan(&arm, &state_on(&arm, &plan, t), t, 10.0, &reference).expect("a re-plan");
    let kept: Vec<f64> = b.iter().filter(|&&k| k > t + 1e-9).map(|k| k - t).collect();
    let new = again.basis().breakpoints();
    assert_eq!(new.len(), kept.len() + 1, "{new:?} against {kept:?}");
    assert!(new[1..].iter().zip(&kept).all(|(a, b)| (a - b).abs() < 1e-12));
    // The effort of the reference's rest, by Simpson's rule on 4000 intervals (a cubic's
    // square rate is a quartic per span: the rule's error is far below the margin).
    let m = 4000;
    let rest: f64 = (0..=m)
        .map(|i| {
            let s = t + (10.0 - t) * i as f64 / m as f64;
            let w = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * plan.joints_at(s).unwrap().rate.iter().map(|r| r * r).sum::<f64>()
        })
        .sum::<f64>()
        * (10.0 - t)
        / (3.0 * m as f64);
    assert!(again.verification.certified);
    assert!(again.effort() <= rest * (1.0 + 1e-6), "re-plan {} against the rest's {rest}", again.effort());
    assert!(again.stats.iterations <= 6, "{} SQP iterations", again.stats.iterations);
}

/// The state of the model moving along `plan` at `t` (zero momentum).
fn state_on(arm: &Arm, plan: &ChainPlan, t: f64) -> plant::State {
    let p = plan.joints_at(t).unwrap();
    let mut dq = vec![arm.base_rate(&p.theta, &p.rate)];
    dq.extend(&p.rate);
    plant::State { q: plan.q(t).unwrap(), dq }
}

/// A reference with the planner's thin end layer (`grading` 1, a span of `h / 4` before `T`):
/// the re-plan keeps every other knot and brakes over a span of the usual width, whose torque
/// at the end is smaller (the actuators' relative noise there is the run's final error).
#[test]
fn a_replan_brakes_over_a_span_of_the_usual_width() {
    let (arm, problem) = hard_set().swap_remove(1);
    let plan = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem).unwrap();
    let b = plan.basis().breakpoints();
    let h = b[b.len() / 2 + 1] - b[b.len() / 2];
    assert!((10.0 - b[b.len() - 2] - h / 4.0).abs() < 1e-12, "a thin last layer");
    let t = b[b.len() / 2] + 0.1 * h;
    let reference = replan::Reference::Initial(&plan);
    let mut replanner = replan::Replanner::new(plan.q(10.0).unwrap(), ReplanOptions::default());
    let again = replanner.replan(&arm, &state_on(&arm, &plan, t), t, 10.0, &reference).expect("a re-plan");
    let new = again.basis().breakpoints();
    let last = new[new.len() - 1] - new[new.len() - 2];
    assert!((last - h).abs() < 1e-9, "last span {last} against {h}");
    let torque = |m: &ChainPlan, s: f64| {
        let p = m.joints_at(s).unwrap();
        crate::dynamics::arm::inverse_dynamics(&arm, &p.theta, &p.rate, &p.acceleration).tau.amax()
    };
    let (before, after) = (torque(&plan, 10.0), torque(&again, 10.0 - t));
    assert!(after < before, "end torque {after:.3} N m against the reference's {before:.3}");
    assert!(again.verification.certified);
}
