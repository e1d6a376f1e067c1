//! The chain planner's search: goal representatives ranked by their seeds' estimated effort,
//! every seed solved on the coarse basis, the best feasible solution refined, the plan certified.

use std::cell::RefCell;
use std::f64::consts::TAU;
use std::sync::Arc;
use std::time::Instant;

use nalgebra::DVector;

use super::discrete::{Discretisation, Table, Targets};
use super::motion::{ChainPlan, ChainStats};
use super::seeds::{self, Line, Seed};
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::model::wrap_angle;
use crate::plan::certificate::verify_chain;
use crate::planners::optimal::Cost;
use crate::planners::optimal::spline::SplineBasis;
use crate::planners::optimal::sqp::{Discretised, SqpOptions, SqpResult, Termination};

/// SQP options of the coarse solves.
const COARSE_SQP: SqpOptions =
    SqpOptions { max_iterations: 40, constraint_tolerance: 1e-10, kkt_tolerance: 1e-6, stall_iterations: 6 };

/// The tables built in one planning call, by (uniform spans, quadrature nodes).
#[derive(Default)]
pub(super) struct Tables(RefCell<Vec<TableEntry>>);

/// A cached table with its (uniform spans, quadrature nodes).
type TableEntry = ((usize, usize), Arc<Table>);

/// A solve: its discretisation and result.
struct Candidate {
    disc: Discretisation,
    result: SqpResult,
    spans: usize,
    nodes: usize,
    iterations: usize,
}

/// A representative with its line and seeds.
struct Prepared {
    targets: Targets,
    line: Line,
    seeds: Vec<Seed>,
    estimate: f64,
    bound: f64,
}

impl ChainPlanner {
    /// Plans and certifies: the certified plan of least effort among the candidates, or the
    /// error of the best attempt ([`Error::OptimalFailed`], [`Error::NotCertified`],
    /// [`Error::HolonomyFixed`] for one joint and an inconsistent goal).
    pub fn plan(&self, problem: &ChainProblem) -> Result<ChainPlan, Error> {
        self.options.validate()?;
        problem.validate(&self.arm)?;
        let clock = Instant::now();
        let tables = Tables::default();
        let prepared = self.prepare(problem)?;
        if self.arm.joints() == 1 {
            return self.single_joint(problem, prepared, &tables, clock);
        }
        let o = &self.options;
        if let Some(path) = &o.warm_start
            && let Some(plan) = self.warm(problem, path, &prepared, &tables, clock)?
        {
            return Ok(plan);
        }
        let (mut seeds, mut iterations) = (0, 0);
        let mut best_failure: Option<Candidate> = None;
        let mut not_certified: Option<Error> = None;
        // Batches of representatives, least effort bound first (branch and bound), skipping those
        // whose bound exceeds the best effort found; every converged refinement is kept.
        let mut best = f64::INFINITY;
        let mut done: Vec<Candidate> = Vec::new();
        let mut queue = prepared.into_iter().peekable();
        while queue.peek().is_some() {
            let mut coarse = Vec::new();
            let mut taken = 0;
            while taken < o.targets_solved {
                let Some(p) = queue.next() else { break };
                if p.bound > best {
                    continue;
                }
                taken += 1;
                let disc = self.discretise(problem, p.targets.clone(), o.coarse_spans, o.quadrature_nodes, &tables)?;
                for result in self.solve_seeds(&disc, &p)? {
                    seeds += 1;
                    iterations += result.iterations;
                    let (spans, nodes, its) = (o.coarse_spans, o.quadrature_nodes, result.iterations);
                    coarse.push(Candidate { disc: disc.clone(), result, spans, nodes, iterations: its });
                }
            }
            let feasible = |c: &Candidate| c.result.c.abs() <= 1e-6 && c.result.f.is_finite();
            coarse.sort_by(|a, b| feasible(b).cmp(&feasible(a)).then(a.result.f.total_cmp(&b.result.f)));
            // Finalists: the best, and the next within 20% of it (a coarse solution further off
            // rarely overtakes on refinement), not above the best refined effort so far.
            let first = coarse.first().filter(|c| feasible(c)).map_or(f64::INFINITY, |c| c.result.f);
            let mut finalists: Vec<Candidate> = Vec::new();
            for c in coarse {
                let too_high = feasible(&c) && (c.result.f > 1.2 * first || c.result.f > best);
                if finalists.len() >= o.finalists || (!finalists.is_empty() && too_high) {
                    break;
                }
                let f = c.result.f;
                if !finalists.iter().any(|d| (d.result.f - f).abs() <= 1e-6 * f.abs().max(1e-12)) {
                    finalists.push(c);
                }
            }
            for c in finalists {
                let c = self.refine(problem, c, &tables)?;
                iterations += c.iterations;
                if c.result.converged() {
                    best = best.min(c.result.f);
                    done.push(c);
                } else if best_failure.as_ref().is_none_or(|b| c.result.c.abs() < b.result.c.abs()) {
                    best_failure = Some(c);
                }
            }
        }
        done.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
        for c in &done {
            match self.certified(problem, c, seeds, iterations, clock) {
                Ok(plan) => return Ok(plan),
                Err(e) => not_certified = not_certified.or(Some(e)),
            }
        }
        if let Some(e) = not_certified {
            return Err(e);
        }
        Err(match best_failure {
            Some(b) => Error::OptimalFailed {
                iterations: b.iterations,
                constraint_residual: b.result.c.abs(),
                kkt_residual: b.result.kkt,
                effort: b.result.f,
                seeds,
                termination: termination_name(b.result.termination),
            },
            None => Error::OptimalFailed {
                iterations,
                constraint_residual: f64::INFINITY,
                kkt_residual: f64::INFINITY,
                effort: f64::INFINITY,
                seeds,
                termination: "no_candidate",
            },
        })
    }

    /// The warm start's plan: its projection on the coarse basis of the representative it ends
    /// at, solved, refined and certified; `None` when no representative matches or any step
    /// fails (the full search follows).
    fn warm(
        &self,
        problem: &ChainProblem,
        path: &super::WarmStart,
        prepared: &[Prepared],
        tables: &Tables,
        clock: Instant,
    ) -> Result<Option<ChainPlan>, Error> {
        path.validate(self.arm.joints())?;
        let o = &self.options;
        let Some(end) = path.theta.last() else { return Ok(None) };
        let near = |p: &&Prepared| p.targets.end.iter().zip(end).all(|(a, b)| (a - b).abs() <= 1e-6);
        let Some(p) = prepared.iter().find(near) else { return Ok(None) };
        let disc = self.discretise(problem, p.targets.clone(), o.coarse_spans, o.quadrature_nodes, tables)?;
        let Ok(x0) = disc.project(|t, out| path.at(t, out)) else { return Ok(None) };
        let Ok(result) = super::limits::solve(self, &disc, x0, &COARSE_SQP, None) else { return Ok(None) };
        if !(result.c.abs() <= 1e-6 && result.f.is_finite()) {
            return Ok(None);
        }
        let (spans, nodes, iterations) = (o.coarse_spans, o.quadrature_nodes, result.iterations);
        let c = self.refine(problem, Candidate { disc, result, spans, nodes, iterations }, tables)?;
        if !c.result.converged() {
            return Ok(None);
        }
        let iterations = c.iterations;
        Ok(self.certified(problem, &c, 1, iterations, clock).ok())
    }

    /// The discretisation of `targets` on `spans` uniform spans and `nodes` nodes per span.
    pub(super) fn discretise(
        &self,
        problem: &ChainProblem,
        targets: Targets,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Discretisation, Error> {
        let cached = tables.0.borrow().iter().find(|(key, _)| *key == (spans, nodes)).map(|(_, t)| t.clone());
        let table = match cached {
            Some(t) => t,
            None => {
                let basis = SplineBasis::graded(self.degree(), problem.horizon, spans, self.options.grading)?;
                let t = Arc::new(Table::new(basis, self.arm.joints(), self.fixed(), nodes)?);
                tables.0.borrow_mut().push(((spans, nodes), t.clone()));
                t
            }
        };
        let disc = Discretisation::on(self.connection.clone(), table, targets);
        Ok(match self.options.cost {
            Cost::Effort => disc,
            Cost::Energy => disc.with_energy(self.arm.clone()),
        })
    }

    /// The goal representatives with their lines and seeds, least effort bound first: `phid`, `phid +- 2 pi` nearest
    /// the start, with `wrap` the joint goals nearest it and one joint a turn further; only those inside the ranges.
    fn prepare(&self, problem: &ChainProblem) -> Result<Vec<Prepared>, Error> {
        let n = self.arm.joints();
        let (q0, qd) = (&problem.start, &problem.goal);
        let theta0 = q0[1..].to_vec();
        let mut joint_goals = Vec::new();
        if problem.wrap {
            let near: Vec<f64> = (1..=n).map(|j| q0[j] + wrap_angle(qd[j] - q0[j])).collect();
            joint_goals.push(near.clone());
            for j in 0..n {
                for turn in [-TAU, TAU] {
                    let mut g = near.clone();
                    g[j] += turn;
                    joint_goals.push(g);
                }
            }
        } else {
            joint_goals.push(qd[1..].to_vec());
        }
        let mut phi_targets: Vec<f64> = if problem.wrap {
            let near = q0[0] + wrap_angle(qd[0] - q0[0]);
            vec![near, near - TAU, near + TAU]
        } else {
            vec![qd[0]]
        };
        super::limits::inside_ranges(&self.arm.limits, &mut joint_goals, &mut phi_targets);
        let kappa_max = seeds::curvature_bound(&self.connection);
        // The bound is in the cost's units: the energy's is the effort's times a floor of R.
        let scale = match self.options.cost {
            Cost::Effort => 1.0,
            Cost::Energy => super::energy::energy_floor(&self.arm),
        };
        let mut out = Vec::new();
        for end in joint_goals {
            let line = Line {
                start: theta0.clone(),
                end: end.clone(),
                initial_velocity: problem.initial_velocity.clone(),
                horizon: problem.horizon,
            };
            // The line's holonomy at rest (the initial-velocity term is small and ignored here).
            let integral = line.holonomy(&self.connection);
            for &phi_end in &phi_targets {
                let needed = phi_end - (q0[0] - integral);
                let loops =
                    line.loops(&self.connection, needed, self.options.loop_planes, self.options.max_loop_radius);
                let estimate = if needed.abs() < 1e-9 || loops.is_empty() {
                    line.effort_estimate(Seed::Line)
                } else {
                    loops.iter().map(|s| line.effort_estimate(*s)).fold(f64::INFINITY, f64::min)
                };
                let mut seeds = vec![Seed::Line];
                seeds.extend(loops);
                let targets = Targets {
                    start: theta0.clone(),
                    initial_velocity: problem.initial_velocity.clone(),
                    end: end.clone(),
                    phi_start: q0[0],
                    phi_end,
                };
                let bound = scale * seeds::effort_lower_bound(&line, needed, kappa_max);
                out.push(Prepared { targets, line: line.clone(), seeds, estimate, bound });
            }
        }
        out.sort_by(|a, b| a.bound.total_cmp(&b.bound).then(a.estimate.total_cmp(&b.estimate)));
        Ok(out)
    }

    /// The coarse solutions of a representative: from the line, then from each loop as
    /// estimated and re-fitted to the constraint, the loops only where the line's solution is
    /// infeasible or costs more than two thirds of the loop's constant-speed effort estimate (a
    /// loop longer than that cannot do better).
    fn solve_seeds(&self, disc: &Discretisation, p: &Prepared) -> Result<Vec<SqpResult>, Error> {
        let line = &p.line;
        let project = |seed: Seed| disc.project(|t, out| line.path(seed, t, out));
        let mut out: Vec<SqpResult> = Vec::new();
        let mut line_effort = f64::INFINITY;
        for &seed in &p.seeds {
            if seed == Seed::Line {
                if let Ok(r) = super::limits::solve(self, disc, project(seed)?, &COARSE_SQP, None) {
                    if r.c.abs() <= 1e-6 {
                        line_effort = r.f;
                    }
                    out.push(r);
                }
                continue;
            }
            if line.effort_estimate(seed) > 1.5 * line_effort {
                continue;
            }
            let residual = |s: Seed| project(s).map_or(f64::NAN, |x| disc.evaluate(&x, 0).c);
            let fitted = line.fit_radius(seed, self.options.max_loop_radius, residual);
            if let Ok(r) = super::limits::solve(self, disc, project(fitted)?, &COARSE_SQP, None) {
                out.push(r);
            }
        }
        Ok(out)
    }

    /// Doubles the spans until the effort settles (or `max_spans`), then raises the quadrature
    /// nodes until the finer quadrature of the plan's base angle agrees to 1% of the tolerance.
    fn refine(&self, problem: &ChainProblem, mut c: Candidate, tables: &Tables) -> Result<Candidate, Error> {
        let o = &self.options;
        let mut previous: Option<f64> = None;
        let mut spans = c.spans;
        while spans < o.max_spans {
            spans = (2 * spans).min(o.max_spans);
            c = self.resolve(problem, &c, spans, c.nodes, tables)?;
            if !c.result.converged() {
                return Ok(c);
            }
            if previous.is_some_and(|p| (c.result.f - p).abs() <= o.refinement_tolerance * c.result.f.abs()) {
                break;
            }
            previous = Some(c.result.f);
        }
        if c.spans == self.options.coarse_spans {
            c = self.resolve(problem, &c, c.spans, c.nodes, tables)?;
        }
        while c.nodes < 32 && self.holonomy_residual(&c) > 0.01 * o.tolerance {
            c = self.resolve(problem, &c, c.spans, (2 * c.nodes).min(32), tables)?;
            if !c.result.converged() {
                break;
            }
        }
        Ok(c)
    }

    /// `|phi(T) - phi_end|` of the candidate with the plan's finer quadrature.
    fn holonomy_residual(&self, c: &Candidate) -> f64 {
        let plan = self.plan_of(c, ChainStats::default_for(c));
        let t = c.disc.basis().horizon();
        (plan.phi(t) - c.disc.targets().phi_end).abs()
    }

    /// Solves on `spans` and `nodes`, warm-started by the projection of `c`'s path.
    fn resolve(
        &self,
        problem: &ChainProblem,
        c: &Candidate,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let disc = self.discretise(problem, c.disc.targets().clone(), spans, nodes, tables)?;
        let old = c.disc.coefficients(&c.result.x);
        let old_basis = c.disc.basis();
        let x0 = disc.project(|t, out| {
            for (o, cj) in out.iter_mut().zip(&old) {
                *o = old_basis.evaluate(cj, t)[0];
            }
        })?;
        let guess = if self.arm.joints() == 1 { None } else { Some(c.result.lambda) };
        let result = super::limits::solve(self, &disc, x0, &self.options.sqp, guess)?;
        let iterations = c.iterations + result.iterations;
        Ok(Candidate { disc, result, spans, nodes, iterations })
    }

    fn plan_of(&self, c: &Candidate, stats: ChainStats) -> ChainPlan {
        let coefficients = c.disc.coefficients(&c.result.x);
        let phi0 = c.disc.targets().phi_start;
        ChainPlan::new(self.connection.clone(), c.disc.basis().clone(), coefficients, phi0, stats)
    }

    /// The plan of a converged candidate with its statistics and certificate; an error when the
    /// certificate fails.
    fn certified(
        &self,
        problem: &ChainProblem,
        c: &Candidate,
        seeds: usize,
        iterations: usize,
        clock: Instant,
    ) -> Result<ChainPlan, Error> {
        let mut stats = ChainStats::default_for(c);
        stats.seeds = seeds;
        stats.iterations = iterations;
        let mut plan = self.plan_of(c, stats);
        plan.stats.holonomy_residual = (plan.phi(problem.horizon) - c.disc.targets().phi_end).abs();
        plan.stats.peak_velocity = peak_velocity(&plan);
        plan.stats.plan_seconds = clock.elapsed().as_secs_f64();
        let o = &self.options;
        plan.verification = verify_chain(&self.arm, &plan, &problem.start, &problem.goal, &o.ode, o.tolerance)?;
        if plan.verification.certified {
            Ok(plan)
        } else {
            Err(Error::NotCertified {
                final_error: plan.verification.final_error,
                tolerance: o.tolerance,
                level: "velocity",
            })
        }
    }

    /// One joint: `phi(T)` is fixed by `theta(T)`; a consistent representative's effort alone is
    /// minimised (the constraint holds on every path).
    fn single_joint(
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
            let c = Candidate {
                disc,
                iterations: result.iterations,
                result,
                spans: o.max_spans,
                nodes: o.quadrature_nodes,
            };
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

impl ChainStats {
    /// The statistics of a candidate before the plan measures it.
    fn default_for(c: &Candidate) -> Self {
        Self {
            iterations: c.iterations,
            seeds: 0,
            effort: c.disc.integrals(&c.result.x).1,
            cost: c.result.f,
            peak_velocity: f64::NAN,
            holonomy_residual: f64::NAN,
            kkt_residual: c.result.kkt,
            multiplier: c.result.lambda,
            termination: c.result.termination,
            spans: c.spans,
            quadrature_nodes: c.nodes,
            plan_seconds: f64::NAN,
        }
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
        let Some(chol) = e.hess_f.clone().cholesky() else { break };
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

/// Largest `|theta_j'|` over joints at 16 points per knot span \[rad/s\].
fn peak_velocity(plan: &ChainPlan) -> f64 {
    let b = plan.basis().breakpoints();
    let mut peak: f64 = 0.0;
    for w in b.windows(2) {
        for k in 0..=16 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 16.0;
            for c in plan.coefficients() {
                peak = peak.max(plan.basis().evaluate(c, t)[1].abs());
            }
        }
    }
    peak
}

fn termination_name(t: Termination) -> &'static str {
    match t {
        Termination::Converged => "converged",
        Termination::MaxIterations => "max_iterations",
        Termination::RadiusCollapsed => "radius_collapsed",
        Termination::DegenerateConstraint => "degenerate_constraint",
        Termination::Stalled => "stalled",
    }
}
