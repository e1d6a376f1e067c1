//! The goal representatives modulo 2 pi and the warm starts of each: the straight line, loops
//! beside it, a coil where the base must turn far, the NFA's joint path, and a given path (the
//! rest of the plan being followed, in re-planning).

use nalgebra::DVector;

use super::discrete::{Discretisation, Targets};
use super::motion::OptimalMotion;
use super::seeds::{self, CoilSite, Line, Sampled, SeedKind};
use super::{COARSE_SQP, Candidate, OptimalPlanner, Tables, sqp};
use crate::error::Error;
use crate::model::wrap_angle;
use crate::plan::{Motion, PlanningProblem};
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::{NfaOptions, NormalFormPlanner};

/// Uniform knot spans per turn of a coil seed (cubic B-splines follow a circle to about 1e-3 of
/// its radius at this resolution; the radius is then re-fitted to the constraint).
pub const SPANS_PER_TURN: usize = 6;

/// A joint goal (the bits of `theta(T)`) with its line's free coefficients on the coarse basis
/// and the line's holonomy integral \[rad\].
pub(super) type LineEntry = ([u64; 2], DVector<f64>, f64);

/// A goal representative with its coarse discretisation and the cheap numbers that rank it.
pub(super) struct Prepared {
    /// The constant-speed effort of its best seed \[rad^2/s\] (the ranking).
    pub estimate: f64,
    /// A lower bound of its effort \[rad^2/s\] (see [`seeds::effort_lower_bound`]).
    pub bound: f64,
    /// The coarse discretisation (the line's, the loops' and, without a coil, the NFA's).
    pub disc: Discretisation,
    /// Uniform knot spans of the coil's discretisation (`coarse_spans` without a coil).
    spans: usize,
    line: Line,
    /// The line's free coefficients on `disc`.
    x_line: DVector<f64>,
    /// The raw loop seeds (one per side), or the coil.
    kinds: Vec<SeedKind>,
    /// The rotation the seeds add to the line's \[rad\].
    needed: f64,
}

/// A warm start: the discretisation it is solved on, its spans, its free coefficients and the
/// SQP's initial multiplier.
pub(super) struct Start {
    /// The discretisation.
    pub disc: Discretisation,
    /// Its uniform knot spans.
    pub spans: usize,
    /// The free coefficients of the seed.
    pub x0: DVector<f64>,
    /// The initial multiplier (a coil's, see [`Prepared::multiplier_guess`]).
    pub guess: Option<f64>,
    /// The line beside a coil: ranked apart, an extra finalist where it beats the others (see
    /// [`OptimalPlanner::starts`]).
    pub extra: bool,
}

impl Prepared {
    /// The multiplier of a coil's solution as estimated at its seed `x0` on `disc`,
    /// `lambda ~ -2 f / needed`: the effort grows as the square of the coil's length, the
    /// rotation linearly, and `df/d phi_end = -lambda`.
    fn multiplier_guess(&self, disc: &Discretisation, x0: &DVector<f64>) -> Option<f64> {
        (self.needed.abs() > 0.0).then(|| -2.0 * disc.evaluate(x0, 0).f / self.needed)
    }

    fn is_coil(&self) -> bool {
        matches!(self.kinds.first(), Some(SeedKind::Coil { .. }))
    }
}

impl OptimalPlanner {
    /// The goal representatives `(theta(T), phi(T))` to try.
    pub(super) fn targets(&self, problem: &PlanningProblem) -> Vec<Targets> {
        let (q0, qd) = (problem.start, problem.goal);
        let start = [q0.theta1, q0.theta2];
        let make = |end: [f64; 2], phi_end: f64| Targets {
            start,
            initial_velocity: problem.start_velocity,
            end,
            phi_start: q0.phi,
            phi_end,
        };
        if !self.options.wrap {
            return vec![make([qd.theta1, qd.theta2], qd.phi)];
        }
        let joint = |from: f64, to: f64| {
            let near = from + wrap_angle(to - from);
            [near, near - std::f64::consts::TAU, near + std::f64::consts::TAU]
        };
        let phi = q0.phi + wrap_angle(qd.phi - q0.phi);
        let mut out = Vec::new();
        for t1 in joint(q0.theta1, qd.theta1) {
            for t2 in joint(q0.theta2, qd.theta2) {
                for k in [0.0, -1.0, 1.0] {
                    out.push(make([t1, t2], phi + k * std::f64::consts::TAU));
                }
            }
        }
        out
    }

    /// The NFA's joint path, sampled, when the NFA plans this problem.
    pub(super) fn nfa_path(&self, problem: &PlanningProblem) -> Option<(Sampled, [f64; 2], f64)> {
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

    /// A representative's line, the rotation its seeds must add, and its ranking numbers. Where
    /// one loop cannot add the rotation (a coil of two or more turns is needed), the coil is its
    /// only seed, on a basis fine enough for its turns.
    pub(super) fn prepare(
        &self,
        problem: &PlanningProblem,
        targets: Targets,
        kappa_max: f64,
        sites: &[CoilSite; 2],
        tables: &Tables,
        lines: &mut Vec<LineEntry>,
    ) -> Result<Prepared, Error> {
        let o = &self.options;
        let k = problem.robot.lumped();
        let disc = self.discretise(problem, targets, o.coarse_spans, o.quadrature_nodes, tables)?;
        let line = Line {
            start: targets.start,
            end: targets.end,
            initial_velocity: targets.initial_velocity,
            horizon: problem.horizon,
        };
        // The representatives of one joint goal share the line and its holonomy integral.
        let key = targets.end.map(f64::to_bits);
        let (x_line, integral) = match lines.iter().find(|(k, ..)| *k == key) {
            Some((_, x, integral)) => (x.clone(), *integral),
            None => {
                let x = disc.project(|t| line.at(t))?;
                let integral = disc.holonomy_integral(&x);
                lines.push((key, x.clone(), integral));
                (x, integral)
            }
        };
        let needed = -(targets.phi_start - integral - targets.phi_end);
        let bound = seeds::effort_lower_bound(&line, needed, kappa_max);
        let site = if needed >= 0.0 { &sites[0] } else { &sites[1] };
        let coil = line.coil(site, needed, o.max_loop_radius);
        if let SeedKind::Coil { turns, .. } = coil
            && turns >= 2
        {
            // The finer basis is built when the representative is solved (see `starts`).
            let spans = o.coarse_spans.max(SPANS_PER_TURN * turns);
            let estimate = line.effort_estimate(coil);
            return Ok(Prepared { estimate, bound, disc, spans, line, x_line, kinds: vec![coil], needed });
        }
        let mut kinds: Vec<SeedKind> =
            [1, -1].map(|side| line.loop_seed(&k, needed, side, 0, o.max_loop_radius)).into();
        kinds.push(line.axis_loop_seed(&k, needed, 0, o.max_loop_radius));
        let estimate = kinds.iter().map(|kind| line.effort_estimate(*kind)).fold(f64::INFINITY, f64::min);
        Ok(Prepared { estimate, bound, disc, spans: o.coarse_spans, line, x_line, kinds, needed })
    }

    /// The warm starts of a prepared representative: the line on the coarse basis; each loop as
    /// estimated and re-fitted to the constraint (they lead to different local minima), or the
    /// fitted coil on its finer basis; and the NFA's path where it ends at this representative.
    ///
    /// The line is solved beside a coil too: the SQP bends it into a path that turns the base
    /// where the curvature is large along the way rather than around one site, which can cost
    /// far less than the coil (the paper's problem at `a = 1, b = -1`: from the line 91.72, from
    /// the coil 111.39 rad^2/s at the same representative).
    pub(super) fn starts(
        &self,
        problem: &PlanningProblem,
        prepared: &Prepared,
        nfa: Option<&(Sampled, [f64; 2], f64)>,
        tables: &Tables,
    ) -> Result<Vec<Start>, Error> {
        let o = &self.options;
        let coarse = &prepared.disc;
        let fine;
        let (disc, spans) = if prepared.is_coil() {
            let targets = *coarse.targets();
            fine = self.discretise(problem, targets, prepared.spans, o.quadrature_nodes, tables)?;
            (&fine, prepared.spans)
        } else {
            (coarse, o.coarse_spans)
        };
        let line = &prepared.line;
        let max_radius = o.max_loop_radius;
        let residual = |kind: SeedKind| disc.project(|t| line.path(kind, t)).map(|x| disc.evaluate(&x, 0).c);
        let start = |x0: DVector<f64>, guess| Start { disc: disc.clone(), spans, x0, guess, extra: false };
        let (x0, extra) = (prepared.x_line.clone(), prepared.is_coil());
        let mut starts = vec![Start { disc: coarse.clone(), spans: o.coarse_spans, x0, guess: None, extra }];
        if !prepared.is_coil() {
            for kind in &prepared.kinds {
                starts.push(start(disc.project(|t| line.path(*kind, t))?, None));
            }
        }
        for kind in &prepared.kinds {
            let fitted = line.fit_radius(*kind, max_radius, |kind| residual(kind).unwrap_or(f64::NAN));
            let x0 = disc.project(|t| line.path(fitted, t))?;
            let guess = if prepared.is_coil() { prepared.multiplier_guess(disc, &x0) } else { None };
            starts.push(start(x0, guess));
        }
        let targets = disc.targets();
        if let Some((path, end, phi)) = nfa {
            let same_end = (end[0] - targets.end[0]).abs() < 1e-6 && (end[1] - targets.end[1]).abs() < 1e-6;
            if same_end && (phi - targets.phi_end).abs() < 1e-6 {
                starts.push(start(disc.project(|t| path.at(t))?, None));
            }
        }
        Ok(starts)
    }

    /// The motion from the warm start `path` ([`super::OptimalOptions::warm_start`]): its
    /// projection on the coarse basis, solved and refined like a finalist, on the representative
    /// whose joint goal it ends at. `None` when no representative matches or the solve does not
    /// converge (the full search follows).
    pub(super) fn warm(
        &self,
        problem: &PlanningProblem,
        path: &Sampled,
        tables: &Tables,
    ) -> Result<Option<OptimalMotion>, Error> {
        let o = &self.options;
        let Some(end) = path.theta.last() else { return Ok(None) };
        let near = |t: &Targets| (0..2).all(|j| (t.end[j] - end[j]).abs() <= 1e-6);
        let Some(targets) = self.targets(problem).into_iter().find(near) else { return Ok(None) };
        let disc = self.discretise(problem, targets, o.coarse_spans, o.quadrature_nodes, tables)?;
        let x0 = disc.project(|t| path.at(t))?;
        let Ok(result) = sqp::solve(&disc, x0, &COARSE_SQP, None) else { return Ok(None) };
        if !(result.c.abs() <= 1e-6 && result.f.is_finite()) {
            return Ok(None);
        }
        let iterations = result.iterations;
        let c = Candidate { disc, iterations, result, spans: o.coarse_spans, nodes: o.quadrature_nodes, motion: None };
        let c = self.refine(problem, c, tables)?;
        if !c.result.converged() {
            return Ok(None);
        }
        let total = c.iterations;
        Ok(Some(self.to_motion(problem, c, 1, total)))
    }
}
