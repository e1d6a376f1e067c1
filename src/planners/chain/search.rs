//! The chain planner's search: goal representatives ranked by their seeds' estimated effort,
//! every seed solved on the coarse basis, the best feasible solution refined, the plan certified.

use std::sync::OnceLock;
use std::time::Instant;

use super::discrete::Discretisation;
use super::motion::{ChainPlan, ChainStats};
use super::queue::Representatives;
use super::starts::Prepared;
use super::tables::Tables;
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::plan::certificate::verify_chain;
use crate::planners::optimal::EXTRA_RESIDUAL;
use crate::planners::optimal::sqp::{SqpOptions, SqpResult, Termination};
use rayon::prelude::*;

/// SQP options of the coarse solves ([`SqpOptions::COARSE`]).
pub(super) const COARSE_SQP: SqpOptions = SqpOptions::COARSE;

/// After the first converged refinement, a representative's loops and coils are solved only
/// when its estimate is at most this times the best cost found (the two-joint planner's rule:
/// coil estimates are pessimistic, but one far above the best plan does not overtake it); its
/// line is solved up to [`UNSOLVED_ESTIMATE_RATIO`]. The two-joint planner's ratio is 10 on
/// estimates without the 1.2 of [`super::seeds::Line::effort_estimate`]; at 10 here, its better
/// plan on one of the 300 recorded problems (index 232, 4.23 against 7.35 rad^2/s) was cut.
const LATER_ESTIMATE_RATIO: f64 = 12.0;

/// After the first converged refinement, a representative whose estimate is more than this
/// times the best cost found is not solved at all, not even its line: on the paper's problem at
/// a = 1, b = -1 the 41 lines it skips, of base targets `phid +- 2 pi` (estimates 109 to 274
/// times the plan's 42.98 rad^2/s), took 494 of its 1476 SQP iterations (after
/// [`super::hopeless`]); run to the end, none came within 1e-2 rad of the constraint or under
/// 140 rad^2/s. On the 300 recorded two-link problems and the 50 random mounts of
/// the paper's problem every effort is the same to 1e-9 at this ratio and at 20.
const UNSOLVED_ESTIMATE_RATIO: f64 = 50.0;

/// A solve: its discretisation and result.
#[derive(Clone)]
pub(super) struct Candidate {
    /// The discretisation solved on.
    pub disc: Discretisation,
    /// The SQP's result.
    pub result: SqpResult,
    /// Uniform knot spans of `disc`.
    pub spans: usize,
    /// Quadrature nodes per span of `disc`.
    pub nodes: usize,
    /// Graded knots per end of `disc` ([`super::ChainOptions::grading`], more where a velocity
    /// limit binds in an end layer: `super::limits::ends`).
    pub grading: usize,
    /// SQP iterations so far.
    pub iterations: usize,
    /// The coarse cost this solve stands for, where it is that coarse solution solved again on
    /// the finest basis (a rate-limited line's, see `ChainPlanner::solve_seed`): another seed's
    /// coarse solution of that cost is the same point, whose refinement this solve already is.
    pub stands_for: Option<f64>,
    /// The plan's base angle at the breakpoints, once computed ([`ChainPlan`]'s, from `disc`
    /// and `result.x`: the refinement's residual check and the certificate share it).
    pub phi: OnceLock<Vec<f64>>,
}

impl Candidate {
    /// A solve on `disc` with (uniform spans, quadrature nodes, end grading) `basis`, after
    /// `iterations` SQP iterations in all, standing for no other solve.
    pub(super) fn new(disc: Discretisation, result: SqpResult, basis: [usize; 3], iterations: usize) -> Self {
        let [spans, nodes, grading] = basis;
        Self { disc, result, spans, nodes, grading, iterations, stands_for: None, phi: OnceLock::new() }
    }

    /// The holonomy constraint met to 1e-6 rad at a finite cost.
    pub(super) fn feasible(&self) -> bool {
        self.result.c.abs() <= 1e-6 && self.result.f.is_finite()
    }
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
        if self.arm.joints() == 1 {
            return self.single_joint(problem, self.prepare(problem)?, &tables, clock);
        }
        if super::limits::keeps_clearance(self) {
            return self.plan_keeping_clearance(problem, &tables, clock);
        }
        self.search(problem, &tables, clock)
    }

    /// The search of [`Self::plan`] after its checks (module docs).
    pub(super) fn search(&self, problem: &ChainProblem, tables: &Tables, clock: Instant) -> Result<ChainPlan, Error> {
        let o = &self.options;
        let mut prepared = None;
        if let Some(plan) = self.warm_start(problem, &mut prepared, tables, clock)? {
            return Ok(plan);
        }
        if self.options.warm_start_only && self.options.warm_start.is_some() {
            return Err(Self::warm_start_failed());
        }
        let mut queue = match prepared {
            Some(p) => Representatives::prepared(p),
            None => Representatives::lazy(self, problem),
        };
        let (mut seeds, mut iterations) = (0, 0);
        let mut best_failure: Option<Candidate> = None;
        let mut not_certified: Option<Error> = None;
        // Batches of representatives, best estimate first, skipping those whose bound exceeds
        // the least feasible cost seen (branch and bound) or, once a plan is refined, whose
        // estimate is far above it; every converged refinement is kept.
        let mut best = f64::INFINITY;
        // The least cost of a converged feasible coarse solve: its refinement starts there (on a
        // basis holding the coarse one), so a coarse cost 20 % above it is no finalist either.
        let mut converged_best = f64::INFINITY;
        let mut done: Vec<Candidate> = Vec::new();
        let mut set_aside: Vec<Candidate> = Vec::new();
        while !queue.is_empty() {
            let (mut coarse, mut extras, mut stood_for) = (Vec::new(), Vec::new(), Vec::new());
            let mut refined_best = done.iter().map(|c| c.result.f).fold(f64::INFINITY, f64::min);
            let mut taken = 0;
            while taken < o.targets_solved {
                // The next whose bound is at most the least feasible cost seen.
                let Some(p) = queue.next(self, problem, best) else { break };
                // The queue is in order of estimate, and the best cost only falls: none after it is
                // solved either.
                if p.estimate > UNSOLVED_ESTIMATE_RATIO * refined_best {
                    queue.clear();
                    break;
                }
                let line_only = |p: &Prepared| {
                    p.estimate > LATER_ESTIMATE_RATIO * refined_best
                        && p.estimate <= UNSOLVED_ESTIMATE_RATIO * refined_best
                };
                let mut group = vec![p];
                if line_only(&group[0]) {
                    // Only the line (one cheap coarse solve; the SQP may bend it into a plan far
                    // cheaper than the seeds' estimate); the next ones, of larger estimates, are
                    // lines too and are solved beside it, in parallel (one seed each), and then
                    // taken in order as if one by one (a result that lowers the best cost drops
                    // the later ones its bound cuts). One line beside it, whatever the thread
                    // count: the group's makeup decides the plan, which must not depend on the
                    // machine (it was the thread count less one: 1 on two cores).
                    group.extend(queue.more(self, problem, best, 1, line_only));
                    group.iter_mut().for_each(|p| p.seeds.truncate(1));
                } else {
                    // Once a plan is refined, the batch's other representatives are solved beside
                    // it, in parallel (their seeds with its seeds; the same ones at any thread
                    // count), then taken in order as if one by one: alone, one representative's
                    // two or three seeds of unequal cost leave a thread idle (the paper's problem
                    // at a = 1, b = -1: nine representatives after the first plan). Before it, one
                    // at a time: the first's converged cost caps the next's solves (paired there
                    // too, the seeds' CPU time rose 2.7 times on the paper's problem at a = b =
                    // 0.1, 2.2 on the 3-link bench). On the 300 recorded problems every effort is
                    // the same; SQP iterations 824229 -> 824369 (19 problems solve a paired one's
                    // seeds under the ceiling before the first's cost).
                    let room = if refined_best.is_finite() { o.targets_solved - taken - 1 } else { 0 };
                    let solved_too =
                        |q: &Prepared| !line_only(q) && q.estimate <= UNSOLVED_ESTIMATE_RATIO * refined_best;
                    group.extend(queue.more(self, problem, best, room, solved_too));
                    taken += group.len();
                }
                // A coarse cost 20 % above the best refined one is no finalist (below): a solve that
                // cannot end under it is given up (`super::hopeless`).
                let ceiling = 1.2 * refined_best.min(converged_best);
                let solved: Vec<_> = group.par_iter().map(|p| self.solve_seeds(problem, p, ceiling, tables)).collect();
                for (p, solved) in group.iter().zip(solved) {
                    if p.bound > best {
                        continue;
                    }
                    for (c, extra) in solved? {
                        seeds += 1;
                        iterations += c.iterations;
                        if c.result.termination == Termination::Abandoned {
                            continue;
                        }
                        // A feasible extra on the finest basis (a rate-limited line,
                        // `solve_seeds`) is a plan's cost too: it bounds the later
                        // representatives (issue 20's 2-link bench: one of bound 40 solved beside
                        // a line of 0.46).
                        if (!extra || c.spans == o.max_spans) && c.feasible() {
                            best = best.min(c.result.f);
                        }
                        if c.feasible() && c.result.converged() {
                            converged_best = converged_best.min(c.result.f);
                        }
                        stood_for.extend(c.stands_for);
                        if extra { extras.push(c) } else { coarse.push(c) }
                    }
                }
            }
            // Near the constraint: within the extra finalist's residual (a coil's coarse solve
            // often stops at 1e-5 rad, short of 1e-6, at the plan it refines into).
            let near = |c: &Candidate| c.result.c.abs() <= EXTRA_RESIDUAL && c.result.f.is_finite();
            // Far from it, least cost first, below the best cost seen: refined besides the
            // finalists (`ChainOptions::far_finalists`).
            let mut far: Vec<Candidate> =
                coarse.iter().chain(&extras).filter(|c| !near(c) && c.result.f < best).cloned().collect();
            far.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
            far.truncate(o.far_finalists);
            coarse.sort_by(|a, b| near(b).cmp(&near(a)).then(a.result.f.total_cmp(&b.result.f)));
            // The best line beside a coil (or on the finest basis, see `solve_seeds`) is refined
            // too, as an extra finalist, where its solution is near the constraint and its cost
            // within 20 % of the best one's.
            let first = coarse.first().filter(|c| near(c)).map_or(refined_best, |c| c.result.f.min(refined_best));
            let extra = extras.into_iter().filter(near).min_by(|a, b| a.result.f.total_cmp(&b.result.f));
            let mut refined: Vec<f64> = std::mem::take(&mut stood_for);
            // The far ones are independent: refined in parallel, taken in their order (issue
            // 20's `--time auto` bench refined two of 129 and 61 QPs one after the other before).
            let refine_far = |far: Vec<Candidate>, refined: &mut Vec<f64>| -> Result<Vec<Candidate>, Error> {
                let far: Vec<Candidate> = far.into_iter().filter(|c| first_refinement(c.result.f, refined)).collect();
                let far: Vec<Result<Candidate, Error>> =
                    far.into_par_iter().map(|c| self.refine(problem, c, tables)).collect();
                far.into_iter().collect()
            };
            // With no coarse finalist near the constraint and no plan refined yet, the far ones
            // before the extra, whose cut their plans set: on issue 21's SPART-like bench the
            // extra line (8.05, stalled) took 71 of 395 SQP iterations to refine to 7.42, thrown
            // away for the coil's 5.39.
            if !first.is_finite() && extra.is_some() {
                for c in refine_far(std::mem::take(&mut far), &mut refined)? {
                    iterations += c.iterations;
                    if c.result.converged() {
                        refined_best = refined_best.min(c.result.f);
                    }
                    keep(c, &mut best, &mut done, &mut best_failure);
                }
            }
            let first = first.min(refined_best);
            // One more than 20 % above is set aside, not dropped: where no refined plan is
            // certified (and clear), it is the search's next answer.
            let (extra, aside) = match extra {
                Some(c) if c.result.f > 1.2 * first => (None, Some(c)),
                extra => (extra, None),
            };
            set_aside.extend(aside);
            // Finalists, best first: a coarse cost 20 % above the best refined one (of earlier
            // batches or of this one) does not overtake on refinement, and one far from the
            // constraint is a finalist only while no plan is found. A refinement that fails
            // does not use up a finalist's place (at most twice as many are tried).
            // The coarse costs stood for by finest-basis solves count as refined already: on
            // issue 20's 2-link bench a loop's coarse solve stalled off the constraint at the
            // rate-limited line's capped solution (cost equal to 12 digits) and its refinement,
            // 18 QPs, found the line's plan again.
            let (mut converged, mut tried) = (0, 0);
            let finalists = extra.into_iter().map(|c| (c, true)).chain(coarse.into_iter().map(|c| (c, false)));
            for (c, extra) in finalists {
                if !extra && (converged >= o.finalists || tried >= 2 * o.finalists) {
                    break;
                }
                if !extra && (c.result.f > 1.2 * refined_best || (!near(&c) && refined_best.is_finite())) {
                    break;
                }
                if let Some(c) = self.refine_new(problem, c, &mut refined, tables)? {
                    tried += usize::from(!extra);
                    iterations += c.iterations;
                    converged += usize::from(!extra && c.result.converged());
                    // The rule above against this batch's refinements too: on issue 20's SPART
                    // bench the second finalist (coarse cost 3.9, stalled off the constraint)
                    // took 277 of 406 ms after the first had refined to 1.31.
                    if c.result.converged() {
                        refined_best = refined_best.min(c.result.f);
                    }
                    keep(c, &mut best, &mut done, &mut best_failure);
                }
            }
            for c in refine_far(far, &mut refined)? {
                iterations += c.iterations;
                keep(c, &mut best, &mut done, &mut best_failure);
            }
        }
        done.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
        set_aside.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
        let none_done = done.is_empty();
        // A plan under the clearance between the rows' points (issue 21) is solved again keeping
        // more; if none clears, the least bad is returned for its certificate to report. After
        // the refined plans, the candidates set aside, least cost first, refined where they are
        // not on the finest basis yet (issue 21's SPART-like arm at 0.03 and 0.035 m: the coarse
        // finalists stalled or came under the clearance, and the line's solution on the finest
        // basis, converged at 7.53 and 7.57 rad^2/s, had been set aside as 20 % above them).
        let (mut closest, mut outside): (Option<ChainPlan>, Option<ChainPlan>) = (None, None);
        let mut refined = Vec::new();
        for (c, later) in done.into_iter().map(|c| (c, false)).chain(set_aside.into_iter().map(|c| (c, true))) {
            let c = if !later || (c.result.converged() && c.spans == o.max_spans) {
                c
            } else {
                match self.refine_new(problem, c, &mut refined, tables)? {
                    Some(c) if c.result.converged() => {
                        iterations += c.iterations;
                        c
                    }
                    _ => continue,
                }
            };
            match self.certified_clear(problem, &c, seeds, iterations, clock, tables) {
                Ok(Ok(plan)) if plan.verification.limits.as_ref().is_none_or(|l| l.inside) => return Ok(plan),
                // Clear but beyond a limit between the rows' points, where the hold's rounds
                // did not suffice: the next candidate may be inside; else this one is returned
                // for its certificate to report.
                Ok(Ok(plan)) => outside = outside.or(Some(plan)),
                Ok(Err(plan)) => {
                    let min = |p: &ChainPlan| p.verification.clearance.map_or(f64::NEG_INFINITY, |r| r.min);
                    if closest.as_ref().is_none_or(|b| min(&plan) > min(b)) {
                        closest = Some(plan);
                    }
                }
                Err(e) => not_certified = not_certified.or(Some(e)),
            }
        }
        // A plan that clears inside every limit from a re-solve that stalled first, then one
        // beyond a limit, then the closest to clearing.
        let inside = |p: &ChainPlan| p.verification.limits.as_ref().is_none_or(|l| l.inside);
        let stalled = closest.take_if(|p| p.verification.clearance.is_none_or(|r| r.holds()) && inside(p));
        if let Some(plan) = stalled.or(outside).or(closest) {
            return Ok(plan);
        }
        // No refinement converged, e.g. the SQP stalled on binding position ranges (issue 20's
        // oracle case 15: feasible to 1e-13 at a KKT residual of 4e-4): the attempt nearest
        // the holonomy is still a motion of the robot, returned when its certificate holds and it
        // stays inside every limit and clearance. Its statistics say it stalled (the report and
        // the table say it is not proven a constrained minimum).
        if none_done
            && let Some(b) = best_failure.as_ref().filter(|b| b.result.termination == Termination::Stalled)
            && let Ok(Ok(plan)) = self.certified_clear(problem, b, seeds, iterations, clock, tables)
            && plan.verification.limits.as_ref().is_none_or(|l| l.inside)
        {
            return Ok(plan);
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
                termination: b.result.termination.name(),
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

    /// [`Self::refine`] of a coarse solution whose cost is not among `refined` (a duplicate
    /// refines into the same plan): `None` for a duplicate, else its cost is recorded.
    fn refine_new(
        &self,
        problem: &ChainProblem,
        c: Candidate,
        refined: &mut Vec<f64>,
        tables: &Tables,
    ) -> Result<Option<Candidate>, Error> {
        if !first_refinement(c.result.f, refined) {
            return Ok(None);
        }
        self.refine(problem, c, tables).map(Some)
    }

    /// Doubles the spans until the effort settles (or `max_spans`; a candidate on the coarse
    /// basis or not converged on `max_spans` is solved again there with the refined solves'
    /// options; where a doubling fails, the last converged basis is kept, the coarse one solved
    /// again so), then raises the quadrature nodes until the finer quadrature of the plan's base
    /// angle agrees to 1% of the tolerance.
    pub(super) fn refine(&self, problem: &ChainProblem, mut c: Candidate, tables: &Tables) -> Result<Candidate, Error> {
        let o = &self.options;
        let mut previous: Option<f64> = None;
        let (mut spans, first) = (c.spans, c.spans);
        let mut resolved = false;
        while spans < o.max_spans {
            spans = (2 * spans).min(o.max_spans);
            let finer = self.resolve(problem, &c, spans, c.nodes, tables)?;
            if !finer.result.converged() {
                // Keep the last converged basis (the certificate judges it).
                if c.spans > first && c.result.converged() {
                    return Ok(c);
                }
                // The first doubling failed: the coarse solution, solved again on its own basis
                // at the refinement's accuracy, where that converges (on binding position ranges
                // the finer solve can stall off the holonomy: issue 20's oracle case 11, a coil
                // converged on 12 spans at 21.5 rad^2/s stalled on 24 at a residual of 1.3e-6).
                let again = self.resolve(problem, &c, c.spans, c.nodes, tables)?;
                if !again.result.converged() {
                    return Ok(finer);
                }
                c = again;
                resolved = true;
                break;
            }
            c = finer;
            if previous.is_some_and(|p| (c.result.f - p).abs() <= o.refinement_tolerance * c.result.f.abs()) {
                break;
            }
            previous = Some(c.result.f);
        }
        // Never doubled (its basis already the finest, e.g. a long line's or a coil's): solved
        // again at the refinement's accuracy, unless its solve met it already (the same basis
        // and point: one QP to measure the KKT residual, 21 interior-point iterations for issue
        // 20's 3-link rate-limited line, converged to 1e-10 and 1e-15 rad off the holonomy).
        let accurate = c.result.termination == Termination::Converged
            && c.result.c.abs() <= o.sqp.constraint_tolerance
            && c.result.kkt <= o.sqp.kkt_tolerance;
        if !resolved && accurate && c.spans == first {
            c.result.kkt_tolerance = o.sqp.kkt_tolerance;
        } else if !resolved && (c.spans == first || !c.result.converged()) {
            c = self.resolve(problem, &c, c.spans, c.nodes, tables)?;
        }
        c = self.sharpen_ends(problem, c, tables)?;
        while c.nodes < 32 && self.holonomy_residual(&c) > 0.01 * o.tolerance {
            c = self.resolve(problem, &c, c.spans, (2 * c.nodes).min(32), tables)?;
            if !c.result.converged() {
                break;
            }
        }
        self.hold_between_points(problem, c, tables)
    }

    /// `|phi(T) - phi_end|` of the candidate with the plan's finer quadrature.
    fn holonomy_residual(&self, c: &Candidate) -> f64 {
        let plan = self.plan_of(c, ChainStats::unmeasured(c));
        let t = c.disc.basis().horizon();
        (plan.phi(t) - c.disc.targets().phi_end).abs()
    }

    /// Solves on `spans` and `nodes`, warm-started by the projection of `c`'s path.
    pub(super) fn resolve(
        &self,
        problem: &ChainProblem,
        c: &Candidate,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        let disc = self.discretise_graded(problem, c.disc.targets().clone(), [spans, nodes, c.grading], tables)?;
        let old = c.disc.coefficients(&c.result.x);
        let old_basis = c.disc.basis();
        let x0 = disc.project(|t, out| old_basis.values_each(&old, t, out))?;
        let guess = if self.arm.joints() == 1 { None } else { Some(c.result.lambda) };
        let result = super::limits::solve_restarting(self, &disc, x0, &self.options.sqp, guess)?;
        let iterations = c.iterations + result.iterations;
        Ok(Candidate::new(disc, result, [spans, nodes, c.grading], iterations))
    }

    /// The plan of `c`, with `stats`.
    pub(super) fn plan_of(&self, c: &Candidate, stats: ChainStats) -> ChainPlan {
        let coefficients = c.disc.coefficients(&c.result.x);
        let (connection, basis) = (self.connection.clone(), c.disc.basis().clone());
        if let Some(phi) = c.phi.get() {
            return ChainPlan::with_phi(connection, basis, coefficients, phi.clone(), stats);
        }
        let plan = ChainPlan::new(connection, basis, coefficients, c.disc.targets().phi_start, stats);
        // Set once: the same plan whoever computes it.
        let _ = c.phi.set(plan.breakpoint_phi().to_vec());
        plan
    }

    /// The plan of a converged candidate with its statistics and certificate; an error when the
    /// certificate fails.
    pub(super) fn certified(
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
        plan.stats.peak_velocity = plan.peak_velocity();
        plan.stats.plan_seconds = clock.elapsed().as_secs_f64();
        let o = &self.options;
        plan.stats.clearance_reserve = o.clearance_reserve;
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
}

impl ChainStats {
    /// The statistics of a candidate before the plan measures it.
    fn default_for(c: &Candidate) -> Self {
        Self { effort: c.disc.integrals(&c.result.x).1, ..Self::unmeasured(c) }
    }

    /// [`Self::default_for`] without the effort (NaN; its quadrature is a pass over the nodes).
    pub(super) fn unmeasured(c: &Candidate) -> Self {
        Self {
            iterations: c.iterations,
            final_iterations: c.result.iterations,
            seeds: 0,
            effort: f64::NAN,
            cost: c.result.f,
            peak_velocity: f64::NAN,
            constraint_residual: c.result.c.abs(),
            holonomy_residual: f64::NAN,
            kkt_residual: c.result.kkt,
            multiplier: c.result.lambda,
            termination: c.result.termination,
            converged: c.result.converged(),
            spans: c.spans,
            grading: c.grading,
            quadrature_nodes: c.nodes,
            plan_seconds: f64::NAN,
            clearance_reserve: 0.0,
        }
    }
}

/// A refined candidate kept: converged, among the plans (and `best` lowered); else the best
/// failure so far where its constraint residual is the least.
fn keep(c: Candidate, best: &mut f64, done: &mut Vec<Candidate>, best_failure: &mut Option<Candidate>) {
    if c.result.converged() {
        *best = best.min(c.result.f);
        done.push(c);
    } else if best_failure.as_ref().is_none_or(|b| c.result.c.abs() < b.result.c.abs()) {
        *best_failure = Some(c);
    }
}

/// Whether a coarse solution of cost `f` is refined first: its cost is not among `refined` (a
/// duplicate refines into the same plan); recorded there when it is.
fn first_refinement(f: f64, refined: &mut Vec<f64>) -> bool {
    if refined.iter().any(|d| (d - f).abs() <= 1e-6 * f.abs().max(1e-12)) {
        return false;
    }
    refined.push(f);
    true
}
