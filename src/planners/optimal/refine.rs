//! Refinement of a coarse solution: the basis doubles until the cost settles, then the
//! optimiser's quadrature is raised until the motion's finer quadrature agrees.

use super::{Candidate, OptimalPlanner, Tables, sqp};
use crate::error::Error;
use crate::plan::PlanningProblem;

impl OptimalPlanner {
    /// Refines a coarse solution: doubles the spans until the cost settles (or `max_spans`),
    /// then raises the quadrature nodes until the motion's finer quadrature agrees with the
    /// optimiser's to 1% of the tolerance.
    pub(super) fn refine(
        &self,
        problem: &PlanningProblem,
        mut c: Candidate,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let o = &self.options;
        let mut levels = Vec::new();
        let mut s = c.spans;
        while s < o.max_spans {
            s = (2 * s).min(o.max_spans);
            levels.push(s);
        }
        if levels.is_empty() {
            levels.push(c.spans);
        }
        let mut previous: Option<f64> = None;
        for spans in levels {
            c = self.resolve(problem, &c, spans, c.nodes, tables)?;
            if !c.result.converged() {
                return Ok(c);
            }
            if previous.is_some_and(|p| (c.result.f - p).abs() <= o.refinement_tolerance * c.result.f.abs()) {
                break;
            }
            previous = Some(c.result.f);
        }
        while c.nodes < 32 {
            let motion = self.motion_of(problem, &c, 0, 0);
            if motion.stats.holonomy_residual <= 0.01 * o.tolerance {
                c.motion = Some(motion);
                break;
            }
            c = self.resolve(problem, &c, c.spans, (2 * c.nodes).min(32), tables)?;
            if !c.result.converged() {
                break;
            }
        }
        Ok(c)
    }

    /// Solves on a basis of `spans` uniform spans and `nodes` quadrature nodes, warm-started by
    /// the projection of `c`'s joint path.
    pub(super) fn resolve(
        &self,
        problem: &PlanningProblem,
        c: &Candidate,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let disc = self.discretise(problem, *c.disc.targets(), spans, nodes, tables)?;
        let old = c.disc.coefficients(&c.result.x);
        let old_basis = c.disc.basis();
        let x0 = disc.project(|t| [old_basis.evaluate(&old[0], t)[0], old_basis.evaluate(&old[1], t)[0]])?;
        let result = sqp::solve(&disc, x0, &self.options.sqp, Some(c.result.lambda))?;
        let iterations = c.iterations + result.iterations;
        Ok(Candidate { disc, result, spans, nodes, iterations, motion: None })
    }
}
