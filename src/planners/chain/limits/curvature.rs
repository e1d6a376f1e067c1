//! The base-range rows' curvature in the SQP's model (issue 20; [`Discretised::curvature`]):
//! the multiplier-weighted Hessian of `phi(t_k)` at the rows' breakpoints, so that the QP's
//! model of a base-range problem is second order in its active rows (their terms outside the
//! band go to the QP as extra variables, [`Discretised::curved_rows`]). Without it the model
//! had the effort's curvature alone, and the trust region's steps on an active base row were
//! gradient-like: the 3-link tests' arm inside `-30:60` deg stopped after 240 SQP iterations
//! (OptimalFailed, KKT 6.9e-5).

use nalgebra::{DMatrix, DVector};

use super::super::connection::Local;
use super::{Limited, torque_times};
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::sqp::Discretised;

impl Limited<'_> {
    /// The indices of the base-range rows among [`Limited::inequalities`]' (empty without a
    /// base range).
    pub(super) fn base_rows(&self) -> std::ops::Range<usize> {
        if self.base.is_none() {
            return 0..0;
        }
        let basis = self.disc.basis();
        let torque = if self.torque.is_empty() { 0 } else { 2 * self.torque.len() * torque_times(basis).len() };
        let from = self.linear.len() + torque;
        from..from + 2 * (basis.breakpoints().len() - 1)
    }

    /// The base-range rows' curvature `sum_k z_k hess g_k` ([`Discretised::curvature`]), `z`
    /// the multipliers of every row of [`Limited::inequalities`] (the base rows after the linear
    /// and the torque ones, two per breakpoint: `phi - hi`, then `lo - phi`); `None` where no
    /// base row has a positive multiplier.
    ///
    /// `phi(t_k) = phi(0) - integral_0^{t_k} g(theta, theta')`, so its Hessian is a sum over the
    /// quadrature's nodes before `t_k` of `-w B^T hess g B`, `B` the node's basis values and
    /// rates (local: inside the band). Weighted by the rows' multipliers it is one pass over the
    /// nodes with the weight `-w sum_{t_k >= t} (z_hi,k - z_lo,k)`; `g = a(theta) . theta'` is
    /// linear in `theta'`, so `hess g` is its `theta`-block and the mixed one.
    pub(super) fn base_curvature(&self, x: &DVector<f64>, z: &[f64]) -> Option<DMatrix<f64>> {
        self.base?;
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let b = basis.breakpoints();
        let spans = b.len() - 1;
        let rows = z.get(self.base_rows())?;
        if rows.iter().all(|v| !(*v > 0.0)) {
            return None;
        }
        // The weight of span `s`'s nodes: the rows' at every breakpoint after it.
        let mut weight = vec![0.0; spans];
        let mut sum = 0.0;
        for s in (0..spans).rev() {
            sum += rows[2 * s] - rows[2 * s + 1];
            weight[s] = sum;
        }
        let c = self.disc.coefficients(x);
        let dim = self.disc.dim();
        let mut h = DMatrix::zeros(dim, dim);
        let rule = GaussLegendre::new(8);
        let mut local = Local::new(n);
        let (mut th, mut w) = (vec![0.0; n], vec![0.0; n]);
        for (s, win) in b.windows(2).enumerate() {
            if weight[s] == 0.0 {
                continue;
            }
            let span = basis.span_of_interval(s);
            let first = span - p;
            let (mid, half) = ((win[0] + win[1]) / 2.0, (win[1] - win[0]) / 2.0);
            for (xi, wi) in rule.nodes.iter().zip(&rule.weights) {
                let t = mid + half * xi;
                let [value, rate] = self.path_at(&c, span, t, &mut th, &mut w);
                self.connection.local(&th, &w, &mut local);
                let scale = -half * wi * weight[s];
                for l in 0..=p {
                    for j in 0..n {
                        let Some(row) = self.index(first + l, j) else { continue };
                        for ll in 0..=p {
                            for jj in 0..n {
                                let Some(col) = self.index(first + ll, jj) else { continue };
                                // d^2 g / dc_lj dc_ll,jj: theta-theta, theta-theta' both ways.
                                let v = local.hessian[j * n + jj] * value[l] * value[ll]
                                    + local.mixed[j * n + jj] * value[l] * rate[ll]
                                    + local.mixed[jj * n + j] * rate[l] * value[ll];
                                h[(row, col)] += scale * v;
                            }
                        }
                    }
                }
            }
        }
        Some(h)
    }
}
