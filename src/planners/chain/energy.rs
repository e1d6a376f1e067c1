//! The kinetic energy of an `n`-link arm at zero angular momentum as a cost density, with its
//! exact gradient and Hessian in `(theta, theta')`.
//!
//! With `M(theta)` the inertia matrix of `(phi, theta)` ([`Arm::inertia_matrix`]), its first row
//! `(F, G)` (Eq. 5) and the base's `phi' = -(G . theta') / F`, the energy is
//! `e = 1/2 w^T R(theta) w` with `w = theta'` and the reduced matrix
//! `R = M_tt - G G^T / F` (the joint block minus the base's share). So
//! `de/dw = R w`, `d^2 e / dw^2 = R`, `de/dtheta_m = 1/2 w^T R_m w`,
//! `d^2 e / dtheta_m dw = R_m w` and `d^2 e / dtheta_m dtheta_p = 1/2 w^T R_mp w`, with the
//! partial derivatives `R_m`, `R_mp` of `R` from hyper-dual numbers (exact to rounding): one
//! evaluation of `M` per pair `m <= p`.

use num_dual::HyperDual64;

use crate::Scalar;
use crate::model::arm::Arm;

/// The energy density at one point with its derivatives; the buffers are reused.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyLocal {
    /// `e = 1/2 w^T R w` \[J\].
    pub value: f64,
    /// `de/dtheta`.
    pub d_theta: Vec<f64>,
    /// `de/dtheta' = R w`.
    pub d_rate: Vec<f64>,
    /// `d^2 e / dtheta_m dtheta_p`, row-major `n x n`.
    pub theta_theta: Vec<f64>,
    /// `d^2 e / dtheta_m dtheta'_j`, row-major `[m * n + j]`.
    pub theta_rate: Vec<f64>,
    /// `d^2 e / dtheta'_i dtheta'_j = R_ij`, row-major.
    pub rate_rate: Vec<f64>,
    // Work space: R_m (per m, row-major n x n each).
    r_first: Vec<f64>,
}

impl EnergyLocal {
    /// Buffers for `n` joints.
    pub fn new(n: usize) -> Self {
        Self {
            value: 0.0,
            d_theta: vec![0.0; n],
            d_rate: vec![0.0; n],
            theta_theta: vec![0.0; n * n],
            theta_rate: vec![0.0; n * n],
            rate_rate: vec![0.0; n * n],
            r_first: vec![0.0; n * n * n],
        }
    }
}

/// The reduced matrix `R = M_tt - G G^T / F` at `theta`, row-major `n x n`, generic over
/// [`Scalar`].
pub fn reduced_inertia<D: Scalar>(arm: &Arm, theta: &[D]) -> Vec<D> {
    let n = arm.joints();
    let m = arm.inertia_matrix(theta);
    let f = m[(0, 0)];
    let mut r = Vec::with_capacity(n * n);
    for i in 1..=n {
        for j in 1..=n {
            r.push(m[(i, j)] - m[(0, i)] * m[(0, j)] / f);
        }
    }
    r
}

/// The kinetic energy `1/2 w^T R(theta) w` \[J\] at zero angular momentum.
pub fn energy(arm: &Arm, theta: &[f64], rate: &[f64]) -> f64 {
    let n = theta.len();
    let r = reduced_inertia(arm, theta);
    let mut e = 0.0;
    for i in 0..n {
        for j in 0..n {
            e += rate[i] * r[i * n + j] * rate[j];
        }
    }
    0.5 * e
}

/// The energy density at `(theta, rate)` with its derivatives into `out`.
pub fn energy_local(arm: &Arm, theta: &[f64], rate: &[f64], out: &mut EnergyLocal) {
    let n = theta.len();
    let quad = |r: &dyn Fn(usize) -> f64| {
        let mut s = 0.0;
        for i in 0..n {
            for j in 0..n {
                s += rate[i] * r(i * n + j) * rate[j];
            }
        }
        0.5 * s
    };
    let mut q: Vec<HyperDual64> = theta.iter().map(|&t| HyperDual64::from_re(t)).collect();
    for m in 0..n {
        for p in m..n {
            q[m] = q[m].derivative1();
            q[p] = q[p].derivative2();
            let r = reduced_inertia(arm, &q);
            q[m] = HyperDual64::from_re(theta[m]);
            q[p] = HyperDual64::from_re(theta[p]);
            let second = quad(&|k| r[k].eps1eps2);
            out.theta_theta[m * n + p] = second;
            out.theta_theta[p * n + m] = second;
            if p == m {
                for (k, rk) in r.iter().enumerate() {
                    out.r_first[m * n * n + k] = rk.eps1;
                }
            }
            if m == 0 && p == 0 {
                for (k, rk) in r.iter().enumerate() {
                    out.rate_rate[k] = rk.re;
                }
            }
        }
    }
    for i in 0..n {
        out.d_rate[i] = (0..n).map(|j| out.rate_rate[i * n + j] * rate[j]).sum();
    }
    out.value = 0.5 * (0..n).map(|i| rate[i] * out.d_rate[i]).sum::<f64>();
    for m in 0..n {
        let rm = &out.r_first[m * n * n..(m + 1) * n * n];
        out.d_theta[m] = quad(&|k| rm[k]);
        for j in 0..n {
            out.theta_rate[m * n + j] = (0..n).map(|i| rm[j * n + i] * rate[i]).sum();
        }
    }
}

/// A floor of the energy per effort, `e >= floor |w|^2` (sampled, with a safety factor 1/2):
/// `1/4 min_k lambda_min(R(theta_k))` over 64 points of the Kronecker sequence of
/// [`super::seeds::curvature_bound`]. It turns the effort's lower bound of a goal
/// representative into one of its energy (branch and bound in the energy).
pub fn energy_floor(arm: &Arm) -> f64 {
    let n = arm.joints();
    let primes = [2.0f64, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0, 31.0, 37.0, 41.0, 43.0, 47.0];
    let mut theta = vec![0.0; n];
    let mut floor = f64::INFINITY;
    for k in 1..=64 {
        for (i, t) in theta.iter_mut().enumerate() {
            *t = std::f64::consts::TAU * (k as f64 * primes[i % 15].sqrt()).fract();
        }
        let r = nalgebra::DMatrix::from_row_slice(n, n, &reduced_inertia(arm, &theta));
        let least = r.symmetric_eigenvalues().iter().copied().fold(f64::INFINITY, f64::min);
        floor = floor.min(least);
    }
    if floor.is_finite() { 0.25 * floor.max(0.0) } else { 0.0 }
}
