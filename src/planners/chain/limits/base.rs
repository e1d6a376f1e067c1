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

use super::super::search::Candidate;
use super::super::tables::Tables;
use super::super::{ChainPlanner, ChainProblem, ChainStats};
use super::MARGIN;
use crate::error::Error;

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
