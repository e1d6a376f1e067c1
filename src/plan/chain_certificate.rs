//! The velocity-level certificate of an `n`-joint plan (docs/spec.md, Sec. 2, for any planar
//! serial arm): the original system, `phi' = -(G . u)/F`, `theta' = u` (Eq. 7 with the arm's
//! momentum coefficients, [`Arm::momentum_coefficients`]), integrated from the start with the
//! planned controls `u(t)` over each knot span, compared with the goal.

use nalgebra::SVector;
use serde::Serialize;

use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::wrap_angle;
use crate::numerics::ode::{OdeOptions, OdeStats, integrate};

/// A planned joint motion of an `n`-joint arm, exact at any time.
pub trait JointMotion {
    /// The number `n` of joints.
    fn joints(&self) -> usize;
    /// Times \[s\] where the controls may lose smoothness, `0` first and `T` last.
    fn breakpoints(&self) -> &[f64];
    /// The joint angles \[rad\] and velocities `u = theta'` \[rad/s\] at `t` into the buffers.
    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]);
    /// The plan's own base rate `phi'(t)` \[rad/s\] (for the momentum check).
    fn phi_rate(&self, t: f64) -> f64;
    /// The joint accelerations \[rad/s^2\] at `t` into `out` (for the torques).
    fn joint_acceleration(&self, t: f64, out: &mut [f64]);
}

/// The certificate of an `n`-joint plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainVerification {
    /// `max_i |wrap(q_i(T) - qd_i)|` over `q = (phi, theta_1..n)` \[rad\].
    pub final_error: f64,
    /// `q(T)` reached by the integration \[rad\].
    pub reached: Vec<f64>,
    /// Largest `|F phi'_plan + G . u|` over the integrator's accepted steps, with the model's
    /// `F, G` at the integrated joint angles and the plan's base rate \[kg m^2/s\].
    pub max_abs_momentum: f64,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance` (and finite).
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
}

impl ChainVerification {
    /// The certificate of a motion not yet verified: not certified, errors unknown (NaN), to be
    /// replaced by [`verify_chain`]'s before the plan is returned.
    pub fn pending() -> Self {
        Self {
            final_error: f64::NAN,
            reached: Vec::new(),
            max_abs_momentum: f64::NAN,
            tolerance: f64::NAN,
            certified: false,
            stats: OdeStats::default(),
        }
    }
}

/// Checks that `motion`, `start` and `goal` (`n + 1` values each) have the joint count of `arm`.
pub fn check_lengths(arm: &Arm, motion: &dyn JointMotion, start: &[f64], goal: &[f64]) -> Result<(), Error> {
    let n = arm.joints();
    if motion.joints() != n || start.len() != n + 1 || goal.len() != n + 1 {
        return Err(Error::from(InputError::InvalidParameter {
            name: "joints".into(),
            value: motion.joints() as f64,
            expected: "a motion, start and goal of the arm's joint count",
        }));
    }
    Ok(())
}

/// Largest number of joints [`verify_chain`] takes.
pub const MAX_CERTIFIED_JOINTS: usize = 15;

/// Integrates the original system with the controls of `motion` from `start` (`n + 1` values,
/// `(phi, theta)`) and compares with `goal` (angles modulo 2 pi), to `tolerance` \[rad\].
pub fn verify_chain(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainVerification, Error> {
    verify_chain_observed(arm, motion, start, goal, ode, tolerance, &mut |_, _| {})
}

/// [`verify_chain`], calling `at_breakpoint(t, q)` with the integrated `q = (phi, theta)` at
/// every breakpoint of `motion` (`t = 0` first, `T` last): the base's attitude along the motion
/// with the certificate's accuracy (`freefloat check`).
pub fn verify_chain_observed(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
    at_breakpoint: &mut dyn FnMut(f64, &[f64]),
) -> Result<ChainVerification, Error> {
    let n = arm.joints();
    check_lengths(arm, motion, start, goal)?;
    macro_rules! dispatch {
        ($($n:literal => $m:literal),*) => {
            match n {
                $($n => run::<$m>(arm, motion, start, goal, ode, tolerance, at_breakpoint),)*
                _ => Err(Error::from(InputError::InvalidParameter {
                    name: "joints".into(),
                    value: n as f64,
                    expected: "1 to 15 joints",
                })),
            }
        };
    }
    dispatch!(1 => 2, 2 => 3, 3 => 4, 4 => 5, 5 => 6, 6 => 7, 7 => 8, 8 => 9, 9 => 10, 10 => 11,
        11 => 12, 12 => 13, 13 => 14, 14 => 15, 15 => 16)
}

/// [`verify_chain`] with the state `(phi, theta)` of static size `M = n + 1`.
fn run<const M: usize>(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
    at_breakpoint: &mut dyn FnMut(f64, &[f64]),
) -> Result<ChainVerification, Error> {
    let n = M - 1;
    let (mut theta, mut rate) = ([0.0; M], [0.0; M]);
    let mut u_at = move |t: f64| {
        motion.joint_state(t, &mut theta[..n], &mut rate[..n]);
        rate
    };
    let mut rhs = |t: f64, y: &SVector<f64, M>| -> Result<SVector<f64, M>, Error> {
        let u = u_at(t);
        let (f, g) = arm.momentum_coefficients(&y.as_slice()[1..]);
        let mut dy = SVector::<f64, M>::zeros();
        let mut s = 0.0;
        for j in 0..n {
            s += g[j] * u[j];
            dy[j + 1] = u[j];
        }
        dy[0] = -s / f;
        Ok(dy)
    };
    let mut y = SVector::<f64, M>::from_column_slice(start);
    let mut stats = OdeStats::default();
    let mut max_momentum: f64 = 0.0;
    let b = motion.breakpoints();
    let mut buffers = ([0.0; M], [0.0; M]);
    // The plan's momentum at every accepted step, with the model's F, G at the integrated angles.
    let mut observe = |t: f64, state: &SVector<f64, M>| {
        let (f, g) = arm.momentum_coefficients(&state.as_slice()[1..]);
        motion.joint_state(t, &mut buffers.0[..n], &mut buffers.1[..n]);
        let p: f64 = f * motion.phi_rate(t) + g.iter().zip(&buffers.1[..n]).map(|(g, u)| g * u).sum::<f64>();
        max_momentum = max_momentum.max(p.abs());
    };
    if let Some(&t0) = b.first() {
        at_breakpoint(t0, y.as_slice());
    }
    for w in b.windows(2) {
        let (y1, s) = integrate(&mut rhs, w[0], y, w[1], ode, &mut observe)?;
        y = y1;
        at_breakpoint(w[1], y.as_slice());
        stats.accepted += s.accepted;
        stats.rejected += s.rejected;
        stats.evaluations += s.evaluations;
    }
    let final_error = (0..M).map(|i| wrap_angle(y[i] - goal[i]).abs()).fold(0.0, f64::max);
    Ok(ChainVerification {
        final_error,
        reached: y.iter().copied().collect(),
        max_abs_momentum: max_momentum,
        tolerance,
        certified: final_error.is_finite() && final_error <= tolerance,
        stats,
    })
}
