//! Minimum-effort motion planning (issue 11): the joint path that minimises
//! `J = integral_0^T |theta'|^2 dt` (or the kinetic energy) among those that reach the goal's
//! joint angles at rest and turn the base to its goal angle.
//!
//! `phi` is cyclic: with zero angular momentum (Eq. 5) it follows the joint path,
//! `phi(t) = phi0 - integral_0^t (G theta1' + H theta2') / F ds` (Eqs. 7-8), and `F > 0` on the
//! whole torus, so a plan is a joint path alone, subject to one scalar holonomy constraint
//! `phi(T) = phi_d`, across the posture singularity `sigma = 0` (Eq. 9) as freely as anywhere.
//!
//! The method:
//! 1. joint paths are clamped cubic B-splines (quintic with [`OptimalOptions::smooth_ends`]) whose
//!    knots are graded geometrically toward both ends, the end conditions built into the first
//!    and last coefficients ([`spline`]); cost and holonomy are Gauss–Legendre sums per knot span
//!    with exact gradients and Hessians ([`discrete`], [`holonomy`]);
//! 2. a Byrd–Omojokun trust-region SQP ([`sqp`]) solves the equality-constrained problem from
//!    several seeds ([`seeds`]): the straight line, loops on either side of it and one along
//!    `theta1` (the n-joint planner's; or a coil where one loop cannot turn the base far
//!    enough), the NFA's path, for each representative of the goal modulo 2 pi; they are solved
//!    on a coarse basis in batches of representatives, best estimate first, the best of each
//!    batch refined on finer bases until the cost settles, until every representative left is
//!    bounded out by its effort lower bound or estimated far above the best plan;
//! 3. the result is an exact [`OptimalMotion`], certified like every plan of the crate.

pub mod band;
pub mod discrete;
pub mod holonomy;
pub mod motion;
#[cfg(test)]
pub(crate) mod reference;
pub mod refine;
pub mod search;
pub mod seeds;
pub mod spline;
pub mod sqp;

use std::cell::RefCell;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::error::Error;
use crate::model::InputError;
use crate::numerics::ode::OdeOptions;
use crate::plan::{Method, Motion, Plan, PlanningProblem};
use crate::planners::{Details, Planned, Planner};

use discrete::{Discretisation, Table, Targets};

pub use motion::{OptimalMotion, OptimalStats};
pub use seeds::Sampled;
use spline::SplineBasis;
pub use sqp::{SqpOptions, Termination};

/// The cost minimised.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Cost {
    /// `integral_0^T |theta'|^2 dt` \[rad^2/s\] (default).
    #[default]
    Effort,
    /// `integral_0^T 1/2 q'^T M q' dt` \[J s\]: the kinetic energy of Eq. (3) with the base's `phi'`
    /// from the momentum constraint (5).
    Energy,
}

/// Options of the [`OptimalPlanner`].
#[derive(Debug, Clone, PartialEq)]
pub struct OptimalOptions {
    /// The cost; default [`Cost::Effort`].
    pub cost: Cost,
    /// Also `theta''(0) = theta''(T) = 0` (quintic splines), so that the torques start and end at
    /// zero; default false (cubic splines).
    pub smooth_ends: bool,
    /// Count the goal's `phi` and joint angles modulo 2 pi: try nearby representatives and keep
    /// the best certified plan; default true. False: the goal's angles literally.
    pub wrap: bool,
    /// Number of samples of the trajectory, including both ends; default 1001.
    pub samples: usize,
    /// Tolerance of the verified final error \[rad\]; default 1e-9.
    pub tolerance: f64,
    /// Integrator options of the verification (default rtol = atol = 1e-12).
    pub ode: OdeOptions,
    /// Uniform knot spans of the coarse basis on which every seed is solved; default 8.
    pub coarse_spans: usize,
    /// Largest number of uniform knot spans of the refinement (doubling from `coarse_spans`);
    /// default 32.
    pub max_spans: usize,
    /// Graded knots at `h / 4^j`, `j = 1..=grading`, in the first and last spans; default 1.
    ///
    /// With `theta'(0) = theta'(T) = 0` the infimum of the effort is that of free end velocities
    /// and is not attained: the optimum steepens the velocity ramps at the ends into layers as
    /// thin as the basis allows, and the accelerations (so the torques) grow as the layers thin.
    /// On the paper's problem at `a = b = 0.1` grading 5 gives effort 0.21954 with a peak torque
    /// of 221 N m inside a 0.3 ms layer; grading 1 gives 0.22013 (+0.3 %) with 0.89 N m. The
    /// default keeps within 1 % of the infimum at a physical torque.
    pub grading: usize,
    /// The refinement stops when the cost changes by less than this, relative; default 1e-6.
    pub refinement_tolerance: f64,
    /// Gauss–Legendre nodes per knot span of the optimiser; default 8 (raised automatically
    /// until the motion's finer quadrature agrees).
    pub quadrature_nodes: usize,
    /// How many of the best coarse solutions are refined; default 2. The best line solved beside
    /// a coil is refined as one more where its coarse cost is below all of theirs.
    pub finalists: usize,
    /// Seed with the NFA's joint path where the paper's transformation (Eq. 12 or 14) plans;
    /// default true.
    pub nfa_seed: bool,
    /// How many goal representatives (best first by the constant-speed effort of their loop
    /// seeds) are solved; default 2.
    pub targets_solved: usize,
    /// Largest radius of a loop seed \[rad\]; larger areas take several turns; default 2.
    pub max_loop_radius: f64,
    /// SQP options of the refined solves.
    pub sqp: SqpOptions,
    /// A joint path to start from, sampled from `t = 0` to the horizon (in re-planning: the rest
    /// of the plan being followed). It is solved first, on the literal goal's representative
    /// whose joint angles it ends at; when that solve converges, its motion is the plan and no
    /// other seed is tried. Default none.
    pub warm_start: Option<Sampled>,
}

impl Default for OptimalOptions {
    fn default() -> Self {
        Self {
            cost: Cost::Effort,
            smooth_ends: false,
            wrap: true,
            samples: 1001,
            tolerance: 1e-9,
            ode: OdeOptions::default(),
            coarse_spans: 8,
            max_spans: 32,
            grading: 1,
            refinement_tolerance: 1e-6,
            quadrature_nodes: 8,
            finalists: 2,
            nfa_seed: true,
            targets_solved: 2,
            max_loop_radius: 2.0,
            sqp: SqpOptions::default(),
            warm_start: None,
        }
    }
}

impl OptimalOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name: &str, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value, expected }))
        };
        crate::plan::limits::check_samples("samples", self.samples as u64)?;
        crate::plan::limits::check_tolerance("tolerance", self.tolerance)?;
        if self.coarse_spans < 2 || self.max_spans < self.coarse_spans || self.max_spans > 4096 {
            return bad("max_spans", self.max_spans as f64, "2 <= coarse_spans <= max_spans <= 4096");
        }
        if self.grading > 12 {
            return bad("grading", self.grading as f64, "at most 12 graded knots per end");
        }
        if !(6..=64).contains(&self.quadrature_nodes) {
            return bad("quadrature_nodes", self.quadrature_nodes as f64, "6 to 64 nodes per knot span");
        }
        if self.targets_solved == 0 {
            return bad("targets_solved", 0.0, "at least 1");
        }
        if !(self.max_loop_radius > 0.0 && self.max_loop_radius < 10.0) {
            return bad("max_loop_radius", self.max_loop_radius, "a radius in (0, 10) rad");
        }
        if self.finalists == 0 {
            return bad("finalists", 0.0, "at least 1");
        }
        if !(self.refinement_tolerance > 0.0) {
            return bad("refinement_tolerance", self.refinement_tolerance, "a positive relative change");
        }
        if let Some(path) = &self.warm_start {
            let finite = path.theta.iter().chain(&path.rate).flatten().chain(&path.t).all(|x| x.is_finite());
            let shape = path.t.len() >= 2 && path.theta.len() == path.t.len() && path.rate.len() == path.t.len();
            if !(finite && shape && path.t[0] == 0.0 && path.t[path.t.len() - 1] > 0.0) {
                return bad("warm_start", path.t.len() as f64, "at least 2 finite samples from t = 0 on");
            }
        }
        Ok(())
    }

    fn degree(&self) -> usize {
        if self.smooth_ends { 5 } else { 3 }
    }
}

/// The minimum-effort planner (see the [module docs](self)).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OptimalPlanner {
    /// Options.
    pub options: OptimalOptions,
}

/// A solve in progress: a target, its discretisation and the SQP result on it.
pub(crate) struct Candidate {
    disc: Discretisation,
    result: sqp::SqpResult,
    spans: usize,
    nodes: usize,
    iterations: usize,
    /// The motion of `result`, where the refinement built it to check its quadrature.
    motion: Option<OptimalMotion>,
}

/// The discretisation tables built in one planning call, by (uniform spans, quadrature nodes).
#[derive(Default)]
pub(crate) struct Tables(RefCell<Vec<TableEntry>>);

/// A cached table with its (uniform spans, quadrature nodes).
type TableEntry = ((usize, usize), Arc<Table>);

/// After the first converged batch, a representative is solved only when its estimate
/// ([`search`]'s constant-speed effort of its best seed) is at most this times the best effort
/// found. The estimates of coils are pessimistic (the line beside a coil often ends far below
/// it), but on the 300 recorded problems (tests/fixtures/two_link_300.csv) every representative
/// that improved on an earlier batch had an estimate below 2.2 times the best effort before it;
/// without the cut, representatives of 20-40 coil turns were solved at 100 times the best effort
/// (seconds per plan).
const LATER_ESTIMATE_RATIO: f64 = 10.0;

/// The largest constraint residual \[rad\] of a coarse line beside a coil that is refined as an
/// extra finalist (here and in the [chain](crate::planners::chain) planner).
pub(crate) const EXTRA_RESIDUAL: f64 = 1e-3;

/// SQP options of the coarse ranking solves.
const COARSE_SQP: SqpOptions =
    SqpOptions { max_iterations: 40, constraint_tolerance: 1e-10, kkt_tolerance: 1e-6, stall_iterations: 6 };

impl OptimalPlanner {
    /// A planner with these options.
    pub fn new(options: OptimalOptions) -> Self {
        Self { options }
    }

    fn basis(&self, horizon: f64, spans: usize) -> Result<SplineBasis, Error> {
        SplineBasis::graded(self.options.degree(), horizon, spans, self.options.grading)
    }

    /// The problem of `targets` on `spans` uniform spans and `nodes` quadrature nodes, its
    /// tables built once per planning call.
    fn discretise(
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

    /// All certified-candidate motions, best cost first (at least one), without verification.
    pub fn motions(&self, problem: &PlanningProblem) -> Result<Vec<OptimalMotion>, Error> {
        self.options.validate()?;
        let o = &self.options;
        let k = problem.robot.lumped();
        let nfa = if o.nfa_seed && problem.starts_at_rest() { self.nfa_path(problem) } else { None };
        let grid = seeds::curvature_grid(&k);
        let kappa_max = seeds::curvature_bound_on(&grid);
        let sites = seeds::coil_sites_on(&k, o.max_loop_radius, &grid);
        let tables = Tables::default();
        if let Some(path) = &o.warm_start
            && let Some(motion) = self.warm(problem, path, &tables)?
        {
            return Ok(vec![motion]);
        }
        let mut lines = Vec::new();
        let mut prepared = Vec::new();
        for targets in self.targets(problem) {
            prepared.push(self.prepare(problem, targets, kappa_max, &sites, &tables, &mut lines)?);
        }
        prepared.sort_by(|a, b| a.estimate.total_cmp(&b.estimate));
        let mut seeds = 0;
        let mut total_iterations = 0;
        // The least feasible cost seen, coarse or refined: a representative whose lower bound
        // exceeds it cannot hold a better plan and is skipped (branch and bound).
        let mut best = f64::INFINITY;
        let mut best_failure: Option<Candidate> = None;
        let mut done: Vec<Candidate> = Vec::new();
        // Batches of `targets_solved` representatives, best estimates first, until every one
        // left is bounded out: the estimate finds a good plan early, the bound proves the rest
        // cannot beat it (stopping after the first converged batch missed better representatives
        // on 92 of 300 random problems, tests/fixtures/two_link_300.csv).
        let mut prepared = prepared.into_iter().peekable();
        while prepared.peek().is_some() {
            let (mut coarse, mut extras): (Vec<Candidate>, Vec<Candidate>) = (Vec::new(), Vec::new());
            let mut taken = 0;
            let refined_best = done.first().map_or(f64::INFINITY, |c| c.result.f);
            while taken < o.targets_solved {
                let Some(p) = prepared.next() else { break };
                // Bounded out; after a plan is found, an estimate far above its effort solves
                // only the line (one cheap coarse solve that the SQP may bend into a plan far
                // cheaper than the seeds' estimate).
                if p.bound > best {
                    continue;
                }
                let only_line = p.estimate > LATER_ESTIMATE_RATIO * refined_best;
                taken += usize::from(!only_line);
                let mut starts = self.starts(problem, &p, nfa.as_ref(), &tables)?;
                if only_line {
                    starts.truncate(1);
                    starts[0].extra = false;
                }
                for start in starts {
                    seeds += 1;
                    let Ok(result) = sqp::solve(&start.disc, start.x0, &COARSE_SQP, start.guess) else { continue };
                    total_iterations += result.iterations;
                    if !start.extra && result.c.abs() <= 1e-6 && result.f < best {
                        best = result.f;
                    }
                    let list = if start.extra { &mut extras } else { &mut coarse };
                    list.push(Candidate {
                        disc: start.disc,
                        iterations: result.iterations,
                        result,
                        spans: start.spans,
                        nodes: o.quadrature_nodes,
                        motion: None,
                    });
                }
            }
            // Rank: feasible first, then by cost.
            let feasible = |c: &Candidate| c.result.c.abs() <= 1e-6 && c.result.f.is_finite();
            coarse.sort_by(|a, b| feasible(b).cmp(&feasible(a)).then(a.result.f.total_cmp(&b.result.f)));
            let mut finalists: Vec<Candidate> = Vec::new();
            for c in coarse {
                if finalists.len() >= o.finalists {
                    break;
                }
                // A coarse cost 20 % above the best refined one does not overtake on refinement,
                // and an infeasible one is refined only while no plan is found.
                if c.result.f > 1.2 * refined_best || (!feasible(&c) && refined_best.is_finite()) {
                    break;
                }
                let duplicate =
                    finalists.iter().any(|f| (f.result.f - c.result.f).abs() <= 1e-6 * c.result.f.abs().max(1e-12));
                if !duplicate {
                    finalists.push(c);
                }
            }
            // The best line beside a coil is refined too where its coarse solution is near the
            // constraint and its cost within 20 % of the best finalist's: an extra finalist, so
            // that the others (and the plan without it) stay. On 8 spans the line often ends near
            // a plan that it cannot quite reach in the coarse solve's 40 iterations and that
            // costs less, refined, than the coil's.
            let first =
                finalists.first().filter(|c| feasible(c)).map_or(refined_best, |c| c.result.f.min(refined_best));
            let near = |c: &Candidate| c.result.c.abs() <= EXTRA_RESIDUAL && c.result.f.is_finite();
            let extra = extras.into_iter().filter(near).min_by(|a, b| a.result.f.total_cmp(&b.result.f));
            if let Some(c) = extra.filter(|c| c.result.f <= 1.2 * first) {
                finalists.push(c);
            }
            for c in finalists {
                let c = self.refine(problem, c, &tables)?;
                total_iterations += c.iterations;
                if c.result.converged() {
                    best = best.min(c.result.f);
                    done.push(c);
                    done.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
                } else if best_failure.as_ref().is_none_or(|b| c.result.c.abs() < b.result.c.abs()) {
                    best_failure = Some(c);
                }
            }
        }
        if !done.is_empty() {
            return Ok(done.into_iter().map(|c| self.to_motion(problem, c, seeds, total_iterations)).collect());
        }
        let (iterations, c, kkt, effort, termination) = match &best_failure {
            Some(b) => (b.iterations, b.result.c.abs(), b.result.kkt, b.disc.effort(&b.result.x), b.result.termination),
            None => (0, f64::INFINITY, f64::INFINITY, f64::INFINITY, Termination::MaxIterations),
        };
        Err(Error::OptimalFailed {
            iterations,
            constraint_residual: c,
            kkt_residual: kkt,
            effort,
            seeds,
            termination: termination_name(termination),
        })
    }

    /// The exact motion of a candidate with the plan's statistics (the motion the refinement
    /// built to check its quadrature, where it did).
    fn to_motion(
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

    /// The best motion, without verification.
    pub fn motion(&self, problem: &PlanningProblem) -> Result<OptimalMotion, Error> {
        self.motions(problem)?.into_iter().next().ok_or_else(no_candidate)
    }

    /// Plans and verifies, returning the exact motion beside the plan: the best candidate whose
    /// certificate holds, else the best candidate's (uncertified) plan.
    pub fn plan_with_motion(&self, problem: &PlanningProblem) -> Result<(Plan, OptimalMotion), Error> {
        let clock = Instant::now();
        let motions = self.motions(problem)?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let mut first: Option<(Plan, OptimalMotion)> = None;
        for motion in motions {
            let trajectory = motion.trajectory(problem, self.options.samples)?;
            let margins = motion.margins(&trajectory);
            let (ode, tolerance) = (&self.options.ode, self.options.tolerance);
            let mut plan =
                Plan::verified(Method::Optimal, problem, &motion, trajectory, margins, plan_seconds, ode, tolerance)?;
            plan.iterations = Some(motion.stats.iterations);
            plan.effort = motion.stats.effort;
            if plan.verification.certified {
                return Ok((plan, motion));
            }
            if first.is_none() {
                first = Some((plan, motion));
            }
        }
        first.ok_or_else(no_candidate)
    }
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

impl Planner for OptimalPlanner {
    fn method(&self) -> Method {
        Method::Optimal
    }

    fn plan(&self, problem: &PlanningProblem) -> Result<Planned, Error> {
        let (plan, motion) = self.plan_with_motion(problem)?;
        let details = Details::Optimal(motion.stats);
        Ok(Planned::new(plan, Box::new(motion), details))
    }
}

/// The error when the search returned no candidate at all.
fn no_candidate() -> Error {
    Error::OptimalFailed {
        iterations: 0,
        constraint_residual: f64::INFINITY,
        kkt_residual: f64::INFINITY,
        effort: f64::INFINITY,
        seeds: 0,
        termination: "no_candidate",
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
pub(crate) mod comparison;
