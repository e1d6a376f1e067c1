//! The `limits=` keyword of `plan` for an arm (issue 20): a dict of the robot's limits in SI
//! units and radians, over the arm's own (from its robot file).
//!
//! ```python
//! limits = {"theta2": {"position": [-2.0, 2.0], "velocity": 0.3, "torque": 50.0, "acceleration": 1.0},
//!           "phi": {"position": [-0.5, 1.0]}}
//! ```
//!
//! A quantity set to `None` drops that limit, a joint set to `None` every limit of the joint.

use freefloat::model::arm::{JointLimits, Limits};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::BindingError;

const EXPECTED: &str = "a dict of joints \"theta1\"..\"thetaN\" or \"phi\", each a dict of \"position\": [lower, upper] \
                        [rad], \"velocity\" [rad/s], \"torque\" [N m], \"acceleration\" [rad/s^2] (or None)";

fn bad(name: String, message: String) -> BindingError {
    BindingError::Key { kind: "invalid_parameter", name, message, expected: EXPECTED }
}

/// `own` with `limits` applied, for an arm of `n` joints (checked afterwards by `Arm::with_limits`).
pub fn apply(own: &Limits, n: usize, limits: &Bound<'_, PyDict>) -> Result<Limits, BindingError> {
    let mut out = own.clone();
    if out.joints.is_empty() {
        out.joints = vec![JointLimits::default(); n];
    }
    for (key, value) in limits.iter() {
        let key: String = key.extract().map_err(|_| bad("limits".into(), "a key that is not a string".into()))?;
        let base = key == "phi";
        let joint = match key.strip_prefix("theta").and_then(|k| k.parse::<usize>().ok()) {
            Some(k) if (1..=n).contains(&k) => Some(k - 1),
            _ if base => None,
            _ => {
                return Err(bad(
                    format!("limits[{key:?}]"),
                    format!("unknown joint {key:?} for an arm of {n} joint(s)"),
                ));
            }
        };
        if value.is_none() {
            match joint {
                Some(k) => out.joints[k] = JointLimits::default(),
                None => out.base = None,
            }
            continue;
        }
        let table =
            value.cast::<PyDict>().map_err(|_| bad(format!("limits[{key:?}]"), "not a dict of quantities".into()))?;
        for (quantity, v) in table.iter() {
            let quantity: String = quantity.extract().unwrap_or_default();
            let name = format!("limits[{key:?}][{quantity:?}]");
            let number = || -> Result<Option<f64>, BindingError> {
                if v.is_none() {
                    return Ok(None);
                }
                v.extract::<f64>().map(Some).map_err(|_| bad(name.clone(), "not a number".into()))
            };
            let range = || -> Result<Option<[f64; 2]>, BindingError> {
                if v.is_none() {
                    return Ok(None);
                }
                v.extract::<[f64; 2]>().map(Some).map_err(|_| bad(name.clone(), "not a pair [lower, upper]".into()))
            };
            match (joint, quantity.as_str()) {
                (None, "position") => out.base = range()?,
                (Some(k), "position") => out.joints[k].position = range()?,
                (Some(k), "velocity") => out.joints[k].velocity = number()?,
                (Some(k), "torque") => out.joints[k].torque = number()?,
                (Some(k), "acceleration") => out.joints[k].acceleration = number()?,
                _ => return Err(bad(name, format!("unknown quantity {quantity:?} of {key:?}"))),
            }
        }
    }
    if out.joints.iter().all(JointLimits::is_empty) {
        out.joints.clear();
    }
    Ok(out)
}
