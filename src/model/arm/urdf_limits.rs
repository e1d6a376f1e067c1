//! The joint limits of a URDF (issue 20; docs/spec.md §1, URDF): each moving joint's `<limit>`.
//!
//! - `revolute`: `lower`, `upper` \[rad\] (the position range), `velocity` \[rad/s\] and `effort`
//!   \[N m\] (the torque limit). The URDF format requires a `<limit>` on a revolute joint, and
//!   `velocity` and `effort` on every `<limit>`: a missing one is an error naming the joint.
//!   `lower` and `upper` default to 0 in the format; a range that is not `lower < upper` is
//!   refused (a locked joint is no joint of a planned arm).
//! - `continuous`: `velocity` and `effort` only (no range; `lower`/`upper` are ignored, as the
//!   format says), and the `<limit>` is optional.
//!
//! `urdf-rs` fills a missing `<limit>` with zeros, so the limits are read from the text itself by
//! one linear scan with quick-xml (the reader of the nesting check): the `<limit>` elements of the
//! `<joint>` elements that are children of `<robot>` (a `<transmission>`'s `<joint>` is not one).

use std::collections::HashMap;
use std::path::Path;

use quick_xml::events::{BytesStart, Event};

use super::limits::{JointLimits, Limits};
use crate::model::robot_file::short_reason;
use crate::model::{InputError, excerpt};

/// The attributes of one `<limit>`, as written (`None`: absent).
#[derive(Debug, Default, Clone)]
struct LimitTag {
    attributes: HashMap<String, String>,
}

/// The `<limit>` of each `<joint>` child of `<robot>`, by joint name (`None`: the joint has none).
fn limit_tags(text: &str, path: &Path) -> Result<HashMap<String, Option<LimitTag>>, InputError> {
    let bad = |e: String| InputError::RobotFile { path: path.to_path_buf(), reason: short_reason(&e) };
    let attributes = |e: &BytesStart| -> Result<HashMap<String, String>, InputError> {
        let mut out = HashMap::new();
        for a in e.attributes() {
            let a = a.map_err(|e| bad(format!("not a valid URDF: {e}")))?;
            let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
            let value = a.unescape_value().map_err(|e| bad(format!("not a valid URDF: {e}")))?.into_owned();
            out.insert(key, value);
        }
        Ok(out)
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut depth = 0usize;
    let mut joint: Option<String> = None;
    let mut tags = HashMap::new();
    loop {
        let event = reader.read_event().map_err(|e| bad(format!("not a valid URDF: {e}")))?;
        let (element, empty) = match &event {
            Event::Start(e) => (Some(e), false),
            Event::Empty(e) => (Some(e), true),
            Event::End(_) => {
                if depth == 2 {
                    joint = None;
                }
                depth = depth.saturating_sub(1);
                continue;
            }
            Event::Eof => return Ok(tags),
            _ => continue,
        };
        let Some(e) = element else { continue };
        let level = depth + 1;
        let name = e.local_name();
        if level == 2 && name.as_ref() == b"joint" {
            let attrs = attributes(e)?;
            let joint_name = attrs.get("name").cloned().unwrap_or_default();
            tags.insert(joint_name.clone(), None);
            joint = (!empty).then_some(joint_name);
        } else if level == 3
            && name.as_ref() == b"limit"
            && let Some(j) = &joint
        {
            tags.insert(j.clone(), Some(LimitTag { attributes: attributes(e)? }));
        }
        if !empty {
            depth += 1;
        }
    }
}

/// The limits of the arm's moving joints `joints` (name and `true` for revolute, `false` for
/// continuous, from the base outwards), read from the URDF `text` by the module's rules. An arm
/// whose joints declare nothing has no limits ([`Limits::is_empty`]).
pub(super) fn read_limits(text: &str, path: &Path, joints: &[(String, bool)]) -> Result<Limits, InputError> {
    let tags = limit_tags(text, path)?;
    let mut out = Vec::with_capacity(joints.len());
    for (name, revolute) in joints {
        let tag = tags.get(name).cloned().flatten();
        let owner = format!("URDF joint \"{}\"", excerpt(name));
        let Some(tag) = tag else {
            if *revolute {
                return Err(InputError::Urdf {
                    path: path.to_path_buf(),
                    element: format!("joint `{}`", excerpt(name)),
                    reason: "is revolute without a <limit>: the URDF format requires <limit lower upper velocity \
                             effort> on a revolute joint (use type=\"continuous\" for a joint without a range)"
                        .into(),
                });
            }
            out.push(JointLimits::default());
            continue;
        };
        let number = |key: &str, default: Option<f64>, expected: &'static str| -> Result<f64, InputError> {
            let invalid =
                |value: f64| InputError::InvalidParameter { name: format!("limit.{key} ({owner})"), value, expected };
            let x = match tag.attributes.get(key) {
                Some(text) => text.trim().parse::<f64>().map_err(|_| InputError::InvalidText {
                    name: format!("limit.{key} ({owner})"),
                    text: text.clone(),
                    expected,
                })?,
                None => default.ok_or_else(|| invalid(f64::NAN))?,
            };
            if x.is_finite() { Ok(x) } else { Err(invalid(x)) }
        };
        let positive = |key: &str, expected: &'static str| -> Result<f64, InputError> {
            let x = number(key, None, expected)?;
            if x > 0.0 {
                Ok(x)
            } else {
                Err(InputError::InvalidParameter { name: format!("limit.{key} ({owner})"), value: x, expected })
            }
        };
        let velocity = positive("velocity", "a finite velocity limit > 0 [rad/s] (required by the URDF format)")?;
        let torque = positive("effort", "a finite effort limit > 0 [N m] (required by the URDF format)")?;
        let position = if *revolute {
            let lower = number("lower", Some(0.0), "a finite lower bound [rad]")?;
            let upper = number("upper", Some(0.0), "a finite upper bound [rad]")?;
            if !(upper > lower) {
                return Err(InputError::InvalidParameter {
                    name: format!("limit.upper ({owner})"),
                    value: upper,
                    expected: "an upper bound above the lower bound [rad] (lower and upper default to 0)",
                });
            }
            Some([lower, upper])
        } else {
            None
        };
        out.push(JointLimits { position, velocity: Some(velocity), torque: Some(torque), acceleration: None });
    }
    let limits = Limits { joints: out, base: None };
    Ok(if limits.is_empty() { Limits::default() } else { limits })
}
