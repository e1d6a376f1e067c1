//! The sweep's effort metric ([`super::SweepOptions::effort`]): at a mounting point, the
//! effort `integral |theta'|^2 dt` of the certified minimum-effort plan of the reference problem,
//! for the arm mounted there with its declared limits and shapes.

use super::SweepOptions;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::plan::Method;
use crate::planners::arm::{ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;

/// The reference problem: rest to rest from `start` to `goal` in `horizon`.
pub(super) fn problem(options: &SweepOptions) -> ChainProblem {
    ChainProblem::rest_to_rest(options.start.clone(), options.goal.clone(), options.horizon)
}

/// The row's `planned` and `effort` for `arm` (mounted at the point): `(true, effort)` with a
/// certified plan; `(false, none)` where there is none, including where an end brings two bodies
/// under the clearance at this mount (no motion can be certified) or the horizon is too short
/// for a limit here; an error only for bad input.
pub(super) fn metric(arm: &Arm, options: &SweepOptions) -> Result<(Option<bool>, Option<f64>), Error> {
    let g = &arm.geometry;
    let ends_clear = [&options.start, &options.goal]
        .iter()
        .all(|q| g.min_clearance(arm, q).is_none_or(|d| d.distance >= g.clearance));
    if !ends_clear {
        return Ok((Some(false), None));
    }
    let request = ArmRequest { samples: 2, tolerance: options.tolerance, ..ArmRequest::new(problem(options)) };
    match plan_arm(arm, Method::Optimal, &request) {
        Ok(planned) if planned.certified().is_ok() => Ok((Some(true), Some(planned.effort()))),
        Ok(_) | Err(Error::HolonomyFixed { .. }) => Ok((Some(false), None)),
        Err(e) if !e.is_bad_input() => Ok((Some(false), None)),
        Err(e) => Err(e),
    }
}
