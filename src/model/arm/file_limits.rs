//! The limits in a TOML robot file with `[[link]]` (issue 20; docs/spec.md §1): SI units and
//! radians, as the file's other numbers and as a URDF's `<limit>`.
//!
//! ```toml
//! [robot]
//! M = 12.9
//! I = 0.208
//! limit = { lower = -0.5, upper = 1.0 }   # optional: the base angle phi's range [rad]
//! [[link]]
//! length = 0.45
//! com = 0.225
//! mass = 3.0
//! inertia = 0.050625
//! # optional, every key optional: range [rad], |theta'| [rad/s], |tau| [N m], |theta''| [rad/s^2]
//! limit = { lower = -2.0, upper = 2.0, velocity = 0.3, effort = 50.0, acceleration = 1.0 }
//! ```
//!
//! `lower` and `upper` go together (one without the other is refused); unknown keys are refused.

use serde::Deserialize;

use super::InputError;
use super::limits::{JointLimits, Limits};

/// A `[[link]]`'s `limit` table.
#[derive(Debug, Default, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinkLimitTable {
    lower: Option<f64>,
    upper: Option<f64>,
    velocity: Option<f64>,
    effort: Option<f64>,
    acceleration: Option<f64>,
}

/// The `[robot]` table's `limit`: the base angle's range.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BaseLimitTable {
    lower: f64,
    upper: f64,
}

/// `lower` and `upper` as a range, both or neither; `key` names the table in the error.
fn range(lower: Option<f64>, upper: Option<f64>, key: &str) -> Result<Option<[f64; 2]>, InputError> {
    match (lower, upper) {
        (Some(l), Some(u)) => Ok(Some([l, u])),
        (None, None) => Ok(None),
        (None, Some(u)) => Err(InputError::InvalidParameter {
            name: format!("{key}.lower"),
            value: u,
            expected: "lower and upper together (the range of the joint) [rad]",
        }),
        (Some(l), None) => Err(InputError::InvalidParameter {
            name: format!("{key}.upper"),
            value: l,
            expected: "lower and upper together (the range of the joint) [rad]",
        }),
    }
}

/// The limits of a file's tables (validated by [`super::Arm::with_limits`] afterwards).
pub(super) fn from_tables(
    base: Option<BaseLimitTable>,
    links: &[Option<LinkLimitTable>],
) -> Result<Limits, InputError> {
    let mut joints = Vec::with_capacity(links.len());
    for (k, table) in links.iter().enumerate() {
        let t = table.unwrap_or_default();
        joints.push(JointLimits {
            position: range(t.lower, t.upper, &format!("link[{}].limit", k + 1))?,
            velocity: t.velocity,
            torque: t.effort,
            acceleration: t.acceleration,
        });
    }
    let limits = Limits { joints, base: base.map(|b| [b.lower, b.upper]) };
    Ok(if limits.joints.iter().all(JointLimits::is_empty) { Limits { joints: vec![], ..limits } } else { limits })
}

/// The base's `limit = { .. }` line for `[robot]`, empty without a base range.
pub(super) fn base_line(limits: &Limits) -> String {
    limits.base.map(|[l, u]| format!("limit = {{ lower = {l:?}, upper = {u:?} }}\n")).unwrap_or_default()
}

/// Joint `k`'s (0-based) `limit = { .. }` line for its `[[link]]`, empty when it has none.
pub(super) fn link_line(limits: &Limits, k: usize) -> String {
    let j = limits.joint(k);
    let mut parts = Vec::new();
    if let Some([l, u]) = j.position {
        parts.push(format!("lower = {l:?}"));
        parts.push(format!("upper = {u:?}"));
    }
    for (key, value) in [("velocity", j.velocity), ("effort", j.torque), ("acceleration", j.acceleration)] {
        if let Some(v) = value {
            parts.push(format!("{key} = {v:?}"));
        }
    }
    if parts.is_empty() { String::new() } else { format!("limit = {{ {} }}\n", parts.join(", ")) }
}
