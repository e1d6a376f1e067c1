//! The end layers of a plan whose velocity limit binds where it leaves or reaches rest (issue 20,
//! the limits oracle's case 13).
//!
//! Without an acceleration limit the minimum-effort path of a joint that runs at its velocity
//! limit from the start jumps to that speed at `t = 0`: the constrained problem's infimum is not
//! attained, and a spline from rest gets near it only by ramping up within its first knot
//! spans. A joint held at its limit loses, in a ramp of duration `tau`, about `v tau / 2` of
//! travel that the rest of the path must make up at a higher cost, an effort gap of order
//! `tau / T` that doubling the uniform spans only halves. The graded knots at `h / 4^j` of the
//! end spans ([`crate::planners::optimal::spline::SplineBasis::graded`]) are such a ramp's room:
//! each further level quarters `tau` at the cost of two knots per end. On case 13 (three joints
//! at their velocity limits from the start or up to the goal, 32 spans) the plan costs 7.2300
//! with one level, 7.1423 with two, 7.1217 with three, 7.1166 with four, against the oracle's
//! 7.1224 on its piecewise-linear transcription (whose first interval may start at full speed),
//! while 64 and 128 uniform spans at one level give 7.1653 and 7.1362.
//!
//! The spline spaces are nested (a level inserts knots), so the refined solution's projection
//! onto the finer basis is the same path, inside the same limits (a knot insertion's control
//! points are convex combinations of the old ones): the solve there starts feasible at the same
//! effort. A refinement at its limit in an end layer is solved once more with the end spans
//! graded to [`END_GRADING`] levels (one solve of 4 to 7 SQP iterations on the benches, about
//! as many from one level to the next), except where a torque limit binds in that end layer:
//! the torque then sets the ramp, and the thin spans gained only between the torque rows'
//! points, beyond the limit.

use super::super::search::Candidate;
use super::super::tables::Tables;
use super::super::{ChainPlanner, ChainProblem, ChainStats};
use super::torque_times;
use crate::dynamics::arm::ArmDynamics;
use crate::error::Error;

/// Graded knots per end of a refinement at its velocity limit in an end layer (`h / 4^3`: on 32
/// spans of a 10 s horizon, 4.9 ms). Deeper levels gain under 0.15 % more (four: the 3-link
/// velocity bench 17.6058 -> 17.5945, the 2-link 0.44707 -> 0.44652, case 13 7.1217 -> 7.1166)
/// while the SQP begins to stall there (at four the oracle's cases 10 and 14 collapsed their
/// trust region; at five and six the benches stall short of their KKT tolerance, and the
/// certificate's finer steps took up to five times longer).
pub(in super::super) const END_GRADING: usize = 3;

/// A joint whose speed is within this relative distance of its limit is at it.
const AT_LIMIT: f64 = 1e-4;

/// Samples of the speed per end layer (the first or last uniform span).
const SAMPLES: usize = 16;

impl ChainPlanner {
    /// A converged refinement `c` at its velocity limit in an end layer (a joint at its limit
    /// within the first or last uniform span) with fewer than [`END_GRADING`] graded knots per
    /// end, solved again, warm-started from itself, with that many: the solution there where it
    /// converges at no higher cost, else `c`. Unchanged elsewhere, on given knots
    /// ([`super::super::ChainOptions::knots`]), and where a torque limit binds in an end layer
    /// ([`Self::torque_held_in_an_end_layer`]). The finer solve, held between the rows' points
    /// ([`Self::hold_between_points`]), is kept only inside every limit ([`Self::inside_limits`]).
    pub(in super::super) fn sharpen_ends(
        &self,
        problem: &ChainProblem,
        c: Candidate,
        tables: &Tables,
    ) -> Result<Candidate, Error> {
        if self.options.knots.is_some()
            || c.grading >= END_GRADING
            || !c.result.converged()
            || !self.at_speed_in_an_end_layer(&c)
            || self.torque_held_in_an_end_layer(&c)
        {
            return Ok(c);
        }
        let graded = Candidate { grading: END_GRADING, ..c.clone() };
        let finer = self.resolve(problem, &graded, c.spans, c.nodes, tables)?;
        let better = |f: &Candidate| f.result.converged() && f.result.f <= c.result.f;
        // Held between the rows' points first ([`super::hold`]): on thin graded spans a torque
        // rises between them (SPART's example with tight limits at 13.5 s: to 1 + 4.3e-5 of its
        // limit, which the certificate's measure below refuses; the plan then stayed on one
        // level, its torque at 54 % of the limit).
        let finer = if better(&finer) { self.hold_between_points(problem, finer, tables)? } else { finer };
        Ok(if better(&finer) && self.inside_limits(problem, &finer) { finer } else { c })
    }

    /// The end grading of a rate-limited line's solve on the finest basis
    /// (`ChainPlanner::solve_seed`): [`END_GRADING`] where a velocity limit is declared and
    /// every declared limit is a row of control points (positions, velocities, accelerations:
    /// the convex hull holds them on the whole path, between any points), else the options'.
    /// The graded basis is the uniform one with knots inserted (a richer space, the solve
    /// starts from the same projection), and the refinement's end-layer solve is then spared
    /// (`profile_limits`: SQP iterations 3v 25 -> 19, 2v 21 -> 18; callgrind 3v 1054 -> 922 M,
    /// 2v 430 -> 353 M; the same efforts to 10 digits). A first version for every arm
    /// (8474d43) was reverted: a torque, bounded at the rows' points only, rose beyond its limit
    /// between them on thin graded spans.
    pub(in super::super) fn graded_line(&self) -> usize {
        let limits = &self.arm.limits;
        let velocity = limits.joints.iter().any(|l| l.velocity.is_some());
        let exact =
            limits.base.is_none() && limits.joints.iter().all(|l| l.torque.is_none()) && !super::keeps_clearance(self);
        if velocity && exact && self.options.knots.is_none() {
            END_GRADING.max(self.options.grading)
        } else {
            self.options.grading
        }
    }

    /// Whether `c`'s plan stays inside every declared limit by the certificate's own measure
    /// ([`crate::plan::limit_use::limit_use`], the limits of the integrated motion between its
    /// steps): a finer solve is kept over a coarser one only where it does (its torque rows hold
    /// at points only, and on thin graded spans a torque rose 0.04 % beyond its limit between
    /// them, the SPART-like arm's `--clearance 0.03` plan of `tests/it/geometry.rs` with its line
    /// solved on the graded ends from the start). False where the integration fails.
    fn inside_limits(&self, problem: &ChainProblem, c: &Candidate) -> bool {
        let plan = self.plan_of(c, ChainStats::unmeasured(c));
        crate::plan::limit_use::limit_use(&self.arm, &plan, &problem.start, &self.options.ode)
            .is_ok_and(|report| report.inside)
    }

    /// Whether a torque-limited joint of `c`'s path is at its limit (to [`AT_LIMIT`]) at a
    /// point of the torque rows in the first or last uniform span: there the torque limit, not
    /// the knots, sets how fast a joint leaves or reaches rest, and a finer grading's thin
    /// spans gain only by riding the torque limit between the rows' points, which the
    /// certificate's measure then refuses ([`Self::inside_limits`]). So it did on every such plan
    /// measured: the 3-link velocity and torque bench (17.9451 -> 17.8252 at points, refused)
    /// and the limits oracle's cases 2, 10, 14 and 18 (seven finer solves, all refused; each
    /// plan the unsharpened one): the finer solve is not attempted there.
    fn torque_held_in_an_end_layer(&self, c: &Candidate) -> bool {
        let limits: Vec<Option<f64>> = (0..self.arm.joints()).map(|j| self.arm.limits.joint(j).torque).collect();
        if limits.iter().all(Option::is_none) {
            return false;
        }
        let basis = c.disc.basis();
        let horizon = basis.horizon();
        let h = horizon / c.spans as f64;
        let coefficients = c.disc.coefficients(&c.result.x);
        let dynamics = ArmDynamics::new(&self.arm);
        let n = self.arm.joints();
        let (mut th, mut w, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let ends = |t: &f64| *t <= h + 1e-12 * horizon || *t >= horizon - h - 1e-12 * horizon;
        torque_times(basis).into_iter().filter(ends).any(|t| {
            for (j, cj) in coefficients.iter().enumerate() {
                [th[j], w[j], a[j]] = basis.evaluate(cj, t);
            }
            let tau = dynamics.inverse(&th, &w, &a).tau;
            limits.iter().zip(&tau).any(|(l, t)| l.is_some_and(|l| t.abs() >= (1.0 - AT_LIMIT) * l))
        })
    }

    /// Whether a velocity-limited joint of `c`'s path is at its limit (to [`AT_LIMIT`]) in the
    /// first or last uniform span.
    fn at_speed_in_an_end_layer(&self, c: &Candidate) -> bool {
        if self.arm.limits.joints.iter().all(|l| l.velocity.is_none()) {
            return false;
        }
        let basis = c.disc.basis();
        let horizon = basis.horizon();
        let h = horizon / c.spans as f64;
        let coefficients = c.disc.coefficients(&c.result.x);
        coefficients.iter().enumerate().any(|(j, cj)| {
            self.arm.limits.joint(j).velocity.is_some_and(|v| {
                (0..=SAMPLES).any(|k| {
                    let s = h * k as f64 / SAMPLES as f64;
                    [s, horizon - s].iter().any(|&t| basis.evaluate(cj, t)[1].abs() >= (1.0 - AT_LIMIT) * v)
                })
            })
        })
    }
}
