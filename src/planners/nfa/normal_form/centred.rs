//! The feedback transformations of Theorem 1, item 1, for the arm mounted at the base's centre
//! of mass (`a = b = 0`): Eq. (11) and Eq. (12). Both exist where `sin theta2 != 0`, and both
//! invert in closed form (no Newton iteration is needed).

use crate::Scalar;
use crate::model::Lumped;

/// Eq. (11): `z1 = phi + theta1`, `z2 = -2 C c2`,
/// `z3 = (I + A + B) phi + (A + B) theta1 + B theta2 + C s2`.
pub fn eq11_h<D: Scalar>(k: &Lumped, q: [D; 3]) -> [D; 3] {
    let [phi, t1, t2] = q;
    let (s2, c2) = t2.sin_cos();
    [phi + t1, c2 * (-2.0 * k.C), phi * (k.IP + k.A + k.B) + t1 * (k.A + k.B) + t2 * k.B + s2 * k.C]
}

/// Eq. (11), feedback: `v1 = (I/F) u1 - (H/F) u2`, `v2 = 2 C s2 u2`.
pub fn eq11_feedback<D: Scalar>(k: &Lumped, q: [D; 3], u: [D; 2]) -> [D; 2] {
    let (f, h) = centred_fh(k, q[2]);
    [(u[0] * k.IP - h * u[1]) / f, q[2].sin() * (2.0 * k.C) * u[1]]
}

/// Eq. (11), inverse feedback: `u2 = v2 / (2 C s2)`, `u1 = (F v1 + H u2) / I`.
pub fn eq11_control<D: Scalar>(k: &Lumped, q: [D; 3], v: [D; 2]) -> [D; 2] {
    let (f, h) = centred_fh(k, q[2]);
    let u2 = v[1] / (q[2].sin() * (2.0 * k.C));
    [(f * v[0] + h * u2) / k.IP, u2]
}

/// Eq. (11), inverse map in closed form: `cos theta2 = -z2 / (2C)` with theta2 kept in its
/// interval `(n pi, (n+1) pi)`, then `theta1 = (U z1 + B theta2 + C s2 - z3) / I` and
/// `phi = z1 - theta1`. Returns `None` when `|z2| >= 2C` (the path reaches `sin theta2 = 0`).
pub fn eq11_invert(k: &Lumped, z: [f64; 3], interval: i64) -> Option<[f64; 3]> {
    let t2 = theta2_in_interval(-z[1] / (2.0 * k.C), interval)?;
    let u = k.IP + k.A + k.B;
    let t1 = (u * z[0] + k.B * t2 + k.C * t2.sin() - z[2]) / k.IP;
    Some([z[0] - t1, t1, t2])
}

/// Eq. (12) with the correction of docs/spec.md §6, item 1 (`sign(s2) theta2 / 2`):
/// `z1 = theta1`, `z2 = -sign(s2) G/F`,
/// `z3 = sign(s2) phi - pi/4 + sign(s2) theta2/2 + (U - 2B)/(2 sqrt(U^2 - 4C^2)) arcsin((2C + U c2)/(U + 2C c2))`.
///
/// `branch = sign(s2)` is constant on the domain's component. The arcsin is evaluated as the
/// equal `atan2(2C + U c2, sign(s2) s2 sqrt(U^2 - 4C^2))` (its cosine is
/// `|s2| sqrt(U^2 - 4C^2) / (U + 2C c2)`), which keeps full precision near `sin theta2 = 0`.
pub fn eq12_h<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3]) -> [D; 3] {
    let [phi, t1, t2] = q;
    let (s2, c2) = t2.sin_cos();
    let u = k.IP + k.A + k.B;
    let root = (u * u - 4.0 * k.C * k.C).sqrt();
    let (f, _) = centred_fh(k, t2);
    let g = c2 * (2.0 * k.C) + (k.A + k.B);
    let arc = (c2 * u + 2.0 * k.C).atan2(s2 * (branch * root));
    let z3 = phi * branch - std::f64::consts::FRAC_PI_4 + t2 * (branch / 2.0) + arc * ((u - 2.0 * k.B) / (2.0 * root));
    [t1, -(g / f) * branch, z3]
}

/// Eq. (12), feedback: `v1 = u1`, `v2 = 2 C I |s2| / (U + 2 C c2)^2 u2`.
pub fn eq12_feedback<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3], u: [D; 2]) -> [D; 2] {
    let (f, _) = centred_fh(k, q[2]);
    [u[0], q[2].sin() * (2.0 * k.C * k.IP * branch) / (f * f) * u[1]]
}

/// Eq. (12), inverse feedback.
pub fn eq12_control<D: Scalar>(k: &Lumped, branch: f64, q: [D; 3], v: [D; 2]) -> [D; 2] {
    let (f, _) = centred_fh(k, q[2]);
    [v[0], v[1] * f * f / (q[2].sin() * (2.0 * k.C * k.IP * branch))]
}

/// Eq. (12), inverse map in closed form: with `y = -sign(s2) z2 = G/F`,
/// `cos theta2 = (A + B - y U) / (2 C (y - 1))`; then `phi` from `z3`. `None` when the cosine
/// leaves (-1, 1).
pub fn eq12_invert(k: &Lumped, branch: f64, z: [f64; 3], interval: i64) -> Option<[f64; 3]> {
    let y = -branch * z[1];
    let u = k.IP + k.A + k.B;
    let t2 = theta2_in_interval((k.A + k.B - y * u) / (2.0 * k.C * (y - 1.0)), interval)?;
    let rest = eq12_h(k, branch, [0.0, z[0], t2])[2];
    Some([branch * (z[2] - rest), z[0], t2])
}

/// `F` and `H` of Eq. (8) at `a = b = 0`, where they depend on theta2 only.
fn centred_fh<D: Scalar>(k: &Lumped, t2: D) -> (D, D) {
    let c2 = t2.cos();
    (c2 * (2.0 * k.C) + (k.IP + k.A + k.B), c2 * k.C + k.B)
}

/// The theta2 in `(n pi, (n+1) pi)` with the given cosine, `n = interval`.
fn theta2_in_interval(cos: f64, interval: i64) -> Option<f64> {
    if !(cos.abs() < 1.0) {
        return None;
    }
    let pi = std::f64::consts::PI;
    let n = interval as f64;
    Some(if interval.rem_euclid(2) == 0 { n * pi + cos.acos() } else { (n + 1.0) * pi - cos.acos() })
}
