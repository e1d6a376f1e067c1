//! The feedback transformation of Theorem 1, item 2 (any mounting point): Eqs. (13)-(15).
//!
//! `z1 = theta1`, `z3 = h2 = -sign(P) phi + R(theta1, theta2)` with
//! `R = -(1/2) arcsin((F - U)/(2f)) + Z/(2 sqrt d) arcsin((F U - d)/(2 f F))`,
//! `z2 = h3 = sign(P) G/F + dR/dtheta1`, `v1 = u1`,
//! `v2 = (dh3/dtheta1) u1 + sign(P) (2 sigma / F^2) u2`.
//!
//! The derivatives the paper leaves "to the computer" (Sec. 6, item 2) are exact: forward-mode
//! automatic differentiation with nested dual numbers.

use num_dual::{Dual, Dual2, Dual64};

use crate::Scalar;
use crate::model::Lumped;
use crate::model::system::{Shape, shape};

/// `R(theta1, theta2)` of Eq. (14), on the branch `sign(P) = branch`.
///
/// Both arcsines are evaluated as the equal `atan2(sin, cos)`, their cosines taken from Eqs.
/// (21)-(22): `sqrt(1 - ((F-U)/(2f))^2) = |P|/f` and
/// `sqrt(1 - ((FU-d)/(2fF))^2) = sqrt(d) |P| / (f F)` (`d (4 f^2 - (F-U)^2) = ((2fF)^2 - (FU-d)^2)`).
/// With `|P| = branch P` the value equals the printed formula on the branch and keeps full
/// precision near `P = 0`, where the arcsin loses half the digits.
pub fn r_function<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> D {
    r_of_shape(&shape(k, theta1, theta2), branch)
}

/// `R` of Eq. (14) from the functions of Eqs. (8)-(15) at one point (see [`r_function`]).
fn r_of_shape<D: Scalar>(s: &Shape<D>, branch: f64) -> D {
    let abs_p = s.P * branch;
    let root_d = s.d.sqrt();
    let first = (s.F - s.U).atan2(abs_p * 2.0);
    let second = (s.F * s.U - s.d).atan2(root_d * abs_p * 2.0);
    -first * 0.5 + s.Z / (root_d * 2.0) * second
}

/// What Newton's method on `z2 = h3(theta1, theta2)` needs at one point, from a single
/// evaluation of Eqs. (8)-(15) over dual numbers.
#[derive(Debug, Clone, Copy)]
pub struct NewtonPoint {
    /// `h3` of Eq. (14).
    pub h3: f64,
    /// `dh3/dtheta2 = sign(P) 2 sigma / F^2`.
    pub slope: f64,
    /// `P` of Eq. (13).
    pub p: f64,
    /// `sigma` of Eq. (9).
    pub sigma: f64,
}

/// `h3`, `dh3/dtheta2`, `P` and `sigma` at `(theta1, theta2)` on the branch `sign(P) = branch`.
pub fn newton_point(k: &Lumped, branch: f64, theta1: f64, theta2: f64) -> NewtonPoint {
    let s = shape(k, Dual64::new(theta1, 1.0), Dual64::from_re(theta2));
    let (f, g, sigma) = (s.F.re, s.G.re, s.sigma.re);
    NewtonPoint {
        h3: g / f * branch + r_of_shape(&s, branch).eps,
        slope: sigma * (2.0 * branch) / (f * f),
        p: s.P.re,
        sigma,
    }
}

/// `dR/dtheta1`, exact (one level of dual numbers over `D`).
pub fn dr_dtheta1<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> D {
    let t1 = Dual::new(theta1, D::one());
    let t2 = Dual::from_re(theta2);
    r_function(k, branch, t1, t2).eps
}

/// `h3 = sign(P) G/F + dh2/dtheta1` of Eq. (14) (`h2` depends on theta1 through `R` only).
pub fn h3<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> D {
    let s = shape(k, theta1, theta2);
    s.G / s.F * branch + dr_dtheta1(k, branch, theta1, theta2)
}

/// `dh3/dtheta1`, exact (two levels of dual numbers over `D`).
pub fn dh3_dtheta1<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> D {
    feedback_terms(k, branch, theta1, theta2).0
}

/// `dh3/dtheta2 = sign(P) 2 sigma / F^2` (Eq. 25, checked against AD in the tests).
pub fn dh3_dtheta2<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> D {
    let s = shape(k, theta1, theta2);
    s.sigma * (2.0 * branch) / (s.F * s.F)
}

/// `(dh3/dtheta1, dh3/dtheta2)`, the feedback's coefficients of Eq. (14), from one evaluation of
/// Eqs. (8)-(15) with second-order dual numbers in theta1:
/// `dh3/dtheta1 = sign(P) d(G/F)/dtheta1 + d^2 R/dtheta1^2`, `dh3/dtheta2 = sign(P) 2 sigma / F^2`.
pub fn feedback_terms<D: Scalar>(k: &Lumped, branch: f64, theta1: D, theta2: D) -> (D, D) {
    let s = shape(k, Dual2::new(theta1, D::one(), D::zero()), Dual2::from_re(theta2));
    let r = r_of_shape(&s, branch);
    let gf = s.G / s.F;
    // num-dual's Dual2 carries (value, first derivative, second derivative).
    let dh3_dtheta1 = gf.v1 * branch + r.v2;
    let f = s.F.re;
    (dh3_dtheta1, s.sigma.re * (2.0 * branch) / (f * f))
}

/// The map `z = h(q)` of Eq. (14).
pub fn eq14_h<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3]) -> [D; 3] {
    let [phi, t1, t2] = q;
    let z3 = -phi * branch + r_function(k, branch, t1, t2);
    [t1, h3(k, branch, t1, t2), z3]
}

/// Eq. (14), feedback `v = alpha(q) + beta(q) u`.
pub fn eq14_feedback<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3], u: [D; 2]) -> [D; 2] {
    let (a, b) = feedback_terms(k, branch, q[1], q[2]);
    [u[0], a * u[0] + b * u[1]]
}

/// Eq. (14), inverse feedback: `u1 = v1`, `u2 = (v2 - (dh3/dtheta1) v1) / (sign(P) 2 sigma / F^2)`.
pub fn eq14_control<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3], v: [D; 2]) -> [D; 2] {
    let (a, b) = feedback_terms(k, branch, q[1], q[2]);
    [v[0], (v[1] - a * v[0]) / b]
}

/// `phi` from `z3 = h2`: `phi = sign(P) (R(theta1, theta2) - z3)`.
pub fn eq14_phi(k: &Lumped, branch: f64, z3: f64, theta1: f64, theta2: f64) -> f64 {
    branch * (r_function(k, branch, theta1, theta2) - z3)
}

/// Eq. (14) exactly as printed (with `arcsin`), for the tests that check the `atan2` form.
#[allow(non_snake_case)]
pub fn r_function_printed(k: &Lumped, theta1: f64, theta2: f64) -> f64 {
    let s = shape(k, theta1, theta2);
    -0.5 * ((s.F - s.U) / (2.0 * s.f)).asin()
        + s.Z / (2.0 * s.d.sqrt()) * ((s.F * s.U - s.d) / (2.0 * s.f * s.F)).asin()
}

/// The literal arcsin arguments of Eq. (14), `((F - U)/(2f), (FU - d)/(2fF))`.
pub fn arcsin_arguments(s: &Shape<f64>) -> (f64, f64) {
    ((s.F - s.U) / (2.0 * s.f), (s.F * s.U - s.d) / (2.0 * s.f * s.F))
}
