//! The robot's declared limits (issue 20; docs/spec.md §1): per joint a position range, a
//! velocity, torque and acceleration limit, and optionally a range of the base angle `phi`.
//! A joint without a position range is continuous: its angles count modulo 2 pi, as before.
//! An arm without limits ([`Limits::is_empty`]) behaves exactly as before issue 20.

use serde::{Deserialize, Serialize};

use super::InputError;

/// The room a tightened limit ([`Limits::with_headroom`]) leaves beyond a state it admits,
/// relative to the limit (to the range's width): far above the planner's own `1e-9`.
pub const HEADROOM_ADMIT: f64 = 1e-6;

/// The limits of one joint; `None` is "unlimited" for that quantity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointLimits {
    /// `[lower, upper]` of the joint angle \[rad\], `lower < upper`. `None`: a continuous joint
    /// (angles modulo 2 pi).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 2]>,
    /// Largest `|theta_i'|` \[rad/s\], `> 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
    /// Largest `|tau_i|` \[N m\], `> 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque: Option<f64>,
    /// Largest `|theta_i''|` \[rad/s^2\], `> 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub acceleration: Option<f64>,
}

impl JointLimits {
    /// True when no quantity of the joint is limited.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// The limits of a robot: one [`JointLimits`] per joint (or none at all), and the base's range.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// One entry per joint, joint 1 first; empty when no joint is limited.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointLimits>,
    /// `[lower, upper]` of the base angle `phi` \[rad\] (antennas, sun pointing), `lower < upper`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<[f64; 2]>,
}

impl Limits {
    /// True when nothing is limited (an arm without limits behaves as before issue 20).
    pub fn is_empty(&self) -> bool {
        self.base.is_none() && self.joints.iter().all(JointLimits::is_empty)
    }

    /// Whether a joint has a velocity, acceleration or torque limit (one that a longer horizon
    /// relieves: time-scaling divides the rates by the factor, the torques by its square).
    pub fn rate_limited(&self) -> bool {
        self.joints.iter().any(|j| j.velocity.is_some() || j.acceleration.is_some() || j.torque.is_some())
    }

    /// The limits of joint `i` (0-based); unlimited where none are declared.
    pub fn joint(&self, i: usize) -> JointLimits {
        self.joints.get(i).copied().unwrap_or_default()
    }

    /// The limits a closed loop plans inside, leaving `fraction` (in `[0, 1)`) of each limit as
    /// headroom for its feedback (docs/spec.md §3, `track --limit-margin`): every velocity,
    /// acceleration and torque limit `(1 - fraction)` of this one, every position range (the
    /// joints' and the base's) `(1 - fraction)` of its width about its centre (`fraction / 2` of
    /// the width off each end). A tightened limit that would exclude a state the plan must start
    /// or end at is widened just enough to hold it, never beyond this limit: each range holds
    /// the angles of every `q = (phi, theta_1, .., theta_n)` of `ends` (the start, the goal, a
    /// re-plan's measured state) and each velocity limit the joint speed `|rate_j|` (a re-plan's
    /// measured velocity; empty at rest), with [`HEADROOM_ADMIT`] of room, so that a re-plan from
    /// a measured state already beyond the tightened limit stays feasible. A state beyond this
    /// limit itself is not admitted (its plan is infeasible). `fraction = 0` gives these limits.
    pub fn with_headroom(&self, fraction: f64, ends: &[&[f64]], rate: &[f64]) -> Limits {
        if fraction == 0.0 || self.is_empty() {
            return self.clone();
        }
        let keep = 1.0 - fraction;
        // A range `[lo, hi]` shrunk about its centre, widened to the values of `axis` in `ends`.
        let range = |[lo, hi]: [f64; 2], axis: usize| {
            let (pad, room) = (0.5 * fraction * (hi - lo), HEADROOM_ADMIT * (hi - lo));
            let (mut a, mut b) = (lo + pad, hi - pad);
            for q in ends.iter().filter_map(|q| q.get(axis)) {
                (a, b) = (a.min(q - room).max(lo), b.max(q + room).min(hi));
            }
            [a, b]
        };
        let joints = self
            .joints
            .iter()
            .enumerate()
            .map(|(j, l)| JointLimits {
                position: l.position.map(|r| range(r, j + 1)),
                velocity: l.velocity.map(|v| {
                    let speed = rate.get(j).map_or(0.0, |u| u.abs() * (1.0 + HEADROOM_ADMIT));
                    (keep * v).max(speed).min(v)
                }),
                torque: l.torque.map(|t| keep * t),
                acceleration: l.acceleration.map(|a| keep * a),
            })
            .collect();
        Limits { joints, base: self.base.map(|r| range(r, 0)) }
    }

    /// Checks the limits for an arm of `n` joints: no entries or exactly `n`; every range
    /// finite with `lower < upper`; every velocity, torque and acceleration limit finite and
    /// `> 0`. Errors name the key as the robot file spells it (`link[k].limit.lower`, with `k`
    /// counted from 1, and `robot.limit.lower`).
    pub fn validate(&self, n: usize) -> Result<(), InputError> {
        let bad = |name: String, value: f64, expected: &'static str| {
            Err(InputError::InvalidParameter { name, value, expected })
        };
        if !self.joints.is_empty() && self.joints.len() != n {
            return bad("limit".into(), self.joints.len() as f64, "limits for every joint of the arm or for none");
        }
        let range = |key: &str, r: [f64; 2]| -> Result<(), InputError> {
            if !r[0].is_finite() {
                return bad(format!("{key}.lower"), r[0], "a finite lower bound [rad]");
            }
            if !(r[1].is_finite() && r[1] > r[0]) {
                return bad(format!("{key}.upper"), r[1], "a finite upper bound above the lower bound [rad]");
            }
            Ok(())
        };
        if let Some(r) = self.base {
            range("robot.limit", r)?;
        }
        for (i, j) in self.joints.iter().enumerate() {
            let key = format!("link[{}].limit", i + 1);
            if let Some(r) = j.position {
                range(&key, r)?;
            }
            for (name, value) in [("velocity", j.velocity), ("effort", j.torque), ("acceleration", j.acceleration)] {
                if let Some(v) = value
                    && !(v.is_finite() && v > 0.0)
                {
                    return bad(format!("{key}.{name}"), v, "a finite limit > 0");
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_limits_are_valid_for_any_arm_and_bad_ones_are_named() {
        assert!(Limits::default().is_empty());
        assert!(Limits::default().validate(3).is_ok());
        let joint =
            JointLimits { position: Some([-2.0, 2.0]), velocity: Some(0.3), torque: Some(50.0), acceleration: None };
        let limits = Limits { joints: vec![joint; 2], base: None };
        assert!(!limits.is_empty());
        assert!(limits.validate(2).is_ok());
        assert!(limits.validate(3).is_err(), "two entries for three joints");
        assert_eq!(limits.joint(5), JointLimits::default());
        let mut flipped = limits.clone();
        flipped.joints[1].position = Some([1.0, -1.0]);
        let Err(InputError::InvalidParameter { name, .. }) = flipped.validate(2) else { panic!("refused") };
        assert_eq!(name, "link[2].limit.upper");
        let mut zero = limits;
        zero.joints[0].velocity = Some(0.0);
        let Err(InputError::InvalidParameter { name, .. }) = zero.validate(2) else { panic!("refused") };
        assert_eq!(name, "link[1].limit.velocity");
    }
}
