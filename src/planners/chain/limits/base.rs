//! The base range held between the rows' points (issue 20 item 3).
//!
//! The base-range rows `lo <= phi(t) <= hi` hold at the breakpoints only ([`super::Limited`]):
//! between two of them `h` apart the base angle can rise by about `h^2 max |phi''| / 8` above
//! the larger of its values there. On the 3-link example with `--limit phi.position=-30:60`
//! (from 0 to 30 deg in 10 s, 32 spans, `h` = 0.31 s) the refined plan dipped to -30.23 deg
//! (-0.527689 rad against the limit -0.523599) between two breakpoints held at -30 deg, and the
//! certificate, which reads the integrated base angle between its steps, refused it.
//!
//! So a refined plan is checked ([`ChainPlanner::hold_base`]): its base angle is sampled at
//! [`SAMPLES`] points per knot span; where it leaves the declared range, the range of the rows is
//! tightened on that side by twice the excursion (never past the start's or the goal's base
//! angle, which every plan passes through) and the plan solved again from itself, at most
//! [`ROUNDS`] times. The tightening holds for a whole solve, so the rows are as smooth as
//! without; a plan that stays inside between its points is kept as it is. The certificate
//! still judges the plan kept.

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};

use super::super::connection::Local;
use super::super::search::Candidate;
use super::super::tables::Tables;
use super::super::{ChainPlanner, ChainProblem, ChainStats};
use super::{Limited, MARGIN, torque_times};
use crate::error::Error;
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::sqp::Discretised;

/// Samples of the base angle per knot span.
const SAMPLES: usize = 16;

/// Solves again with the range tightened, at most.
const ROUNDS: usize = 3;

impl ChainPlanner {
    /// `c` with its base angle inside the declared base range between the rows' points (see the
    /// [module docs](self)): `c` itself where it already is, where no base range is declared
    /// or where `c` did not converge; else `c` solved again with the rows' range tightened by
    /// twice the excursion, up to [`ROUNDS`] times, the last converged solve kept (the
    /// certificate judges it).
    pub(in super::super) fn hold_base(
        &self,
        problem: &ChainProblem,
        c: Candidate,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let Some([lo, hi]) = self.arm.limits.base else { return Ok(c) };
        if !c.result.converged() {
            return Ok(c);
        }
        let targets = c.disc.targets();
        let ends = [targets.phi_start, targets.phi_end];
        let (end_lo, end_hi) = (ends[0].min(ends[1]), ends[0].max(ends[1]));
        let [mut tight_lo, mut tight_hi] = [lo, hi];
        let mut kept = c;
        for _ in 0..ROUNDS {
            let [below, above] = self.base_excursion(&kept, [lo, hi]);
            if below <= 0.0 && above <= 0.0 {
                break;
            }
            if above > 0.0 {
                tight_hi = (tight_hi - 2.0 * above).max(end_hi);
            }
            if below > 0.0 {
                tight_lo = (tight_lo + 2.0 * below).min(end_lo);
            }
            let mut arm = (*self.arm).clone();
            arm.limits.base = Some([tight_lo, tight_hi]);
            let tight = ChainPlanner { arm: Arc::new(arm), ..self.clone() };
            let again = tight.resolve(problem, &kept, kept.spans, kept.nodes, tables)?;
            if !again.result.converged() {
                break;
            }
            kept = again;
        }
        Ok(kept)
    }

    /// How far `c`'s base angle goes below `lo` and above `hi` (each tightened by the rows'
    /// relative margin; negative where it stays inside), over [`SAMPLES`] points per knot span.
    fn base_excursion(&self, c: &Candidate, [lo, hi]: [f64; 2]) -> [f64; 2] {
        let plan = self.plan_of(c, ChainStats::unmeasured(c));
        let pad = MARGIN * (hi - lo);
        let (mut below, mut above) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for w in c.disc.basis().breakpoints().windows(2) {
            for k in 0..=SAMPLES {
                let phi = plan.phi(w[0] + (w[1] - w[0]) * k as f64 / SAMPLES as f64);
                below = below.max(lo + pad - phi);
                above = above.max(phi - (hi - pad));
            }
        }
        [below, above]
    }
}

impl Limited<'_> {
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
                let [value, rate] = basis.values_and_rates(span, t);
                for j in 0..n {
                    th[j] = (0..=p).map(|l| value[l] * c[j][first + l]).sum();
                    w[j] = (0..=p).map(|l| rate[l] * c[j][first + l]).sum();
                }
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

#[cfg(test)]
mod tests {
    use super::super::super::{ChainOptions, ChainPlanner, ChainProblem};
    use crate::model::arm::{Arm, Limits};
    use crate::plan::limit_use::limit_use;

    const THREE_LINK: &str = include_str!("../../../../examples/robots/three_link.toml");

    /// The module docs' case: the 3-link example turning its base from 0 to 30 deg in 10 s
    /// dips below -30 deg without a base range (so the range binds), and inside
    /// `phi.position = -30:60` deg its plan is certified with the integrated base angle inside
    /// the range between the breakpoints too (the certificate's measure, `limit_use`), and
    /// sampled densely on the plan.
    #[test]
    fn a_binding_base_range_holds_between_the_breakpoints() {
        let free = Arm::from_toml(THREE_LINK, std::path::Path::new("three_link.toml")).expect("the example");
        let deg = |v: [f64; 4]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
        let problem = ChainProblem::rest_to_rest(deg([0.0; 4]), deg([30.0, 10.0, 10.0, 10.0]), 10.0);
        let [lo, hi] = [(-30f64).to_radians(), 60f64.to_radians()];
        let unconstrained = ChainPlanner::new(free.clone(), ChainOptions::default()).plan(&problem).expect("a plan");
        let dips = (0..=1000).map(|k| unconstrained.phi(0.01 * k as f64)).fold(f64::INFINITY, f64::min);
        assert!(dips < lo, "without the range the base dips to {dips} rad, below {lo}");
        let limited = free.with_limits(Limits { joints: Vec::new(), base: Some([lo, hi]) }).expect("a base range");
        let plan = ChainPlanner::new(limited.clone(), ChainOptions::default()).plan(&problem).expect("a plan inside");
        assert!(plan.verification.certified);
        let report = limit_use(&limited, &plan, &problem.start, &Default::default()).expect("the limits' use");
        assert!(report.inside, "{report:?}");
        for w in plan.basis().breakpoints().windows(2) {
            for k in 0..=64 {
                let phi = plan.phi(w[0] + (w[1] - w[0]) * k as f64 / 64.0);
                assert!((lo..=hi).contains(&phi), "phi {phi} outside [{lo}, {hi}]");
            }
        }
        assert!(plan.effort() >= unconstrained.effort() * (1.0 - 1e-9));
    }
}
