//! Nonlinear limit rows that hold between their points (issue 20 item 3): the base range and the
//! torque limits, one mechanism for both.
//!
//! A linear limit (position, velocity, acceleration) is a row of control points and holds on the
//! whole path (the convex hull). A nonlinear one is a row at points only ([`super::Limited`]):
//! the base range at every breakpoint, each torque limit at [`super::TORQUE_POINTS`] points per
//! knot span. Between two points `d` apart the quantity can rise by about `d^2 max |x''| / 8`
//! above the larger of its values there:
//! - the base angle: on the 3-link example with `--limit phi.position=-30:60` (from 0 to 30 deg
//!   in 10 s, 32 spans, `h` = 0.31 s) the refined plan dipped to -30.23 deg (-0.527689 rad
//!   against the limit -0.523599) between two breakpoints held at -30 deg;
//! - the torque, whose `tau''` holds the jerk (`2 (dM/dt) theta'''`), large where the path
//!   changes its acceleration quickly, as on end spans graded to `h / 64` ([`super::ends`]): on
//!   the SPART-like arm (20 N m, the `--clearance 0.03` plan of `tests/it/geometry.rs` with its
//!   line solved on that grading, commit 8474d43) the torque, held at 20 N m at the points,
//!   reached 20.0074 N m between two of them in a 14.6 ms span.
//!
//! The certificate reads both between its integration steps and refuses such a plan (the torque
//! since it reads the peak between a step's points: before, it certified SPART's example with
//! +-2 rad, 0.3 rad/s, 50 N m at 13.5 s with joint 1's torque at 50.00217 N m, a use of
//! 1 + 4.3e-5, in a graded end span).
//!
//! So a converged refined plan is checked ([`ChainPlanner::hold_between_points`]): every knot
//! span is sampled at [`SAMPLES`] points (the rows' points among them) and, in a span whose
//! samples come within [`NEAR`] of a limit, each such limit's uses are polished by successive
//! parabolas about every local maximum of the samples (not only the largest). Where a use goes beyond 1 (the declared limit), the margin of that
//! limit's rows in that span ([`Margins`], rows at a breakpoint take the larger of their two
//! spans') becomes twice its rise above the span's points (at least twice the excess), and the
//! plan is solved again from itself with the margins fixed for the whole solve (the rows as
//! smooth as without), at most [`ROUNDS`] times; a base row is never tightened past the start's
//! or the goal's base angle, which every plan passes through. A row added at the peak instead
//! only moved the peak along an arc where the torque rides its limit (1.2e-8 beyond after three
//! rounds, 536e0f3).
//!
//! What it guarantees: a plan with no use beyond 1 at the samples and polished peaks is returned
//! as it is, the same plan as without the check (one pass of inverse dynamics and base angles
//! over the samples, on each refined plan and sharpened solve only, not per solve); otherwise the plan returned is the
//! last converged re-solve, inside at the samples and peaks where the rounds sufficed. It is a
//! sampled check, not a bound: the certificate ([`crate::plan::limit_use`]), which reads the
//! integrated motion, still judges the plan kept.

use std::sync::Arc;

use super::super::search::Candidate;
use super::super::tables::Tables;
use super::super::{ChainPlanner, ChainProblem, ChainStats};
use super::TORQUE_POINTS;
use crate::dynamics::arm::ArmDynamics;
use crate::error::Error;
use crate::model::arm::lumped::SIZE;

/// Samples per knot span of the check: a multiple of every held limit's points per span, so that
/// the rows' points are samples.
const SAMPLES: usize = 4 * TORQUE_POINTS;

/// A span's peak is polished where a sample's use is above `1 - NEAR` (the rows near-active):
/// between samples `h / 12` apart the use rises by a sixteenth of its rise between the rows'
/// points, so a peak beyond the limit has a sample above `1 - NEAR` unless the rows' points miss
/// it by over 80 %.
const NEAR: f64 = 0.05;

/// Parabolic polishing steps of a peak's time.
const POLISH: usize = 4;

/// Solves again with tightened rows, at most.
const ROUNDS: usize = 3;

/// The largest margin of a row (half the limit).
const MOST: f64 = 0.5;

/// A nonlinear limit held by rows at points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Held {
    /// The base range's upper bound, `phi <= hi`; its use `1 + (phi - hi) / (hi - lo)`.
    BaseAbove,
    /// The base range's lower bound, `phi >= lo`; its use `1 + (lo - phi) / (hi - lo)`.
    BaseBelow,
    /// The torque limit of joint `j` (from 0), `|tau_j| <= tau_max`; its use `|tau_j| / tau_max`.
    Torque(usize),
}

impl Held {
    /// The rows' points per knot span (the span's start among them).
    fn points(self) -> usize {
        match self {
            Held::Torque(_) => TORQUE_POINTS,
            Held::BaseAbove | Held::BaseBelow => 1,
        }
    }
}

/// The margins of the held limits' rows by knot span, in units of the limit's use: a row of span
/// `s` holds the use at `1 - margin` (a row at a breakpoint at the larger margin of the spans it
/// joins). Zero where not set.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Margins {
    /// Knot spans of the basis the margins are for.
    spans: usize,
    /// Each held limit's margins, span by span.
    limits: Vec<(Held, Vec<f64>)>,
}

impl Margins {
    /// The margin of `held`'s rows in span `s`.
    fn span(&self, held: Held, s: usize) -> f64 {
        self.limits.iter().find(|(h, _)| *h == held).and_then(|(_, m)| m.get(s).copied()).unwrap_or(0.0)
    }

    /// The margin of `held`'s row at breakpoint `i` (`0..=spans`): the larger of the spans' it
    /// joins.
    pub(super) fn at_breakpoint(&self, held: Held, i: usize) -> f64 {
        let before = if i > 0 { self.span(held, i - 1) } else { 0.0 };
        before.max(if i < self.spans { self.span(held, i) } else { 0.0 })
    }

    /// The margin of `held`'s row at its `k`-th point of span `s` (`k = 0` the breakpoint).
    pub(super) fn at_point(&self, held: Held, s: usize, k: usize) -> f64 {
        if k == 0 { self.at_breakpoint(held, s) } else { self.span(held, s) }
    }

    /// Whether these margins are for a basis of `spans` knot spans (else they are not used).
    pub(super) fn fits(&self, spans: usize) -> bool {
        self.spans == spans
    }

    /// Takes the peaks of a check into account (module docs): `true` where a use is beyond 1.
    fn widen(&mut self, peaks: &[Peak]) -> bool {
        let mut beyond = false;
        for p in peaks.iter().filter(|p| p.used > 1.0) {
            let i = match self.limits.iter().position(|(h, _)| *h == p.held) {
                Some(i) => i,
                None => {
                    self.limits.push((p.held, vec![0.0; self.spans]));
                    self.limits.len() - 1
                }
            };
            let margin = &mut self.limits[i].1[p.span];
            let rise = (p.used - p.at_points).max(p.used - 1.0);
            *margin = margin.max(2.0 * rise).min(MOST);
            beyond = true;
        }
        beyond
    }
}

/// A held limit's largest use in a knot span.
#[derive(Debug, Clone, Copy)]
struct Peak {
    held: Held,
    span: usize,
    /// The largest use found (samples, then polished).
    used: f64,
    /// The largest use at the rows' points of the span (its ends included).
    at_points: f64,
}

impl ChainPlanner {
    /// The nonlinear limits of the arm, each held by rows at points.
    fn held_limits(&self) -> Vec<Held> {
        let limits = &self.arm.limits;
        let base = limits.base.iter().flat_map(|_| [Held::BaseAbove, Held::BaseBelow]);
        let torque = (0..self.arm.joints()).filter(|&j| limits.joint(j).torque.is_some()).map(Held::Torque);
        base.chain(torque).collect()
    }

    /// `c` with its torques and base angle inside their declared limits between the rows' points
    /// (see the [module docs](self)): `c` itself where it already is, where no such limit is
    /// declared or where `c` did not converge; else `c` solved again with the rows of the spans
    /// beyond tightened, up to [`ROUNDS`] times, the last converged solve kept (the certificate
    /// judges it).
    pub(in super::super) fn hold_between_points(
        &self,
        problem: &ChainProblem,
        c: Candidate,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let held = self.held_limits();
        if held.is_empty() || !c.result.converged() {
            return Ok(c);
        }
        let mut margins = Margins { spans: c.disc.basis().breakpoints().len() - 1, limits: Vec::new() };
        let mut kept = c;
        for _ in 0..ROUNDS {
            if !margins.widen(&self.peaks(&kept, &held)) {
                break;
            }
            let tight = ChainPlanner { held: Some(Arc::new(margins.clone())), ..self.clone() };
            let again = tight.resolve(problem, &kept, kept.spans, kept.nodes, tables)?;
            if !again.result.converged() {
                break;
            }
            kept = again;
        }
        Ok(kept)
    }

    /// Each of `held`'s largest use in every knot span of `c`'s plan where it comes within
    /// [`NEAR`] of its limit (module docs).
    fn peaks(&self, c: &Candidate, held: &[Held]) -> Vec<Peak> {
        let limits = &self.arm.limits;
        let (basis, coefficients) = (c.disc.basis(), c.disc.coefficients(&c.result.x));
        // The base angle's plan only with a base range (its breakpoints' angles a quadrature).
        let plan = limits.base.map(|_| self.plan_of(c, ChainStats::unmeasured(c)));
        let n = self.arm.joints();
        let base = limits.base.map(|[lo, hi]| (lo, hi, hi - lo));
        let torque = held.iter().any(|h| matches!(h, Held::Torque(_)));
        let dynamics = torque.then(|| ArmDynamics::new(&self.arm));
        let (mut th, mut w, mut a, mut tau) = ([0.0; SIZE], [0.0; SIZE], [0.0; SIZE], [0.0; SIZE]);
        let mut spare = ([0.0; SIZE], [0.0; SIZE]);
        // Every held limit's use at `t`, in `held`'s order.
        let mut uses = |t: f64, out: &mut [f64]| {
            let phi = plan.as_ref().map(|plan| plan.phi(t));
            if let Some(dynamics) = &dynamics {
                basis.evaluate_each(&coefficients, t, |j, [v, d, dd]| {
                    (th[j], w[j], a[j]) = (v, d, dd);
                });
                dynamics.inverse_into(
                    &th[..n],
                    &w[..n],
                    &a[..n],
                    &mut tau[..n],
                    &mut spare.0[..=n],
                    &mut spare.1[..=n],
                );
            }
            for (u, h) in out.iter_mut().zip(held) {
                *u = match (*h, base, phi) {
                    (Held::BaseAbove, Some((_, hi, width)), Some(phi)) => 1.0 + (phi - hi) / width,
                    (Held::BaseBelow, Some((lo, _, width)), Some(phi)) => 1.0 + (lo - phi) / width,
                    (Held::Torque(j), ..) => tau[j].abs() / limits.joint(j).torque.unwrap_or(f64::INFINITY),
                    _ => f64::NEG_INFINITY,
                };
            }
        };
        let k = held.len();
        let mut samples = vec![vec![0.0; k]; SAMPLES + 1];
        let mut probe = vec![0.0; k];
        let mut peaks = Vec::new();
        for (s, win) in basis.breakpoints().windows(2).enumerate() {
            let step = (win[1] - win[0]) / SAMPLES as f64;
            for (i, out) in samples.iter_mut().enumerate() {
                uses(win[0] + step * i as f64, out);
            }
            for (m, &h) in held.iter().enumerate() {
                // Every local maximum of the samples near the limit is polished, not only the
                // largest: where a torque rides its limit the samples at the rows' points are all
                // at it, and the peak between two of them lay beside another sample than the
                // largest (the 3-link example at 80 s inside `all.torque=0.01`: the largest
                // sample 1 - 1e-9 at the span's end, the peak 1 + 4.8e-8 at 79.789 s beside the
                // row at 79.792 s, refused by the certificate).
                let near = |i: usize| samples[i][m] >= 1.0 - NEAR;
                let local = |i: usize| {
                    (i == 0 || samples[i][m] >= samples[i - 1][m])
                        && (i == SAMPLES || samples[i][m] >= samples[i + 1][m])
                };
                let mut peak = (f64::NEG_INFINITY, win[0]);
                for best in (0..=SAMPLES).filter(|&i| near(i) && local(i)) {
                    let mut top = (samples[best][m], win[0] + step * best as f64);
                    // Successive parabolas through three points about the sample (inside the
                    // span, so that a peak next to a breakpoint is found too), each a quarter as
                    // wide.
                    let mut width = step;
                    for _ in 0..POLISH {
                        let mid = top.1.clamp(win[0] + width, win[1] - width);
                        let [x, y, z] = [mid - width, mid, mid + width].map(|t| {
                            uses(t, &mut probe);
                            probe[m]
                        });
                        let curvature = x - 2.0 * y + z;
                        if curvature < 0.0 {
                            let t = (mid + width * 0.5 * (x - z) / curvature).clamp(win[0], win[1]);
                            uses(t, &mut probe);
                            if probe[m] > top.0 {
                                top = (probe[m], t);
                            }
                        }
                        width *= 0.25;
                    }
                    if top.0 > peak.0 {
                        peak = top;
                    }
                }
                if peak.0 < 1.0 - NEAR {
                    continue;
                }
                let points = h.points();
                let at_points =
                    (0..=points).map(|i| samples[i * SAMPLES / points][m]).fold(f64::NEG_INFINITY, f64::max);
                peaks.push(Peak { held: h, span: s, used: peak.0, at_points });
            }
        }
        peaks
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
