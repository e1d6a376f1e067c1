//! The goal representatives of a chain problem and the coarse solutions of each: from the
//! straight line, loops beside it, or a coil on a basis fine enough for its turns (the two-joint
//! planner's seeds, in the joint planes of largest curvature).

use std::cell::RefCell;
use std::f64::consts::TAU;

use nalgebra::DVector;
use rayon::prelude::*;

use super::coil::Sites;
use super::discrete::{Discretisation, Targets};
use super::hopeless::Hopeless;
use super::search::{COARSE_SQP, Candidate};
use super::seeds::{self, Line, Seed};
use super::tables::Tables;
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::model::wrap_angle;
use crate::planners::optimal::Cost;
use crate::planners::optimal::sqp::{Discretised, SqpOptions, SqpResult, Termination};

/// Uniform knot spans per turn of a coil seed (cubic B-splines follow a circle to about 1e-3 of
/// its radius at this resolution; the radius is then re-fitted to the constraint), as the
/// two-joint planner's.
pub const SPANS_PER_TURN: usize = 6;

/// Arms of three up to this many joints also try the goal representatives with two joints a
/// turn further each (two-joint arms try [`TWO_JOINT_TURNS`] instead).
pub const PAIRED_JOINTS: usize = 3;

/// Two-joint arms try every joint goal up to this many turns further on each joint (25 at 2): on
/// 50 random mounts of the paper's problem the exhaustive reference found its least effort two
/// turns of `theta1` further on 4 (at one turn the plan cost 1.3 to 1.9 times more).
pub const TWO_JOINT_TURNS: i32 = 2;

/// Uniform knot spans per turn of a line's longest joint travel on which its line and loop
/// seeds are solved too, where that is more than [`super::ChainOptions::coarse_spans`]. On
/// the 50 random mounts of the paper's problem, two representatives of two turns on both joints
/// reached their best basin only from a basis this fine (at a = 1.446, b = -1.417 the plan
/// 445.14 -> 349.54 rad^2/s, at a = 1.254, b = -1.236 179.13 -> 169.33), and one of two turns
/// on `theta1` only from the coarse one (a = 1.244, b = 0.766: 46.36 there, 48.18 on 18 spans):
/// both are solved.
pub(crate) const LINE_SPANS_PER_TURN: usize = 8;

/// The ceiling of a representative's other coarse solves, in the first batch, as a multiple of
/// its line's converged coarse cost (the search's rule: a coarse cost 20 % above the best
/// refined one is no finalist, and a refinement, on a basis holding the coarse one, starts from
/// the coarse solution's cost). On the paper's problem at a = b = 0.1 a loop's solve ran all 40
/// coarse iterations to 0.43 rad^2/s beside the line's 0.22 (4 iterations): 73 SQP iterations
/// in all, 38 with the line first; on 60 random 3- and 4-link problems 22362 -> 20811, every
/// effort the same to 1e-9.
const LINE_CEILING: f64 = 1.2;

/// The holonomy residual \[rad\] beyond which a rate-limited line's full coarse solve with
/// clearance rows (not capped, see `ChainPlanner::solve_seed`) is given up: neither solved again
/// on the finest basis nor kept as a candidate. On issue 21's SPART-like bench the line to
/// `phid - 2 pi` ended 4.3 rad off on 8 spans (33 SQP iterations), 4.1 rad off on the finest
/// basis (33 more), and its refinement as a far finalist stalled 4.2 rad off (79 more): 575
/// SQP iterations instead of 430, the same plan. A capped line's residual says nothing of the
/// kind (on the chain tests, lines 4.4 and 4.7 rad off after their 8 iterations came within
/// 1e-2 and 1e-4 rad on the finest basis; the farthest that met it to 1e-6 was 0.62 rad off), and
/// without rows the line is capped: those are solved as before.
const STALLED_FAR: f64 = 1.0;

/// A loop whose radius re-fitted to the constraint is within this fraction of its estimate is
/// solved from the re-fitted loop alone, not from the estimate too: on issue 19's 3-link bench
/// each of its six loops' two starts converged to the same minimum (SQP iterations 133 -> 77,
/// 7-link 251 -> 188, the same plans). Every effort the same to 1e-9 on the 300 recorded
/// two-link problems, the 50 random mounts of the paper's problem and 60 random 3- and 4-link
/// problems; with the re-fitted loop alone at any ratio, one of those 60 lost its plan
/// (5.722 -> 6.415 rad^2/s).
const ONE_LOOP_START: f64 = 0.25;

/// The uniform knot spans of [`LINE_SPANS_PER_TURN`] for `line`.
fn line_spans(line: &Line) -> usize {
    let travel = line.start.iter().zip(&line.end).map(|(a, b)| (b - a).abs()).fold(0.0, f64::max);
    (LINE_SPANS_PER_TURN as f64 * travel / TAU).ceil() as usize
}

/// What the seeds of every representative share ([`ChainPlanner::seed_context`]).
pub(super) struct SeedContext {
    /// The curvature's comass bound ([`seeds::curvature_bound`]).
    pub kappa_max: f64,
    /// The coil sites found so far.
    pub sites: Sites,
    /// The scale of the effort bound in the cost's units.
    pub scale: f64,
}

/// A representative with its line and seeds.
pub(super) struct Prepared {
    /// The goal representative.
    pub targets: Targets,
    /// The line between its joint ends.
    pub line: Line,
    /// The line first, then the loops or coils.
    pub seeds: Vec<Seed>,
    /// The constant-speed effort of its best seed (the ranking).
    pub estimate: f64,
    /// A lower bound of its cost (see [`seeds::effort_lower_bound`]).
    pub bound: f64,
    /// The rotation the seeds add to the line's \[rad\].
    pub needed: f64,
}

impl ChainPlanner {
    /// The goal representatives with their lines and seeds, least estimate first: `phid`,
    /// `phid +- 2 pi` nearest the start, with `wrap` the joint goals nearest it, one joint a turn
    /// further, and (up to [`PAIRED_JOINTS`] joints) two joints a turn further each, or for two
    /// joints every goal up to [`TWO_JOINT_TURNS`] turns further on each; only those inside the
    /// ranges and within the joints' reach in the horizon. (The search takes them lazily, in the
    /// same order, from [`Representatives`](super::queue::Representatives).)
    pub(super) fn prepare(&self, problem: &ChainProblem) -> Result<Vec<Prepared>, Error> {
        let (lines, phi_targets) = self.lines(problem);
        let mut context = self.seed_context();
        let mut out = Vec::new();
        for line in &lines {
            // The line's holonomy at rest (the initial-velocity term is small and ignored here).
            let integral = line.holonomy(&self.connection);
            for &phi_end in &phi_targets {
                out.push(self.representative(problem, line, integral, phi_end, &mut context));
            }
        }
        out.sort_by(|a, b| a.estimate.total_cmp(&b.estimate));
        Ok(out)
    }

    /// The lines from the start to [`Self::goals`]' joint goals, with the base-angle targets.
    pub(super) fn lines(&self, problem: &ChainProblem) -> (Vec<Line>, Vec<f64>) {
        let theta0 = problem.start[1..].to_vec();
        let (joint_goals, phi_targets) = self.goals(problem);
        let lines = joint_goals
            .into_iter()
            .map(|end| Line {
                start: theta0.clone(),
                end,
                initial_velocity: problem.initial_velocity.clone(),
                horizon: problem.horizon,
            })
            .collect();
        (lines, phi_targets)
    }

    /// What the seeds of every representative share: the curvature's comass bound, the coil
    /// sites found so far, the bound's scale.
    pub(super) fn seed_context(&self) -> SeedContext {
        let sites = self.sites.with_ranges((0..self.arm.joints()).map(|j| self.arm.limits.joint(j).position).collect());
        // The bound is in the cost's units: the energy's is the effort's times a floor of R.
        let scale = match self.options.cost {
            Cost::Effort => 1.0,
            Cost::Energy => super::energy::energy_floor(&self.arm),
        };
        SeedContext { kappa_max: seeds::curvature_bound(&self.connection), sites, scale }
    }

    /// The representative of `line` (whose holonomy is `integral`) and `phi_end`, with its seeds,
    /// estimate and bound.
    pub(super) fn representative(
        &self,
        problem: &ChainProblem,
        line: &Line,
        integral: f64,
        phi_end: f64,
        context: &mut SeedContext,
    ) -> Prepared {
        let q0 = &problem.start;
        let needed = phi_end - (q0[0] - integral);
        let (planes, radius) = (self.options.loop_planes, self.options.max_loop_radius);
        let loops = line.loops(&self.connection, needed, planes, radius, &mut context.sites);
        let estimate = if needed.abs() < 1e-9 || loops.is_empty() {
            line.effort_estimate(Seed::Line)
        } else {
            loops.iter().map(|s| line.effort_estimate(*s)).fold(f64::INFINITY, f64::min)
        };
        let mut seeds = vec![Seed::Line];
        seeds.extend(loops);
        let targets = Targets {
            start: line.start.clone(),
            initial_velocity: problem.initial_velocity.clone(),
            end: line.end.clone(),
            phi_start: q0[0],
            phi_end,
        };
        let bound = context.scale * seeds::effort_lower_bound(line, needed, context.kappa_max);
        Prepared { targets, line: line.clone(), seeds, estimate, bound, needed }
    }

    /// The representatives of a problem whose goal is taken literally (`wrap = false`): the goal
    /// itself, or none where it is outside a range or out of the joints' reach (those of
    /// [`Self::prepare`], without their seeds); none with `wrap`.
    pub(super) fn literal_targets(&self, problem: &ChainProblem) -> Vec<Targets> {
        if problem.wrap {
            return Vec::new();
        }
        let (joint_goals, phi_targets) = self.goals(problem);
        let q0 = &problem.start;
        let mut out = Vec::new();
        for end in joint_goals {
            for &phi_end in &phi_targets {
                out.push(Targets {
                    start: q0[1..].to_vec(),
                    initial_velocity: problem.initial_velocity.clone(),
                    end: end.clone(),
                    phi_start: q0[0],
                    phi_end,
                });
            }
        }
        out
    }

    /// The joint goals and base goals of [`Self::prepare`]'s representatives: those inside the
    /// ranges and within the joints' reach in the horizon.
    fn goals(&self, problem: &ChainProblem) -> (Vec<Vec<f64>>, Vec<f64>) {
        let n = self.arm.joints();
        let (q0, qd) = (&problem.start, &problem.goal);
        let mut joint_goals = Vec::new();
        if problem.wrap {
            let near: Vec<f64> = (1..=n).map(|j| q0[j] + wrap_angle(qd[j] - q0[j])).collect();
            joint_goals.push(near.clone());
            if n == 2 {
                let turns = -TWO_JOINT_TURNS..=TWO_JOINT_TURNS;
                for (i, k) in turns.clone().flat_map(|i| turns.clone().map(move |k| (i, k))) {
                    if (i, k) != (0, 0) {
                        joint_goals.push(vec![near[0] + TAU * f64::from(i), near[1] + TAU * f64::from(k)]);
                    }
                }
            } else {
                for j in 0..n {
                    for turn in [-TAU, TAU] {
                        let mut g = near.clone();
                        g[j] += turn;
                        joint_goals.push(g);
                    }
                }
                for j in (0..n).filter(|_| n <= PAIRED_JOINTS) {
                    for k in j + 1..n {
                        for (tj, tk) in [(-TAU, -TAU), (-TAU, TAU), (TAU, -TAU), (TAU, TAU)] {
                            let mut g = near.clone();
                            (g[j], g[k]) = (g[j] + tj, g[k] + tk);
                            joint_goals.push(g);
                        }
                    }
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
        // One joint has no path to choose: its turns fix phi(T) ([`Error::HolonomyFixed`]).
        if problem.wrap && n >= 2 {
            let tried = if n == 2 { TWO_JOINT_TURNS } else { 1 };
            joint_goals.extend(self.spin_goals(problem, &joint_goals[0], &phi_targets, tried));
        }
        super::limits::inside_ranges(&self.arm.limits, &mut joint_goals, &mut phi_targets);
        let at_rest = problem.initial_velocity.iter().all(|w| *w == 0.0);
        super::limits::within_reach(&self.arm.limits, &q0[1..], at_rest, problem.horizon, &mut joint_goals);
        (joint_goals, phi_targets)
    }

    /// The coarse solutions of a representative, each marked `true` where it is the line beside
    /// a coil or the line on the finest basis (ranked apart, see [`ChainPlanner::plan`]), each
    /// seed on its bases ([`Self::seed_bases`]): the line (with a rate limit, where it cannot
    /// meet the constraint on its basis, on the finest basis too); each loop as estimated and
    /// re-fitted to the constraint (they lead to different local minima); each coil re-fitted,
    /// with the multiplier guessed from
    /// `lambda ~ -2 f / needed` (the effort grows as the square of the coil's length, the
    /// rotation linearly, and `df/d phi_end = -lambda`).
    ///
    /// A solve whose cost cannot end at or below `ceiling` is given up ([`Hopeless`]; infinite:
    /// none is), with the limits' and the clearance's rows too.
    pub(super) fn solve_seeds(
        &self,
        problem: &ChainProblem,
        p: &Prepared,
        ceiling: f64,
        tables: &Tables,
    ) -> Result<Vec<(Candidate, bool)>, Error> {
        // A coil of two turns or more (one turn is a seed beside the loops at `n = 2`).
        let coil = p.seeds.iter().any(|s| matches!(s, Seed::Coil { turns, .. } if *turns >= 2));
        // The seeds are independent: solved in parallel, gathered in their order (the first
        // error in that order is returned), so that the result does not depend on the threads.
        let mut bases = self.seed_bases(p);
        bases.retain(|(seed, _)| *seed != Seed::Line || !self.line_decided(&p.targets));
        // Where no plan bounds the cost yet (the first batch, an infinite ceiling) and the
        // watch applies, the line on the coarse basis first (one cheap solve): its converged
        // cost is a ceiling for the other seeds ([`LINE_CEILING`]).
        let watched = !ceiling.is_finite() && !super::limits::constrained(self);
        let split = usize::from(watched && bases.first().is_some_and(|(s, _)| *s == Seed::Line));
        let mut out = Vec::new();
        for &basis in &bases[..split] {
            out.extend(self.solve_seed(problem, p, basis, coil, ceiling, tables)?);
        }
        let line_best = out
            .iter()
            .filter(|(c, _)| c.feasible() && c.result.converged())
            .map(|(c, _)| c.result.f)
            .fold(f64::INFINITY, f64::min);
        let ceiling = ceiling.min(LINE_CEILING * line_best);
        let solved: Vec<Result<Vec<(Candidate, bool)>, Error>> =
            bases[split..].par_iter().map(|&basis| self.solve_seed(problem, p, basis, coil, ceiling, tables)).collect();
        for s in solved {
            out.extend(s?);
        }
        // Where no coil or loop was solved (all beyond the joints' reach), the lines are the
        // representative's only solutions: ranked with the others, not apart.
        if out.iter().all(|(_, extra)| *extra) {
            out.iter_mut().for_each(|(_, extra)| *extra = false);
        }
        Ok(out)
    }

    /// The coarse solutions of one seed of [`Self::solve_seeds`] on its `spans` uniform spans
    /// (`coil`: the representative has a coil of two turns or more).
    fn solve_seed(
        &self,
        problem: &ChainProblem,
        p: &Prepared,
        (seed, spans): (Seed, usize),
        coil: bool,
        ceiling: f64,
        tables: &Tables,
    ) -> Result<Vec<(Candidate, bool)>, Error> {
        let o = &self.options;
        let line = &p.line;
        let mut out = Vec::new();
        let disc = self.discretise(problem, p.targets.clone(), spans, o.quadrature_nodes, tables)?;
        // The seeds `fit_radius` projected, with their costs: a start among them (the seed as
        // estimated, the re-fitted one) is taken from there, not projected again.
        let fitted_seeds = RefCell::new(Vec::<(Seed, DVector<f64>, f64)>::new());
        let project = |seed: Seed| match fitted_seeds.borrow().iter().find(|(s, ..)| *s == seed) {
            Some((_, x, _)) => Ok(x.clone()),
            None => disc.project(line.path_of(seed)),
        };
        let residual = |s: Seed| {
            let Ok(x) = project(s) else { return f64::NAN };
            let e = disc.evaluate(&x, 0);
            fitted_seeds.borrow_mut().push((s, x, e.f));
            e.c
        };
        let cost = |seed: Seed, x: &DVector<f64>| match fitted_seeds.borrow().iter().find(|(s, ..)| *s == seed) {
            Some((.., f)) => *f,
            None => disc.evaluate(x, 0).f,
        };
        let mut starts = Vec::new();
        let reach = |s: Seed| seed == Seed::Line || self.within_speeds(line, s);
        match seed {
            Seed::Line => starts.push((project(seed)?, None)),
            Seed::Loop { .. } => {
                let fitted = line.fit_radius(seed, o.max_loop_radius, residual);
                let radius = |s: Seed| match s {
                    Seed::Loop { radius, .. } => radius,
                    _ => f64::NAN,
                };
                // A re-fitted radius near the estimate: one start, the re-fitted one
                // ([`ONE_LOOP_START`]).
                let near = (radius(fitted) / radius(seed) - 1.0).abs() < ONE_LOOP_START;
                let loops = if near { vec![fitted] } else { vec![seed, fitted] };
                for s in loops.into_iter().filter(|s| reach(*s)) {
                    starts.push((project(s)?, None));
                }
            }
            Seed::Coil { .. } => {
                let fitted = line.fit_radius(seed, self.coil_room(seed, o.max_loop_radius), residual);
                if reach(fitted) {
                    let x0 = project(fitted)?;
                    let guess = (p.needed.abs() > 0.0).then(|| -2.0 * cost(fitted, &x0) / p.needed);
                    starts.push((x0, guess));
                }
            }
        }
        let nodes = o.quadrature_nodes;
        // Not with clearance rows: capped there, the SPART-like clearance bench took 5.0 s
        // instead of 3.8 s (its line's finest-basis solve from the capped start is longer).
        let rate_limited_line = seed == Seed::Line
            && self.arm.limits.rate_limited()
            && o.max_spans > spans
            && !super::limits::keeps_clearance(self);
        // A loop whose re-fitted radius is its own (the fit found none better) starts from the
        // same point twice: its solutions are the first start's again, taken without solving
        // (the solves are deterministic; issue 21's SPART-like bench solved two such pairs).
        let mut previous: Option<(DVector<f64>, Option<f64>, usize)> = None;
        // A solve under the ceiling's watch where it is finite ([`Hopeless`]), with the limits'
        // and the clearance's rows too: on issue 21's SPART-like bench the plan without the
        // clearance rows solved its second representative's rate-limited line on the finest
        // basis twice (28 and 40 iterations, 173 QPs, a third of the plan's time) to end 1.4 rad
        // off the holonomy at 29.2, five times its ceiling.
        let watched = |disc: &Discretisation, x0, options: &SqpOptions, guess| {
            let mut watch = Hopeless::new(ceiling, options.max_iterations);
            let mut abandon = |k, f, c| ceiling.is_finite() && watch.abandon(k, f, c);
            super::limits::solve_watched(self, disc, x0, options, guess, &mut abandon)
        };
        for (x0, guess) in starts {
            if let Some((same, g, from)) = &previous
                && *same == x0
                && *g == guess
            {
                let again = out[*from..].to_vec();
                out.extend(again);
                continue;
            }
            previous = Some((x0.clone(), guess, out.len()));
            let coarse = |x0, options: &SqpOptions| {
                let result = watched(&disc, x0, options, guess);
                let result = result.ok()?;
                let iterations = result.iterations;
                Some(Candidate::new(disc.clone(), result, [spans, nodes, self.options.grading], iterations))
            };
            // The rate-limited line's coarse solve to `super::limits::CAPPED_LINE` iterations
            // first: where it is still infeasible there it serves only as the finest basis' warm
            // start (below), and the rest of its solve was wasted (issue 20's 3-link bench: 24
            // iterations, 67 QPs, to a stall off the constraint; from the 8th the finest basis'
            // solve takes the same 9). Elsewhere, solved in full from the seed, as without a cap.
            let capped = SqpOptions { max_iterations: super::limits::CAPPED_LINE, ..COARSE_SQP };
            let Some(mut c) = coarse(x0.clone(), if rate_limited_line { &capped } else { &COARSE_SQP }) else {
                continue;
            };
            let full = |c: Candidate| if rate_limited_line { coarse(x0.clone(), &COARSE_SQP) } else { Some(c) };
            if rate_limited_line && c.feasible() && !c.result.converged() {
                // Feasible there: the rest of the solve, from where it stopped.
                let rest = SqpOptions { max_iterations: COARSE_SQP.max_iterations - c.iterations, ..COARSE_SQP };
                let more = super::limits::solve(self, &disc, c.result.x.clone(), &rest, Some(c.result.lambda));
                let Ok(result) = more else { continue };
                let iterations = c.iterations + result.iterations;
                c = Candidate::new(disc.clone(), result, [spans, nodes, self.options.grading], iterations);
            }
            let feasible = c.feasible();
            // A rate limit's control-point rows are conservative by `O(h^2)` on spans of
            // width `h`: where the coarse line cannot meet the constraint inside them, the
            // line again on the finest basis. Where that one is feasible it stands for the
            // coarse line, which is dropped: refining the coarse line (a far finalist) solves
            // the same seed again on finer bases (on issue 20's 3-link bench 75 to 104 of 400
            // ms, to a worse plan or none).
            if seed == Seed::Line && !feasible && self.arm.limits.rate_limited() && o.max_spans > spans {
                // With clearance rows the coarse line is solved in full (not capped): where it
                // ended far off the holonomy, the line is given up (`STALLED_FAR`).
                if super::limits::keeps_clearance(self) && c.result.c.abs() > STALLED_FAR {
                    continue;
                }
                // On the end layers' grading where every limit is a control-point row
                // (`ChainPlanner::graded_line`).
                let grading = self.graded_line();
                let fine = self.discretise_graded(
                    problem,
                    p.targets.clone(),
                    [o.max_spans, o.quadrature_nodes, grading],
                    tables,
                )?;
                // From the coarse line's solution (nearer the limits' minimum than the line; on
                // the 3-link bench the plan's iterations 46 -> 18), and from the line where that
                // start is not feasible (issue 20's oracle case 6 stalled from it), but not where
                // the watch gave it up: on issue 21's SPART-like bench (its plan without rows) the
                // solve from the line was given up after 10 iterations too (9.73 -> 8.79 G).
                let (old, basis) = (c.disc.coefficients(&c.result.x), c.disc.basis());
                let warm = fine.project(|t, out| basis.values_each(&old, t, out))?;
                // The penalty balanced at the start ([`SqpOptions::balanced`]).
                let solve = |x0: DVector<f64>| watched(&fine, x0.clone(), &COARSE_SQP.balanced(&fine, &x0), None).ok();
                let mut result = solve(warm);
                let given_up = |r: &SqpResult| r.termination == Termination::Abandoned;
                if !result.as_ref().is_some_and(|r| (r.c.abs() <= 1e-6 && r.f.is_finite()) || given_up(r)) {
                    result = solve(fine.project(line.path_of(seed))?);
                }
                if let Some(result) = result {
                    let iterations = result.iterations;
                    let mut f = Candidate::new(fine, result, [o.max_spans, nodes, grading], iterations);
                    // Feasible, it stands for the coarse line (`Candidate::stands_for`).
                    f.stands_for = f.feasible().then_some(c.result.f);
                    if !f.feasible()
                        && let Some(c) = full(c)
                    {
                        out.push((c, coil));
                    }
                    out.push((f, true));
                    continue;
                }
                let Some(again) = full(c) else { continue };
                c = again;
            }
            out.push((c, coil && seed == Seed::Line));
        }
        Ok(out)
    }

    /// The seeds of a representative with the uniform spans each is solved on: a coil on
    /// [`SPANS_PER_TURN`] per turn; the line and loops on the coarse basis and, where the line
    /// travels far, on [`LINE_SPANS_PER_TURN`] per turn too.
    fn seed_bases(&self, p: &Prepared) -> Vec<(Seed, usize)> {
        let o = &self.options;
        let long = line_spans(&p.line).min(o.max_spans);
        let mut out = Vec::new();
        for &seed in &p.seeds {
            if let Seed::Coil { turns, .. } = seed {
                out.push((seed, o.coarse_spans.max(SPANS_PER_TURN * turns)));
                continue;
            }
            out.push((seed, o.coarse_spans));
            if long > o.coarse_spans {
                out.push((seed, long));
            }
        }
        out
    }

    /// The largest radius, at most `max` \[rad\], of a coil about `seed`'s centre inside the
    /// position ranges of its plane's joints, where the coil is inside them (a site's disc is,
    /// see [`super::coil::sites`]; the radius re-fitted to the constraint stays inside too);
    /// `max` for a coil that leaves a range (one that rides its bound once clipped).
    fn coil_room(&self, seed: Seed, max: f64) -> f64 {
        let Seed::Coil { i, j, centre, radius, .. } = seed else { return max };
        let room = [(i, centre[0]), (j, centre[1])]
            .iter()
            .fold(max, |r, &(k, c)| self.arm.limits.joint(k).position.map_or(r, |[lo, hi]| r.min(c - lo).min(hi - c)));
        if radius <= room { room } else { max }
    }

    /// Whether every velocity-limited joint can follow `seed`'s path in the horizon: its total
    /// variation along the path (sampled at 64 points per turn) at most `v T`. A rule of thumb,
    /// not a proof: the solve from a loop or coil beyond it keeps the seed's winding, and is
    /// skipped (a smaller loop of the same winding might fit, and is then not tried).
    fn within_speeds(&self, line: &Line, seed: Seed) -> bool {
        let limits = &self.arm.limits;
        let n = self.arm.joints();
        if (0..n).all(|j| limits.joint(j).velocity.is_none()) {
            return true;
        }
        let turns = match seed {
            Seed::Loop { turns, .. } | Seed::Coil { turns, .. } => turns.max(1),
            Seed::Line => 1,
        };
        let samples = 64 * turns;
        let (mut previous, mut at) = (vec![0.0; n], vec![0.0; n]);
        let mut variation = vec![0.0; n];
        let path = line.path_of(seed);
        path(0.0, &mut previous);
        for k in 1..=samples {
            path(line.horizon * k as f64 / samples as f64, &mut at);
            for j in 0..n {
                variation[j] += (at[j] - previous[j]).abs();
            }
            std::mem::swap(&mut previous, &mut at);
        }
        (0..n).all(|j| limits.joint(j).velocity.is_none_or(|v| variation[j] <= v * line.horizon * (1.0 + 1e-9)))
    }
}
