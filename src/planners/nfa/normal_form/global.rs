//! A global normal form, beyond the paper: a feedback transformation to the chained form (10)
//! whose only singular set is `sigma = 0` (the robot's posture singularity, Eq. 9).
//!
//! `z1 = theta1`, `z3 = h2 = phi + Psi(theta1, theta2)` with
//! `Psi = integral_0^theta2 H(theta1, s) / F(theta1, s) ds`, `z2 = h3 = dh2 . g1 = -G/F + dPsi/dtheta1`,
//! `v1 = u1`, `v2 = (dh3/dtheta1) u1 + (dh3/dtheta2) u2` with `dh3/dtheta2 = -2 sigma / F^2` (Eq. 25).
//! `h2` solves `dh2 . g2 = 0` (Appendix, Eq. 18) everywhere: the method of characteristics with
//! `theta2` itself as the parameter, instead of the paper's change of variables `theta2 -> F`
//! (with `dF/dtheta2 = 2P`), whose Jacobian vanishes on `P = 0`: that condition of Theorem 1 is
//! an artefact of the closed form, not a singularity of the system.
//!
//! **Closed form of Psi.** `F = U + 2 f cos(theta2 - delta(theta1))` with
//! `f cos(delta) = C + E (a c1 + b s1)`, `f sin(delta) = E (-a s1 + b c1)` (Eq. 15's `f`), and
//! `H = B + (F - U)/2`, so `H/F = 1/2 - Z/(2F)` and
//! `Psi = theta2/2 - (Z/2) (J(theta2 - delta) - J(-delta))`, where
//! `J(x) = integral_0^x ds / (U + 2 f cos s) = (x - 2 atan((1-k) sin x / ((1+k) + (1-k) cos x))) / sqrt(d)`,
//! `k = sqrt((U - 2f)/(U + 2f))`, `d = U^2 - 4 f^2 > 0`. `J` equals the textbook
//! `(2/sqrt d) atan(k tan(x/2))` on `(-pi, pi)` and is smooth for every real `x` (the denominator
//! is at least `2k > 0`): no log term, no branch jumps.
//!
//! **Bands.** At fixed `theta1`, `sigma = sigma_c + R cos(theta2 - eps)` (with
//! `a s12 ... = ... c2 - ... s2`), so `{sigma != 0}` is a union of bands between consecutive zeros,
//! `theta2 = eps +- acos(-sigma_c / R) + 2 pi n`, found in closed form. On a band `h3` is strictly
//! monotone in `theta2`, so the inverse map is a bracketed one-dimensional root.

use num_dual::{Dual, Dual2};

use crate::Scalar;
use crate::model::Lumped;
use crate::model::system::shape;

/// The functions of `theta1` alone that [`psi`] needs: `U, Z, f, d` (Eq. 15) and `delta`.
#[allow(non_snake_case)]
fn theta1_terms<D: Scalar>(k: &Lumped, theta1: D) -> (D, D, D, D, D) {
    let (s1, c1) = theta1.sin_cos();
    let k1 = c1 * k.a + s1 * k.b;
    let m1 = c1 * k.b - s1 * k.a;
    let U = k1 * (2.0 * k.D) + (k.IP + k.A + k.B);
    let Z = U - 2.0 * k.B;
    let f_cos = k1 * k.E + k.C;
    let f_sin = m1 * k.E;
    let f = (f_cos * f_cos + f_sin * f_sin).sqrt();
    let d = U * U - f * f * 4.0;
    (U, Z, f, d, f_sin.atan2(f_cos))
}

/// `J(x) = integral_0^x ds / (U + 2 f cos s)`, smooth for all real `x` (module docs).
#[allow(non_snake_case)]
fn j_integral<D: Scalar>(x: D, kk: D, root_d: D) -> D {
    let (s, c) = x.sin_cos();
    let one_minus = -kk + 1.0;
    let ratio = one_minus * s / (kk + 1.0 + one_minus * c);
    (x - ratio.atan() * 2.0) / root_d
}

/// `Psi(theta1, theta2) = integral_0^theta2 H/F ds` in closed form (module docs).
#[allow(non_snake_case)]
pub fn psi<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> D {
    let (U, Z, f, d, delta) = theta1_terms(k, theta1);
    let kk = ((U - f * 2.0) / (U + f * 2.0)).sqrt();
    let root_d = d.sqrt();
    theta2 * 0.5 - Z * 0.5 * (j_integral(theta2 - delta, kk, root_d) - j_integral(-delta, kk, root_d))
}

/// `h3 = -G/F + dPsi/dtheta1`.
pub fn h3<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> D {
    let s = shape(k, theta1, theta2);
    let dpsi = psi(k, Dual::new(theta1, D::one()), Dual::from_re(theta2)).eps;
    -s.G / s.F + dpsi
}

/// `(h3, dh3/dtheta2)` at one point from a single evaluation of Eqs. (8)-(15) over dual numbers
/// (`dh3/dtheta2 = -2 sigma / F^2`): what Newton's method on `z2 = h3` needs.
pub fn newton_point(k: &Lumped, theta1: f64, theta2: f64) -> (f64, f64) {
    let t1 = num_dual::Dual64::new(theta1, 1.0);
    let t2 = num_dual::Dual64::from_re(theta2);
    let s = shape(k, theta1, theta2);
    let dpsi = psi(k, t1, t2).eps;
    (-s.G / s.F + dpsi, -2.0 * s.sigma / (s.F * s.F))
}

/// The map `z = h(q) = (theta1, h3, phi + Psi)`.
pub fn global_h<D: Scalar>(k: &Lumped, q: [D; 3]) -> [D; 3] {
    let [phi, t1, t2] = q;
    [t1, h3(k, t1, t2), phi + psi(k, t1, t2)]
}

/// `(dh3/dtheta1, dh3/dtheta2)`: the first by second-order dual numbers, the second
/// `-2 sigma / F^2` (Eq. 25; checked against AD in the tests).
pub fn feedback_terms<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> (D, D) {
    let t1 = Dual2::new(theta1, D::one(), D::zero());
    let t2 = Dual2::from_re(theta2);
    let s = shape(k, t1, t2);
    let dpsi2 = psi(k, t1, t2).v2;
    let gf = s.G / s.F;
    let f = s.F.re;
    (-gf.v1 + dpsi2, s.sigma.re * (-2.0) / (f * f))
}

/// Feedback `v = alpha(q) + beta(q) u`.
pub fn global_feedback<D: Scalar>(k: &Lumped, q: [D; 3], u: [D; 2]) -> [D; 2] {
    let (a, b) = feedback_terms(k, q[1], q[2]);
    [u[0], a * u[0] + b * u[1]]
}

/// Inverse feedback `u = beta^-1 (v - alpha)`.
pub fn global_control<D: Scalar>(k: &Lumped, q: [D; 3], v: [D; 2]) -> [D; 2] {
    let (a, b) = feedback_terms(k, q[1], q[2]);
    [v[0], (v[1] - a * v[0]) / b]
}

/// The band of `{sigma != 0}` with `sign(sigma) = sign` at `theta1` nearest to `theta2_ref`:
/// `(lo, hi)`, or `None` when sigma has no zero at this `theta1` (the band is the whole line).
pub fn band(k: &Lumped, sign: f64, theta1: f64, theta2_ref: f64) -> Option<(f64, f64)> {
    use std::f64::consts::{PI, TAU};
    let (sigma_c, r, eps) = sigma_harmonics(k, theta1);
    if sigma_c.abs() >= r {
        return None;
    }
    let alpha = (-sigma_c / r).acos();
    // sigma > 0 on |theta2 - eps - 2 pi n| < alpha; sigma < 0 on the complement.
    let (centre, half) = if sign > 0.0 { (eps, alpha) } else { (eps + PI, PI - alpha) };
    let n = ((theta2_ref - centre) / TAU).round();
    let c = centre + n * TAU;
    Some((c - half, c + half))
}

/// `sigma(theta1, .) = sigma_c + R cos(theta2 - eps)`: returns `(sigma_c, R, eps)` (Eq. 9 with
/// `-a s12 + b c12 = (-a s1 + b c1) c2 - (a c1 + b s1) s2`).
pub fn sigma_harmonics(k: &Lumped, theta1: f64) -> (f64, f64, f64) {
    let (s1, c1) = theta1.sin_cos();
    let k1 = k.a * c1 + k.b * s1;
    let m1 = -k.a * s1 + k.b * c1;
    let sigma_c = (k.B * k.D - k.C * k.E) * m1;
    let sigma_a = (k.C * k.D - k.A * k.E) * m1;
    let sigma_b = -(k.C * k.D - k.A * k.E) * k1 + (k.D * k.E * (k.a * k.a + k.b * k.b) - k.C * k.IP);
    (sigma_c, sigma_a.hypot(sigma_b), sigma_b.atan2(sigma_a))
}

/// Solves `h3(theta1, theta2) = z2` for `theta2` strictly inside the band `(lo, hi)`, where `h3`
/// is strictly monotone: Newton's method safeguarded by bisection (it cannot leave the band).
/// `Err((h3(lo), h3(hi)))` when `z2` is outside the band's range.
pub fn solve_in_band(k: &Lumped, theta1: f64, z2: f64, (lo, hi): (f64, f64), guess: f64) -> Result<f64, (f64, f64)> {
    let point = |th2: f64| {
        let (h, slope) = newton_point(k, theta1, th2);
        (h - z2, slope)
    };
    let inside = |x: f64| x > lo && x < hi;
    // Newton from the warm start while it stays inside the band and converges fast.
    if inside(guess) {
        let mut x = guess;
        for _ in 0..8 {
            let (f, slope) = point(x);
            let step = -f / slope;
            let next = x + step;
            if !inside(next) || !step.is_finite() {
                break;
            }
            if step.abs() <= 1e-10 * (1.0 + x.abs()) {
                return Ok(next);
            }
            x = next;
        }
    }
    // Safeguarded: keep a bracket f(a) < 0 < f(b) and bisect when Newton would leave it.
    let (flo, fhi) = (point(lo).0, point(hi).0);
    if flo * fhi >= 0.0 {
        return Err((flo + z2, fhi + z2));
    }
    let (mut a, mut b) = if flo < 0.0 { (lo, hi) } else { (hi, lo) };
    let mut x = if inside(guess) { guess } else { 0.5 * (lo + hi) };
    for _ in 0..200 {
        let (fx, slope) = point(x);
        if fx < 0.0 {
            a = x;
        } else {
            b = x;
        }
        let newton = x - fx / slope;
        let next = if newton > a.min(b) && newton < a.max(b) { newton } else { 0.5 * (a + b) };
        if (next - x).abs() <= 1e-15 * (1.0 + x.abs()) || (a - b).abs() <= 1e-15 * (1.0 + x.abs()) {
            return Ok(next);
        }
        x = next;
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Mount, RobotParams};
    use crate::numerics::quadrature::GaussLegendre;
    use num_dual::{Dual64, first_derivative};
    use proptest::prelude::*;

    fn lumped(a: f64, b: f64) -> Lumped {
        RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap().lumped()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// The closed-form Psi equals Gauss–Legendre quadrature of H/F to 1e-13, for any real
        /// theta2 (several turns).
        #[test]
        fn psi_equals_quadrature(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -7.0..7.0f64, t2 in -13.0..13.0f64) {
            let k = lumped(a, b);
            let rule = GaussLegendre::new(20);
            let q = rule.integrate_composite(0.0, t2, 64, |s| { let sh = shape(&k, t1, s); sh.H / sh.F });
            let closed = psi(&k, t1, t2);
            prop_assert!((closed - q).abs() < 1e-13, "{closed} vs {q}");
        }

        /// `dPsi/dtheta2 = H/F` exactly (AD), i.e. `dh2 . g2 = 0`.
        #[test]
        fn psi_derivative_is_h_over_f(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -7.0..7.0f64, t2 in -13.0..13.0f64) {
            let k = lumped(a, b);
            let (_, d) = first_derivative(|x: Dual64| psi(&k, Dual64::from_re(t1), x), t2);
            let s = shape(&k, t1, t2);
            prop_assert!((d - s.H / s.F).abs() < 1e-13);
        }

        /// sigma's harmonic form and the closed-form band edges: sigma vanishes at the edges and
        /// has the band's sign inside.
        #[test]
        fn band_edges_are_zeros_of_sigma(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -7.0..7.0f64, t2 in -7.0..7.0f64) {
            let k = lumped(a, b);
            let s = shape(&k, t1, t2);
            let (c, r, e) = sigma_harmonics(&k, t1);
            prop_assert!((c + r * (t2 - e).cos() - s.sigma).abs() < 1e-13);
            if let Some((lo, hi)) = band(&k, s.sigma.signum(), t1, t2) {
                prop_assert!(lo < t2 && t2 < hi, "{lo} < {t2} < {hi}");
                for edge in [lo, hi] {
                    prop_assert!(shape(&k, t1, edge).sigma.abs() < 1e-12);
                }
            }
        }
    }
}
