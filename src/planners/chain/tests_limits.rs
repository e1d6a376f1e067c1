//! The planner inside the robot's limits (issue 20 items 3, 4): SPART's 4-link example with its
//! own limits and with tight ones, the integrated motion checked against every limit.

use super::horizon::uses;
use super::*;
use crate::dynamics::arm::inverse_dynamics;
use crate::model::arm::{JointLimits, Limits};

const SPART: &str = include_str!("../../../examples/robots/spart_like_4dof.urdf");

/// The example without its shapes: these tests are of the limits (the clearance rows, a
/// constraint of their own, are tested in `tests_clearance` and tests/it/geometry.rs).
fn shape_free() -> Arm {
    let arm = Arm::from_urdf_str(SPART, std::path::Path::new("spart_like_4dof.urdf")).expect("the example URDF");
    Arm { geometry: Default::default(), ..arm }
}

fn spart(position: f64, velocity: f64, torque: f64) -> Arm {
    let arm = shape_free();
    let joint = JointLimits {
        position: Some([-position, position]),
        velocity: Some(velocity),
        torque: Some(torque),
        acceleration: None,
    };
    let n = arm.joints();
    arm.with_limits(Limits { joints: vec![joint; n], base: None }).expect("valid limits")
}

/// Every limit of `arm` on the certified plan, sampled densely (64 points per knot span), and on
/// the integrated motion (the certificate's): positions, velocities, torques within their limit
/// to a relative 1e-6 (torques are bounded at 3 points per span by the planner).
fn assert_inside(arm: &Arm, plan: &ChainPlan) {
    let b = plan.basis().breakpoints().to_vec();
    for w in b.windows(2) {
        for k in 0..=64 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 64.0;
            let p = plan.at(t);
            let tau = inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
            for j in 0..arm.joints() {
                let l = arm.limits.joint(j);
                if let Some([lo, hi]) = l.position {
                    assert!(p.theta[j] >= lo && p.theta[j] <= hi, "joint {} at {t}: {} outside", j + 1, p.theta[j]);
                }
                if let Some(v) = l.velocity {
                    assert!(p.rate[j].abs() <= v, "joint {} at {t}: speed {}", j + 1, p.rate[j]);
                }
                if let Some(m) = l.torque {
                    assert!(tau[j].abs() <= m * (1.0 + 1e-9), "joint {} at {t}: torque {}", j + 1, tau[j]);
                }
            }
        }
    }
    assert!(plan.verification.certified, "certified: {:?}", plan.verification.final_error);
}

fn deg(v: [f64; 5]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// Issue 20: theta1 = 170 -> -170 deg with SPART's +-3.14159 rad range: the default wraps the
/// goal to 190 deg (through the limit); inside the range the plan must go the long way round
/// (theta1 passes 0 on the way, it never exceeds 3.14159 rad).
#[test]
fn the_long_way_round_inside_spart_range() {
    // SPART's declared range, 3.14159 rad (2.65e-6 rad inside pi).
    let arm = spart(std::f64::consts::PI - 2.65e-6, 100.0, 1000.0);
    let problem =
        ChainProblem::rest_to_rest(deg([0.0, 170.0, 10.0, 10.0, 10.0]), deg([30.0, -170.0, 10.0, 10.0, 10.0]), 10.0);
    let planner = ChainPlanner::new(arm.clone(), ChainOptions::default());
    let plan = planner.plan(&problem).expect("a plan inside the range");
    assert_inside(&arm, &plan);
    let end = plan.at(plan.horizon());
    assert!((end.theta[0] - (-170f64).to_radians()).abs() < 1e-9, "theta1 ends at -170 deg, not 190: {}", end.theta[0]);
    let passes_zero = (0..=100).any(|k| plan.at(plan.horizon() * k as f64 / 100.0).theta[0].abs() < 0.2);
    assert!(passes_zero, "the long way round passes theta1 = 0");
    eprintln!("spart own limits: effort {:.6} rad^2/s, {:.3} ms", plan.effort(), 1e3 * plan.stats.plan_seconds);
}

/// A start outside a joint's range is bad input naming the joint and the range.
#[test]
fn a_start_outside_a_range_is_refused_naming_it() {
    let arm = spart(2.0, 0.3, 50.0);
    let problem = ChainProblem::rest_to_rest(deg([0.0, 130.0, 0.0, 0.0, 0.0]), deg([0.0, 0.0, 0.0, 0.0, 0.0]), 10.0);
    let e = ChainPlanner::new(arm, ChainOptions::default()).plan(&problem).expect_err("outside");
    assert!(e.is_bad_input(), "{e}");
    assert!(e.to_string().contains("theta1") && e.to_string().contains("link[1].limit"), "{e}");
}

/// The tight copy (+-2 rad, 0.3 rad/s, 50 N m): the unconstrained plan breaks a limit (the issue's
/// 0.67 rad/s), the constrained one stays inside on the integrated motion and costs at least as
/// much (it is feasible for the unconstrained problem).
#[test]
fn tight_limits_bind_and_hold() {
    let free = shape_free();
    let tight = spart(2.0, 0.3, 50.0);
    let problem =
        ChainProblem::rest_to_rest(deg([0.0, 20.0, -30.0, 40.0, 10.0]), deg([30.0, 60.0, 30.0, -20.0, 40.0]), 30.0);
    let unconstrained = ChainPlanner::new(free, ChainOptions::default()).plan(&problem).expect("unconstrained plan");
    let planner = ChainPlanner::new(tight.clone(), ChainOptions::default());
    let (before, _) = uses(&planner, &unconstrained);
    let before = before.expect("limits");
    assert!(before.used > 1.0, "the unconstrained plan breaks a limit: {before:?}");
    let plan = planner.plan(&problem).expect("constrained plan");
    assert_inside(&tight, &plan);
    assert!(plan.effort() >= unconstrained.effort() * (1.0 - 1e-9), "{} < {}", plan.effort(), unconstrained.effort());
    let (after, _) = uses(&planner, &plan);
    eprintln!(
        "tight: effort {:.6} vs unconstrained {:.6}; unconstrained uses {before:?}; binding {after:?}; {:.3} ms",
        plan.effort(),
        unconstrained.effort(),
        1e3 * plan.stats.plan_seconds
    );
}

/// The shortest horizon (item 4): certified inside every limit at `T*`, and a plan at
/// `T* / 1.01` (1 % shorter, beyond the search's accuracy bound `infeasible_below`) is not
/// found; a too-short given horizon names the binding limit and the shortest horizon.
#[test]
fn shortest_horizon_is_within_one_percent_and_too_short_names_the_limit() {
    let tight = spart(2.0, 0.3, 50.0);
    let problem =
        ChainProblem::rest_to_rest(deg([0.0, 20.0, -30.0, 40.0, 10.0]), deg([30.0, 60.0, 30.0, -20.0, 40.0]), 30.0);
    let planner = ChainPlanner::new(tight.clone(), ChainOptions::default());
    let s = planner.shortest_horizon(&problem).expect("a horizon");
    assert_inside(&tight, &s.plan);
    assert!(s.horizon <= s.infeasible_below * 1.01 + 1e-12, "{} / {}", s.horizon, s.infeasible_below);
    let below = ChainProblem { horizon: s.horizon / 1.012, ..problem.clone() };
    assert!(planner.plan(&below).is_err(), "a plan 1.2 % below the shortest horizon");
    eprintln!(
        "auto: T = {:.4} s ({} probes, {:.1} ms), effort {:.6}, binding {:?}",
        s.horizon,
        s.probes,
        1e3 * s.seconds,
        s.plan.effort(),
        s.binding
    );
    let short = ChainProblem { horizon: s.horizon * 0.8, ..problem };
    let e = planner.plan_within_limits(&short).expect_err("too short");
    let Error::HorizonTooShort { shortest, quantity, joint, .. } = e else { panic!("{e}") };
    assert!((shortest / s.horizon - 1.0).abs() < 0.02, "{shortest} vs {}", s.horizon);
    assert!(joint >= 1 && !quantity.is_empty());
}

/// A torque limit that binds holds between the rows' points (`limits::hold`): SPART's example
/// with tight limits at 13.5 s, near its shortest horizon (13.24 s), where the torque of joint 1
/// rides its 50 N m limit into the graded end spans. Without the check the plan was certified
/// with joint 1's torque at 50.00217 N m (a use of 1 + 4.3e-5) at t = 13.4945 s, between two
/// rows' points (the certificate reads the torque at its steps' ends and middles). The torque of
/// the certified plan, the plan's inverse dynamics as the certificate's, sampled at 1024 points
/// per knot span, is within every declared limit, and the limit binds.
#[test]
fn a_binding_torque_limit_holds_between_the_rows_points() {
    let tight = spart(2.0, 0.3, 50.0);
    let problem =
        ChainProblem::rest_to_rest(deg([0.0, 20.0, -30.0, 40.0, 10.0]), deg([30.0, 60.0, 30.0, -20.0, 40.0]), 13.5);
    let plan = ChainPlanner::new(tight.clone(), ChainOptions::default()).plan(&problem).expect("a plan");
    assert!(plan.verification.certified);
    let mut most: f64 = 0.0;
    for w in plan.basis().breakpoints().windows(2) {
        for k in 0..=1024 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 1024.0;
            let p = plan.at(t);
            let tau = inverse_dynamics(&tight, &p.theta, &p.rate, &p.acceleration).tau;
            for (j, tau) in tau.iter().enumerate() {
                let limit = tight.limits.joint(j).torque.expect("a torque limit");
                assert!(tau.abs() <= limit, "joint {} at {t} s: torque {tau} beyond {limit}", j + 1);
                most = most.max(tau.abs() / limit);
            }
        }
    }
    assert!(most > 1.0 - 1e-6, "the torque limit binds: largest use {most}");
}
