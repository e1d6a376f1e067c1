//! The goal representatives inside the joints' and the base's position ranges, the least time
//! a velocity or acceleration limit allows, and the start's and goal's check against the ranges
//! (issue 20 items 2 and 4).

use std::f64::consts::TAU;

use super::super::ChainProblem;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::{Arm, Limits};

/// Keeps the goal representatives inside the ranges: each limited joint's goal is moved by whole
/// turns to the representative inside its range nearest the given one (dropped when none is
/// inside), duplicates removed; the base-angle targets likewise with a base range
/// ([`base_inside`]). Without limits both are unchanged.
pub(crate) fn inside_ranges(limits: &Limits, goals: &mut Vec<Vec<f64>>, phi_targets: &mut Vec<f64>) {
    base_inside(limits, phi_targets);
    if limits.joints.iter().all(|j| j.position.is_none()) {
        return;
    }
    let mut kept: Vec<Vec<f64>> = Vec::new();
    for mut g in goals.drain(..) {
        let ok = g.iter_mut().enumerate().all(|(j, v)| match limits.joint(j).position {
            Some(range) => shift_inside(v, range),
            None => true,
        });
        if ok && !kept.iter().any(|k| k.iter().zip(&g).all(|(a, b)| (a - b).abs() <= 1e-12)) {
            kept.push(g);
        }
    }
    *goals = kept;
}

/// The least time in which one joint can move by `distance` \[rad\] with `|theta'| <= v` and
/// `|theta''| <= a` (either may be absent): `distance / v` from any start velocity; from rest to
/// rest, the bang-bang time `2 sqrt(distance / a)`, or with both `distance / v + v / a` once the
/// joint reaches `v` (`distance >= v^2 / a`). 0 without either limit.
pub(crate) fn least_time(distance: f64, velocity: Option<f64>, acceleration: Option<f64>, at_rest: bool) -> f64 {
    let d = distance.abs();
    match (velocity, acceleration.filter(|_| at_rest)) {
        (Some(v), Some(a)) if d >= v * v / a => d / v + v / a,
        (_, Some(a)) => 2.0 * (d / a).sqrt(),
        (Some(v), None) => d / v,
        (None, None) => 0.0,
    }
}

/// Drops the goal representatives that a joint cannot reach in `horizon` within its velocity
/// and acceleration limits ([`least_time`]; a necessary condition, so no feasible plan is lost).
pub(crate) fn within_reach(limits: &Limits, start: &[f64], at_rest: bool, horizon: f64, goals: &mut Vec<Vec<f64>>) {
    goals.retain(|g| {
        g.iter().zip(start).enumerate().all(|(j, (g, s))| {
            let l = limits.joint(j);
            least_time(g - s, l.velocity, l.acceleration, at_rest) <= horizon * (1.0 + 1e-9)
        })
    });
}

/// Keeps the base-angle targets inside the base range (moved by whole turns, as
/// [`inside_ranges`]); unchanged without a base range.
fn base_inside(limits: &Limits, targets: &mut Vec<f64>) {
    let Some(range) = limits.base else { return };
    let mut kept: Vec<f64> = Vec::new();
    for mut v in targets.drain(..) {
        if shift_inside(&mut v, range) && !kept.iter().any(|k| (k - v).abs() <= 1e-12) {
            kept.push(v);
        }
    }
    *targets = kept;
}

/// Moves `v` by whole turns into `[lo, hi]` (nearest its value); false when no turn fits.
fn shift_inside(v: &mut f64, [lo, hi]: [f64; 2]) -> bool {
    if (lo..=hi).contains(v) {
        return true;
    }
    let k = if *v > hi { ((*v - hi) / TAU).ceil() } else { -((lo - *v) / TAU).ceil() };
    let moved = *v - k * TAU;
    if (lo..=hi).contains(&moved) {
        *v = moved;
        true
    } else {
        false
    }
}

impl ChainProblem {
    /// Checks the start and goal against `arm`'s ranges: a limited joint's angle (and `phi`
    /// with a base range) outside its range is an [`InputError`] naming the joint, the value and
    /// the range (a limited joint is never wrapped).
    pub(crate) fn validate_ranges(&self, arm: &Arm) -> Result<(), Error> {
        // Degrees as the command line takes them, to a millionth; radians to six digits.
        let deg = |x: f64| (x.to_degrees() * 1e6).round() / 1e6;
        let check = |name: &str, value: f64, range: Option<[f64; 2]>, key: String| match range {
            Some([lo, hi]) if !(lo..=hi).contains(&value) => Err(Error::from(InputError::InvalidParameter {
                name: format!(
                    "{name} = {} deg, outside {key} = [{}, {}] deg ([{lo:.6}, {hi:.6}] rad)",
                    deg(value),
                    deg(lo),
                    deg(hi)
                ),
                value,
                expected: "an angle inside the declared range (a limited angle is literal, never wrapped)",
            })),
            _ => Ok(()),
        };
        for (name, q) in [("start", &self.start), ("goal", &self.goal)] {
            check(&format!("{name} phi"), q[0], arm.limits.base, "base.limit".into())?;
            for (j, v) in q.iter().enumerate().skip(1) {
                let range = arm.limits.joint(j - 1).position;
                check(&format!("{name} theta{j}"), *v, range, format!("link[{j}].limit"))?;
            }
        }
        Ok(())
    }
}
