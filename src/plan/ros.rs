//! ROS 2 trajectory messages (docs/spec.md §3, "ROS 2"): `trajectory_msgs/JointTrajectory` and
//! `trajectory_msgs/MultiDOFJointTrajectory` as plain serde data, field for field as the
//! `.msg` files define them, so that the YAML that `ros2 topic echo` prints and `ros2 topic pub`
//! reads (and its JSON twin) is read and written as is.
//!
//! Units are ROS's (REP 103): seconds and nanoseconds (`builtin_interfaces/Duration`), radians,
//! rad/s, rad/s^2, N m (`effort` of a revolute joint), metres; quaternions `(x, y, z, w)`.
//! Fields left out of an input take ROS's defaults (empty arrays, zero times), as with
//! `ros2 topic pub`; unknown fields are errors (a typo must not pass silently).

use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::model::InputError;

/// `builtin_interfaces/Time`: a time stamp.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, `0 <= nanosec < 1e9`.
    pub nanosec: u32,
}

/// `builtin_interfaces/Duration`: `sec + nanosec 1e-9` seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, `0 <= nanosec < 1e9` (a message with more is refused on input).
    pub nanosec: u32,
}

/// The largest duration a [`Duration`] holds \[s\] (`i32::MAX` seconds).
pub const MAX_DURATION: f64 = i32::MAX as f64;

impl Duration {
    /// The duration of `t` seconds (finite, `0 <= t <= MAX_DURATION`) rounded to the nearest
    /// nanosecond, with `nanosec < 1e9` (a rounding up to a whole second carries).
    pub fn from_seconds(t: f64) -> Result<Self, InputError> {
        if !(t.is_finite() && (0.0..=MAX_DURATION).contains(&t)) {
            return Err(InputError::InvalidParameter {
                name: "time_from_start".into(),
                value: t,
                expected: "a time from 0 to 2147483647 s",
            });
        }
        let mut sec = t.floor();
        let mut nanosec = ((t - sec) * 1e9).round();
        if nanosec >= 1e9 {
            sec += 1.0;
            nanosec -= 1e9;
        }
        // In range: 0 <= sec <= i32::MAX (t <= i32::MAX), 0 <= nanosec < 1e9.
        Ok(Self { sec: sec.min(MAX_DURATION) as i32, nanosec: nanosec as u32 })
    }

    /// The duration in seconds.
    pub fn seconds(self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }
}

/// `std_msgs/Header`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Header {
    /// The stamp (zero: "start now" for a joint trajectory controller).
    pub stamp: Time,
    /// The frame (empty for joint space; the base's parent frame for the base's trajectory).
    pub frame_id: String,
}

/// `trajectory_msgs/JointTrajectoryPoint`: one point, each array empty or one value per joint
/// in the order of [`JointTrajectory::joint_names`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JointTrajectoryPoint {
    /// Joint angles \[rad\].
    pub positions: Vec<f64>,
    /// Joint velocities \[rad/s\].
    pub velocities: Vec<f64>,
    /// Joint accelerations \[rad/s^2\].
    pub accelerations: Vec<f64>,
    /// Joint torques [N m].
    pub effort: Vec<f64>,
    /// Time of the point from the trajectory's start.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/JointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JointTrajectory {
    /// The header.
    pub header: Header,
    /// The joints' names, in the order of every point's arrays.
    pub joint_names: Vec<String>,
    /// The points, in time order.
    pub points: Vec<JointTrajectoryPoint>,
}

/// `geometry_msgs/Vector3`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Vector3 {
    /// `x`.
    pub x: f64,
    /// `y`.
    pub y: f64,
    /// `z`.
    pub z: f64,
}

/// `geometry_msgs/Quaternion` `(x, y, z, w)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Quaternion {
    /// `x`.
    pub x: f64,
    /// `y`.
    pub y: f64,
    /// `z`.
    pub z: f64,
    /// `w`.
    pub w: f64,
}

impl Default for Quaternion {
    /// The identity, as ROS defaults it.
    fn default() -> Self {
        Self { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }
    }
}

impl Quaternion {
    /// The rotation by `angle` \[rad\] about `+z`: `(0, 0, sin(angle/2), cos(angle/2))`.
    pub fn about_z(angle: f64) -> Self {
        let (s, c) = (0.5 * angle).sin_cos();
        Self { x: 0.0, y: 0.0, z: s, w: c }
    }

    /// The angle about `+z` of a rotation about `z` \[rad\], in `(-pi, pi]`: `2 atan2(z, w)`
    /// wrapped.
    pub fn yaw(&self) -> f64 {
        crate::model::wrap_angle(2.0 * self.z.atan2(self.w))
    }
}

/// `geometry_msgs/Transform`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Transform {
    /// Translation \[m\].
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/Twist`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Twist {
    /// Linear velocity \[m/s\] (or acceleration \[m/s^2\]).
    pub linear: Vector3,
    /// Angular velocity \[rad/s\] (or acceleration \[rad/s^2\]).
    pub angular: Vector3,
}

/// `trajectory_msgs/MultiDOFJointTrajectoryPoint`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultiDOFJointTrajectoryPoint {
    /// One transform per joint.
    pub transforms: Vec<Transform>,
    /// One twist per joint (or none).
    pub velocities: Vec<Twist>,
    /// One twist per joint (or none).
    pub accelerations: Vec<Twist>,
    /// Time of the point from the trajectory's start.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/MultiDOFJointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultiDOFJointTrajectory {
    /// The header (`frame_id`: the frame the transforms are in).
    pub header: Header,
    /// The joints' names (here one: the base's floating joint).
    pub joint_names: Vec<String>,
    /// The points.
    pub points: Vec<MultiDOFJointTrajectoryPoint>,
}

/// The text encoding of a message file, chosen by the file name's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// YAML, as `ros2 topic echo` prints a message (`.yaml`, `.yml`).
    Yaml,
    /// JSON (`.json`).
    Json,
}

impl Encoding {
    /// The encoding of a file name by its extension (any case): `.yaml`/`.yml` or `.json`;
    /// `None` for another.
    pub fn of_path(path: &std::path::Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "yaml" | "yml" => Some(Self::Yaml),
            "json" => Some(Self::Json),
            _ => None,
        }
    }
}

/// A message as text. Every number must be finite (JSON has no NaN, and a trajectory with one is
/// no trajectory): a non-finite value is an [`InputError::InvalidParameter`] naming the message.
pub fn to_text<T: Serialize>(message: &T, encoding: Encoding) -> Result<String, Error> {
    let value = serde_json::to_value(message).map_err(|e| encode_error(&e.to_string()))?;
    if !all_finite(&value) {
        return Err(Error::from(InputError::InvalidParameter {
            name: "trajectory message".into(),
            value: f64::NAN,
            expected: "finite numbers only",
        }));
    }
    match encoding {
        Encoding::Json => {
            serde_json::to_string_pretty(message).map(|s| s + "\n").map_err(|e| encode_error(&e.to_string()))
        }
        Encoding::Yaml => serde_saphyr::to_string(message).map_err(|e| encode_error(&e.to_string())),
    }
}

/// A message read from text; `name` names the source in messages. YAML may end with `---` (as
/// `ros2 topic echo` prints it) but holds one message. A parse error (bad syntax, a wrong type,
/// an unknown field, several messages) is an [`InputError::Trajectory`] quoting at most a few short
/// lines of the parser's message.
pub fn from_text<T: serde::de::DeserializeOwned>(text: &str, encoding: Encoding, name: &str) -> Result<T, InputError> {
    let parsed = match encoding {
        Encoding::Json => serde_json::from_str(text).map_err(|e| e.to_string()),
        // `ros2 topic echo` ends each message with `---`: empty documents are skipped, and the
        // file must hold one message.
        Encoding::Yaml => {
            serde_saphyr::from_multiple(text).map_err(|e| e.to_string()).and_then(|mut all: Vec<T>| match all.len() {
                1 => Ok(all.remove(0)),
                n => Err(format!("{n} YAML documents: the file must hold one message")),
            })
        }
    };
    parsed.map_err(|reason| InputError::Trajectory {
        path: name.into(),
        element: "message".into(),
        reason: short(&format!("not a {} message: {reason}", kind(encoding))),
    })
}

fn kind(encoding: Encoding) -> &'static str {
    match encoding {
        Encoding::Yaml => "YAML",
        Encoding::Json => "JSON",
    }
}

/// A parser's message cut to a few lines of a few dozen characters.
fn short(reason: &str) -> String {
    let mut lines: Vec<String> = reason.lines().take(6).map(crate::model::excerpt).collect();
    if reason.lines().count() > 6 {
        lines.push("...".into());
    }
    lines.join("\n")
}

fn encode_error(reason: &str) -> Error {
    Error::from(InputError::Io { path: "<message>".into(), source: std::io::Error::other(reason.to_string()) })
}

fn all_finite(value: &serde_json::Value) -> bool {
    match value {
        // serde_json writes a non-finite f64 as null; a message has no null field.
        serde_json::Value::Null => false,
        serde_json::Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
        serde_json::Value::Array(a) => a.iter().all(all_finite),
        serde_json::Value::Object(o) => o.values().all(all_finite),
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Durations round to the nanosecond with `nanosec < 1e9`, and back to within 0.5 ns.
    #[test]
    fn durations_are_seconds_and_nanoseconds() {
        for t in [0.0, 0.01, 0.29, 1.5, 9.999_999_999_7, 10.0, 123_456.789] {
            let d = Duration::from_seconds(t).unwrap();
            assert!(d.nanosec < 1_000_000_000, "{t}: {d:?}");
            assert!((d.seconds() - t).abs() <= 0.5e-9 + 1e-15 * t, "{t}: {d:?}");
        }
        // 9.9999999997 s rounds up to the whole second: carried, not 10^9 ns.
        assert_eq!(Duration::from_seconds(9.999_999_999_7).unwrap(), Duration { sec: 10, nanosec: 0 });
        assert_eq!(Duration::from_seconds(1.5).unwrap(), Duration { sec: 1, nanosec: 500_000_000 });
        for bad in [-1.0, f64::NAN, f64::INFINITY, 3e9] {
            assert!(Duration::from_seconds(bad).is_err(), "{bad}");
        }
    }

    /// The quaternion about z of an angle gives the angle back (wrapped), and has unit norm.
    #[test]
    fn quaternion_about_z() {
        for angle in [-3.0, -0.5, 0.0, 0.7, 3.1] {
            let q = Quaternion::about_z(angle);
            assert!((q.x.hypot(q.y).hypot(q.z).hypot(q.w) - 1.0).abs() < 1e-15);
            assert!((q.yaw() - angle).abs() < 1e-14, "{angle}");
        }
    }
}
