//! The chain planner where the arm keeps a clearance (issue 21): the search without the
//! clearance rows first, its plan repaired in its own basin where it does not clear, the search
//! with the rows of the robot's own bodies last; and the certificate's clearance retries.

use std::sync::Arc;
use std::time::Instant;

use super::discrete::Targets;
use super::motion::ChainPlan;
use super::search::{Candidate, Tables};
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;

/// How many times a plan under the clearance between the rows' points is solved again.
const CLEARANCE_RETRIES: usize = 3;

impl ChainPlanner {
    /// [`Self::plan`] where the arm keeps a clearance. First the search without the clearance
    /// rows: where its plan clears, it is the
    /// constrained minimum too (the rows would not be active), found at the unconstrained
    /// search's speed. Else, where there are obstacles, that plan pushed clear by the rows in its
    /// own basin (a few solves on its own basis); else the search with the rows of the robot's own bodies (every seed
    /// under them; the obstacles' rows are dense, and that search would not be bounded in
    /// time), its plan pushed clear of the obstacles likewise. Where none clears, the least
    /// bad is returned for its certificate to report (the pair, the time and the depth).
    pub(super) fn plan_keeping_clearance(
        &self,
        problem: &ChainProblem,
        tables: &Tables,
        clock: Instant,
    ) -> Result<ChainPlan, Error> {
        let clears = |p: &ChainPlan| p.verification.clearance.is_none_or(|r| r.holds());
        // A re-plan: the rest of a plan that clears, solved with every row from itself first
        // (without the rows it slides into the unconstrained basin, e.g. 0.27 m inside the base
        // on the SPART-like arm's track, and no repair pulls it back out in time).
        if let Some(plan) = self.warm_start(problem, &mut None, tables, clock)?.filter(clears) {
            return Ok(plan);
        }
        let own = ChainPlanner { obstacle_rows: false, ..self.clone() };
        let with_own_rows = super::limits::keeps_clearance(&own);
        let free = ChainPlanner { clearance_rows: false, ..self.clone() }.plan(problem);
        let Ok(free) = free else {
            return if with_own_rows { own.search(problem, tables, clock) } else { free };
        };
        if clears(&free) {
            return Ok(free);
        }
        // The repair pulls a plan clear of obstacles (the track tests' re-plans). Clear of the
        // robot's own bodies it is a local fix in the free plan's basin: it did not converge on
        // the SPART-like bench at eight clearances nor on 7 of the 8 random problems that need
        // it (`examples/profile_clearance.rs random`; from 0.25 m inside the base the rows push
        // toward the nearest face, off the holonomy), at 0.7 to 0.8 s a time, and where it did
        // (problem 8) the search with the rows finds 0.9 to 2 % less effort (3.8961 against
        // 3.9323 at 0 m, 3.9525 / 4.0296 at 0.02 m, 4.0576 / 4.0896 at 0.04 m). So without
        // obstacles the search with the rows follows at once.
        let obstacles = !self.arm.geometry.obstacles.is_empty();
        if obstacles && let Ok(Some(repaired)) = self.repair(problem, &free, tables, clock) {
            return Ok(repaired);
        }
        if !with_own_rows {
            return Ok(free);
        }
        let kept = match own.search(problem, tables, clock) {
            Ok(k) if !clears(&k) && !self.arm.geometry.obstacles.is_empty() => {
                match self.repair(problem, &k, tables, clock) {
                    Ok(Some(repaired)) => return Ok(repaired),
                    _ => Ok(k),
                }
            }
            kept => kept,
        };
        let least = |p: &ChainPlan| p.verification.clearance.map_or(f64::INFINITY, |r| r.min);
        match kept {
            Ok(k) if least(&free) > least(&k) => Ok(free),
            Err(_) => Ok(free),
            kept => kept,
        }
    }

    /// The certified plan that keeps the clearance from `free`'s path: solved with the rows on
    /// `free`'s own basis from its exact coefficients, to the goal representative it reaches,
    /// then [`Self::certified_clear`]; `None` when the solve does not converge or no plan clears
    /// (an error, e.g. a failed projection, likewise leaves the caller's plan as it is).
    fn repair(
        &self,
        problem: &ChainProblem,
        free: &ChainPlan,
        tables: &Tables,
        clock: Instant,
    ) -> Result<Option<ChainPlan>, Error> {
        let end = free.at(problem.horizon);
        let near = |x: f64, goal: f64| goal + std::f64::consts::TAU * ((x - goal) / std::f64::consts::TAU).round();
        let targets = Targets {
            start: problem.start[1..].to_vec(),
            initial_velocity: problem.initial_velocity.clone(),
            end: end.theta.iter().zip(&problem.goal[1..]).map(|(x, g)| near(*x, *g)).collect(),
            phi_start: problem.start[0],
            phi_end: near(end.phi, problem.goal[0]),
        };
        let (spans, nodes, grading) = (free.stats.spans, free.stats.quadrature_nodes, free.stats.grading);
        let disc = self.discretise_graded(problem, targets, [spans, nodes, grading], tables)?;
        let x0 = disc.project(|t, out| {
            for (o, c) in out.iter_mut().zip(&free.coefficients) {
                *o = free.basis.evaluate(c, t)[0];
            }
        })?;
        let Ok(result) = super::limits::solve(self, &disc, x0, &self.options.sqp, Some(free.stats.multiplier)) else {
            return Ok(None);
        };
        if !result.converged() {
            return Ok(None);
        }
        let iterations = result.iterations;
        let c = Candidate { disc, result, spans, nodes, grading, iterations, stands_for: None };
        Ok(self.certified_clear(problem, &c, 1, iterations, clock, tables).ok().and_then(Result::ok))
    }

    /// [`Self::certified`], and where the certified plan comes under the clearance (the rows
    /// hold at their points only, see [`super::limits`]), the candidate solved again with the
    /// rows keeping the deficit twice over, up to [`CLEARANCE_RETRIES`] times; `Ok(Err(plan))`
    /// with the closest plan when none clears.
    pub(super) fn certified_clear(
        &self,
        problem: &ChainProblem,
        c: &Candidate,
        seeds: usize,
        iterations: usize,
        clock: Instant,
        tables: &Tables,
    ) -> Result<Result<ChainPlan, ChainPlan>, Error> {
        let mut plan = self.certified(problem, c, seeds, iterations, clock)?;
        if !super::limits::keeps_clearance(self) {
            return Ok(if plan.verification.clearance.is_none_or(|r| r.holds()) { Ok(plan) } else { Err(plan) });
        }
        let required = self.arm.geometry.clearance;
        let mut keep = required;
        for _ in 0..CLEARANCE_RETRIES {
            let Some(report) = plan.verification.clearance.filter(|r| !r.holds()) else { return Ok(Ok(plan)) };
            keep += 2.0 * (required - report.min);
            let mut arm = (*self.arm).clone();
            arm.geometry.clearance = keep;
            let stricter = ChainPlanner { arm: Arc::new(arm), ..self.clone() };
            let again = stricter.resolve(problem, c, c.spans, c.nodes, tables)?;
            if !again.result.converged() {
                break;
            }
            match self.certified(problem, &again, seeds, iterations + again.iterations, clock) {
                Ok(p) => {
                    plan = p;
                    plan.stats.clearance_reserve += keep - required;
                }
                Err(_) => break,
            }
        }
        if plan.verification.clearance.is_none_or(|r| r.holds()) { Ok(Ok(plan)) } else { Ok(Err(plan)) }
    }
}
