//! Dynamics of any planar serial arm ([`Arm`]): the Lagrangian (3), the momentum (5) and the
//! Euler–Lagrange equations (6) for `n` links, with `q = (phi, theta_1, ..., theta_n)`.
//!
//! With `L = (1/2) q'^T M(theta) q'` ([`Arm::inertia_matrix`], the centre of mass at rest at the
//! origin as in Eq. 4) the equations of motion are
//!
//! $$ M(\theta)\,\ddot q + c(\theta, \dot q) = (0, \tau_1, \dots, \tau_n)^\top, \qquad
//!    c = \dot M \dot q - \tfrac12 \big(\dot q^\top \partial_{q_i} M\, \dot q\big)_i , $$
//!
//! (the Christoffel form of the Coriolis and centrifugal terms); their first row is the
//! conservation of the angular momentum (5), the base being unactuated, the others Eq. (6). The
//! inertia matrix, its partial derivatives `dM/dtheta_k` and `c` come in closed form from the
//! arm's lumped constants ([`ArmLumped`], the `n`-link analogue of the paper's `A..E`), exact and
//! without dual numbers; [`inertia_matrix_derivatives_ad`] keeps the dual-number derivatives of
//! [`Arm::inertia_matrix`] as their reference. [`ArmDynamics`] holds the constants for the hot
//! loops (the torque certificate, the plant, the controllers) and works on slices without
//! allocating; the free functions build them per call and return `DVector`/`DMatrix`.

use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;

use crate::model::arm::Arm;
use crate::model::arm::lumped::{ArmLumped, SIZE};

mod fast;

pub use fast::{ArmDynamics, InverseAt, ModelTerms};

/// The inertia matrix is not positive definite at `theta`: impossible for a validated [`Arm`]
/// at finite angles, so it means non-finite input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the inertia matrix is not positive definite at theta = {theta:?} rad (non-finite input?)")]
pub struct SingularInertia {
    /// The joint angles \[rad\].
    pub theta: Vec<f64>,
}

/// `M(theta)` [kg m^2] and its partial derivatives `dM/dtheta_k`, `k = 1..n` (closed form, from
/// the lumped constants [`ArmLumped`]), at the joint angles `theta` \[rad\] (`n` values).
pub fn inertia_matrix_derivatives(arm: &Arm, theta: &[f64]) -> (DMatrix<f64>, Vec<DMatrix<f64>>) {
    let n = arm.joints();
    assert_eq!(theta.len(), n, "theta has n = {n} values");
    let terms = ArmLumped::new(arm).terms(theta);
    let mut square = [[0.0; SIZE]; SIZE];
    terms.inertia_matrix(&mut square);
    let m = DMatrix::from_fn(n + 1, n + 1, |i, j| square[i][j]);
    let partials = (1..=n)
        .map(|k| {
            terms.inertia_derivative(k, &mut square);
            DMatrix::from_fn(n + 1, n + 1, |i, j| square[i][j])
        })
        .collect();
    (m, partials)
}

/// [`inertia_matrix_derivatives`] by dual numbers (num-dual) through [`Arm::inertia_matrix`],
/// one joint at a time: the reference the closed forms are tested against.
pub fn inertia_matrix_derivatives_ad(arm: &Arm, theta: &[f64]) -> (DMatrix<f64>, Vec<DMatrix<f64>>) {
    let n = arm.joints();
    assert_eq!(theta.len(), n, "theta has n = {n} values");
    let mut m = DMatrix::zeros(n + 1, n + 1);
    let mut partials = Vec::with_capacity(n);
    for k in 0..n {
        let seeded: Vec<Dual64> =
            theta.iter().enumerate().map(|(j, &t)| Dual64::new(t, if j == k { 1.0 } else { 0.0 })).collect();
        let md = arm.inertia_matrix(&seeded);
        if k == 0 {
            m = md.map(|x| x.re);
        }
        partials.push(md.map(|x| x.eps));
    }
    (m, partials)
}

/// The Coriolis and centrifugal terms `c = M' q' - (1/2) (q'^T dM/dq_i q')_i` [N m] at the joint
/// angles `theta` \[rad\] (`n` values) and velocity `dq = (phi', theta')` [rad/s] (`n + 1`).
pub fn coriolis(arm: &Arm, theta: &[f64], dq: &DVector<f64>) -> DVector<f64> {
    let n = arm.joints();
    assert_eq!(dq.len(), n + 1, "dq has n + 1 = {} values", n + 1);
    let mut c = DVector::zeros(n + 1);
    ArmLumped::new(arm).terms(theta).coriolis(dq.as_slice(), c.as_mut_slice());
    c
}

/// The left-hand side of the Euler–Lagrange equations, `M q'' + c` [N m]: the generalised forces
/// `(Q_phi, tau_1, .., tau_n)` that produce the acceleration `ddq` [rad/s^2] at the joint angles
/// `theta` \[rad\] and velocity `dq` [rad/s] (`n + 1` values each). Rows `1..n` are Eq. (6); row
/// 0 is the rate of the angular momentum (5), zero for the free-floating base.
pub fn generalized_forces(arm: &Arm, theta: &[f64], dq: &DVector<f64>, ddq: &DVector<f64>) -> DVector<f64> {
    let (m, _) = inertia_matrix_derivatives(arm, theta);
    &m * ddq + coriolis(arm, theta, dq)
}

/// The kinetic energy `T = (1/2) q'^T M q'` \[J\] (the Lagrangian (3) without the centre of
/// mass' term, Eq. 4) at the joint angles `theta` \[rad\] and velocity `dq` [rad/s].
pub fn kinetic_energy(arm: &Arm, theta: &[f64], dq: &DVector<f64>) -> f64 {
    0.5 * dq.dot(&(arm.inertia_matrix(theta) * dq))
}

/// The angular momentum about the system's centre of mass, the first row of `M q'`
/// [kg m^2/s] (Eq. 5), at the joint angles `theta` \[rad\] and velocity `dq` [rad/s].
pub fn angular_momentum(arm: &Arm, theta: &[f64], dq: &DVector<f64>) -> f64 {
    let (f, g) = arm.momentum_coefficients(theta);
    f * dq[0] + g.iter().zip(dq.iter().skip(1)).map(|(g, w)| g * w).sum::<f64>()
}

/// The result of the inverse dynamics at one point of a joint motion at zero angular momentum.
#[derive(Debug, Clone, PartialEq)]
pub struct InverseDynamics {
    /// Joint torques `(tau_1, .., tau_n)` of Eq. (6) [N m].
    pub tau: DVector<f64>,
    /// The base row of the Euler–Lagrange equations, the rate of the angular momentum (5)
    /// [N m]: zero up to rounding (the base is unactuated).
    pub base_residual: f64,
    /// The full velocity `(phi', theta')` [rad/s], `phi'` from Eq. (7).
    pub dq: DVector<f64>,
    /// The full acceleration `(phi'', theta'')` [rad/s^2], `phi''` keeping the momentum zero.
    pub ddq: DVector<f64>,
}

/// Inverse dynamics of the free-floating arm at zero angular momentum: given the joint angles
/// `theta` \[rad\], velocities `dtheta` [rad/s] and accelerations `ddtheta` [rad/s^2] (`n`
/// values each), the base follows from Eq. (7), `phi' = -(G . theta') / F`, and from the rate of
/// the momentum (5), `F phi'' + G . theta'' + c_0 = 0` (`c_0 = (M' q')_0` since `M` does not
/// depend on `phi`); then `(Q_phi, tau) = M q'' + c` (Eq. 6). [`ArmDynamics::inverse`] without
/// building the arm's constants at every call.
pub fn inverse_dynamics(arm: &Arm, theta: &[f64], dtheta: &[f64], ddtheta: &[f64]) -> InverseDynamics {
    ArmDynamics::new(arm).inverse(theta, dtheta, ddtheta)
}

/// Forward dynamics of the free-floating arm: the acceleration `q'' = M^-1 ((0, tau) - c)`
/// [rad/s^2] at the joint angles `theta` \[rad\] and velocity `dq` [rad/s] (`n + 1` values) under
/// the joint torques `tau` [N m] (`n` values), the base unactuated. `M` is solved by its Cholesky
/// factor; one that does not exist (non-finite input) is a [`SingularInertia`].
/// [`ArmDynamics::forward`] without building the arm's constants at every call.
pub fn forward_dynamics(
    arm: &Arm,
    theta: &[f64],
    dq: &DVector<f64>,
    tau: &DVector<f64>,
) -> Result<DVector<f64>, SingularInertia> {
    let n = arm.joints();
    assert_eq!(tau.len(), n, "tau has n = {n} values");
    assert_eq!(dq.len(), n + 1, "dq has n + 1 = {} values", n + 1);
    let mut ddq = DVector::zeros(n + 1);
    ArmDynamics::new(arm).forward(theta, dq.as_slice(), tau.as_slice(), ddq.as_mut_slice())?;
    Ok(ddq)
}

#[cfg(test)]
mod tests;
