//! The unconstrained search first, where the straight line uses little of every rate limit
//! (issue 20): the minimum found without the limits (the search of the arm without them, its
//! seeds not cut to the limits), certified inside every one of them, is the minimum with them
//! (no row would be active), found at the unconstrained search's speed (on issue 20's SPART-like
//! bench, whose declared limits do not bind, 11 ms against 90 ms on a shared machine, the same
//! plan). Where its plan leaves a limit, the search with the rows follows (the first search's
//! tables kept), so no plan is lost; the test on the line only spares that first search where a
//! limit is likely to bind. Not for a goal taken modulo 2 pi with a range (the unconstrained
//! search would try representatives the ranges rule out).

use std::sync::Arc;
use std::time::Instant;

use super::super::search::Tables;
use super::super::{ChainPlan, ChainPlanner, ChainProblem};
use crate::dynamics::arm::inverse_dynamics;
use crate::error::Error;
use crate::model::wrap_angle;
use crate::plan::certificate::verify_chain;

/// The largest use of a rate limit by the straight line's estimate at which the search without
/// the rows is tried first.
const LOOSE_USE: f64 = 0.5;

impl ChainPlanner {
    /// The plan of the unconstrained search when the straight line uses at most [`LOOSE_USE`]
    /// of every rate limit ([`Self::line_use`]) and that plan's certificate, with this arm's
    /// limits, finds every use at most 1 (inside the declared limits, not only within the
    /// check's slack); `None` otherwise (and for an arm without limits). An input error is
    /// returned as such.
    pub(in super::super) fn plan_inside_without_rows(
        &self,
        problem: &ChainProblem,
        tables: &Tables,
        clock: Instant,
    ) -> Result<Option<ChainPlan>, Error> {
        let limits = &self.arm.limits;
        let ranges = limits.base.is_some() || limits.joints.iter().any(|j| j.position.is_some());
        if limits.is_empty() || (problem.wrap && ranges) || self.line_use(problem) > LOOSE_USE {
            return Ok(None);
        }
        let arm = self.arm.as_ref().clone().with_limits(Default::default())?;
        let free = ChainPlanner { arm: Arc::new(arm), ..self.clone() };
        let mut plan = match free.search(problem, tables, clock) {
            Ok(plan) => plan,
            Err(e) if e.is_bad_input() => return Err(e),
            Err(_) => return Ok(None),
        };
        let o = &self.options;
        plan.verification = verify_chain(&self.arm, &plan, &problem.start, &problem.goal, &o.ode, o.tolerance)?;
        let inside = plan.verification.limits.as_ref().is_some_and(|l| l.uses.iter().all(|u| u.used <= 1.0));
        Ok((plan.verification.certified && inside).then_some(plan))
    }

    /// The largest use of a velocity, acceleration or torque limit by the rest-to-rest cubic
    /// from the start to the goal (to the nearest representative of a joint without a range
    /// when the goal wraps): peak velocity `1.5 |delta| / T + |u0|`, peak acceleration
    /// `6 |delta| / T^2 + 4 |u0| / T`, the torque of that acceleration at rest at the start and
    /// at the goal (0 without rate limits). An estimate, not a bound: the plan may wind.
    fn line_use(&self, problem: &ChainProblem) -> f64 {
        let (arm, t) = (&*self.arm, problem.horizon);
        let n = arm.joints();
        let mut delta = vec![0.0; n];
        for (j, d) in delta.iter_mut().enumerate() {
            let raw = problem.goal[j + 1] - problem.start[j + 1];
            *d = if problem.wrap && arm.limits.joint(j).position.is_none() { wrap_angle(raw) } else { raw };
        }
        let u0 = &problem.initial_velocity;
        let acceleration: Vec<f64> = (0..n).map(|j| 6.0 * delta[j] / (t * t) + 4.0 * u0[j] / t).collect();
        let rest = vec![0.0; n];
        let tau: Vec<nalgebra::DVector<f64>> = [(&problem.start, 1.0), (&problem.goal, -1.0)]
            .iter()
            .map(|(q, sign)| {
                let a: Vec<f64> = acceleration.iter().map(|a| sign * a).collect();
                inverse_dynamics(arm, &q[1..], &rest, &a).tau
            })
            .collect();
        let mut used: f64 = 0.0;
        for j in 0..n {
            let l = arm.limits.joint(j);
            let velocity = 1.5 * delta[j].abs() / t + u0[j].abs();
            let torque = tau[0][j].abs().max(tau[1][j].abs());
            for (value, limit) in [(velocity, l.velocity), (acceleration[j].abs(), l.acceleration), (torque, l.torque)]
            {
                if let Some(limit) = limit {
                    used = used.max(value / limit);
                }
            }
        }
        used
    }
}
