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
//! partial derivatives `dM/dtheta_k` are exact: [`Arm::inertia_matrix`] evaluated on dual numbers
//! (num-dual), one joint at a time (`dM/dphi = 0`). `f64` at the boundary, `DVector`/`DMatrix`
//! since `n` is known at run time only.

use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;

use crate::model::arm::Arm;

/// The inertia matrix is not positive definite at `theta`: impossible for a validated [`Arm`]
/// at finite angles, so it means non-finite input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the inertia matrix is not positive definite at theta = {theta:?} rad (non-finite input?)")]
pub struct SingularInertia {
    /// The joint angles \[rad\].
    pub theta: Vec<f64>,
}

/// `M(theta)` [kg m^2] and its partial derivatives `dM/dtheta_k`, `k = 1..n` (exact, dual
/// numbers), at the joint angles `theta` \[rad\] (`n` values).
pub fn inertia_matrix_derivatives(arm: &Arm, theta: &[f64]) -> (DMatrix<f64>, Vec<DMatrix<f64>>) {
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
    let (_, partials) = inertia_matrix_derivatives(arm, theta);
    coriolis_from(&partials, dq)
}

/// [`coriolis`] from the partial derivatives of `M`.
fn coriolis_from(partials: &[DMatrix<f64>], dq: &DVector<f64>) -> DVector<f64> {
    let n = partials.len();
    assert_eq!(dq.len(), n + 1, "dq has n + 1 = {} values", n + 1);
    let mut m_dot = DMatrix::zeros(n + 1, n + 1);
    for (k, dm) in partials.iter().enumerate() {
        m_dot += dm * dq[k + 1];
    }
    let mut c = m_dot * dq;
    for (k, dm) in partials.iter().enumerate() {
        c[k + 1] -= 0.5 * dq.dot(&(dm * dq));
    }
    c
}

/// The left-hand side of the Euler–Lagrange equations, `M q'' + c` [N m]: the generalised forces
/// `(Q_phi, tau_1, .., tau_n)` that produce the acceleration `ddq` [rad/s^2] at the joint angles
/// `theta` \[rad\] and velocity `dq` [rad/s] (`n + 1` values each). Rows `1..n` are Eq. (6); row
/// 0 is the rate of the angular momentum (5), zero for the free-floating base.
pub fn generalized_forces(arm: &Arm, theta: &[f64], dq: &DVector<f64>, ddq: &DVector<f64>) -> DVector<f64> {
    let (m, partials) = inertia_matrix_derivatives(arm, theta);
    &m * ddq + coriolis_from(&partials, dq)
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
/// the momentum (5), `F phi'' + G . theta'' + (M' q')_0 = 0`; then `(Q_phi, tau) = M q'' + c`
/// (Eq. 6).
pub fn inverse_dynamics(arm: &Arm, theta: &[f64], dtheta: &[f64], ddtheta: &[f64]) -> InverseDynamics {
    let n = arm.joints();
    assert!(dtheta.len() == n && ddtheta.len() == n, "dtheta and ddtheta have n = {n} values");
    let (m, partials) = inertia_matrix_derivatives(arm, theta);
    let phi_rate = -(1..=n).map(|j| m[(0, j)] * dtheta[j - 1]).sum::<f64>() / m[(0, 0)];
    let dq = DVector::from_iterator(n + 1, std::iter::once(phi_rate).chain(dtheta.iter().copied()));
    let mut m_dot_row = 0.0;
    for (k, dm) in partials.iter().enumerate() {
        m_dot_row += dtheta[k] * dm.row(0).dot(&dq.transpose());
    }
    let phi_acc = -((1..=n).map(|j| m[(0, j)] * ddtheta[j - 1]).sum::<f64>() + m_dot_row) / m[(0, 0)];
    let ddq = DVector::from_iterator(n + 1, std::iter::once(phi_acc).chain(ddtheta.iter().copied()));
    let forces = &m * &ddq + coriolis_from(&partials, &dq);
    InverseDynamics { tau: forces.rows(1, n).into_owned(), base_residual: forces[0], dq, ddq }
}

/// Forward dynamics of the free-floating arm: the acceleration `q'' = M^-1 ((0, tau) - c)`
/// [rad/s^2] at the joint angles `theta` \[rad\] and velocity `dq` [rad/s] (`n + 1` values) under
/// the joint torques `tau` [N m] (`n` values), the base unactuated. `M` is solved by its Cholesky
/// factor; one that does not exist (non-finite input) is a [`SingularInertia`].
pub fn forward_dynamics(
    arm: &Arm,
    theta: &[f64],
    dq: &DVector<f64>,
    tau: &DVector<f64>,
) -> Result<DVector<f64>, SingularInertia> {
    let n = arm.joints();
    assert_eq!(tau.len(), n, "tau has n = {n} values");
    let (m, partials) = inertia_matrix_derivatives(arm, theta);
    let c = coriolis_from(&partials, dq);
    let mut rhs = -c;
    for j in 0..n {
        rhs[j + 1] += tau[j];
    }
    let singular = || SingularInertia { theta: theta.to_vec() };
    let cholesky = m.cholesky().ok_or_else(singular)?;
    let ddq = cholesky.solve(&rhs);
    if ddq.iter().all(|x| x.is_finite()) { Ok(ddq) } else { Err(singular()) }
}

#[cfg(test)]
mod tests;
