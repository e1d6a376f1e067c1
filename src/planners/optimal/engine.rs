//! The two-joint planner's solve-and-refine engine, kept as the engine of the test oracle
//! ([`super::reference`]) and of the tests that check a plan against the paper's two-joint
//! discretisation (issue 19: the planner itself is the one for every arm,
//! [`crate::planners::chain`]): a coarse solve of a seed on a basis of uniform spans, refined by
//! doubling the spans until the cost settles, then raising the quadrature until the motion's
//! finer quadrature agrees.

use std::cell::RefCell;
use std::sync::Arc;

use super::discrete::{Discretisation, Table, Targets};
use super::motion::OptimalMotion;
use super::seeds::Sampled;
use super::spline::SplineBasis;
use super::sqp::{self, SqpOptions};
use super::{OptimalPlanner, OptimalStats};
use crate::error::Error;
use crate::plan::{Motion, PlanningProblem};
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::{NfaOptions, NormalFormPlanner};

/// Uniform knot spans per turn of a coil seed (cubic B-splines follow a circle to about 1e-3 of
/// its radius at this resolution; the radius is then re-fitted to the constraint).
pub(crate) const SPANS_PER_TURN: usize = 6;

/// A solve in progress: a target, its discretisation and the SQP result on it.
pub(crate) struct Candidate {
    pub disc: Discretisation,
    pub result: sqp::SqpResult,
    pub spans: usize,
    pub nodes: usize,
    pub iterations: usize,
    /// The motion of `result`, where the refinement built it to check its quadrature.
    pub motion: Option<OptimalMotion>,
}

/// The discretisation tables built in one planning call, by (uniform spans, quadrature nodes).
#[derive(Default)]
pub(crate) struct Tables(RefCell<Vec<TableEntry>>);

/// A cached table with its (uniform spans, quadrature nodes).
type TableEntry = ((usize, usize), Arc<Table>);

/// SQP options of the coarse ranking solves ([`SqpOptions::COARSE`]).
pub(crate) const COARSE_SQP: SqpOptions = SqpOptions::COARSE;

impl OptimalPlanner {
    fn basis(&self, horizon: f64, spans: usize) -> Result<SplineBasis, Error> {
        SplineBasis::graded(if self.options.smooth_ends { 5 } else { 3 }, horizon, spans, self.options.grading)
    }

    /// The problem of `targets` on `spans` uniform spans and `nodes` quadrature nodes, its
    /// tables built once per planning call.
    pub(crate) fn discretise(
        &self,
        problem: &PlanningProblem,
        targets: Targets,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Discretisation, Error> {
        let o = &self.options;
        let cached = tables.0.borrow().iter().find(|(key, _)| *key == (spans, nodes)).map(|(_, t)| t.clone());
        let table = match cached {
            Some(t) => t,
            None => {
                let t = Arc::new(Table::new(self.basis(problem.horizon, spans)?, o.smooth_ends, nodes)?);
                tables.0.borrow_mut().push(((spans, nodes), t.clone()));
                t
            }
        };
        Ok(Discretisation::on(problem.robot.lumped(), o.cost, table, targets))
    }

    /// The exact motion of a candidate with the plan's statistics (the motion the refinement
    /// built to check its quadrature, where it did).
    pub(crate) fn to_motion(
        &self,
        problem: &PlanningProblem,
        mut c: Candidate,
        seeds: usize,
        total_iterations: usize,
    ) -> OptimalMotion {
        if let Some(mut motion) = c.motion.take() {
            let holonomy_residual = motion.stats.holonomy_residual;
            motion.stats = Self::stats(&c, seeds, total_iterations);
            motion.stats.holonomy_residual = holonomy_residual;
            return motion;
        }
        self.motion_of(problem, &c, seeds, total_iterations)
    }

    /// The statistics of a candidate (`holonomy_residual` NaN: the motion measures it).
    fn stats(c: &Candidate, seeds: usize, total_iterations: usize) -> OptimalStats {
        let targets = *c.disc.targets();
        OptimalStats {
            iterations: total_iterations,
            final_iterations: c.result.iterations,
            cost: c.result.f,
            effort: c.disc.effort(&c.result.x),
            constraint_residual: c.result.c.abs(),
            holonomy_residual: f64::NAN,
            kkt_residual: c.result.kkt,
            multiplier: c.result.lambda,
            termination: c.result.termination,
            spans: c.spans,
            degree: c.disc.basis().degree(),
            quadrature_nodes: c.nodes,
            seeds,
            theta_end: targets.end,
            phi_end: targets.phi_end,
        }
    }

    /// The exact motion of a candidate, its holonomy residual measured by the motion's quadrature.
    fn motion_of(
        &self,
        problem: &PlanningProblem,
        c: &Candidate,
        seeds: usize,
        total_iterations: usize,
    ) -> OptimalMotion {
        let targets = *c.disc.targets();
        let coefficients = c.disc.coefficients(&c.result.x);
        let stats = Self::stats(c, seeds, total_iterations);
        let mut motion =
            OptimalMotion::new(problem.robot.lumped(), c.disc.basis().clone(), coefficients, problem.start.phi, stats);
        let phi_t = motion.at(problem.horizon).map(|p| p.q.phi).unwrap_or(f64::NAN);
        motion.stats.holonomy_residual = (phi_t - targets.phi_end).abs();
        motion
    }

    /// The NFA's joint path, sampled, when the NFA plans this problem.
    pub(crate) fn nfa_path(&self, problem: &PlanningProblem) -> Option<(Sampled, [f64; 2], f64)> {
        // The paper's transformation only: the global normal form's band steering costs more than
        // the whole optimisation.
        let n = 101;
        let options = NfaOptions { samples: n, transform: Some(Transform::auto(&problem.robot)), ..Default::default() };
        let motion = NormalFormPlanner::new(options).motion(problem).ok()?;
        let times: Vec<f64> = (0..n)
            .map(|i| if i + 1 == n { problem.horizon } else { problem.horizon * i as f64 / (n - 1) as f64 })
            .collect();
        let points = motion.points(&times).ok()?;
        let theta: Vec<[f64; 2]> = points.iter().map(|p| [p.q.theta1, p.q.theta2]).collect();
        let rate: Vec<[f64; 2]> = points.iter().map(|p| p.u).collect();
        let last = points.last()?.q;
        Some((Sampled { t: times, theta, rate }, [last.theta1, last.theta2], last.phi))
    }
}

impl OptimalPlanner {
    /// Refines a coarse solution: doubles the spans until the cost settles (or `max_spans`),
    /// then raises the quadrature nodes until the motion's finer quadrature agrees with the
    /// optimiser's to 1% of the tolerance.
    pub(crate) fn refine(
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
    pub(crate) fn resolve(
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
