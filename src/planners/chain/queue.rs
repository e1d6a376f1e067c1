//! The goal representatives of a search, taken least estimate first and prepared only when
//! needed: a representative's seeds (loops, coil sites) and its line's holonomy cost more than
//! many a search's solves, and most representatives are cut by the branch and bound before they
//! are solved.
//!
//! Both the seeds' estimate and the effort bound are at least what the straight line alone gives
//! (`1.2 d^2 / T` and `d^2 / T`, `d` the line's length: every seed is at least as long as the
//! line), so a representative is prepared only when that floor could put it first, and dropped
//! unprepared where the floor of its bound is above the best cost already (the cost only
//! decreases, so the search would skip it when it came to it). The representatives taken, and
//! their order, are those of the eager [`ChainPlanner::prepare`].

use super::seeds::Line;
use super::starts::{Prepared, SeedContext};
use super::{ChainPlanner, ChainProblem};

/// Below the exact estimate by more than its rounding (a coil's legs sum to the line's length
/// up to rounding where its entry lies on the line).
const FLOOR_MARGIN: f64 = 1.0 - 1e-9;

/// A representative, prepared or not yet.
struct Entry {
    /// Its place in the eager order before sorting (ties of the estimate keep it).
    index: usize,
    /// Its line in [`Representatives::lines`].
    line: usize,
    /// `phi(T)` \[rad\].
    phi_end: f64,
    /// At most its estimate.
    floor: f64,
    /// At most its bound.
    bound_floor: f64,
    prepared: Option<Prepared>,
}

/// The representatives not yet taken (see the [module docs](self)).
pub(super) struct Representatives {
    /// The lines with their holonomy once computed.
    lines: Vec<(Line, Option<f64>)>,
    entries: Vec<Entry>,
    context: Option<SeedContext>,
    /// The place of the representative taken last.
    last: usize,
}

impl Representatives {
    /// The representatives of `problem` (those of [`ChainPlanner::prepare`]), none prepared.
    pub fn lazy(planner: &ChainPlanner, problem: &ChainProblem) -> Self {
        let (lines, phi_targets) = planner.lines(problem);
        let context = planner.seed_context();
        let mut entries = Vec::new();
        for (k, line) in lines.iter().enumerate() {
            let d = line.length();
            let floor = 1.2 * d * d / line.horizon * FLOOR_MARGIN;
            let bound_floor = context.scale * (d * d / line.horizon) * FLOOR_MARGIN;
            for &phi_end in &phi_targets {
                let index = entries.len();
                entries.push(Entry { index, line: k, phi_end, floor, bound_floor, prepared: None });
            }
        }
        let lines = lines.into_iter().map(|l| (l, None)).collect();
        Self { lines, entries, context: Some(context), last: 0 }
    }

    /// Representatives prepared already, in their order.
    pub fn prepared(prepared: Vec<Prepared>) -> Self {
        let entries = prepared
            .into_iter()
            .enumerate()
            .map(|(index, p)| Entry {
                index,
                line: 0,
                phi_end: p.targets.phi_end,
                floor: 0.0,
                bound_floor: 0.0,
                prepared: Some(p),
            })
            .collect();
        Self { lines: Vec::new(), entries, context: None, last: 0 }
    }

    /// Drops every representative left.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Whether every representative is taken or dropped.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The next representative whose bound is at most `best` (the least estimate, the first
    /// prepared of equal ones), prepared; those whose bound exceeds `best` are dropped.
    pub fn next(&mut self, planner: &ChainPlanner, problem: &ChainProblem, best: f64) -> Option<Prepared> {
        loop {
            self.entries.retain(|e| match &e.prepared {
                Some(p) => !(p.bound > best),
                None => !(e.bound_floor > best),
            });
            let order = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
            let first = |prepared: bool| {
                self.entries
                    .iter()
                    .enumerate()
                    .filter(|(_, e)| e.prepared.is_some() == prepared)
                    .map(|(k, e)| (k, (e.prepared.as_ref().map_or(e.floor, |p| p.estimate), e.index)))
                    .min_by(|a, b| order(&a.1, &b.1))
            };
            let (top, low) = (first(true), first(false));
            let k = match (top, low) {
                (None, None) => return None,
                (Some((k, _)), None) => k,
                (Some((k, t)), Some((_, l))) if order(&t, &l).is_lt() => k,
                (_, Some((k, _))) => {
                    self.prepare(planner, problem, k);
                    continue;
                }
            };
            if !self.beyond_gauge(planner, k, best) {
                return self.take(k);
            }
            self.entries.remove(k);
        }
    }

    /// Up to `count` more representatives of [`Self::next`] while `alike` holds for them (the
    /// first for which it does not is left first in the queue).
    pub fn more(
        &mut self,
        planner: &ChainPlanner,
        problem: &ChainProblem,
        best: f64,
        count: usize,
        alike: impl Fn(&Prepared) -> bool,
    ) -> Vec<Prepared> {
        let mut out = Vec::new();
        while out.len() < count {
            let Some(p) = self.next(planner, problem, best) else { break };
            if !alike(&p) {
                // Back in its place: the least of those left, it is the next again.
                let (index, phi_end) = (self.last, p.targets.phi_end);
                self.entries.push(Entry { index, line: 0, phi_end, floor: 0.0, bound_floor: 0.0, prepared: Some(p) });
                break;
            }
            out.push(p);
        }
        out
    }

    /// Whether the prepared entry `k`'s bound, raised to the gauge's ([`super::gauge`]) where a
    /// plan bounds the cost (`best` finite: the planner's gauge is made only then, and most plans
    /// of the paper's problem at a = b = 0.1 never need it), is above `best`.
    fn beyond_gauge(&mut self, planner: &ChainPlanner, k: usize, best: f64) -> bool {
        let Some(scale) = self.context.as_ref().map(|c| c.scale).filter(|_| best.is_finite()) else { return false };
        let Some(gauge) = planner.gauge.get(&planner.connection) else { return false };
        let Some(p) = self.entries[k].prepared.as_mut() else { return false };
        let holonomy = p.targets.phi_start - p.targets.phi_end;
        let enough = best / scale;
        let bound = scale * gauge.effort_bound(&p.line.start, &p.line.end, holonomy, p.line.horizon, enough);
        p.bound = p.bound.max(bound);
        p.bound > best
    }

    /// Removes entry `k`, prepared, and keeps its place.
    fn take(&mut self, k: usize) -> Option<Prepared> {
        let e = self.entries.remove(k);
        self.last = e.index;
        e.prepared
    }

    /// Prepares entry `k` (its line's holonomy computed once for all its base targets).
    fn prepare(&mut self, planner: &ChainPlanner, problem: &ChainProblem, k: usize) {
        let e = &mut self.entries[k];
        let (line, integral) = &mut self.lines[e.line];
        // The line's holonomy at rest (the initial-velocity term is small and ignored here).
        let integral = *integral.get_or_insert_with(|| line.holonomy(&planner.connection));
        let context = self.context.as_mut().expect("invariant: unprepared entries come with their context");
        e.prepared = Some(planner.representative(problem, line, integral, e.phi_end, context));
    }
}
