//! Certificates (docs/spec.md, Sec. 2): a plan is a success only when the original system, or
//! the full dynamics, integrated with the planned controls or torques, reaches the goal.
//!
//! Both levels run one routine, [`follow`]: integrate from the start, measure the deviation
//! from the planned path at every accepted step, and the final error against the goal.

use nalgebra::{SVector, Vector3, Vector6};
use serde::Serialize;

use super::motion::Motion;
use super::problem::PlanningProblem;
use super::torques::TorqueOptions;
use crate::dynamics::{forward_dynamics, joint_torques};
use crate::error::Error;
use crate::model::Configuration;
use crate::model::system::{momentum, velocity};
use crate::numerics::ode::{OdeError, OdeOptions, OdeStats, integrate};

/// The certificate of a plan: system (7) integrated from `q0` with the planned controls.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Verification {
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\] (docs/spec.md §2).
    pub final_error: f64,
    /// `q(T)` reached by the integration \[rad\].
    pub reached: Configuration,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's steps \[rad\].
    pub max_path_deviation: f64,
    /// Tolerance the final error is held to \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
}

/// What an integration meant to follow `motion` reached: the common part of both certificates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Followed {
    /// `q(T)` reached \[rad\] (the first three components of the state).
    pub reached: Configuration,
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\].
    pub final_error: f64,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's accepted steps \[rad\].
    pub max_path_deviation: f64,
    /// Integrator work.
    pub stats: OdeStats,
}

/// Integrates `y' = rhs(t, y)` from `y0` over `[0, T]` of `problem`, one piece between
/// [`Motion::breakpoints`] at a time, where `y` starts with
/// `q = (phi, theta1, theta2)`; measures the deviation of `q` from `motion` at every accepted step
/// (after `observe(y)`) and the final error of `q(T)` against the goal.
pub fn follow<const N: usize>(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    y0: SVector<f64, N>,
    ode: &OdeOptions,
    mut rhs: impl FnMut(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, Error>,
    mut observe: impl FnMut(&SVector<f64, N>),
) -> Result<Followed, Error> {
    let mut deviation: f64 = 0.0;
    let mut observe_error = None;
    // One integration per piece between the motion's breakpoints: the adaptive steps never
    // straddle a point where the controls lose smoothness.
    let mut ends: Vec<f64> = motion.breakpoints().into_iter().filter(|&t| t > 0.0 && t < problem.horizon).collect();
    ends.push(problem.horizon);
    let (mut y, mut t0, mut stats) = (y0, 0.0, OdeStats::default());
    for t1 in ends {
        if !(t1 > t0) {
            continue;
        }
        let (y1, piece) = integrate(&mut rhs, t0, y, t1, ode, |t, y| {
            observe(y);
            match motion.at(t) {
                Ok(p) => {
                    let d = (Vector3::new(y[0], y[1], y[2]) - Vector3::from(p.q.to_array())).abs().max();
                    deviation = deviation.max(d);
                }
                Err(e) => observe_error = Some(e),
            }
        })?;
        stats.accepted += piece.accepted;
        stats.rejected += piece.rejected;
        stats.evaluations += piece.evaluations;
        (y, t0) = (y1, t1);
    }
    if let Some(e) = observe_error {
        return Err(e);
    }
    let reached = Configuration::new(y[0], y[1], y[2]);
    Ok(Followed { reached, final_error: reached.distance(&problem.goal), max_path_deviation: deviation, stats })
}

/// The velocity-level certificate: integrates system (7) from `q0` with `u(t)` of `motion`
/// (evaluated exactly at every stage time) and measures the final error against the goal.
pub fn verify(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<Verification, Error> {
    let k = problem.robot.lumped();
    let y0 = Vector3::from(problem.start.to_array());
    let rhs = |t, y: &Vector3<f64>| {
        let u = motion.controls(t)?;
        Ok(Vector3::from(velocity(&k, [y[0], y[1], y[2]], u)))
    };
    let f = follow(motion, problem, y0, ode, rhs, |_| {})?;
    Ok(Verification {
        final_error: f.final_error,
        reached: f.reached,
        max_path_deviation: f.max_path_deviation,
        tolerance,
        certified: f.final_error.is_finite() && f.final_error <= tolerance,
        stats: f.stats,
    })
}

/// The forward-dynamics certificate of a torque plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TorqueCertificate {
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\] of the forward dynamics (docs/spec.md §2).
    pub final_error: f64,
    /// `q(T)` reached by the forward dynamics \[rad\].
    pub reached: Configuration,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's steps \[rad\].
    pub max_path_deviation: f64,
    /// Largest `|F phi' + G theta1' + H theta2'|` (Eq. 5) over the integrator's steps
    /// [kg m^2/s]: the angular momentum, zero for the plan.
    pub max_abs_momentum: f64,
    /// Tolerance the final error is held to \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
}

/// The forward-dynamics certificate: integrates `M q'' + c = (0, tau1(t), tau2(t))` (base
/// unactuated) from `q0` with the problem's start velocity (at rest unless set; the base at
/// zero angular momentum, Eq. 7), with the torques of `motion` evaluated exactly at every stage
/// time ([`joint_torques`] of [`Motion::at`]), and measures the final error against the goal,
/// the deviation from the planned path and the angular momentum along the way.
///
/// The start velocity is the problem's (docs/spec.md, Sec. 2), whatever the motion's `u(0)`: a
/// motion whose joint velocities do not vanish at `t = 0` on a rest-to-rest problem (ECSA's
/// trigonometric controls, docs/spec.md, Sec. 6, item 8) cannot be followed from rest, and the
/// certificate shows it.
pub fn certify_torques(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    options: &TorqueOptions,
) -> Result<TorqueCertificate, Error> {
    options.validate()?;
    let k = problem.robot.lumped();
    let q0 = problem.start.to_array();
    let [w1, w2] = problem.start_velocity;
    let base = velocity(&k, q0, [w1, w2])[0];
    let y0 = Vector6::new(q0[0], q0[1], q0[2], base, w1, w2);
    let split = |y: &Vector6<f64>| (Configuration::new(y[0], y[1], y[2]), [y[3], y[4], y[5]]);
    let mut max_momentum: f64 = 0.0;
    let rhs = |t, y: &Vector6<f64>| {
        let tau = joint_torques(&k, &motion.at(t)?);
        let (q, dq) = split(y);
        let ddq = forward_dynamics(&k, &q, dq, [0.0, tau[0], tau[1]]);
        Ok(Vector6::new(dq[0], dq[1], dq[2], ddq[0], ddq[1], ddq[2]))
    };
    let observe = |y: &Vector6<f64>| {
        let (q, dq) = split(y);
        max_momentum = max_momentum.max(momentum(&k, &q, dq).abs());
    };
    let f = follow(motion, problem, y0, &options.ode, rhs, observe).map_err(|e| match e {
        Error::Integration(OdeError { t, reason }) => Error::TorqueDiverges { t, reason },
        e => e,
    })?;
    Ok(TorqueCertificate {
        final_error: f.final_error,
        reached: f.reached,
        max_path_deviation: f.max_path_deviation,
        max_abs_momentum: max_momentum,
        tolerance: options.tolerance,
        certified: f.final_error.is_finite() && f.final_error <= options.tolerance,
        stats: f.stats,
    })
}
