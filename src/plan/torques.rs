//! The torque level of a plan (Sec. 3.1, Eq. 6, for any planar serial arm), one routine for
//! every arm and method: the joint torques along the planned motion by the arm's inverse
//! dynamics ([`crate::dynamics::arm`]), and their certificate, the full dynamics
//! `M q'' + c = (0, tau(t))` (base unactuated) integrated from the start with those torques by
//! the velocity certificate's piecewise scheme, compared with the goal.
//!
//! A 2-link [`Motion`] is certified through its [`MotionView`] on [`Arm::from_params`]
//! ([`torque_plan`], [`add_torques`], [`certify_torques`]); at `n = 2` the arm's inertia matrix,
//! Coriolis terms and inverse dynamics are the paper's closed forms (Eqs. 3, 6; tested to 1e-12
//! in `dynamics/arm/tests.rs`).

use std::time::Instant;

use nalgebra::SVector;
use serde::Serialize;

use super::Plan;
use super::certificate::{JointMotion, MotionView, by_joints, check_lengths, final_error, piecewise};
use super::motion::Motion;
use super::problem::PlanningProblem;
use crate::dynamics::arm::{ArmDynamics, InverseDynamics, inverse_dynamics};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::lumped::SIZE;
use crate::model::{Configuration, InputError};
use crate::numerics::ode::{OdeError, OdeOptions, OdeStats};

/// The inverse dynamics of `motion` at `t` \[s\]: joint torques \[N m\], the base's residual and
/// the full velocity and acceleration.
pub fn chain_torques_at(arm: &Arm, motion: &dyn JointMotion, t: f64) -> InverseDynamics {
    let n = arm.joints();
    let (mut theta, mut rate, mut acceleration) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    motion.joint_state(t, &mut theta, &mut rate);
    motion.joint_acceleration(t, &mut acceleration);
    inverse_dynamics(arm, &theta, &rate, &acceleration)
}

/// The joint torques of `motion` at `t` into `tau` (`n` values) [N m]: [`chain_torques_at`]
/// on stack buffers, with the arm's constants held by `dynamics`.
pub(crate) fn torques_into(dynamics: &ArmDynamics, motion: &dyn JointMotion, t: f64, tau: &mut [f64]) {
    let n = dynamics.joints();
    let (mut theta, mut rate, mut acceleration) = ([0.0; SIZE], [0.0; SIZE], [0.0; SIZE]);
    let (mut dq, mut ddq) = ([0.0; SIZE], [0.0; SIZE]);
    motion.joint_state(t, &mut theta[..n], &mut rate[..n]);
    motion.joint_acceleration(t, &mut acceleration[..n]);
    dynamics.inverse_into(&theta[..n], &rate[..n], &acceleration[..n], tau, &mut dq, &mut ddq);
}

/// The torque-level certificate of an `n`-joint plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainTorqueCertificate {
    /// `max_i |wrap(q_i(T) - qd_i)|` over `q = (phi, theta)` \[rad\].
    pub final_error: f64,
    /// `q(T)` reached \[rad\].
    pub reached: Vec<f64>,
    /// Largest `|F phi' + G . theta'|` of the integrated state over the accepted steps
    /// \[kg m^2/s\].
    pub max_abs_momentum: f64,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the accepted steps \[rad\], when the motion
    /// knows its configuration ([`JointMotion::planned_configuration`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_path_deviation: Option<f64>,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance` (and finite).
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
}

/// Integrates the full dynamics with the planned torques ([`chain_torques_at`] at every stage
/// time) from `start` (`n + 1` angles) with the plan's velocity at `t = 0` (the base's from the
/// momentum), over each knot span of `motion`, and compares with `goal` (modulo 2 pi).
pub fn certify_chain_torques(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainTorqueCertificate, Error> {
    certify_joint_torques(arm, motion, start, None, goal, ode, tolerance)
}

/// [`certify_chain_torques`] from the joint velocities `start_rate` \[rad/s\] (`n` values; the
/// base's from zero angular momentum, Eq. 7) instead of the plan's own at `t = 0`, when given:
/// the start state belongs to the problem (docs/spec.md, Sec. 2), and a motion whose velocities
/// do not match it (ECSA's plain series from rest) cannot be followed; the certificate shows it.
/// The integration failing (the torques drive the state to where the dynamics cannot be
/// evaluated) is [`Error::TorqueDiverges`].
pub fn certify_joint_torques(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    start_rate: Option<&[f64]>,
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainTorqueCertificate, Error> {
    check_lengths(arm, motion, start, goal)?;
    if let Some(rate) = start_rate
        && rate.len() != arm.joints()
    {
        return Err(Error::from(InputError::InvalidParameter {
            name: "start velocity".into(),
            value: rate.len() as f64,
            expected: "one velocity per joint",
        }));
    }
    by_joints!(arm.joints(), 2, run(arm, motion, start, start_rate, goal, ode, tolerance)).map_err(|e| match e {
        Error::Integration(OdeError { t, reason }) => Error::TorqueDiverges { t, reason },
        e => e,
    })
}

/// [`certify_joint_torques`] with the state `(q, q')` of static size `M = 2 (n + 1)`.
fn run<const M: usize>(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    start_rate: Option<&[f64]>,
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainTorqueCertificate, Error> {
    let n1 = M / 2;
    let n = n1 - 1;
    let mut y = SVector::<f64, M>::zeros();
    y.as_mut_slice()[..n1].copy_from_slice(start);
    match start_rate {
        Some(rate) => {
            y[n1] = arm.base_rate(&start[1..], rate);
            y.as_mut_slice()[n1 + 1..].copy_from_slice(rate);
        }
        None => {
            let first = chain_torques_at(arm, motion, 0.0);
            motion.check()?;
            y.as_mut_slice()[n1..].copy_from_slice(first.dq.as_slice());
        }
    }
    let dynamics = ArmDynamics::new(arm);
    let rhs = |t: f64, y: &SVector<f64, M>| -> Result<SVector<f64, M>, Error> {
        let mut tau = [0.0; SIZE];
        torques_into(&dynamics, motion, t, &mut tau[..n]);
        motion.check()?;
        let mut out = SVector::<f64, M>::zeros();
        let (q, dq) = y.as_slice().split_at(n1);
        out.as_mut_slice()[..n1].copy_from_slice(dq);
        dynamics
            .forward(&q[1..], dq, &tau[..n], &mut out.as_mut_slice()[n1..])
            .map_err(|_| Error::from(OdeError { t, reason: "singular inertia matrix" }))?;
        Ok(out)
    };
    let mut max_momentum: f64 = 0.0;
    let mut deviation: Option<f64> = None;
    let mut planned = [0.0; M];
    let observe = |t: f64, y: &SVector<f64, M>| {
        let (f, g) = arm.momentum_coefficients(&y.as_slice()[1..n1]);
        let p = f * y[n1] + (0..n).map(|j| g[j] * y[n1 + 1 + j]).sum::<f64>();
        max_momentum = max_momentum.max(p.abs());
        if motion.planned_configuration(t, &mut planned[..n1]) {
            let d = (0..n1).map(|i| (y[i] - planned[i]).abs()).fold(0.0, f64::max);
            deviation = Some(deviation.map_or(d, |m: f64| m.max(d)));
        }
    };
    let (y, stats) = piecewise(motion.breakpoints(), y, ode, rhs, observe, |_, _| {})?;
    motion.check()?;
    let final_error = final_error(&y.as_slice()[..n1], goal);
    Ok(ChainTorqueCertificate {
        final_error,
        reached: y.iter().take(n1).copied().collect(),
        max_abs_momentum: max_momentum,
        max_path_deviation: deviation,
        tolerance,
        certified: final_error.is_finite() && final_error <= tolerance,
        stats,
    })
}

/// Joint torques `(tau1, tau2)` [N m] of the 2-link `arm` ([`Arm::from_params`] of the plan's
/// robot) along `motion` at the given times \[s\] (e.g. a trajectory's samples), exact: the
/// motion's own `u` and `u'` at each time ([`Motion::points`]) through the arm's
/// [`inverse_dynamics`], no finite differences.
pub fn torques_at(arm: &Arm, motion: &dyn Motion, times: &[f64]) -> Result<Vec<[f64; 2]>, Error> {
    Ok(inverse_at(arm, motion, times)?.iter().map(|id| [id.tau[0], id.tau[1]]).collect())
}

/// The arm's inverse dynamics at each of `times` along a 2-link `motion`.
fn inverse_at(arm: &Arm, motion: &dyn Motion, times: &[f64]) -> Result<Vec<InverseDynamics>, Error> {
    if arm.joints() != 2 {
        return Err(Error::from(InputError::InvalidParameter {
            name: "joints".into(),
            value: arm.joints() as f64,
            expected: "a 2-link arm for a 2-link motion",
        }));
    }
    let dynamics = ArmDynamics::new(arm);
    Ok(motion.points(times)?.iter().map(|p| dynamics.inverse(&[p.q.theta1, p.q.theta2], &p.u, &p.du)).collect())
}

/// Options of the torque-level certificate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueOptions {
    /// Integrator options of the forward dynamics (default rtol = atol = 1e-12, docs/spec.md §2).
    pub ode: OdeOptions,
    /// Largest certified final error of the torque plan \[rad\]; default 1e-6 (docs/spec.md §2).
    pub tolerance: f64,
}

impl Default for TorqueOptions {
    fn default() -> Self {
        Self { ode: OdeOptions::default(), tolerance: 1e-6 }
    }
}

impl TorqueOptions {
    /// Checks the options (a positive tolerance).
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.tolerance > 0.0) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "torque tolerance".into(),
                value: self.tolerance,
                expected: "a positive number [rad]",
            }));
        }
        Ok(())
    }
}

/// The forward-dynamics certificate of a 2-link torque plan.
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

/// The forward-dynamics certificate of a 2-link plan: [`certify_joint_torques`] of the
/// [`MotionView`] of `motion`, from `q0` with the problem's start velocity (at rest unless set;
/// the base at zero angular momentum, Eq. 7), the torques of `motion` evaluated exactly at every
/// stage time.
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
    let view = MotionView::new(motion, problem);
    let (start, goal) = (problem.start.to_array(), problem.goal.to_array());
    let (ode, tolerance) = (&options.ode, options.tolerance);
    let c = certify_joint_torques(view.arm(), &view, &start, Some(&problem.start_velocity), &goal, ode, tolerance)?;
    Ok(TorqueCertificate {
        final_error: c.final_error,
        reached: Configuration::new(c.reached[0], c.reached[1], c.reached[2]),
        max_path_deviation: c.max_path_deviation.unwrap_or(f64::NAN),
        max_abs_momentum: c.max_abs_momentum,
        tolerance,
        certified: c.certified,
        stats: c.stats,
    })
}

/// Wall time of the torque stages \[s\].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct TorqueSeconds {
    /// Inverse dynamics at the samples.
    pub torques: f64,
    /// The forward-dynamics certificate and the base-row check.
    pub verify: f64,
}

/// The torque level of a plan: peak torques at the samples and the forward-dynamics certificate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TorqueReport {
    /// `[max |tau1|, max |tau2|]` over the samples [N m].
    pub max_abs_torque: [f64; 2],
    /// Largest `|Q_phi|` over the samples [N m]: the base row of the Euler–Lagrange equations
    /// by the arm's [`inverse_dynamics`], zero up to rounding since the motion conserves the
    /// angular momentum.
    pub max_abs_base_residual: f64,
    /// The forward-dynamics certificate.
    pub certificate: TorqueCertificate,
    /// Wall time.
    pub seconds: TorqueSeconds,
}

impl TorqueReport {
    /// `Ok` if the certificate holds, else [`Error::NotCertified`] at the `torque` level.
    pub fn check(&self) -> Result<(), Error> {
        let c = &self.certificate;
        if c.certified {
            Ok(())
        } else {
            Err(Error::NotCertified { final_error: c.final_error, tolerance: c.tolerance, level: "torque" })
        }
    }
}

/// The torque plan: torques at the samples (to fill [`crate::Trajectory::tau`]) and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct TorquePlan {
    /// `(tau1, tau2)` [N m] at each sample time.
    pub tau: Vec<[f64; 2]>,
    /// Peaks and certificate.
    pub report: TorqueReport,
}

/// Inverse dynamics of `motion` at `times` ([`torques_at`], with the base row) followed by the
/// forward-dynamics certificate ([`certify_torques`]), each timed.
pub fn torque_plan(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    times: &[f64],
    options: &TorqueOptions,
) -> Result<TorquePlan, Error> {
    options.validate()?;
    let clock = Instant::now();
    let arm = Arm::from_params(&problem.robot);
    let inverse = inverse_at(&arm, motion, times)?;
    let tau: Vec<[f64; 2]> = inverse.iter().map(|id| [id.tau[0], id.tau[1]]).collect();
    let torques_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let certificate = certify_torques(motion, problem, options)?;
    let max_abs_base_residual = inverse.iter().map(|id| id.base_residual.abs()).fold(0.0, f64::max);
    let verify_seconds = clock.elapsed().as_secs_f64();
    let max_abs_torque = tau.iter().fold([0.0_f64; 2], |m, t| [m[0].max(t[0].abs()), m[1].max(t[1].abs())]);
    Ok(TorquePlan {
        tau,
        report: TorqueReport {
            max_abs_torque,
            max_abs_base_residual,
            certificate,
            seconds: TorqueSeconds { torques: torques_seconds, verify: verify_seconds },
        },
    })
}

/// The torque level of `plan` (docs/spec.md §2) along its `motion`: [`torque_plan`] at the plan's
/// samples, the torques into `plan.trajectory.tau`, their wall time into
/// `plan.seconds.torques`; returns the report with the forward-dynamics certificate.
pub fn add_torques(plan: &mut Plan, motion: &dyn Motion, options: &TorqueOptions) -> Result<TorqueReport, Error> {
    let tp = torque_plan(motion, &plan.problem, &plan.trajectory.t, options)?;
    plan.trajectory.tau = Some(tp.tau);
    plan.seconds.torques = Some(tp.report.seconds.torques);
    Ok(tp.report)
}
