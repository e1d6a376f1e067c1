//! A given horizon too short for the robot's rate limits (issue 20 item 4; docs/spec.md §2), and
//! where the arm keeps a clearance (issue 21) the cheap proof of it: the plan without the rate
//! limits, time-scaled until it fits them, certified as it is.
//!
//! The system is driftless at zero momentum (Eq. 7: `phi' = -(G(theta) . theta') / F(theta)`),
//! so a plan of horizon `T` played `k` times slower, `theta_k(t) = theta(t / k)` on `[0, k T]`,
//! has the same path in `(phi, theta)`: the same base angle at the same point of the path, the
//! same distances between the bodies, velocities divided by `k`, accelerations and torques (Eq. 6
//! at zero momentum, `M(theta) theta'' + C(theta, theta') theta'`) by `k^2`, and its effort by
//! `k`. The plan without the rate limits (ranges and clearance kept) at `T`, using `r_v`, `r_a`,
//! `r_tau` of the velocity, acceleration and torque limits at most ([`super::horizon::uses`]),
//! thus fits every limit at `T max(1, r_v, sqrt(r_a), sqrt(r_tau))`; at the same cost it is the
//! minimum of the relaxed problem there too (the effort of every path scales by the same `1 / k`),
//! so where it fits the limits it is the constrained minimum.

use super::horizon::uses;
use super::{ChainPlan, ChainPlanner, ChainProblem, ChainStats};
use crate::error::Error;
use crate::plan::HORIZON_RANGE;
use crate::plan::certificate::verify_chain;
use crate::planners::optimal::spline::SplineBasis;

/// The factors above the time-scaling factor tried in turn: [`uses`] reads the plan's peaks at
/// 32 points per knot span (below the true peak by the rate's curvature there), and the
/// certificate judges the integrated motion; the second is tried only where the first leaves a
/// limit.
const SCALE_MARGINS: [f64; 2] = [1.002, 1.02];

impl ChainPlan {
    /// This plan time-scaled to `horizon` (`k = horizon / T`): the joint splines' coefficients on
    /// the breakpoints times `k`, the base angle at them unchanged; effort, cost (effort or
    /// energy), peak velocity and holonomy multiplier divided by `k`. Its certificate is to be
    /// computed (pending). An error where `horizon` is not positive and finite.
    pub fn time_scaled(&self, horizon: f64) -> Result<ChainPlan, Error> {
        let k = horizon / self.horizon();
        let mut b: Vec<f64> = self.basis.breakpoints().iter().map(|t| t * k).collect();
        if let Some(last) = b.last_mut() {
            *last = horizon;
        }
        let basis = SplineBasis::on_breakpoints(self.basis.degree(), &b)?;
        let s = &self.stats;
        let stats = ChainStats {
            effort: s.effort / k,
            cost: s.cost / k,
            peak_velocity: s.peak_velocity / k,
            multiplier: s.multiplier / k,
            ..*s
        };
        Ok(ChainPlan::with_phi(
            self.connection.clone(),
            basis,
            self.coefficients.clone(),
            self.phi_at_breakpoints.clone(),
            stats,
        ))
    }
}

/// The verified motion inside every limit and clear by the clearance asked for.
fn fits(plan: &ChainPlan) -> bool {
    let v = &plan.verification;
    v.certified && v.limits.as_ref().is_none_or(|l| l.inside) && v.clearance.is_none_or(|r| r.holds())
}

impl ChainPlanner {
    /// [`ChainPlanner::plan`], and when the arm has a rate limit (velocity, acceleration or
    /// torque: [`crate::model::arm::Limits::rate_limited`]) and no plan is found, an
    /// [`Error::HorizonTooShort`] naming a longer horizon that fits and the limit that binds
    /// there (else the planner's own error). Where the arm keeps a clearance and no plan clears
    /// (or none is found), [`Self::time_scaled_fit`] first: where it certifies at the problem's
    /// horizon it is the plan; at a longer one, that horizon, proven to fit (`searched: false`);
    /// else the least bad plan (its certificate reports the collision) or, where there is none,
    /// the search below. Else (no clearance, or no scaled plan fits) [`Self::shortest_horizon`]:
    /// the shortest feasible horizon, to 1 % (`searched: true`).
    pub fn plan_within_limits(&self, problem: &ChainProblem) -> Result<ChainPlan, Error> {
        let rate_limited = self.arm().limits.rate_limited();
        let clearance = super::limits::keeps_clearance(self);
        let clears = |p: &ChainPlan| p.verification.clearance.is_none_or(|r| r.holds());
        let error = match self.plan(problem) {
            Ok(plan) if !(rate_limited && clearance) || clears(&plan) => return Ok(plan),
            Err(e) if e.is_bad_input() || !rate_limited => return Err(e),
            result if clearance => match self.time_scaled_fit(problem)? {
                Some(fit) if fit.horizon() <= problem.horizon => return Ok(fit),
                Some(fit) if let Some(binding) = uses(self, &fit).0 => {
                    return Err(Error::HorizonTooShort {
                        horizon: problem.horizon,
                        shortest: fit.horizon(),
                        searched: false,
                        joint: binding.joint,
                        quantity: binding.quantity,
                        limit: binding.limit,
                    });
                }
                // None, or a longer horizon where no limit binds (a scale above 1 means one
                // does): the least bad plan's report, never a limit without a number.
                _ => match result {
                    Ok(plan) => return Ok(plan),
                    Err(e) => e,
                },
            },
            Ok(plan) => return Ok(plan),
            Err(e) => e,
        };
        let shortest = match self.shortest_horizon(&ChainProblem { horizon: problem.horizon * 1.5, ..problem.clone() })
        {
            Ok(s) if s.horizon > problem.horizon => s,
            // A limit no horizon satisfies: that, rather than the planner's failure here.
            Err(e) if e.is_bad_input() => return Err(e),
            _ => return Err(error),
        };
        Err(Error::HorizonTooShort {
            horizon: problem.horizon,
            shortest: shortest.horizon,
            searched: true,
            joint: shortest.binding.joint,
            quantity: shortest.binding.quantity,
            limit: shortest.binding.limit,
        })
    }

    /// The plan without the rate limits (ranges and clearance kept) at the problem's horizon,
    /// time-scaled to where it fits them ([`uses`]' factor times each of `SCALE_MARGINS` in
    /// turn, at least the problem's horizon) and certified there as it is: the first that is
    /// certified inside every limit and clear (docs/spec.md §2; this module's docs). `None` from a moving
    /// start (a time-scaling changes the initial velocity), where that plan is not found or does
    /// not clear, or where the horizon would pass [`HORIZON_RANGE`]. Its cost: one search
    /// without the rate limits and up to two certificates.
    pub fn time_scaled_fit(&self, problem: &ChainProblem) -> Result<Option<ChainPlan>, Error> {
        if problem.initial_velocity.iter().any(|w| *w != 0.0) {
            return Ok(None);
        }
        let free = match self.without_rate_limits().plan(problem) {
            Ok(free) if fits(&free) => free,
            Err(e) if e.is_bad_input() => return Err(e),
            _ => return Ok(None),
        };
        self.scaled_fit(problem, &free)
    }

    /// `free`, a plan of `problem` without the rate limits that clears, time-scaled and certified
    /// as [`Self::time_scaled_fit`] does (its second half: up to two certificates, no search);
    /// `None` from a moving start or where no margin fits.
    pub(super) fn scaled_fit(&self, problem: &ChainProblem, free: &ChainPlan) -> Result<Option<ChainPlan>, Error> {
        if problem.initial_velocity.iter().any(|w| *w != 0.0) || !fits(free) {
            return Ok(None);
        }
        let (_, scale) = uses(self, free);
        let o = &self.options;
        for margin in SCALE_MARGINS {
            let horizon = problem.horizon * (scale * margin).max(1.0);
            if horizon > HORIZON_RANGE.1 {
                return Ok(None);
            }
            let mut plan = free.time_scaled(horizon)?;
            plan.verification = verify_chain(self.arm(), &plan, &problem.start, &problem.goal, &o.ode, o.tolerance)?;
            if fits(&plan) {
                return Ok(Some(plan));
            }
        }
        Ok(None)
    }
}
