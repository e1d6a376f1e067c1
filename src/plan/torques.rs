//! The torque level of a plan (Sec. 3.1, Eq. 6): inverse dynamics along its motion, and the
//! forward-dynamics certificate.

use std::time::Instant;

use serde::Serialize;

use super::Plan;
use super::certificate::{TorqueCertificate, certify_torques};
use super::motion::Motion;
use super::problem::PlanningProblem;
use crate::dynamics::{inverse_dynamics, joint_torques};
use crate::error::Error;
use crate::model::{InputError, Lumped};
use crate::numerics::ode::OdeOptions;

/// Joint torques `(tau1, tau2)` [N m] along `motion` at the given times \[s\] (e.g. a
/// trajectory's samples), exact: the motion's own `u` and `u'` at each time
/// ([`Motion::points`]) through [`joint_torques`], no finite differences.
pub fn torques_at(k: &Lumped, motion: &dyn Motion, times: &[f64]) -> Result<Vec<[f64; 2]>, Error> {
    Ok(motion.points(times)?.iter().map(|p| joint_torques(k, p)).collect())
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
    /// by the reference [`inverse_dynamics`], zero up to rounding since the motion conserves the
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

/// Inverse dynamics of `motion` at `times` ([`torques_at`]) followed by the forward-dynamics
/// certificate ([`certify_torques`]), each timed.
pub fn torque_plan(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    times: &[f64],
    options: &TorqueOptions,
) -> Result<TorquePlan, Error> {
    options.validate()?;
    let clock = Instant::now();
    let k = problem.robot.lumped();
    let tau = torques_at(&k, motion, times)?;
    let torques_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let certificate = certify_torques(motion, problem, options)?;
    // The base row of the Euler–Lagrange equations at the samples, by the reference path.
    let mut max_abs_base_residual = 0.0_f64;
    for p in motion.points(times)? {
        max_abs_base_residual = max_abs_base_residual.max(inverse_dynamics(&k, &p).base_residual.abs());
    }
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
