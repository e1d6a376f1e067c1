//! The arm's lumped constants: the `n`-link analogue of the paper's `A..E, I_P` (Sec. 3.1,
//! Eqs. 3-4), from which the inertia matrix, its derivatives and the Coriolis terms follow by
//! `n` sines and cosines and `O(n^2)` products, in `f64`, without dual numbers or allocation.
//!
//! Relative to the system's centre of mass, every body's centre of mass is a fixed combination
//! of `n + 1` planar vectors turning with the bodies: the mount `u_0 = R(phi) (a, b)` (angle
//! `Psi_0 = phi + atan2(b, a)`) and the unit vectors `u_j = e(psi_j)` of the links (angle
//! `Psi_j = psi_j = phi + theta_1 + .. + theta_j`). Link `k` sits at
//! `r_k = u_0 + sum_{j<k} l_j u_j + d_k u_k` from the base, i.e. `rho_kj` times `u_j`
//! (`rho_k0 = 1`, `rho_kj = l_j` for `j < k`, `rho_kk = d_k`), the base at `rho_0j = 0`, and the
//! centre of mass keeps every body at `rho_kj - mu_j`, `mu_j = sum_k m_k rho_kj / m_c`. So the
//! kinetic energy is
//!
//! ```text
//! T = 1/2 w^T N w,   N_ij = K_ij (v_i . v_j) + I_i [i = j],   w_j = Psi_j',
//! K_ij = sum_k m_k rho_ki rho_kj - m_c mu_i mu_j,
//! ```
//!
//! with `v_j = u_j` at `phi = 0` (`v_0 = (a, b)`), `I_0` the base's and `I_k` the links'
//! rotational inertias. At `n = 2` this is Eq. (3): `K_00 (a^2 + b^2) + I_0 = I_P`,
//! `K_11 + I_1 = A`, `K_22 + I_2 = B`, `K_12 = C`, `K_01 = D`, `K_02 = E` (the test
//! `two_links_give_the_papers_constants`). Since `w = S q'` with `S` the lower triangle of ones,
//! `M = S^T N S` (suffix sums), `dN_ij/dtheta_k = K_ij X_ij ([k <= i] - [k <= j])` with
//! `X_ij = v_i x v_j`, and the Christoffel terms in the angles `Psi` reduce to
//! `c_i = -sum_j K_ij X_ij w_j^2`, so that `c(q, q') = S^T c` (the Coriolis and centrifugal
//! terms of `M q'' + c`, [`crate::dynamics::arm`]).

use super::{Arm, MAX_LINKS};

/// The largest size `n + 1` of the inertia matrix.
pub const SIZE: usize = MAX_LINKS + 1;

/// A square `(n + 1) x (n + 1)` array on the stack, indexed `[row][column]`.
pub type Square = [[f64; SIZE]; SIZE];

/// The lumped constants of an [`Arm`] (module docs): built once per arm in `O(n^3)`, they give
/// `M(theta)`, `dM/dtheta` and the Coriolis terms at any configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmLumped {
    n: usize,
    k: Square,
    inertia: [f64; SIZE],
    mount: [f64; 2],
}

/// The configuration-dependent part of [`ArmLumped`] at one `theta`: `N` and `K X`, in arrays
/// of capacity `C >= n + 1` (a small `C` for small arms keeps them cheap to fill).
#[derive(Debug, Clone)]
pub struct LumpedTerms<const C: usize = SIZE> {
    n1: usize,
    /// `N_ij = K_ij (v_i . v_j) + I_i [i = j]` [kg m^2].
    pub n: [[f64; C]; C],
    /// `K_ij X_ij`, `X_ij = v_i x v_j` [kg m^2].
    pub kx: [[f64; C]; C],
}

impl ArmLumped {
    /// The constants of `arm` (`K_ij`, the rotational inertias and the mount).
    pub fn new(arm: &Arm) -> Self {
        let n = arm.joints().min(MAX_LINKS);
        let links = &arm.links[..n];
        let total = arm.total_mass();
        // rho[k][j] for link k (0-based, vector j = 0 the mount, j = 1..n the links).
        let rho = |k: usize, j: usize| -> f64 {
            match j {
                0 => 1.0,
                j if j - 1 < k => links[j - 1].length,
                j if j - 1 == k => links[k].com,
                _ => 0.0,
            }
        };
        let mut mu = [0.0; SIZE];
        for (j, m) in mu.iter_mut().enumerate().take(n + 1) {
            *m = links.iter().enumerate().map(|(k, l)| l.mass * rho(k, j)).sum::<f64>() / total;
        }
        let mut k = [[0.0; SIZE]; SIZE];
        for i in 0..=n {
            for j in 0..=i {
                let sum: f64 = links.iter().enumerate().map(|(kk, l)| l.mass * rho(kk, i) * rho(kk, j)).sum();
                let v = sum - total * mu[i] * mu[j];
                k[i][j] = v;
                k[j][i] = v;
            }
        }
        let mut inertia = [0.0; SIZE];
        inertia[0] = arm.base.inertia;
        for (slot, link) in inertia[1..].iter_mut().zip(links) {
            *slot = link.inertia;
        }
        Self { n, k, inertia, mount: [arm.mount.a, arm.mount.b] }
    }

    /// The number `n` of joints.
    pub fn joints(&self) -> usize {
        self.n
    }

    /// `K_ij` (module docs) for `i, j` in `0..=n`: \[kg\] for `i = j = 0`, \[kg m\] when one
    /// of them is 0, [kg m^2] otherwise.
    pub fn constant(&self, i: usize, j: usize) -> f64 {
        self.k[i][j]
    }

    /// The rotational inertia turning with `w_j` [kg m^2]: the base's for `j = 0`, link `j`'s.
    pub fn rotational(&self, j: usize) -> f64 {
        self.inertia[j]
    }

    /// `N` and `K X` at the joint angles `theta` (`n` values) \[rad\]: `n` sines and cosines.
    pub fn terms(&self, theta: &[f64]) -> LumpedTerms {
        self.terms_in::<SIZE>(theta)
    }

    /// [`ArmLumped::terms`] in arrays of capacity `C` (at least `n + 1`).
    pub fn terms_in<const C: usize>(&self, theta: &[f64]) -> LumpedTerms<C> {
        let n1 = self.n + 1;
        assert!(n1 <= C, "a capacity of {C} holds arms of at most {} joints", C - 1);
        let mut v = [[0.0; 2]; C];
        v[0] = self.mount;
        let mut sum = 0.0;
        for (j, t) in theta.iter().take(self.n).enumerate() {
            sum += t;
            let (s, c) = sum.sin_cos();
            v[j + 1] = [c, s];
        }
        let mut n = [[0.0; C]; C];
        let mut kx = [[0.0; C]; C];
        for i in 0..n1 {
            for j in 0..=i {
                let k = self.k[i][j];
                let dot = k * (v[i][0] * v[j][0] + v[i][1] * v[j][1]);
                let cross = k * (v[i][0] * v[j][1] - v[i][1] * v[j][0]);
                n[i][j] = dot;
                n[j][i] = dot;
                kx[i][j] = cross;
                kx[j][i] = -cross;
            }
            n[i][i] += self.inertia[i];
        }
        LumpedTerms { n1, n, kx }
    }
}

impl<const C: usize> LumpedTerms<C> {
    /// The size `n + 1`.
    pub fn size(&self) -> usize {
        self.n1
    }

    /// The inertia matrix `M = S^T N S` [kg m^2] into `m` (its leading `(n + 1)` block):
    /// `M_ab = sum_{i >= a, j >= b} N_ij`, the same matrix as [`Arm::inertia_matrix`].
    pub fn inertia_matrix(&self, m: &mut [[f64; C]; C]) {
        suffix_sums(&self.n, self.n1, m);
    }

    /// The first row of the inertia matrix, `(F, G_1..G_n)` into `row` (`n + 1` values), as
    /// [`Arm::momentum_coefficients`]: `M_0b = sum_{j >= b} sum_i N_ij`.
    pub fn momentum_row(&self, row: &mut [f64]) {
        let mut acc = 0.0;
        for b in (0..self.n1).rev() {
            acc += (0..self.n1).map(|i| self.n[i][b]).sum::<f64>();
            row[b] = acc;
        }
    }

    /// `dM/dtheta_k` (`k = 1..n`) into `dm`: `S^T dN_k S` with
    /// `(dN_k)_ij = K_ij X_ij ([k <= i] - [k <= j])`.
    pub fn inertia_derivative(&self, k: usize, dm: &mut [[f64; C]; C]) {
        let mut dn = [[0.0; C]; C];
        for (i, row) in dn.iter_mut().enumerate().take(self.n1) {
            for (j, x) in row.iter_mut().enumerate().take(self.n1) {
                let s = f64::from(u8::from(k <= i)) - f64::from(u8::from(k <= j));
                *x = self.kx[i][j] * s;
            }
        }
        suffix_sums(&dn, self.n1, dm);
    }

    /// The Coriolis and centrifugal terms `c(theta, q')` [N m] of `M q'' + c` into `c`
    /// (`n + 1` values) at the velocity `dq = (phi', theta')`: `S^T` of
    /// `c_i = -sum_j K_ij X_ij w_j^2`, `w = S q'`.
    pub fn coriolis(&self, dq: &[f64], c: &mut [f64]) {
        let mut w2 = [0.0; C];
        let mut w = 0.0;
        for (slot, v) in w2.iter_mut().zip(&dq[..self.n1]) {
            w += v;
            *slot = w * w;
        }
        let mut acc = 0.0;
        for i in (0..self.n1).rev() {
            let ci: f64 = (0..self.n1).map(|j| self.kx[i][j] * w2[j]).sum();
            acc -= ci;
            c[i] = acc;
        }
    }
}

/// `out_ab = sum_{i >= a, j >= b} x_ij` over the leading `n1 x n1` block.
fn suffix_sums<const C: usize>(x: &[[f64; C]; C], n1: usize, out: &mut [[f64; C]; C]) {
    for i in (0..n1).rev() {
        let mut row = 0.0;
        for j in (0..n1).rev() {
            row += x[i][j];
            out[i][j] = row + if i + 1 < n1 { out[i + 1][j] } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests;
