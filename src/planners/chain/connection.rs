//! The holonomy integrand of an `n`-link arm, `g = a(theta) . theta'` with `a = G/F`
//! (`phi' = -g`, Eq. 7 with zero momentum), with its exact gradient and Hessian in
//! `(theta, theta')`, in closed form.
//!
//! Relative to the base's centre of mass every body's centre of mass is a sum of segment vectors
//! `P_bs e(alpha_s)`: the mount (`s = 0`, length `|(a, b)|`, angle `alpha_0 = phi + beta`) and the
//! links (`s = i`, angle `alpha_i = phi + Psi_i`, `Psi_i = theta_1 + .. + theta_i`). With the
//! system's centre of mass fixed, the orbital angular momentum is
//! `sum_{s,t} K_st cos(alpha_s - alpha_t) alpha_t'` with
//! `K_st = sum_b m_b P_bs P_bt - (sum_b m_b P_bs)(sum_b m_b P_bt) / m_total`, and the bodies'
//! spins add `I_0 phi' + sum_k I_k alpha_k'`. Reading off the coefficients of `phi'` and
//! `theta_j'` gives `F` and `G_j` as sums over segment pairs of `cos(Psi_s - Psi_t)` (with
//! `Psi_0 = beta`), whose derivatives in `theta` are those of a cosine of a sum of angles. The
//! test `connection_matches_the_model` holds them to [`Arm::momentum_coefficients`] and to
//! num-dual's second derivatives.

use crate::model::arm::Arm;
// `sin` and `cos` together from the `libm` crate (the Rust project's port of musl's): the
// connection takes `n` of them at every quadrature node, and the C library's `sincos` behind
// `f64::sin_cos` was a sixth of a plan's time at a = b = 0.1.
use libm::sincos as sin_cos;

mod curvature;
mod known;
mod specialised;
mod work;
pub use curvature::Angles;
pub(crate) use specialised::specialised;
use work::{STACK_JOINTS, Work, WorkSlices};

/// Largest number of joints the chain planner takes.
pub const MAX_JOINTS: usize = crate::model::arm::MAX_LINKS;

/// The outputs of [`Connection::local_in`]: `(value, plain)`, `a`, the gradient, the Hessian
/// and the mixed derivatives.
type Outputs<'a> = ((&'a mut f64, &'a mut f64), &'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]);

/// The constants of an arm's momentum coefficients (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct Connection {
    n: usize,
    /// `K_st`, `(n + 1) x (n + 1)`, row-major.
    k: Vec<f64>,
    /// `beta = atan2(b, a)` of the mount \[rad\].
    beta: f64,
    /// `(sin beta, cos beta)`, the first segment's (constant) direction.
    beta_sin_cos: (f64, f64),
    /// The constant part of `F`: `sum_t K_tt + I_0 + sum_k I_k`.
    f0: f64,
    /// The constant part of `G_j`: `sum_{t >= j} (K_tt + I_t)`.
    g0: Vec<f64>,
}

/// The integrand at one point with its derivatives; the buffers are reused from point to point.
#[derive(Debug, Clone, PartialEq)]
pub struct Local {
    /// `g = a . theta'` \[rad/s\].
    pub value: f64,
    /// `g` rounded as [`Connection::value`] rounds it, bit for bit (`value` is the quotient of
    /// the derivatives' sums): a base angle the same at every order of its derivatives.
    pub plain: f64,
    /// `a = G / F`, which is also `dg/dtheta'`.
    pub a: Vec<f64>,
    /// `dg/dtheta`.
    pub gradient: Vec<f64>,
    /// `d^2 g / dtheta_m dtheta_p`, row-major `n x n`.
    pub hessian: Vec<f64>,
    /// `d^2 g / dtheta_m dtheta'_j = da_j / dtheta_m`, row-major `[m * n + j]`.
    pub mixed: Vec<f64>,
    /// Work space of [`Connection::local`] beyond [`STACK_JOINTS`] joints (empty up to them,
    /// whose work space is on the stack).
    work: Work,
}

impl Local {
    /// Buffers for `n` joints.
    pub fn new(n: usize) -> Self {
        Self {
            value: 0.0,
            plain: 0.0,
            a: vec![0.0; n],
            gradient: vec![0.0; n],
            hessian: vec![0.0; n * n],
            mixed: vec![0.0; n * n],
            work: if n > STACK_JOINTS { Work::new(n) } else { Work::default() },
        }
    }
}

impl Connection {
    /// The constants of `arm`.
    pub fn new(arm: &Arm) -> Self {
        let n = arm.joints();
        let total = arm.total_mass();
        let r_mount = arm.mount.a.hypot(arm.mount.b);
        let beta = if r_mount > 0.0 { arm.mount.b.atan2(arm.mount.a) } else { 0.0 };
        // P_bs for the links' bodies (the base's are zero).
        let p = |body: usize, s: usize| -> f64 {
            match s {
                0 => r_mount,
                s if s < body + 1 => arm.links[s - 1].length,
                s if s == body + 1 => arm.links[body].com,
                _ => 0.0,
            }
        };
        let mut k = vec![0.0; (n + 1) * (n + 1)];
        let moment: Vec<f64> =
            (0..=n).map(|s| arm.links.iter().enumerate().map(|(b, l)| l.mass * p(b, s)).sum()).collect();
        for s in 0..=n {
            for t in 0..=n {
                let second: f64 = arm.links.iter().enumerate().map(|(b, l)| l.mass * p(b, s) * p(b, t)).sum();
                k[s * (n + 1) + t] = second - moment[s] * moment[t] / total;
            }
        }
        let spin = |t: usize| if t == 0 { arm.base.inertia } else { arm.links[t - 1].inertia };
        let f0 = (0..=n).map(|t| k[t * (n + 1) + t] + spin(t)).sum();
        let g0 = (1..=n).map(|j| (j..=n).map(|t| k[t * (n + 1) + t] + spin(t)).sum()).collect();
        Self { n, k, beta, beta_sin_cos: beta.sin_cos(), f0, g0 }
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.n
    }

    /// `(F, N = G . rate)` at `theta` (values only; `n <=` [`MAX_JOINTS`]).
    fn f_and_n(&self, theta: &[f64], rate: &[f64]) -> (f64, f64) {
        specialised!(self.n, |n| self.f_and_n_of(n, theta, rate, None))
    }

    /// [`Self::f_and_n`] for `n = self.n` (inlined where `n` is a constant).
    #[inline(always)]
    fn f_and_n_of(&self, n: usize, theta: &[f64], rate: &[f64], keep: Option<&mut [(f64, f64)]>) -> (f64, f64) {
        let (theta, rate) = (&theta[..n], &rate[..n]);
        let mut e = [(0.0, 0.0); MAX_JOINTS + 1];
        let mut w = [0.0; MAX_JOINTS + 1];
        let mut psi = self.beta;
        e[0] = self.beta_sin_cos;
        for j in 0..n {
            psi = if j == 0 { theta[0] } else { psi + theta[j] };
            e[j + 1] = sin_cos(psi);
            w[j + 1] = w[j] + rate[j];
        }
        if let Some(keep) = keep {
            keep[..n].copy_from_slice(&e[1..=n]);
        }
        let mut f = self.f0;
        let mut nn: f64 = self.g0[..n].iter().zip(&rate[..n]).map(|(g, r)| g * r).sum();
        for s in 0..n {
            let (ss, cs) = e[s];
            for t in s + 1..=n {
                let kk = 2.0 * self.k[s * (n + 1) + t];
                let c = cs * e[t].1 + ss * e[t].0;
                f += kk * c;
                nn += 0.5 * kk * c * (w[s] + w[t]);
            }
        }
        (f, nn)
    }

    /// `a = G / F` at `theta`.
    pub fn a(&self, theta: &[f64]) -> Vec<f64> {
        let mut local = Local::new(self.n);
        self.local(theta, &vec![0.0; self.n], &mut local);
        local.a
    }

    /// `g = a(theta) . rate` alone \[rad/s\].
    pub fn value(&self, theta: &[f64], rate: &[f64]) -> f64 {
        let (f, n) = self.f_and_n(theta, rate);
        n / f
    }

    /// [`Self::value`] for `n = self.n` joints (inlined where `n` is a constant), the sines and
    /// cosines of the links' angles kept in `keep` (`n` of them) where given.
    #[inline(always)]
    pub(super) fn value_of(&self, n: usize, theta: &[f64], rate: &[f64], keep: Option<&mut [(f64, f64)]>) -> f64 {
        let (f, nn) = self.f_and_n_of(n, theta, rate, keep);
        nn / f
    }

    /// `g`, its gradient and Hessian in `(theta, rate)` into `out`.
    ///
    /// Every pair `s < t` of segments contributes `2 K_st cos(Psi_s - Psi_t)` to `F` (and with
    /// the weights of `G_j` and `N = G . rate`), and its derivatives act on the joints
    /// `s <= m < t` (0-based) alone, so the sums over pairs of the gradients and Hessians are
    /// two-dimensional prefix sums `Q[a][b] = sum_{s <= a} sum_{t > b} X_st`: `O(n^2)` work after
    /// `n + 1` sines and cosines.
    pub fn local(&self, theta: &[f64], rate: &[f64], out: &mut Local) {
        specialised!(self.n, |n| self.local_of(n, theta, rate, out, None))
    }

    /// [`Self::local`]'s value, `a` and gradient alone, bit for bit (`hessian`, `mixed` untouched).
    pub fn first_order(&self, theta: &[f64], rate: &[f64], out: &mut Local) {
        specialised!(self.n, |n| self.local_with::<false>(n, theta, rate, out, None))
    }

    /// [`Self::local`] for `n = self.n` (inlined where `n` is a constant), with the sines and
    /// cosines of the links' angles `known` already where given (those [`Self::value_of`] kept at
    /// the same `theta`: the same bits).
    #[inline(always)]
    pub(super) fn local_of(
        &self,
        n: usize,
        theta: &[f64],
        rate: &[f64],
        out: &mut Local,
        known: Option<&[(f64, f64)]>,
    ) {
        self.local_with::<true>(n, theta, rate, out, known)
    }

    /// [`Self::local_of`], the second derivatives only with `SECOND`.
    #[inline(always)]
    fn local_with<const SECOND: bool>(
        &self,
        n: usize,
        theta: &[f64],
        rate: &[f64],
        out: &mut Local,
        known: Option<&[(f64, f64)]>,
    ) {
        let Local { value, plain, a, gradient, hessian, mixed, work } = out;
        let outputs = ((value, plain), &mut a[..n], &mut gradient[..n], &mut hessian[..n * n], &mut mixed[..n * n]);
        // The work space on the stack, `N1 = n + 1` and `SQ = N1^2` constants, up to
        // [`STACK_JOINTS`] joints; on the heap beyond.
        macro_rules! on_stack {
            ($n1:literal) => {{
                const SQ: usize = $n1 * $n1;
                let (mut f_grad, mut f_hess, mut g_jac) = ([0.0; $n1], [0.0; SQ], [0.0; SQ]);
                let (mut psi, mut rate_sum, mut cs) = ([0.0; $n1], [0.0; $n1], [(0.0, 0.0); $n1]);
                let (mut pairs, mut suffix, mut prefix) = ([[0.0; 4]; SQ], [[0.0; 4]; SQ], [[0.0; 4]; SQ]);
                let work = WorkSlices {
                    f_grad: &mut f_grad,
                    f_hess: &mut f_hess,
                    g_jac: &mut g_jac,
                    psi: &mut psi,
                    rate_sum: &mut rate_sum,
                    cs: &mut cs,
                    pairs: &mut pairs,
                    suffix: &mut suffix,
                    prefix: &mut prefix,
                };
                self.local_in::<SECOND>(n, theta, rate, outputs, work, known)
            }};
        }
        match n {
            0 | 1 => on_stack!(2),
            2 => on_stack!(3),
            3 => on_stack!(4),
            4 => on_stack!(5),
            5 => on_stack!(6),
            6 => on_stack!(7),
            7 => on_stack!(8),
            _ => {
                if work.pairs.len() != (n + 1) * (n + 1) {
                    *work = Work::new(n);
                }
                let Work { f_grad, f_hess, g_jac, psi, rate_sum, cs, pairs, suffix, prefix } = work;
                let work = WorkSlices { f_grad, f_hess, g_jac, psi, rate_sum, cs, pairs, suffix, prefix };
                self.local_in::<SECOND>(n, theta, rate, outputs, work, known)
            }
        }
    }

    /// [`Self::local_of`] with its work space (the second derivatives only with `SECOND`).
    #[allow(non_snake_case)]
    #[inline(always)]
    fn local_in<const SECOND: bool>(
        &self,
        n: usize,
        theta: &[f64],
        rate: &[f64],
        ((value, plain), a, gradient, hessian, mixed): Outputs,
        work: WorkSlices,
        known: Option<&[(f64, f64)]>,
    ) {
        let (theta, rate) = (&theta[..n], &rate[..n]);
        let n1 = n + 1;
        // The buffers as separate slices (no reloads of their addresses between the loops).
        let WorkSlices { f_grad, f_hess, g_jac, psi, rate_sum, cs, pairs, suffix, prefix } = work;
        let (a, gradient, f_grad) = (&mut a[..n], &mut gradient[..n], &mut f_grad[..n]);
        let (hessian, mixed, f_hess, g_jac) =
            (&mut hessian[..n * n], &mut mixed[..n * n], &mut f_hess[..n * n], &mut g_jac[..n * n]);
        let (psi, rate_sum, cs) = (&mut psi[..n1], &mut rate_sum[..n1], &mut cs[..n1]);
        let (pairs, suffix, prefix) = (&mut pairs[..n1 * n1], &mut suffix[..n1 * n1], &mut prefix[..n1 * n1]);
        psi[0] = self.beta;
        rate_sum[0] = 0.0;
        for j in 0..n {
            psi[j + 1] = if j == 0 { theta[0] } else { psi[j] + theta[j] };
            rate_sum[j + 1] = rate_sum[j] + rate[j];
        }
        cs[0] = self.beta_sin_cos;
        match known {
            Some(known) => cs[1..n1].copy_from_slice(&known[..n]),
            None => {
                for s in 1..n1 {
                    cs[s] = sin_cos(psi[s]);
                }
            }
        }
        // X_st for s < t: [2K C, h C, 2K S, h S] with h = K (W_s + W_t).
        let mut F = self.f0;
        let mut N: f64 = self.g0[..n].iter().zip(&rate[..n]).map(|(g, r)| g * r).sum();
        // `N` as [`Self::f_and_n`] sums it.
        let mut N_plain = N;
        for s in 0..n {
            let (ss, cs_s) = cs[s];
            let k = &self.k[s * n1..(s + 1) * n1];
            for t in s + 1..=n {
                let (st, ct) = cs[t];
                let (C, S) = (cs_s * ct + ss * st, ss * ct - cs_s * st);
                let kk = 2.0 * k[t];
                let h = 0.5 * kk * (rate_sum[s] + rate_sum[t]);
                F += kk * C;
                N += h * C;
                N_plain += 0.5 * kk * C * (rate_sum[s] + rate_sum[t]);
                pairs[s * n1 + t] = [kk * C, h * C, kk * S, h * S];
            }
        }
        // E[s][b] = sum_{t > b} X_st (suffix over t), then Q[a][b] = sum_{s <= a} E[s][b]; only
        // `s <= b` and `a <= b` are read (`X_st` vanishes for `t <= s`).
        for s in 0..n1 {
            let mut acc = [0.0; 4];
            for b in (s..n1).rev() {
                suffix[s * n1 + b] = acc;
                if b > s {
                    let x = pairs[s * n1 + b];
                    for (a, v) in acc.iter_mut().zip(x) {
                        *a += v;
                    }
                }
            }
        }
        for b in 0..n1 {
            let mut acc = [0.0; 4];
            for a in 0..=b {
                let e = suffix[a * n1 + b];
                for (c, v) in acc.iter_mut().zip(e) {
                    *c += v;
                }
                prefix[a * n1 + b] = acc;
            }
        }
        let prefix = &*prefix;
        let q = |a: usize, b: usize, k: usize| {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prefix[lo * n1 + hi][k]
        };
        // G_j = g0_j + sum_{j < s < t} 2K C + 1/2 sum_{s <= j < t} 2K C.
        let mut tail = 0.0;
        for j in (0..n).rev() {
            a[j] = self.g0[j] + tail + 0.5 * q(j, j, 0);
            tail += suffix[j * n1 + j][0];
        }
        for m in 0..n {
            f_grad[m] = q(m, m, 2);
            gradient[m] = q(m, m, 3);
            if !SECOND {
                continue;
            }
            for p in 0..n {
                f_hess[m * n + p] = -q(m, p, 0);
                hessian[m * n + p] = -q(m, p, 1);
            }
        }
        // dG_j/dtheta_m = sum_{j < s <= m} E_2K S[s][m] + 1/2 Q_2K S[min(j, m)][max(j, m)].
        for m in (0..n).filter(|_| SECOND) {
            let mut first = 0.0;
            for j in (0..n).rev() {
                g_jac[j * n + m] = first + 0.5 * q(j, m, 2);
                if j >= 1 && j <= m {
                    first += suffix[j * n1 + m][2];
                }
            }
        }
        let g = N / F;
        (*value, *plain) = (g, N_plain / F);
        // One division (the quotient rule's `1 / F` as a factor).
        let inv = 1.0 / F;
        for j in 0..n {
            a[j] *= inv;
            gradient[j] = (gradient[j] - g * f_grad[j]) * inv;
        }
        for m in (0..n).filter(|_| SECOND) {
            for p in 0..n {
                let i = m * n + p;
                hessian[i] = (hessian[i] - gradient[m] * f_grad[p] - gradient[p] * f_grad[m] - g * f_hess[i]) * inv;
            }
            for j in 0..n {
                mixed[m * n + j] = (g_jac[j * n + m] - a[j] * f_grad[m]) * inv;
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::model::arm::{Base, Link};
    use crate::model::{Mount, RobotParams};
    use nalgebra::SVector;
    use num_dual::{Dual2Vec64, hessian};

    pub(crate) fn arm(n: usize) -> Arm {
        let links = (0..n)
            .map(|i| Link {
                length: 0.3 + 0.05 * i as f64,
                com: 0.12 + 0.02 * i as f64,
                mass: 1.0 + 0.3 * i as f64,
                inertia: 0.01 * (i as f64 + 1.0),
            })
            .collect();
        Arm {
            base: Base { mass: 12.0, inertia: 0.4 },
            mount: Mount { a: 0.2, b: -0.1 },
            links,
            limits: Default::default(),
            geometry: Default::default(),
        }
    }

    /// num-dual's value, gradient and Hessian of the model's `g` in `(theta, rate)`, `M = 2 n`.
    fn dual<const M: usize>(arm: &Arm, x: &[f64]) -> (f64, Vec<f64>, Vec<Vec<f64>>) {
        let n = M / 2;
        let x = SVector::<f64, M>::from_iterator(x.iter().copied());
        let (v, g, h) = hessian(
            |v: SVector<Dual2Vec64<nalgebra::Const<M>>, M>| {
                let (f, g) = arm.momentum_coefficients(&v.as_slice()[..n]);
                let mut s = g[0] * v[n];
                for j in 1..n {
                    s += g[j] * v[n + j];
                }
                s / f
            },
            &x,
        );
        (v, g.iter().copied().collect(), (0..M).map(|i| (0..M).map(|j| h[(i, j)]).collect()).collect())
    }

    /// The curvature of a plane is, bit for bit, the one read off [`Connection::local`] at zero
    /// rate (the coil sites rely on it: their grid's argmax must not move), for every plane of
    /// n = 2..15 joints, the SRC robot and a mount on the axis (`beta = 0`).
    #[test]
    fn curvature_is_that_of_local_bit_for_bit() {
        let mut arms: Vec<Arm> = (2..=MAX_JOINTS).map(arm).collect();
        arms.push(Arm::from_params(&RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap()));
        arms.push(Arm { mount: Mount { a: 0.3, b: 0.0 }, ..arm(3) });
        for arm in arms {
            let n = arm.joints();
            let c = Connection::new(&arm);
            let mut local = Local::new(n);
            for trial in 0..20 {
                let theta: Vec<f64> = (0..n).map(|i| ((i * 7 + trial * 3) as f64 * 0.77).sin() * 3.0).collect();
                c.local(&theta, &vec![0.0; n], &mut local);
                for i in 0..n {
                    for j in (0..n).filter(|&j| j != i) {
                        let expected = -(local.mixed[i * n + j] - local.mixed[j * n + i]);
                        let got = c.curvature(&theta, i, j);
                        assert_eq!(got.to_bits() & !(1 << 63), expected.to_bits() & !(1 << 63), "n {n} ({i}, {j})");
                    }
                }
            }
        }
    }

    /// [`Connection::first_order`] is [`Connection::local`]'s first order, bit for bit, and its
    /// `plain` value [`Connection::value`]'s.
    #[test]
    fn first_order_is_local_bit_for_bit() {
        for n in 2..=MAX_JOINTS {
            let (c, mut local, mut first) = (Connection::new(&arm(n)), Local::new(n), Local::new(n));
            for trial in 0..10 {
                let theta: Vec<f64> = (0..n).map(|i| ((i * 7 + trial * 3) as f64 * 0.77).sin() * 3.0).collect();
                c.local(&theta, &theta, &mut local);
                c.first_order(&theta, &theta, &mut first);
                assert_eq!(first.plain.to_bits(), c.value(&theta, &theta).to_bits(), "n {n}");
                let bits = |l: &Local| -> Vec<u64> {
                    [[l.value].as_slice(), &l.a, &l.gradient].concat().iter().map(|x| x.to_bits()).collect()
                };
                assert_eq!(bits(&local), bits(&first), "n {n}");
            }
        }
    }

    /// `F, G` of the closed form equal the model's at random configurations, and the gradient and
    /// Hessian of `g = G . w / F` equal num-dual's on the model, for n = 1..7 and the SRC robot.
    #[test]
    fn connection_matches_the_model() {
        let mut arms: Vec<Arm> = (1..=7).map(arm).collect();
        arms.push(Arm::from_params(&RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap()));
        for arm in arms {
            let n = arm.joints();
            let c = Connection::new(&arm);
            let mut local = Local::new(n);
            for trial in 0..5 {
                let theta: Vec<f64> = (0..n).map(|i| ((i * 7 + trial * 3) as f64 * 0.77).sin() * 3.0).collect();
                let rate: Vec<f64> = (0..n).map(|i| ((i * 5 + trial) as f64 * 1.3).cos()).collect();
                c.local(&theta, &rate, &mut local);
                let (f, g) = arm.momentum_coefficients(&theta);
                let expected: f64 = g.iter().zip(&rate).map(|(g, r)| g * r).sum::<f64>() / f;
                assert!((local.value - expected).abs() <= 1e-12 * expected.abs().max(1.0), "n = {n}");
                assert!((c.value(&theta, &rate) - expected).abs() <= 1e-12 * expected.abs().max(1.0));
                for (j, gj) in g.iter().enumerate() {
                    assert!((local.a[j] - gj / f).abs() <= 1e-12, "n = {n}: a_{j}");
                }
                let x: Vec<f64> = theta.iter().chain(&rate).copied().collect();
                let (v, grad, hess) = match n {
                    1 => dual::<2>(&arm, &x),
                    2 => dual::<4>(&arm, &x),
                    3 => dual::<6>(&arm, &x),
                    4 => dual::<8>(&arm, &x),
                    5 => dual::<10>(&arm, &x),
                    6 => dual::<12>(&arm, &x),
                    _ => dual::<14>(&arm, &x),
                };
                assert!((v - local.value).abs() <= 1e-12);
                for m in 0..n {
                    assert!((grad[m] - local.gradient[m]).abs() <= 1e-11, "n = {n}: dg/dtheta_{m}");
                    assert!((grad[n + m] - local.a[m]).abs() <= 1e-11);
                    for p in 0..n {
                        assert!((hess[m][p] - local.hessian[m * n + p]).abs() <= 1e-10, "n = {n}: ({m}, {p})");
                        assert!((hess[m][n + p] - local.mixed[m * n + p]).abs() <= 1e-10, "n = {n}: mixed");
                        assert!(hess[n + m][n + p].abs() <= 1e-12);
                    }
                }
            }
        }
    }
}
