//! The holonomy of a joint path and the costs, with their exact first and second derivatives in
//! the joint angles and velocities at one point.
//!
//! With zero angular momentum (Eq. 5, `p = 0`) the base turns at
//! `phi' = -(G theta1' + H theta2') / F` (Eq. 7), so along a joint path
//! `phi(T) = phi(0) - integral_0^T (a theta1' + b theta2') dt` with `a = G/F`, `b = H/F`
//! (Eq. 8). `F > 0` everywhere, so the integrand is smooth on the whole torus, across the posture
//! singularity `sigma = 0` (Eq. 9).

use num_dual::{Dual2SVec64, hessian};

use crate::Scalar;
use crate::model::Lumped;
use crate::model::system::shape;

/// A function of `(theta1, theta2, theta1', theta2')` with its gradient and Hessian in those
/// four variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Local {
    /// The value.
    pub value: f64,
    /// The gradient.
    pub gradient: [f64; 4],
    /// The Hessian (symmetric).
    pub hessian: [[f64; 4]; 4],
}

/// `(a, b) = (G/F, H/F)` (Eq. 8) at `(theta1, theta2)` \[rad\], generic over [`Scalar`].
pub fn connection<D: Scalar>(k: &Lumped, theta1: D, theta2: D) -> (D, D) {
    let s = shape(k, theta1, theta2);
    (s.G / s.F, s.H / s.F)
}

/// The holonomy integrand `g = a theta1' + b theta2' = (G theta1' + H theta2') / F` (`phi' = -g`,
/// Eqs. 7, 8) alone: the value of [`holonomy_local`], for the quadratures of a motion's base
/// angle.
#[allow(non_snake_case)]
pub fn holonomy_integrand(k: &Lumped, theta: [f64; 2], rate: [f64; 2]) -> f64 {
    let [F, G, H] = Trig::new(k, theta).fgh(k);
    (G * rate[0] + H * rate[1]) / F
}

/// The trigonometric terms of Eq. (8) at `(theta1, theta2)`: `k1 = a c1 + b s1`,
/// `k12 = a c12 + b s12` and their derivatives `m = dk/dtheta`.
struct Trig {
    s2: f64,
    c2: f64,
    k1: f64,
    k12: f64,
    m1: f64,
    m12: f64,
}

impl Trig {
    fn new(k: &Lumped, theta: [f64; 2]) -> Self {
        let (a, b) = (k.a, k.b);
        let (s1, c1) = theta[0].sin_cos();
        let (s2, c2) = theta[1].sin_cos();
        let (s12, c12) = (s1 * c2 + c1 * s2, c1 * c2 - s1 * s2);
        Self { s2, c2, k1: a * c1 + b * s1, k12: a * c12 + b * s12, m1: b * c1 - a * s1, m12: b * c12 - a * s12 }
    }

    /// The values of `F, G, H` (Eq. 8).
    #[allow(non_snake_case)]
    fn fgh(&self, k: &Lumped) -> [f64; 3] {
        let Lumped { A, B, C, D: Dk, E, IP, .. } = *k;
        let Self { c2, k1, k12, .. } = *self;
        [
            2.0 * C * c2 + 2.0 * Dk * k1 + 2.0 * E * k12 + IP + A + B,
            2.0 * C * c2 + Dk * k1 + E * k12 + A + B,
            C * c2 + E * k12 + B,
        ]
    }
}

/// The holonomy integrand `g = a theta1' + b theta2'` (`phi' = -g`, Eq. 7) with its exact
/// gradient and Hessian in `(theta1, theta2, theta1', theta2')`.
///
/// `F, G, H` of Eq. (8) are trigonometric polynomials; their first and second partial derivatives
/// are written out (with `k1 = a c1 + b s1`, `k12 = a c12 + b s12`, `m = dk/dtheta`,
/// `d^2 k / dtheta^2 = -k`) and the quotient rule gives those of `a = G/F`, `b = H/F`. The test
/// `holonomy_derivatives_match_dual_numbers` holds them to num-dual's second derivatives.
#[allow(non_snake_case)]
pub fn holonomy_local(k: &Lumped, theta: [f64; 2], rate: [f64; 2]) -> Local {
    let Lumped { C, D: Dk, E, .. } = *k;
    let trig = Trig::new(k, theta);
    let [f, g, h] = trig.fgh(k);
    let Trig { s2, c2, k1, k12, m1, m12 } = trig;
    // Values, gradients [d1, d2] and Hessians [d11, d12, d22] of F, G, H.
    let F = [
        f,
        2.0 * Dk * m1 + 2.0 * E * m12,
        -2.0 * C * s2 + 2.0 * E * m12,
        -2.0 * Dk * k1 - 2.0 * E * k12,
        -2.0 * E * k12,
        -2.0 * C * c2 - 2.0 * E * k12,
    ];
    let G = [g, Dk * m1 + E * m12, -2.0 * C * s2 + E * m12, -Dk * k1 - E * k12, -E * k12, -2.0 * C * c2 - E * k12];
    let H = [h, E * m12, -C * s2 + E * m12, -E * k12, -E * k12, -C * c2 - E * k12];
    let ra = quotient(&G, &F);
    let rb = quotient(&H, &F);
    let [w1, w2] = rate;
    let mut out = Local { value: ra[0] * w1 + rb[0] * w2, gradient: [0.0; 4], hessian: [[0.0; 4]; 4] };
    out.gradient = [ra[1] * w1 + rb[1] * w2, ra[2] * w1 + rb[2] * w2, ra[0], rb[0]];
    let h11 = ra[3] * w1 + rb[3] * w2;
    let h12 = ra[4] * w1 + rb[4] * w2;
    let h22 = ra[5] * w1 + rb[5] * w2;
    out.hessian =
        [[h11, h12, ra[1], rb[1]], [h12, h22, ra[2], rb[2]], [ra[1], ra[2], 0.0, 0.0], [rb[1], rb[2], 0.0, 0.0]];
    out
}

/// Value, gradient and Hessian `[r, r1, r2, r11, r12, r22]` of `r = N / F` from those of `N` and
/// `F` (quotient rule).
fn quotient(n: &[f64; 6], f: &[f64; 6]) -> [f64; 6] {
    let r = n[0] / f[0];
    let r1 = (n[1] - r * f[1]) / f[0];
    let r2 = (n[2] - r * f[2]) / f[0];
    let r11 = (n[3] - 2.0 * r1 * f[1] - r * f[3]) / f[0];
    let r12 = (n[4] - r1 * f[2] - r2 * f[1] - r * f[4]) / f[0];
    let r22 = (n[5] - 2.0 * r2 * f[2] - r * f[5]) / f[0];
    [r, r1, r2, r11, r12, r22]
}

/// The effort density `|theta'|^2` \[rad^2/s^2\] with its derivatives (constant Hessian).
pub fn effort_local(rate: [f64; 2]) -> Local {
    let [w1, w2] = rate;
    Local {
        value: w1 * w1 + w2 * w2,
        gradient: [0.0, 0.0, 2.0 * w1, 2.0 * w2],
        hessian: [[0.0; 4], [0.0; 4], [0.0, 0.0, 2.0, 0.0], [0.0, 0.0, 0.0, 2.0]],
    }
}

/// The kinetic energy \[J\] of the robot (Eq. 3 without the centre of mass, Eq. 4) moving with
/// joint velocities `rate` at zero angular momentum: `1/2 q'^T M q'` with
/// `phi' = -(G theta1' + H theta2') / F` (Eq. 5), i.e. `1/2 w^T (M_tt - m m^T / F) w` with
/// `w = theta'`, `M_tt` the joint block of the inertia matrix and `m = (G, H)` (Eq. 8).
#[allow(non_snake_case)]
pub fn kinetic_energy<D: Scalar>(k: &Lumped, theta: [D; 2], rate: [D; 2]) -> D {
    let s = shape(k, theta[0], theta[1]);
    let c2 = theta[1].cos();
    let m11 = c2 * (2.0 * k.C) + (k.A + k.B);
    let m12 = c2 * k.C + k.B;
    let m22 = D::from(k.B);
    let [w1, w2] = rate;
    let joint = w1 * w1 * m11 + w1 * w2 * m12 * 2.0 + w2 * w2 * m22;
    let momentum = s.G * w1 + s.H * w2;
    (joint - momentum * momentum / s.F) * 0.5
}

/// [`kinetic_energy`] with its gradient and Hessian in `(theta1, theta2, theta1', theta2')`, by
/// num-dual's second-order dual numbers.
pub fn energy_local(k: &Lumped, theta: [f64; 2], rate: [f64; 2]) -> Local {
    let x = nalgebra::SVector::<f64, 4>::from([theta[0], theta[1], rate[0], rate[1]]);
    let (value, g, h) =
        hessian(|v: nalgebra::SVector<Dual2SVec64<4>, 4>| kinetic_energy(k, [v[0], v[1]], [v[2], v[3]]), &x);
    Local {
        value,
        gradient: std::array::from_fn(|i| g[i]),
        hessian: std::array::from_fn(|i| std::array::from_fn(|j| h[(i, j)])),
    }
}
