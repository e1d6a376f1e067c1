//! The driftless control system (7) of the free-floating robot at zero angular momentum, and the
//! functions `F, G, H` (Eq. 8), `sigma` (Eq. 9), `P` (Eq. 13), `U, Z, f, d` (Eq. 15) built on it.
//!
//! Everything is generic over [`Scalar`], so exact derivatives come from dual numbers.

use crate::Scalar;
use crate::model::{Configuration, Lumped};

/// The configuration-dependent functions of Secs. 3-4 at one `(theta1, theta2)`; none depends
/// on `phi`. Field names copy the paper's symbols.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy)]
pub struct Shape<D> {
    /// `F` of Eq. (8): the base's effective moment of inertia, `F > 0` [kg m^2].
    pub F: D,
    /// `G` of Eq. (8) [kg m^2].
    pub G: D,
    /// `H` of Eq. (8) [kg m^2].
    pub H: D,
    /// `sigma` of Eq. (9): the controllability condition [kg^2 m^3... lumped units].
    pub sigma: D,
    /// `P` of Eq. (13): `P = (1/2) dF/dtheta2`.
    pub P: D,
    /// `U = I_P + A + B + 2 D (a c1 + b s1)` of Eq. (15).
    pub U: D,
    /// `Z = U - 2 B` of Eq. (15).
    pub Z: D,
    /// `f = sqrt(C^2 + 2 C E (a c1 + b s1) + E^2 (a^2 + b^2))` of Eq. (15).
    pub f: D,
    /// `d = U^2 - 4 f^2` of Eq. (15).
    pub d: D,
}

/// Evaluates Eqs. (8), (9), (13) and (15) at `(theta1, theta2)` \[rad\].
pub fn shape<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> Shape<D> {
    let (s1, c1) = theta1.sin_cos();
    let (s2, c2) = theta2.sin_cos();
    // theta12 = theta1 + theta2 by the addition formulas: one sin_cos fewer.
    let s12 = (s1 * c2 + c1 * s2, c1 * c2 - s1 * s2);
    shape_from_trig(k, (s1, c1), (s2, c2), s12)
}

/// [`shape`] from the sines and cosines `(sin, cos)` of `theta1`, `theta2` and
/// `theta1 + theta2`, for callers that tabulate them (the domain maps of [`crate::analysis::domain`]).
#[allow(non_snake_case)]
pub fn shape_from_trig<D: Scalar>(k: &Lumped, (s1, c1): (D, D), (s2, c2): (D, D), (s12, c12): (D, D)) -> Shape<D> {
    let Lumped { A, B, C, D: Dk, E, IP, a, b, .. } = *k;
    // a c1 + b s1, a c12 + b s12 and their theta-derivatives -a s + b c.
    let k1 = c1 * a + s1 * b;
    let k12 = c12 * a + s12 * b;
    let m1 = c1 * b - s1 * a;
    let m12 = c12 * b - s12 * a;
    let F = c2 * (2.0 * C) + k1 * (2.0 * Dk) + k12 * (2.0 * E) + (IP + A + B);
    let G = c2 * (2.0 * C) + k1 * Dk + k12 * E + (A + B);
    let H = c2 * C + k12 * E + B;
    let sigma = m1 * (B * Dk - C * E) + m12 * (C * Dk - A * E) + s2 * (Dk * E * (a * a + b * b) - C * IP);
    let P = s2 * (-C) + m12 * E;
    let U = k1 * (2.0 * Dk) + (IP + A + B);
    let Z = U - 2.0 * B;
    let f = (k1 * (2.0 * C * E) + (C * C + E * E * (a * a + b * b))).sqrt();
    let d = U * U - f * f * 4.0;
    Shape { F, G, H, sigma, P, U, Z, f, d }
}

/// The control vector fields of Eq. (7): `g1 = (-G/F, 1, 0)`, `g2 = (-H/F, 0, 1)`.
/// Returns `(g1, g2)` as `[phi, theta1, theta2]` components.
pub fn vector_fields<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> ([D; 3], [D; 3]) {
    let s = shape(k, theta1, theta2);
    let one = D::one();
    let zero = D::zero();
    ([-s.G / s.F, one, zero], [-s.H / s.F, zero, one])
}

/// The velocity `q' = g1(q) u1 + g2(q) u2` of the driftless system (7) \[rad/s\], with the joint
/// velocities `u = (theta1', theta2')` as controls.
pub fn velocity<D: Scalar>(k: &Lumped, q: [D; 3], u: [D; 2]) -> [D; 3] {
    let (g1, g2) = vector_fields(k, q[1], q[2]);
    [g1[0] * u[0] + g2[0] * u[1], u[0], u[1]]
}

/// Velocity and acceleration `(q', q'')` along system (7) at `q` with controls `u` and their
/// time derivatives `du`: `q' = g(q) u`, `q'' = (dg/dq q') u + g(q) du`, exact (dual numbers).
pub fn velocity_acceleration(k: &Lumped, q: &Configuration, u: [f64; 2], du: [f64; 2]) -> ([f64; 3], [f64; 3]) {
    use num_dual::Dual64;
    let qa = q.to_array();
    let dq = velocity(k, qa, u);
    let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(qa[i], dq[i]));
    let ud = [Dual64::new(u[0], du[0]), Dual64::new(u[1], du[1])];
    let v = velocity(k, qd, ud);
    (dq, [v[0].eps, v[1].eps, v[2].eps])
}

/// Angular momentum `F phi' + G theta1' + H theta2'` of Eq. (5) [kg m^2/s] at `q` with velocity
/// `dq`.
pub fn momentum(k: &Lumped, q: &Configuration, dq: [f64; 3]) -> f64 {
    let s = shape(k, q.theta1, q.theta2);
    s.F * dq[0] + s.G * dq[1] + s.H * dq[2]
}

/// A point of a motion of system (7): the configuration, the controls `u` (joint velocities)
/// and their rates; what the inverse dynamics needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPoint {
    /// Planned configuration \[rad\].
    pub q: Configuration,
    /// Joint velocities `(theta1', theta2')` \[rad/s\]: the controls of system (7).
    pub u: [f64; 2],
    /// Their time derivatives \[rad/s^2\].
    pub du: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Mount, RobotParams};
    use num_dual::{Dual64, first_derivative};
    use proptest::prelude::*;

    fn lumped(a: f64, b: f64) -> Lumped {
        RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap().lumped()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        /// `F` is the base's effective inertia, hence positive everywhere (docs/spec.md §6, item 4),
        /// `P = (1/2) dF/dtheta2`, Eq. (21) `P^2 + (F - U)^2 / 4 = f^2`, and `d > 0`.
        #[test]
        fn shape_identities(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -7.0..7.0f64, t2 in -7.0..7.0f64) {
            let k = lumped(a, b);
            let s = shape(&k, t1, t2);
            prop_assert!(s.F > 0.0);
            prop_assert!(s.d > 0.0);
            let (_, df_dtheta2) = first_derivative(|x: Dual64| shape(&k, Dual64::from_re(t1), x).F, t2);
            prop_assert!((s.P - df_dtheta2 / 2.0).abs() < 1e-13);
            let lhs = s.P * s.P + (s.F - s.U).powi(2) / 4.0;
            prop_assert!((lhs - s.f * s.f).abs() < 1e-13 * (1.0 + s.f * s.f));
            // Z = F - 2H does not depend on theta2 (Appendix, after Eq. 19).
            prop_assert!((s.F - 2.0 * s.H - s.Z).abs() < 1e-13);
        }

        /// Eq. (25): `d(G/F)/dtheta2 - d(H/F)/dtheta1 = 2 sigma / F^2`, i.e. sigma is F^2/2 times
        /// the phi-component of the Lie bracket `[g1, g2]`; derivatives by AD.
        #[test]
        fn sigma_is_the_lie_bracket(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -7.0..7.0f64, t2 in -7.0..7.0f64) {
            let k = lumped(a, b);
            let s = shape(&k, t1, t2);
            let (_, dgf) = first_derivative(|x: Dual64| { let s = shape(&k, Dual64::from_re(t1), x); s.G / s.F }, t2);
            let (_, dhf) = first_derivative(|x: Dual64| { let s = shape(&k, x, Dual64::from_re(t2)); s.H / s.F }, t1);
            let rhs = 2.0 * s.sigma / (s.F * s.F);
            prop_assert!((dgf - dhf - rhs).abs() < 1e-12 * (1.0 + rhs.abs()), "{} vs {}", dgf - dhf, rhs);
        }
    }
}
