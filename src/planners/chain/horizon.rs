//! The shortest horizon inside the robot's limits (issue 20 item 4; docs/spec.md §2): the least
//! `T`, to 1 %, at which the constrained planner finds a certified plan, and that plan.
//!
//! Feasibility is monotone in `T`: a plan of horizon `T` played `k > 1` times slower is a plan of
//! horizon `k T` with the same path (positions and base angle unchanged), velocities divided by
//! `k`, and accelerations and torques (Eq. 6 at zero momentum: `M theta'' + C theta'`) by `k^2`.
//! So the search brackets the shortest horizon and bisects it (geometrically). Two bounds
//! shorten it: below, a rest-to-rest joint path cannot average more than its velocity limit,
//! `T >= |theta_d - theta_0| / v_max`; above, a feasible plan at `T` with the largest uses
//! `u_v` of a velocity, `u_a` of an acceleration and `u_tau` of a torque limit time-scales to a
//! feasible motion at `T max(u_v, sqrt(u_a), sqrt(u_tau))`, which is probed next when it lies
//! in the upper half of the bracket. Its cost is that of the plans it probes (reported in
//! [`ShortestHorizon::probes`]): about 1 + log2(log(hi / lo) / log 1.01) plans, fewer when the
//! time-scaling bound is tight.

use std::time::Instant;

use super::{ChainPlan, ChainPlanner, ChainProblem};
use crate::dynamics::arm::inverse_dynamics;
use crate::error::Error;
use crate::model::wrap_angle;
use crate::plan::HORIZON_RANGE;

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
    for w in b.windows(2) {
        for k in 0..32 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 32.0;
            let p = plan.at(t);
            let tau = inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
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
            if let Some(v) = l.velocity
                && problem.initial_velocity.iter().all(|u| u.abs() < 1e-300)
            {
                lo = lo.max(delta.abs() / v);
            }
        }
        let mut probes = 0;
        let mut attempt = |t: f64| {
            probes += 1;
            self.plan(&ChainProblem { horizon: t, ..problem.clone() })
        };
        // The bracket: up from the first horizon until a plan is found.
        let mut t = problem.horizon.max(lo * (1.0 + HORIZON_ACCURACY));
        let mut found: Option<(f64, ChainPlan)> = None;
        let mut last_error = None;
        while found.is_none() && t <= HORIZON_RANGE.1 {
            match attempt(t) {
                Ok(plan) => found = Some((t, plan)),
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
        while hi > lo * (1.0 + HORIZON_ACCURACY) {
            let (_, scale) = uses(self, &plan);
            let mid = (lo * hi).sqrt();
            let scaled = hi * scale * 1.002;
            let probe = if scale > 0.0 && scaled > mid && scaled < hi * 0.998 { scaled } else { mid };
            match attempt(probe) {
                Ok(p) => (hi, plan) = (probe, p),
                Err(e) if e.is_bad_input() => return Err(e),
                Err(_) => lo = probe,
            }
        }
        let (binding, _) = uses(self, &plan);
        let binding = binding.unwrap_or(Binding { joint: 0, quantity: "none", limit: f64::NAN, used: 0.0 });
        Ok(ShortestHorizon {
            horizon: hi,
            infeasible_below: lo,
            plan,
            probes,
            seconds: clock.elapsed().as_secs_f64(),
            binding,
        })
    }

    /// [`ChainPlanner::plan`], and when the arm has a rate limit (velocity, acceleration or
    /// torque: [`crate::model::arm::Limits::rate_limited`]) and no plan is found, the shortest
    /// feasible horizon: an [`Error::HorizonTooShort`] naming the limit that binds there when it
    /// is longer than the problem's horizon (else the planner's own error).
    pub fn plan_within_limits(&self, problem: &ChainProblem) -> Result<ChainPlan, Error> {
        let error = match self.plan(problem) {
            Ok(plan) => return Ok(plan),
            Err(e) if e.is_bad_input() || !self.arm().limits.rate_limited() => return Err(e),
            Err(e) => e,
        };
        let shortest = match self.shortest_horizon(&ChainProblem { horizon: problem.horizon * 1.5, ..problem.clone() })
        {
            Ok(s) if s.horizon > problem.horizon => s,
            _ => return Err(error),
        };
        Err(Error::HorizonTooShort {
            horizon: problem.horizon,
            shortest: shortest.horizon,
            joint: shortest.binding.joint,
            quantity: shortest.binding.quantity,
            limit: shortest.binding.limit,
        })
    }
}
