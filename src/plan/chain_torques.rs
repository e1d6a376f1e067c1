//! The torque level of an `n`-joint plan (Eq. 6 for any planar serial arm): the joint torques
//! along the planned motion by inverse dynamics, and their certificate: the full dynamics
//! `M q'' + c = (0, tau(t))` (base unactuated) integrated from the start with those torques,
//! compared with the goal.

use nalgebra::{DVector, SVector};
use serde::Serialize;

use super::chain_certificate::{JointMotion, check_lengths};
use crate::dynamics::arm::{InverseDynamics, forward_dynamics, inverse_dynamics};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::wrap_angle;
use crate::numerics::ode::{OdeError, OdeOptions, OdeStats, integrate};

/// The inverse dynamics of `motion` at `t` \[s\]: joint torques \[N m\], the base's residual and
/// the full velocity and acceleration.
pub fn chain_torques_at(arm: &Arm, motion: &dyn JointMotion, t: f64) -> InverseDynamics {
    let n = arm.joints();
    let (mut theta, mut rate, mut acceleration) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    motion.joint_state(t, &mut theta, &mut rate);
    motion.joint_acceleration(t, &mut acceleration);
    inverse_dynamics(arm, &theta, &rate, &acceleration)
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
    let n = arm.joints();
    check_lengths(arm, motion, start, goal)?;
    macro_rules! dispatch {
        ($($n:literal => $m:literal),*) => {
            match n {
                $($n => run::<$m>(arm, motion, start, goal, ode, tolerance),)*
                _ => Err(Error::from(InputError::InvalidParameter {
                    name: "joints".into(),
                    value: n as f64,
                    expected: "1 to 15 joints",
                })),
            }
        };
    }
    dispatch!(1 => 4, 2 => 6, 3 => 8, 4 => 10, 5 => 12, 6 => 14, 7 => 16, 8 => 18, 9 => 20, 10 => 22,
        11 => 24, 12 => 26, 13 => 28, 14 => 30, 15 => 32)
}

/// [`certify_chain_torques`] with the state `(q, q')` of static size `M = 2 (n + 1)`.
fn run<const M: usize>(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainTorqueCertificate, Error> {
    let n1 = M / 2;
    let n = n1 - 1;
    let first = chain_torques_at(arm, motion, 0.0);
    let mut y = SVector::<f64, M>::zeros();
    for i in 0..n1 {
        y[i] = start[i];
        y[n1 + i] = first.dq[i];
    }
    let mut rhs = |t: f64, y: &SVector<f64, M>| -> Result<SVector<f64, M>, Error> {
        let tau = chain_torques_at(arm, motion, t).tau;
        let dq = DVector::from_iterator(n1, y.iter().skip(n1).copied());
        let ddq = forward_dynamics(arm, &y.as_slice()[1..n1], &dq, &tau)
            .map_err(|_| Error::from(OdeError { t, reason: "singular inertia matrix" }))?;
        let mut out = SVector::<f64, M>::zeros();
        for i in 0..n1 {
            out[i] = y[n1 + i];
            out[n1 + i] = ddq[i];
        }
        Ok(out)
    };
    let mut max_momentum: f64 = 0.0;
    let mut observe = |_: f64, y: &SVector<f64, M>| {
        let (f, g) = arm.momentum_coefficients(&y.as_slice()[1..n1]);
        let p = f * y[n1] + (0..n).map(|j| g[j] * y[n1 + 1 + j]).sum::<f64>();
        max_momentum = max_momentum.max(p.abs());
    };
    let mut stats = OdeStats::default();
    for w in motion.breakpoints().windows(2) {
        let (y1, s) = integrate(&mut rhs, w[0], y, w[1], ode, &mut observe)?;
        y = y1;
        stats.accepted += s.accepted;
        stats.rejected += s.rejected;
        stats.evaluations += s.evaluations;
    }
    let final_error = (0..n1).map(|i| wrap_angle(y[i] - goal[i]).abs()).fold(0.0, f64::max);
    Ok(ChainTorqueCertificate {
        final_error,
        reached: y.iter().take(n1).copied().collect(),
        max_abs_momentum: max_momentum,
        tolerance,
        certified: final_error.is_finite() && final_error <= tolerance,
        stats,
    })
}
