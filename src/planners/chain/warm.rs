//! The warm start of the chain planner ([`super::ChainOptions::warm_start`], the re-plans of
//! `track`): a given path solved, refined and certified to the representative it ends at, without
//! the search.

use std::time::Instant;

use super::discrete::Targets;
use super::motion::ChainPlan;
use super::search::{COARSE_SQP, Candidate};
use super::starts::Prepared;
use super::tables::Tables;
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::planners::optimal::sqp::{SqpOptions, Termination};

/// What a solve from a given path ([`ChainPlanner::solve_from`]) must end in for its plan to be
/// certified.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Ending {
    /// A refinement that converged (the warm start: the least cost near the path).
    Converged,
    /// A refinement that ends on the constraints, converged or stalled (moved onto the holonomy,
    /// [`super::limits::onto_holonomy`]), from a coarse solve that stopped within
    /// [`FEASIBLE_NEAR`] of it: a probe of the shortest horizon (`horizon.rs`) asks whether its
    /// horizon fits, the certificate deciding; the full search at the horizon found gives the
    /// least cost there.
    Feasible,
}

/// The holonomy residual \[rad\] under which a probe's coarse solve is refined
/// ([`Ending::Feasible`]; 1e-6 otherwise): on issue 21's SPART-like example at 0.02 m the probes'
/// coarse solves gave up their crawl 1.1e-6 to 2.3e-6 rad off the holonomy at horizons 0.5 to
/// 10 % under ones that fit.
const FEASIBLE_NEAR: f64 = 1e-5;

impl ChainPlanner {
    /// The plan of [`super::ChainOptions::warm_start`] when there is one ([`Self::warm`]);
    /// `prepared` keeps the representatives of a goal taken modulo 2 pi for the search.
    pub(super) fn warm_start(
        &self,
        problem: &ChainProblem,
        prepared: &mut Option<Vec<Prepared>>,
        tables: &Tables,
        clock: Instant,
    ) -> Result<Option<ChainPlan>, Error> {
        let Some(path) = &self.options.warm_start else { return Ok(None) };
        // A literal goal has one representative, found without the seeds (whose loops and
        // coils cost a re-plan more than its solve does).
        let targets = if problem.wrap {
            prepared.insert(self.prepare(problem)?).iter().map(|p| p.targets.clone()).collect()
        } else {
            self.literal_targets(problem)
        };
        self.warm(problem, path, &targets, tables, clock)
    }

    /// The warm start's plan: its projection on the coarse basis of the representative it ends
    /// at, solved, refined and certified; `None` when no representative matches or any step
    /// fails (the full search follows).
    fn warm(
        &self,
        problem: &ChainProblem,
        path: &super::WarmStart,
        representatives: &[Targets],
        tables: &Tables,
        clock: Instant,
    ) -> Result<Option<ChainPlan>, Error> {
        path.validate(self.arm.joints())?;
        let Some(end) = path.theta.last() else { return Ok(None) };
        let near = |t: &&Targets| t.end.iter().zip(end).all(|(a, b)| (a - b).abs() <= 1e-6);
        let Some(targets) = representatives.iter().find(near) else { return Ok(None) };
        let basis = (self.options.coarse_spans, self.options.grading);
        Ok(self
            .solve_from(problem, targets.clone(), path, (basis, None, &COARSE_SQP, Ending::Converged), tables, clock)?
            .ok())
    }

    /// The error of a warm start that gave no plan where no search follows
    /// ([`super::ChainOptions::warm_start_only`]).
    pub(super) fn warm_start_failed() -> Error {
        Error::OptimalFailed {
            iterations: 0,
            constraint_residual: f64::INFINITY,
            kkt_residual: f64::INFINITY,
            effort: f64::INFINITY,
            seeds: 1,
            termination: "warm_start",
        }
    }

    /// The plan from `path` to `targets` alone (no search): its projection on `spans` uniform
    /// spans with `grading` graded knots per end, solved with `options` (from the holonomy
    /// multiplier `guess` where one is known, see [`crate::planners::optimal::sqp::solve`]),
    /// refined (to what `ending` asks) and certified;
    /// where a step fails, the coarse solve's residual ([`SqpResult::c`]'s size: the holonomy's
    /// or the largest scaled violation of a limit) when that one ended off the constraints, else
    /// NaN.
    ///
    /// [`SqpResult::c`]: crate::planners::optimal::sqp::SqpResult::c
    pub(super) fn solve_from(
        &self,
        problem: &ChainProblem,
        targets: Targets,
        path: &super::WarmStart,
        ((spans, grading), guess, options, ending): ((usize, usize), Option<f64>, &SqpOptions, Ending),
        tables: &Tables,
        clock: Instant,
    ) -> Result<Result<ChainPlan, f64>, Error> {
        let o = &self.options;
        let disc = self.discretise_graded(problem, targets, [spans, o.quadrature_nodes, grading], tables)?;
        let Ok(x0) = disc.project(|t, out| path.at(t, out)) else { return Ok(Err(f64::NAN)) };
        let Ok(result) = super::limits::solve(self, &disc, x0, options, guess) else { return Ok(Err(f64::NAN)) };
        let near = if ending == Ending::Feasible { FEASIBLE_NEAR } else { 1e-6 };
        if !(result.c.abs() <= near && result.f.is_finite()) {
            return Ok(Err(if result.f.is_finite() { result.c.abs() } else { f64::NAN }));
        }
        let (nodes, iterations) = (o.quadrature_nodes, result.iterations);
        let mut c = self.refine(problem, Candidate::new(disc, result, [spans, nodes, grading], iterations), tables)?;
        if ending == Ending::Feasible && c.feasible() && c.result.termination != Termination::Abandoned {
            super::limits::onto_holonomy(self, &c.disc, &mut c.result);
        } else if !c.result.converged() {
            return Ok(Err(f64::NAN));
        }
        let iterations = c.iterations;
        // Under the clearance between the rows' points, solved again keeping more (issue 21);
        // a plan that still does not clear is returned for the caller to judge.
        Ok(match self.certified_clear(problem, &c, 1, iterations, clock, tables) {
            Ok(Ok(plan) | Err(plan)) => Ok(plan),
            Err(_) => Err(f64::NAN),
        })
    }
}
