//! One joint: `a(theta) dtheta` is exact, so `phi(T)` is fixed by `theta(T)`; the planner checks
//! the goal for consistency ([`Error::HolonomyFixed`]) and minimises the cost alone.

use std::time::Instant;

use nalgebra::DVector;

use super::discrete::{Discretisation, Targets};
use super::motion::ChainPlan;
use super::search::Candidate;
use super::seeds::Seed;
use super::starts::Prepared;
use super::tables::Tables;
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::model::wrap_angle;
use crate::planners::optimal::Cost;
use crate::planners::optimal::sqp::{Discretised, SqpResult, Termination};

impl ChainPlanner {
    /// One joint: `phi(T)` is fixed by `theta(T)`; a consistent representative's effort alone is
    /// minimised (the constraint holds on every path).
    pub(super) fn single_joint(
        &self,
        problem: &ChainProblem,
        prepared: Vec<Prepared>,
        tables: &Tables,
        clock: Instant,
    ) -> Result<ChainPlan, Error> {
        let o = &self.options;
        let (mut gap, mut nearest) = (f64::INFINITY, (f64::NAN, f64::NAN));
        let mut done: Vec<[f64; 2]> = Vec::new();
        for p in prepared {
            let key = [p.targets.end[0], 0.0];
            if done.contains(&key) {
                continue;
            }
            done.push(key);
            let reachable = p.targets.phi_start - p.line.holonomy(&self.connection);
            let g = wrap_angle(reachable - problem.goal[0]).abs();
            if g < gap {
                (gap, nearest) = (g, (p.targets.end[0], reachable));
            }
            if g > o.tolerance {
                continue;
            }
            let targets = Targets { phi_end: reachable, ..p.targets };
            let disc = self.discretise(problem, targets, o.max_spans, o.quadrature_nodes, tables)?;
            let x0 = disc.project(|t, out| p.line.path(Seed::Line, t, out))?;
            // The effort is quadratic: one Newton step from any point is its minimiser.
            let e = disc.evaluate(&x0, 1);
            let chol = disc.effort_cholesky().ok_or(Error::OptimalFailed {
                iterations: 0,
                constraint_residual: e.c.abs(),
                kkt_residual: f64::INFINITY,
                effort: e.f,
                seeds: 1,
                termination: "singular_effort_hessian",
            })?;
            let mut x = &x0 - chol.solve(&e.grad_f);
            if self.options.cost == Cost::Energy {
                x = minimise_energy(&disc, x);
            }
            let end = disc.evaluate(&x, 0);
            let result = SqpResult {
                x,
                lambda: 0.0,
                f: end.f,
                c: end.c,
                kkt: 0.0,
                iterations: 1,
                termination: Termination::Converged,
                kkt_tolerance: o.sqp.kkt_tolerance,
            };
            let iterations = result.iterations;
            let c = Candidate::new(disc, result, [o.max_spans, o.quadrature_nodes, o.grading], iterations);
            return self.certified(problem, &c, 1, c.iterations, clock);
        }
        Err(Error::HolonomyFixed {
            joints: 1,
            theta_goal: nearest.0,
            reachable: nearest.1,
            goal: problem.goal[0],
            gap,
            tolerance: o.tolerance,
        })
    }
}

/// The energy's minimiser from `x` (one joint: the constraint holds on every path): damped
/// Newton steps on the energy's Hessian, halved until the energy decreases, until the gradient
/// is below 1e-10 of the energy's scale or 50 steps.
fn minimise_energy(disc: &Discretisation, mut x: DVector<f64>) -> DVector<f64> {
    for _ in 0..50 {
        let e = disc.evaluate(&x, 2);
        if e.grad_f.norm() <= 1e-10 * e.f.abs().max(1e-12) {
            break;
        }
        let Some(chol) = e.hess_f_or(disc.effort_hessian()).clone().cholesky() else { break };
        let step = chol.solve(&e.grad_f);
        let mut t = 1.0;
        let mut improved = false;
        for _ in 0..30 {
            let trial = &x - &step * t;
            if disc.evaluate(&trial, 0).f < e.f {
                x = trial;
                improved = true;
                break;
            }
            t *= 0.5;
        }
        if !improved {
            break;
        }
    }
    x
}
