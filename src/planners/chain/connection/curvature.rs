//! The curvature of a joint plane alone, from the segments' angles (the coil sites evaluate it
//! on a grid of a thousand points per plane, most of whose angles repeat along a row).

use super::{Connection, MAX_JOINTS, sin_cos, specialised};

/// The angles `Psi_k` of the links (the sums of the joint angles up to each) with the sines and
/// cosines of every segment's, the mount's first.
#[derive(Debug, Clone, Copy)]
pub struct Angles {
    psi: [f64; MAX_JOINTS],
    cs: [(f64, f64); MAX_JOINTS + 1],
}

impl Default for Angles {
    fn default() -> Self {
        Self { psi: [0.0; MAX_JOINTS], cs: [(0.0, 0.0); MAX_JOINTS + 1] }
    }
}

impl Connection {
    /// The curvature `kappa_ij = -(da_j/dtheta_i - da_i/dtheta_j)` of the plane of joints `i`
    /// and `j` at `theta` \[rad / rad^2\]: bit for bit what [`Self::local`] gives at zero rate
    /// (the same sums in the same order), at a fraction of its cost (the coil sites evaluate it
    /// on a grid of a thousand points per plane).
    pub fn curvature(&self, theta: &[f64], i: usize, j: usize) -> f64 {
        let mut angles = Angles::default();
        self.angles_from(theta, 0, &mut angles);
        self.curvature_at(&angles, i, j)
    }

    /// `angles` of the segments at `theta` from joint `from` on: those of the joints before it
    /// are kept (unchanged where those joints are, as on a row of the coil sites' grid, whose
    /// sines and cosines are then taken once per row, not once per point). Bit for bit the
    /// angles of [`Self::curvature`].
    pub fn angles_from(&self, theta: &[f64], from: usize, angles: &mut Angles) {
        let Angles { psi, cs } = angles;
        cs[0] = self.beta_sin_cos;
        for k in from..self.n {
            psi[k] = if k == 0 { theta[0] } else { psi[k - 1] + theta[k] };
            cs[k + 1] = sin_cos(psi[k]);
        }
    }

    /// [`Self::curvature`] of the plane `(i, j)` at the segments' `angles` ([`Self::angles_from`]).
    pub fn curvature_at(&self, angles: &Angles, i: usize, j: usize) -> f64 {
        if i > j {
            return -self.curvature_at(angles, j, i);
        }
        specialised!(self.n, |n| self.curvature_of(n, &angles.cs, i, j))
    }

    /// [`Self::curvature_at`] for `i < j` and `n = self.n` (inlined where `n` is a constant).
    #[inline(always)]
    fn curvature_of(&self, n: usize, cs: &[(f64, f64); MAX_JOINTS + 1], i: usize, j: usize) -> f64 {
        // Per segment `s`: the suffix sums `sum_{t > b} X_st` of `[2K C, 2K S]` at `b = i`,
        // `b = j` and `b = s` (those `local` reads for the plane), summed as `local` sums them.
        let mut at_i = [[0.0; 2]; MAX_JOINTS + 1];
        let mut at_j = [[0.0; 2]; MAX_JOINTS + 1];
        let mut diagonal = [0.0; MAX_JOINTS + 1];
        let mut pairs = [[0.0; 2]; MAX_JOINTS + 1];
        let mut f = self.f0;
        for s in 0..=n {
            let (ss, cs_s) = cs[s];
            for t in s + 1..=n {
                let (st, ct) = cs[t];
                let (c, sn) = (cs_s * ct + ss * st, ss * ct - cs_s * st);
                let kk = 2.0 * self.k[s * (n + 1) + t];
                f += kk * c;
                pairs[t] = [kk * c, kk * sn];
            }
            let mut acc = [0.0; 2];
            for b in (s..=n).rev() {
                if b == i {
                    at_i[s] = acc;
                }
                if b == j {
                    at_j[s] = acc;
                }
                if b == s {
                    diagonal[s] = acc[0];
                }
                if b > s {
                    for (a, v) in acc.iter_mut().zip(pairs[b]) {
                        *a += v;
                    }
                }
            }
        }
        // Q[a][b] = sum_{s <= a} suffix[s][b] (component `k`).
        let q = |a: usize, column: &[[f64; 2]], k: usize| column[..=a].iter().fold(0.0, |acc, x| acc + x[k]);
        let g = |m: usize| {
            let tail = (m + 1..n).rev().fold(0.0, |acc, s| acc + diagonal[s]);
            let column = if m == i { &at_i } else { &at_j };
            self.g0[m] + tail + 0.5 * q(m, column, 0)
        };
        let (f_grad_i, f_grad_j) = (q(i, &at_i, 1), q(j, &at_j, 1));
        let q_ij = q(i, &at_j, 1);
        // dG_j/dtheta_i and dG_i/dtheta_j.
        let dg_j_i = 0.0 + 0.5 * q_ij;
        let first = (i + 1..=j).rev().fold(0.0, |acc, s| acc + at_j[s][1]);
        let dg_i_j = first + 0.5 * q_ij;
        let inv = 1.0 / f;
        let (a_i, a_j) = (g(i) * inv, g(j) * inv);
        let mixed_ij = (dg_j_i - a_j * f_grad_i) * inv;
        let mixed_ji = (dg_i_j - a_i * f_grad_j) * inv;
        -(mixed_ij - mixed_ji)
    }
}
