//! The shortest horizon inside the robot's limits (issue 20 item 4; docs/spec.md §2): the least
//! `T`, to 1 %, at which the constrained planner finds a certified plan, and that plan. Where
//! the arm keeps a clearance (issue 21), a plan found is one that keeps it too.
//!
//! Feasibility is monotone in `T`: a plan of horizon `T` played `k > 1` times slower is a plan of
//! horizon `k T` with the same path (positions and base angle unchanged), velocities divided by
//! `k`, and accelerations and torques (Eq. 6 at zero momentum: `M theta'' + C theta'`) by `k^2`;
//! with the same path, the bodies keep the same distances. So the search brackets the shortest
//! horizon and bisects it (geometrically). Two bounds shorten it: below, a joint cannot average
//! more than its velocity limit,
//! `T >= |theta_d - theta_0| / v_max` (with an acceleration limit from rest, the bang-bang
//! time, `limits::least_time`); above, a plan at `T` with the largest uses `u_v` of a
//! velocity, `u_a` of an acceleration and `u_tau` of a torque limit time-scales to a feasible
//! motion at `T max(u_v, sqrt(u_a), sqrt(u_tau))`.
//!
//! The bracket's top is the plan without the rate limits (ranges kept) time-scaled that way and
//! re-solved with them; where that fails, the time-scaled plan as it is, certified there
//! (`too_short.rs`: a certified upper bound at the cost of that one search); full searches at
//! doubling horizons only when both fail. Each probe of
//! the bisection starts from the best plan so far, time-scaled to the probe's horizon (its
//! holonomy multiplier too), and is solved on its goal representative alone (a failed full
//! search costs every seed of every representative; a probe about as much as one refinement);
//! where the arm keeps a clearance, a probe's refinement that stalls on the constraints fits as
//! well as a converged one (the certificate decides; `warm::Ending::Feasible`).
//! The first probes step down from the top by 10 % until one fails (the bound below is often far
//! from the shortest horizon, and a probe far below it fails at the cost of a stalled solve).
//! The shortest horizon is thus that of the plan's own family of paths; the full search then runs
//! once at it (without the clearance search's last resort: a plan that clears is known there) and
//! its plan is kept where it costs less; where it is another family's, that family is probed at
//! the probes' failing horizon, and the bisection goes on from it where it fits there; else the
//! full search at the failing horizon decides it (a family that is not the cheapest at the
//! horizon found may fit shorter ones), and the bisection goes on below a plan it finds (without
//! the line of the probes' goal representative where the search at the horizon found solved
//! that line alone into the probes' plan: the probes decided it; and without the clearance
//! search's last resort). Its
//! cost: one unconstrained search, two constrained ones (one of them failing), and about
//! `log2(log(hi / lo) / log 1.01)` probes, fewer when the time-scaling bound is tight
//! ([`ShortestHorizon::probes`]).

use std::f64::consts::TAU;
use std::sync::Arc;
use std::time::Instant;

use super::discrete::Targets;
use super::search::COARSE_SQP;
use super::tables::Tables;
use super::warm::Ending;
use super::{ChainPlan, ChainPlanner, ChainPoint, ChainProblem, WarmStart};
use crate::dynamics::arm::inverse_dynamics;
use crate::error::Error;
use crate::model::InputError;
use crate::model::wrap_angle;
use crate::plan::HORIZON_RANGE;
use crate::planners::optimal::sqp::SqpOptions;

/// The relative accuracy of the shortest horizon.
pub const HORIZON_ACCURACY: f64 = 0.01;

/// The limit a plan uses most.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Binding {
    /// The joint, counted from 1 (0 for the base angle).
    pub joint: usize,
    /// `position`, `velocity`, `acceleration`, `torque` or `base`.
    pub quantity: &'static str,
    /// The declared limit (rad, rad/s, rad/s^2 or N m; the range's bound for positions).
    pub limit: f64,
    /// The fraction of the limit used, 1 on the limit (for ranges: the distance from the
    /// range's middle over its half-width).
    pub used: f64,
}

/// The result of [`ChainPlanner::shortest_horizon`].
#[derive(Debug, Clone)]
pub struct ShortestHorizon {
    /// The shortest horizon found \[s\]: a certified plan inside every limit exists at it.
    pub horizon: f64,
    /// The largest horizon known to fail \[s\] (by a probe, or by the velocity bound): the
    /// shortest feasible horizon lies in `(infeasible_below, horizon]`, within 1 %.
    pub infeasible_below: f64,
    /// The minimum-effort plan at `horizon`.
    pub plan: ChainPlan,
    /// Plans probed.
    pub probes: usize,
    /// Wall time of the search \[s\].
    pub seconds: f64,
    /// The limit the plan uses most (the one that binds).
    pub binding: Binding,
}

/// Largest use of each limit of `planner`'s arm by `plan` at 32 samples per knot span; the most
/// used limit, and the time-scaling factor `max(u_v, sqrt(u_a), sqrt(u_tau))` (0 without rate
/// limits).
pub fn uses(planner: &ChainPlanner, plan: &ChainPlan) -> (Option<Binding>, f64) {
    let arm = planner.arm();
    let n = arm.joints();
    let b = plan.basis().breakpoints();
    let mut best: Option<Binding> = None;
    let mut scale: f64 = 0.0;
    let mut note = |joint: usize, quantity: &'static str, limit: f64, used: f64| {
        if best.is_none_or(|x| used > x.used) {
            best = Some(Binding { joint, quantity, limit, used });
        }
    };
    let mut peak = vec![[0.0_f64; 4]; n];
    let mut range = vec![[f64::INFINITY, f64::NEG_INFINITY]; n + 1];
    // The inverse dynamics only where a torque is limited (on issue 20's 3-link velocity bench
    // it was 3.7 % of `--time auto`'s instructions, for torques no limit reads).
    let torques = (0..n).any(|j| arm.limits.joint(j).torque.is_some());
    for w in b.windows(2) {
        for k in 0..32 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 32.0;
            let p = joints_at(plan, t, arm.limits.base.is_some());
            let tau = if torques {
                inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau
            } else {
                nalgebra::DVector::zeros(n)
            };
            for j in 0..n {
                peak[j][0] = peak[j][0].max(p.rate[j].abs());
                peak[j][1] = peak[j][1].max(p.acceleration[j].abs());
                peak[j][2] = peak[j][2].max(tau[j].abs());
                range[j + 1] = [range[j + 1][0].min(p.theta[j]), range[j + 1][1].max(p.theta[j])];
            }
            range[0] = [range[0][0].min(p.phi), range[0][1].max(p.phi)];
        }
    }
    let extent = |r: [f64; 2], [lo, hi]: [f64; 2]| {
        let (mid, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
        ((r[1] - mid).max(mid - r[0]) / half, if r[1] - mid > mid - r[0] { hi } else { lo })
    };
    for j in 0..n {
        let l = arm.limits.joint(j);
        for (q, limit, used, root) in [
            ("velocity", l.velocity, peak[j][0], false),
            ("acceleration", l.acceleration, peak[j][1], true),
            ("torque", l.torque, peak[j][2], true),
        ] {
            if let Some(v) = limit {
                let u = used / v;
                scale = scale.max(if root { u.sqrt() } else { u });
                note(j + 1, q, v, u);
            }
        }
        if let Some(r) = l.position {
            let (u, bound) = extent(range[j + 1], r);
            note(j + 1, "position", bound, u);
        }
    }
    if let Some(r) = arm.limits.base {
        let (u, bound) = extent(range[0], r);
        note(0, "base", bound, u);
    }
    (best, scale)
}

/// `plan`'s joint angles, rates and accelerations at `t` (clamped to `[0, T]`), and its base
/// angle only `with_phi` (0 otherwise): the holonomy's quadrature from the breakpoint before `t`
/// was 9 % of `--time auto`'s instructions on issue 20's 3-link velocity bench, in [`uses`] and
/// the probes' warm starts, which read no base angle without a base range.
fn joints_at(plan: &ChainPlan, t: f64, with_phi: bool) -> ChainPoint {
    let t = t.clamp(0.0, plan.horizon());
    let phi = if with_phi { plan.phi(t) } else { 0.0 };
    let mut point = ChainPoint { t, phi, theta: Vec::new(), rate: Vec::new(), acceleration: Vec::new() };
    plan.basis().evaluate_each(plan.coefficients(), t, |_, [v, d, a]| {
        point.theta.push(v);
        point.rate.push(d);
        point.acceleration.push(a);
    });
    point
}

/// The margin above the secant's estimate of the shortest horizon at which it is probed: a
/// probe that fits there closes the bracket when the estimate is within 0.75 % above the
/// failure. The probes' residuals are those at which they stop ([`PROBE_SQP`]), up to 3 %
/// above the plateau a longer crawl reaches (5.08e-3 against 4.92e-3 rad at 9.874 s on issue
/// 20's 3-link velocity bench), which moves the estimate up by about 0.01 %; at 0.3 % the
/// bench's horizon rose from 9.9329 to 9.9339 s, at 0.25 % it is 9.9289 s.
const SECANT_MARGIN: f64 = 0.0025;

/// The secant estimate of the shortest horizon from the last two failing probes `(t, residual)`
/// of a family: the residual its solve stopped at falls to 0 at the shortest horizon (about
/// linearly near it: 8.2e-2 and 4.9e-3 rad at 9.41 and 9.87 s on issue 20's 3-link velocity
/// bench, whose shortest horizon is in (9.87, 9.93] s). `None` without two finite residuals
/// falling with the horizon.
fn secant(failures: &[(f64, f64)]) -> Option<f64> {
    let [.., (t1, r1), (t2, r2)] = failures else { return None };
    (r1.is_finite() && r2.is_finite() && *r2 > 0.0 && r1 > r2 && t2 > t1).then(|| t2 + r2 * (t2 - t1) / (r1 - r2))
}

/// SQP options of a probe's solve: the coarse solves', an infeasible one given up after 6
/// iterations (not 12) that reduce its infeasibility by under 30 % (not 1 %), as a deciding
/// search's solves (`limits::DECIDING_PROGRESS`): a probe only asks whether the horizon fits.
/// The probes that failed on issue 20's 3-link velocity bench had reached their plateau
/// (8.24e-2 and 4.92e-3 rad off the holonomy) 12 iterations before they stopped (3.57 -> 3.08 G
/// instructions with 6 iterations); the one at 9.874 s then still crawled from 6.06e-3 to
/// 4.92e-3 rad in 16 iterations at radii of 1e-3 .. 8e-2 (43 QPs), and stops at 5.08e-3 after
/// 9 with this (the bench's QPs 134 -> 106).
const PROBE_SQP: SqpOptions = SqpOptions { stall_iterations: 3, feasibility_progress: 0.3, ..COARSE_SQP };

/// A full search's plan cheaper than the probes' by more than this fraction is another family of
/// paths (the same one's differ by the refinement's tolerance).
const OTHER_FAMILY: f64 = 1e-3;

/// The first step down from a plan that fits, before any probe of its family has failed: the
/// probe at `hi / FIRST_STEP` (a probe far below the shortest horizon fails at the cost of a
/// stalled solve, 100 to 180 ms against 12 to 50 ms for one that fits on issue 20's 3-link
/// velocity bench, and the bound below is often far: 1.18 s there, against 9.92 s).
const FIRST_STEP: f64 = 1.1;

/// A plan's use of a rate limit (the time-scaling factor of [`uses`]) from which a longer horizon
/// may find what this one did not.
const RATE_BINDS: f64 = 0.99;

/// Joint ends and base targets closer than this are the same goal representative \[rad\]
/// (representatives differ by turns; a plan reaches its ends to the certificate's 1e-9).
const SAME_TARGET: f64 = 1e-6;

/// The goal representative `plan` ends at: its joint ends, and the base goal's turn nearest its
/// base angle at the end.
fn targets(problem: &ChainProblem, plan: &ChainPlan) -> Targets {
    let end = plan.at(plan.horizon());
    let goal0 = problem.goal[0];
    Targets {
        start: problem.start[1..].to_vec(),
        initial_velocity: problem.initial_velocity.clone(),
        end: end.theta,
        phi_start: problem.start[0],
        phi_end: goal0 + TAU * ((end.phi - goal0) / TAU).round(),
    }
}

/// The verified motion inside every limit and clear of every body and obstacle by the clearance
/// asked for: a plan the search may stop at. The planner returns a plan that does not clear as
/// its least bad one (`keep_clear`), which is no horizon found.
fn fits(plan: &ChainPlan) -> bool {
    let v = &plan.verification;
    v.limits.as_ref().is_none_or(|l| l.inside) && v.clearance.is_none_or(|r| r.holds())
}

impl ChainPlanner {
    /// The shortest horizon, to 1 %, at which this planner finds a certified plan inside every
    /// limit of the arm, and the minimum-effort plan at it (see the [module docs](self)).
    /// `problem.horizon` is the first horizon probed. An error when no horizon up to the largest
    /// of [`HORIZON_RANGE`] gives a plan (the last attempt's error).
    pub fn shortest_horizon(&self, problem: &ChainProblem) -> Result<ShortestHorizon, Error> {
        problem.validate(self.arm())?;
        let clock = Instant::now();
        let arm = self.arm();
        let mut lo = HORIZON_RANGE.0;
        for j in 0..arm.joints() {
            let l = arm.limits.joint(j);
            let delta = problem.goal[j + 1] - problem.start[j + 1];
            let delta = if problem.wrap && l.position.is_none() { wrap_angle(delta) } else { delta };
            let at_rest = problem.initial_velocity.iter().all(|w| *w == 0.0);
            let least = super::limits::least_time(delta, l.velocity, l.acceleration, at_rest);
            // No horizon the planner takes is long enough: the limit is the input to change.
            if least > HORIZON_RANGE.1 {
                return Err(Error::from(InputError::InvalidParameter {
                    name: format!(
                        "joint {}'s velocity or acceleration limit (the joint needs at least {least:.3e} s to move \
                         {:.6} rad within it)",
                        j + 1,
                        delta.abs()
                    ),
                    value: l.velocity.or(l.acceleration).unwrap_or(f64::NAN),
                    expected: "limits that let every joint reach its goal within the longest horizon, 1e6 s",
                }));
            }
            lo = lo.max(least);
        }
        let mut probes = 0;
        // The bracket: the plan without the rate limits at the first horizon, time-scaled to
        // where it fits them (see the module docs), and re-solved there with them; when that
        // fails, full searches at doubling horizons.
        let mut t = problem.horizon.max(lo * (1.0 + HORIZON_ACCURACY));
        let mut found: Option<(f64, ChainPlan)> = None;
        let mut last_error = None;
        probes += 1;
        match self.without_rate_limits().plan(&ChainProblem { horizon: t, ..problem.clone() }) {
            Ok(free) => {
                let (_, scale) = uses(self, &free);
                let scaled = t * (scale * 1.002).max(1.0);
                if scaled <= HORIZON_RANGE.1
                    && let Ok(plan) = self.probe(problem, &free, scaled)?
                {
                    found = Some((scaled, plan));
                } else if let Some(fit) = self.scaled_fit(&ChainProblem { horizon: t, ..problem.clone() }, &free)? {
                    // That plan as it is, certified there (`too_short.rs`): on issue 21's
                    // SPART-like example at 0.02 m the re-solve at 15.00 s stalled, and full
                    // searches at doubling horizons, each with the clearance search, followed.
                    found = Some((fit.horizon(), fit));
                }
            }
            Err(e) if e.is_bad_input() => return Err(e),
            Err(e) => last_error = Some(e),
        }
        while found.is_none() && t <= HORIZON_RANGE.1 {
            probes += 1;
            match self.plan(&ChainProblem { horizon: t, ..problem.clone() }) {
                Ok(plan) if fits(&plan) => found = Some((t, plan)),
                // The least bad plan where none clears (`keep_clear`): a longer horizon only
                // relaxes the rate limits, so the search goes on past a collision only while one
                // binds.
                Ok(plan) => {
                    let v = &plan.verification;
                    match v.collision() {
                        Err(e) if uses(self, &plan).1 < RATE_BINDS => return Err(e),
                        Err(e) => last_error = Some(e),
                        Ok(()) => last_error = v.limits.as_ref().and_then(|l| l.check().err()),
                    }
                    lo = lo.max(t);
                    t *= 2.0;
                }
                Err(e) if e.is_bad_input() => return Err(e),
                Err(e) => {
                    last_error = Some(e);
                    lo = lo.max(t);
                    t *= 2.0;
                }
            }
        }
        let Some((mut hi, mut plan)) = found else {
            return Err(last_error.unwrap_or(Error::OptimalFailed {
                iterations: 0,
                constraint_residual: f64::INFINITY,
                kkt_residual: f64::INFINITY,
                effort: f64::INFINITY,
                seeds: 0,
                termination: "no_horizon",
            }));
        };
        // Bisection, each probe from the time-scaled plan at `hi` alone (its family of paths),
        // then the full search at the horizon found: the minimum-effort plan there. Where that
        // is another family's, cheaper than the probes' plan, the other family may reach
        // shorter horizons: probed at the probes' failing horizon, and where it fits there the
        // bisection goes on below it from that plan (the probes' failures bound the old family
        // only); else the full search at the probes' failing horizon decides it (below).
        let failed = loop {
            let mut below = lo;
            // This round's failing probes with their residuals, and whether the last one failed.
            let (mut failures, mut failed_last) = (Vec::new(), false);
            while hi > below * (1.0 + HORIZON_ACCURACY) {
                let secant = if failed_last { secant(&failures) } else { None };
                let t = self.next_probe(&plan, below, lo, hi, secant);
                probes += 1;
                match self.probe(problem, &plan, t)? {
                    Ok(p) => (hi, plan, failed_last) = (t, p, false),
                    Err(residual) => {
                        (below, failed_last) = (t, true);
                        failures.push((t, residual));
                    }
                }
            }
            // The minimum-effort plan at the horizon found: the full search, where it does
            // better. Without the clearance search's last resort (`keep_clear`), which only looks
            // for a plan that clears where the search found none: there is one at `hi` already.
            // On the SPART-like tight fixture's issue 20/21 case (`docs/spec.md` §2) it found
            // none there, and the search took 262 s of CPU with it, 196 s without (the same
            // plan).
            probes += 1;
            let last = ChainPlanner { last_resort: false, ..self.clone() };
            let full = last.plan(&ChainProblem { horizon: hi, ..problem.clone() });
            // The full search solved one seed, its first representative's line (no warm start,
            // no clearance search's phases), into the probes' family: the probes' failure at
            // `below` decided that line ([`ChainPlanner::line_decided`]).
            let line = full.as_ref().is_ok_and(|f| {
                f.stats.seeds == 1
                    && f.stats.cost >= plan.stats.cost * (1.0 - OTHER_FAMILY)
                    && self.options.warm_start.is_none()
                    && !super::limits::keeps_clearance(self)
            });
            if let Ok(f) = full
                && fits(&f)
                && f.stats.cost < plan.stats.cost
            {
                let other = f.stats.cost < plan.stats.cost * (1.0 - OTHER_FAMILY);
                plan = f;
                if other && below > lo {
                    probes += 1;
                    if let Ok(p) = self.probe(problem, &plan, below)? {
                        (hi, plan) = (below, p);
                        continue;
                    }
                }
            }
            if below <= lo {
                break below;
            }
            // The probes' failure bounds their family only: the full search at the failing
            // horizon decides it, and a plan there moves the top down. Another family that is
            // not the cheapest at the horizon found may fit shorter ones: the 3-link example from
            // rest at 0 to (30, 10, 10, 10) deg inside 10 deg/s, whose cheapest family at
            // 37.07 s fits no shorter, fits down to 33.01 s by another (found so, at the cost of
            // one failed full search: 840 of 2090 ms on issue 20's 3-link velocity bench). The
            // search only decides whether the horizon fits (a plan there is not kept as the
            // answer: the full search at the top runs again), so its solves give up an infeasible
            // crawl as the probes do and are not restarted off the constraint
            // (`ChainPlanner::deciding`): on issue 20's `--time auto` bench it failed in 292 QPs
            // instead of 426 (3564 Clarabel iterations instead of 5461), the same horizon and plan.
            // Without the line the probes decided ([`ChainPlanner::line_decided`]): there it
            // solved nothing else, and `--time auto` took 2041 M instructions instead of 4199 M.
            probes += 1;
            let decided_line = line.then(|| Arc::new(targets(problem, &plan)));
            // Without the clearance search's last resort (`keep_clear`), a soft search per goal
            // representative: on issue 21's SPART-like example at 0.02 m it found a plan at
            // every failing horizon, from which every probe failed, 0.6 % a round at 60 to 90 s
            // each (8.40 s in 11.5 min of CPU); with the probes that accept a stalled refinement
            // and without it, 7.79 s in 52 s (with it, the same in 79 s).
            let deciding = ChainPlanner { deciding: true, decided_line, last_resort: false, ..self.clone() };
            match deciding.plan(&ChainProblem { horizon: below, ..problem.clone() }) {
                Ok(p) if fits(&p) => (hi, plan) = (below, p),
                Err(e) if e.is_bad_input() => return Err(e),
                _ => break below,
            }
        };
        let (binding, _) = uses(self, &plan);
        let binding = binding.unwrap_or(Binding { joint: 0, quantity: "none", limit: f64::NAN, used: 0.0 });
        Ok(ShortestHorizon {
            horizon: hi,
            infeasible_below: failed,
            plan,
            probes,
            seconds: clock.elapsed().as_secs_f64(),
            binding,
        })
    }

    /// The next horizon the bisection probes in `(below, hi)`, `plan` fitting at `hi`: where the
    /// plan's rate limits are not all used, the horizon it time-scales to (when that is at least
    /// 2 % shorter: nearer, a probe a round moves the top by under 2 %); else the geometric
    /// middle, and while no probe has failed (`below` is the bound `lo`) at most
    /// [`FIRST_STEP`] below `hi`. Right after a failure, the `secant` estimate of the shortest
    /// horizon where it lies in the bracket, [`SECANT_MARGIN`] above it.
    fn next_probe(&self, plan: &ChainPlan, below: f64, lo: f64, hi: f64, secant: Option<f64>) -> f64 {
        let (_, scale) = uses(self, plan);
        let mid = (below * hi).sqrt();
        let scaled = hi * scale * 1.002;
        let secant = secant.map(|t| t * (1.0 + SECANT_MARGIN)).filter(|t| *t > below && *t < hi);
        if let Some(t) = secant {
            t
        } else if scale > 0.0 && scaled > mid && scaled < hi / 1.02 {
            scaled
        } else if below <= lo {
            mid.max(hi / FIRST_STEP)
        } else {
            mid
        }
    }

    /// This planner with the arm's velocity, acceleration and torque limits removed (its ranges
    /// kept).
    pub(super) fn without_rate_limits(&self) -> ChainPlanner {
        let mut limits = self.arm().limits.clone();
        for j in &mut limits.joints {
            (j.velocity, j.acceleration, j.torque) = (None, None, None);
        }
        let arm = self.arm().clone().with_limits(limits).expect("the arm's own ranges");
        ChainPlanner::new(arm, self.options.clone())
    }

    /// The plan at horizon `t` from `plan` time-scaled to it (same path, same goal
    /// representative) alone, inside every limit and clear; where it does not converge, certify
    /// and fit, the residual its coarse solve stopped at (NaN when that one met the constraints;
    /// see `ChainPlanner::solve_from`).
    pub(super) fn probe(
        &self,
        problem: &ChainProblem,
        plan: &ChainPlan,
        t: f64,
    ) -> Result<Result<ChainPlan, f64>, Error> {
        let horizon = plan.horizon();
        let k = horizon / t;
        let samples = 16 * plan.stats.spans.max(8);
        let (mut times, mut theta, mut rate) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..=samples {
            let p = joints_at(plan, horizon * i as f64 / samples as f64, false);
            times.push(t * i as f64 / samples as f64);
            theta.push(p.theta);
            rate.push(p.rate.iter().map(|v| v * k).collect());
        }
        let path = WarmStart { t: times, theta, rate };
        let targets = targets(problem, plan);
        let scaled = ChainProblem { horizon: t, ..problem.clone() };
        // A table is built on one horizon's basis: a probe's are its own. On the plan's own
        // spans: near the shortest horizon the coarse basis' velocity rows (conservative by
        // `O(h^2)`, `limits`) rule out what the plan's finer basis fits, and every probe there
        // failed where the full search (which solves the line on the finest basis too) did not,
        // moving the top down by under 1 % a round (119 probes, 9.7 s on issue 20's bench).
        // Its end grading likewise (`super::limits::ends`: a plan at its velocity limit from rest
        // fits a shorter horizon on finer end spans).
        let basis = (plan.stats.spans.max(self.options.coarse_spans), plan.stats.grading.max(self.options.grading));
        let tables = Tables::default();
        // From the plan's holonomy multiplier, time-scaled as its effort (by `k`): the first
        // steps keep to the holonomy instead of trading it for effort at a unit penalty (from
        // none, the 3-link velocity bench's probes first stepped 1.9 rad off it).
        let guess = Some(plan.stats.multiplier * k).filter(|g| g.is_finite() && *g != 0.0);
        // Where the arm keeps a clearance, a refinement that stalls on the constraints is a plan
        // that fits too (`Ending::Feasible`): on issue 21's SPART-like example at 0.02 m every
        // probe's refinement stalled (KKT) 5e-11 rad off the holonomy, and the search went on
        // by full searches at the failing horizons, one per 0.6 % (8.40 s in 11.5 min of CPU).
        let ending = if super::limits::keeps_clearance(self) { Ending::Feasible } else { Ending::Converged };
        Ok(self
            .solve_from(&scaled, targets, &path, (basis, guess, &PROBE_SQP, ending), &tables, Instant::now())?
            .and_then(|p| if fits(&p) { Ok(p) } else { Err(f64::NAN) }))
    }

    /// Whether a deciding search skips the line of the goal representative `targets`: the
    /// shortest horizon's probe at the search's horizon, from the plan at the top of the
    /// bracket, failed on that representative, and the full search at the top solved that line
    /// alone into the probe's family of paths (one seed, the probes' cost). The line solved
    /// again from scratch at the failing horizon crawls off the holonomy to where the probe
    /// stopped: on issue 20's 3-link `--time auto` bench the deciding search at 9.874 s solved
    /// only that line (154 QPs, 45 % of the instructions) to stall 5.08e-3 rad off the holonomy,
    /// the probe there 4.92e-3. The representative's other seeds and every other representative
    /// are still solved.
    pub(super) fn line_decided(&self, targets: &Targets) -> bool {
        self.decided_line.as_ref().is_some_and(|d| {
            let near = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= SAME_TARGET);
            near(&d.end, &targets.end) && (d.phi_end - targets.phi_end).abs() <= SAME_TARGET
        })
    }
}
