//! The robot's dynamics from the Lagrangian (3) (Sec. 3.1): inertia matrix, Coriolis and
//! centrifugal terms, the Euler–Lagrange equations (6), inverse and forward dynamics at one point
//! of a motion. (The torques along a plan and their certificate are in [`crate::plan`].)
//!
//! The centre of mass `(x, y)` moves uniformly and decouples (Eq. 4), so the dynamics live on
//! `q = (phi, theta1, theta2)`: with `L = (1/2) q'^T M(q) q'` the equations of motion are
//!
//! $$ M(q)\,\ddot q + c(q, \dot q) = (0, \tau_1, \tau_2)^\top, \qquad
//!    c = \dot M \dot q - \tfrac12 \big(\dot q^\top \partial_{q_i} M\, \dot q\big)_i , $$
//!
//! whose first row is `d/dt (F phi' + G theta1' + H theta2') = 0`, the conservation of angular
//! momentum (5) (the base is not actuated), and whose last two rows are Eq. (6).
//!
//! These closed forms are the paper's formulas, kept as the reference the arm's dynamics
//! ([`arm`], which computes the torque level of every plan) is tested against at `n = 2`
//! (`dynamics/arm/tests.rs`, to 1e-12), and for the closed loop of `track` until it runs on
//! [`arm`] too ([`inertia_matrix`], [`coriolis`], [`joint_torques`], [`forward_dynamics`]).

pub mod arm;

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use crate::Scalar;
use crate::model::system::{MotionPoint, shape, velocity_acceleration};
use crate::model::{Configuration, Lumped};

/// The Lagrangian (3) without the decoupled term `(1/2) m_c (x'^2 + y'^2)` of the centre of mass
/// (Eq. 4): kinetic energy of the base and the arm \[J\] at `q = (phi, theta1, theta2)` \[rad\] with
/// velocity `dq` [rad/s].
///
/// Implements Eq. (3) term by term, generic over [`Scalar`] so that its derivatives can be taken
/// by automatic differentiation (the hand-derived [`inertia_matrix`] and [`coriolis`] are tested
/// against it).
#[allow(non_snake_case)]
pub fn lagrangian<D: Scalar>(k: &Lumped, q: [D; 3], dq: [D; 3]) -> D {
    let Lumped { A, B, C, D: Dk, E, IP, a, b, .. } = *k;
    let (s1, c1) = q[1].sin_cos();
    let c2 = q[2].cos();
    let (s12, c12) = (q[1] + q[2]).sin_cos();
    let w = dq[0];
    let w1 = dq[0] + dq[1];
    let w12 = dq[0] + dq[1] + dq[2];
    w * w * (0.5 * IP)
        + w1 * w1 * (0.5 * A)
        + w12 * w12 * (0.5 * B)
        + w1 * w12 * c2 * C
        + w * w1 * (c1 * a + s1 * b) * Dk
        + w * w12 * (c12 * a + s12 * b) * E
}

/// The inertia matrix `M(q)` of `(phi, theta1, theta2)` [kg m^2], `L = (1/2) q'^T M q'` (Eq. 3):
///
/// ```text
/// M = | F   G                H          |
///     | G   A + B + 2 C c2   B + C c2   |
///     | H   B + C c2         B          |
/// ```
///
/// with `F, G, H` of Eq. (8), so that the first row of `M q'` is the angular momentum of Eq. (5).
/// Symmetric positive definite for every configuration (it is a kinetic energy). Independent of
/// `phi`.
#[allow(non_snake_case)]
pub fn inertia_matrix(k: &Lumped, theta1: f64, theta2: f64) -> Matrix3<f64> {
    let s = shape(k, theta1, theta2);
    let c2 = theta2.cos();
    let m11 = k.A + k.B + 2.0 * k.C * c2;
    let m12 = k.B + k.C * c2;
    Matrix3::new(s.F, s.G, s.H, s.G, m11, m12, s.H, m12, k.B)
}

/// The partial derivatives `(dM/dtheta1, dM/dtheta2)` of the [`inertia_matrix`] (`dM/dphi = 0`),
/// derived by hand from Eq. (3). With `m_1 = -a s1 + b c1`, `m_12 = -a s12 + b c12`,
/// `alpha = D m_1 + E m_12` and `P = -C s2 + E m_12` (Eq. 13, `P = (1/2) dF/dtheta2`):
///
/// ```text
/// dM/dtheta1 = | 2 alpha  alpha  E m_12 |    dM/dtheta2 = | 2 P         P - C s2   P      |
///              | alpha    0      0      |                 | P - C s2    -2 C s2    -C s2  |
///              | E m_12   0      0      |                 | P           -C s2      0      |
/// ```
#[allow(non_snake_case)]
pub fn inertia_matrix_derivatives(k: &Lumped, theta1: f64, theta2: f64) -> (Matrix3<f64>, Matrix3<f64>) {
    let Lumped { C, D: Dk, E, a, b, .. } = *k;
    let (s1, c1) = theta1.sin_cos();
    let s2 = theta2.sin();
    let (s12, c12) = (theta1 + theta2).sin_cos();
    let m1 = -a * s1 + b * c1;
    let m12 = -a * s12 + b * c12;
    let alpha = Dk * m1 + E * m12;
    let em = E * m12;
    let P = -C * s2 + em;
    let cs = C * s2;
    let d1 = Matrix3::new(2.0 * alpha, alpha, em, alpha, 0.0, 0.0, em, 0.0, 0.0);
    let d2 = Matrix3::new(2.0 * P, P - cs, P, P - cs, -2.0 * cs, -cs, P, -cs, 0.0);
    (d1, d2)
}

/// Coriolis and centrifugal terms `c(q, q') = M' q' - (1/2) (q'^T dM/dq_i q')_i` of the
/// Euler–Lagrange equations of Eq. (3) [N m], as `[phi, theta1, theta2]` components.
pub fn coriolis(k: &Lumped, q: &Configuration, dq: [f64; 3]) -> [f64; 3] {
    let (d1, d2) = inertia_matrix_derivatives(k, q.theta1, q.theta2);
    let w = Vector3::from(dq);
    let m_dot = d1 * dq[1] + d2 * dq[2];
    let c = m_dot * w - Vector3::new(0.0, 0.5 * w.dot(&(d1 * w)), 0.5 * w.dot(&(d2 * w)));
    [c[0], c[1], c[2]]
}

/// The left-hand side of the Euler–Lagrange equations, `d/dt dL/dq' - dL/dq = M q'' + c`
/// [N m]: the generalised forces `(Q_phi, tau1, tau2)` that produce the acceleration `ddq` at
/// `(q, dq)`. Rows 2-3 are Eq. (6); row 1 is `d/dt` of the angular momentum (5), zero for a
/// free-floating (unactuated) base.
pub fn generalized_forces(k: &Lumped, q: &Configuration, dq: [f64; 3], ddq: [f64; 3]) -> [f64; 3] {
    let m = inertia_matrix(k, q.theta1, q.theta2);
    let c = coriolis(k, q, dq);
    let f = m * Vector3::from(ddq) + Vector3::from(c);
    [f[0], f[1], f[2]]
}

/// Forward dynamics: the acceleration `q'' = M^-1 (Q - c)` [rad/s^2] under generalised forces
/// `Q = (Q_phi, tau1, tau2)` [N m] (for the free-floating robot `Q_phi = 0`). `M` is solved by
/// its Cholesky factor; non-finite input gives non-finite output (never a panic).
pub fn forward_dynamics(k: &Lumped, q: &Configuration, dq: [f64; 3], forces: [f64; 3]) -> [f64; 3] {
    let m = inertia_matrix(k, q.theta1, q.theta2);
    let c = coriolis(k, q, dq);
    let r = [forces[0] - c[0], forces[1] - c[1], forces[2] - c[2]];
    solve_spd(&m, r)
}

/// Solves `M x = r` for a symmetric positive definite 3x3 `M` by Cholesky, `M = L L^T`.
fn solve_spd(m: &Matrix3<f64>, r: [f64; 3]) -> [f64; 3] {
    let l00 = m[(0, 0)].sqrt();
    let l10 = m[(1, 0)] / l00;
    let l20 = m[(2, 0)] / l00;
    let l11 = (m[(1, 1)] - l10 * l10).sqrt();
    let l21 = (m[(2, 1)] - l20 * l10) / l11;
    let l22 = (m[(2, 2)] - l20 * l20 - l21 * l21).sqrt();
    let y0 = r[0] / l00;
    let y1 = (r[1] - l10 * y0) / l11;
    let y2 = (r[2] - l20 * y0 - l21 * y1) / l22;
    let x2 = y2 / l22;
    let x1 = (y1 - l21 * x2) / l11;
    let x0 = (y0 - l10 * x1 - l20 * x2) / l00;
    [x0, x1, x2]
}

/// The result of the inverse dynamics at one point of a motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InverseDynamics {
    /// Joint torques `(tau1, tau2)` of Eq. (6) [N m].
    pub tau: [f64; 2],
    /// The base row of the Euler–Lagrange equations, `d/dt` of the angular momentum (5)
    /// [N m]: zero up to rounding along a motion of system (7), whose base is unactuated.
    pub base_residual: f64,
}

/// Inverse dynamics at one point of a motion of system (7): `q' = g(q) u` and
/// `q'' = (dg/dq q') u + g(q) u'` exactly (dual numbers, [`velocity_acceleration`]), then
/// `(Q_phi, tau1, tau2) = M q'' + c` (Eqs. 3, 6).
pub fn inverse_dynamics(k: &Lumped, point: &MotionPoint) -> InverseDynamics {
    let (dq, ddq) = velocity_acceleration(k, &point.q, point.u, point.du);
    let f = generalized_forces(k, &point.q, dq, ddq);
    InverseDynamics { tau: [f[1], f[2]], base_residual: f[0] }
}

/// Joint torques `(tau1, tau2)` [N m] of Eq. (6) at one point of a motion of system (7): the
/// same numbers as [`inverse_dynamics`], in one pass.
///
/// From one evaluation of the trigonometric functions: `F, G, H` (Eq. 8) and their partial
/// derivatives (the first rows of [`inertia_matrix_derivatives`]), `phi' = -(G u1 + H u2)/F`
/// (Eq. 7), `phi''` its exact time derivative, then the rows 2-3 of
/// `M q'' + M' q' - (1/2)(q'^T dM/dq_i q')_i` with `M` of [`inertia_matrix`]:
/// `q'^T (dM/dtheta1) q' = F_1 phi'^2 + 2 G_1 phi' u1 + 2 H_1 phi' u2` and
/// `q'^T (dM/dtheta2) q' = F_2 phi'^2 + 2 G_2 phi' u1 + 2 H_2 phi' u2 - 2 C s2 u1^2 - 2 C s2 u1 u2`.
#[allow(non_snake_case)]
pub fn joint_torques(k: &Lumped, point: &MotionPoint) -> [f64; 2] {
    let Lumped { A, B, C, D: Dk, E, IP, a, b, .. } = *k;
    let q = &point.q;
    let [u1, u2] = point.u;
    let [du1, du2] = point.du;
    let (s1, c1) = q.theta1.sin_cos();
    let (s2, c2) = q.theta2.sin_cos();
    let (s12, c12) = (s1 * c2 + c1 * s2, c1 * c2 - s1 * s2);
    let (k1, k12) = (a * c1 + b * s1, a * c12 + b * s12);
    let (m1, m12) = (b * c1 - a * s1, b * c12 - a * s12);
    let m11 = A + B + 2.0 * C * c2;
    let m12c = B + C * c2;
    let F = m11 + IP + 2.0 * Dk * k1 + 2.0 * E * k12;
    let G = m11 + Dk * k1 + E * k12;
    let H = m12c + E * k12;
    // Partial derivatives (inertia_matrix_derivatives): alpha = D m1 + E m12, P = -C s2 + E m12.
    let alpha = Dk * m1 + E * m12;
    let P = -C * s2 + E * m12;
    let (F1, G1, H1) = (2.0 * alpha, alpha, E * m12);
    let (F2, G2, H2) = (2.0 * P, P - C * s2, P);
    // Time derivatives along the motion: X' = X_1 u1 + X_2 u2.
    let dF = F1 * u1 + F2 * u2;
    let dG = G1 * u1 + G2 * u2;
    let dH = H1 * u1 + H2 * u2;
    let w = -(G * u1 + H * u2) / F;
    let dw = -(dG * u1 + G * du1 + dH * u2 + H * du2 + dF * w) / F;
    let dm11 = -2.0 * C * s2 * u2;
    let dm12 = -C * s2 * u2;
    let tau1 = G * dw + m11 * du1 + m12c * du2 + dG * w + dm11 * u1 + dm12 * u2
        - 0.5 * (F1 * w * w + 2.0 * w * (G1 * u1 + H1 * u2));
    let tau2 = H * dw + m12c * du1 + B * du2 + dH * w + dm12 * u1
        - 0.5 * (F2 * w * w + 2.0 * w * (G2 * u1 + H2 * u2) - 2.0 * C * s2 * u1 * (u1 + u2));
    [tau1, tau2]
}

#[cfg(test)]
mod tests;
