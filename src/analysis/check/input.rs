//! The trajectory file of `freefloat check` (docs/spec.md §3): a ROS 2
//! `trajectory_msgs/JointTrajectory` as YAML or JSON, or freefloat's own plan CSV, read and
//! checked into [`JointSamples`] in the robot's joint order. Every refusal is an
//! [`InputError::Trajectory`] naming the point (counted from 0), the joint or the field.

use std::path::Path;

use super::motion::JointSamples;
use crate::model::InputError;
use crate::model::read_regular_file;
use crate::plan::ros::{Encoding, JointTrajectory, from_text};

/// The most points a trajectory may have (a 10 s motion at 10 kHz): beyond it the file is
/// refused before any work.
pub const MAX_POINTS: usize = 100_000;

/// The largest trajectory file read \[bytes\] (64 MiB: 100 000 points of a 15-joint arm with
/// every array, as YAML).
pub const TRAJECTORY_FILE_LIMIT: u64 = 64 << 20;

/// Largest `|position|` accepted \[rad\] (as `--from`/`--to`, docs/spec.md §2).
pub const MAX_POSITION: f64 = crate::plan::MAX_ANGLE;

/// Largest `|velocity|` \[rad/s\] and `|acceleration|` \[rad/s^2\] accepted: far beyond any
/// robot, small enough that no product overflows.
pub const MAX_RATE: f64 = 1e6;

/// A trajectory read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryInput {
    /// The points in the robot's joint order.
    pub samples: JointSamples,
    /// The base's angle at the first point \[rad\], when the file has it (freefloat's CSV).
    pub base_start: Option<f64>,
}

fn fail(path: &Path, element: impl Into<String>, reason: impl Into<String>) -> InputError {
    InputError::Trajectory { path: path.to_path_buf(), element: element.into(), reason: reason.into() }
}

/// Reads the trajectory file `path` (`.yaml`/`.yml`/`.json`: a JointTrajectory message, `.csv`:
/// freefloat's plan CSV; any case) for a robot whose joints are `joint_names`, in order. A
/// message's joints are matched by name; a CSV's `theta1..thetan` are joints `1..n`.
pub fn read_trajectory(path: &Path, joint_names: &[String]) -> Result<TrajectoryInput, InputError> {
    let is_csv = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let encoding = Encoding::of_path(path);
    if !is_csv && encoding.is_none() {
        return Err(fail(path, "file name", "must end in .yaml, .yml, .json (a JointTrajectory message) or .csv"));
    }
    let bytes = read_regular_file(path, TRAJECTORY_FILE_LIMIT)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        fail(path, "text", format!("not UTF-8 (invalid byte at offset {})", e.utf8_error().valid_up_to()))
    })?;
    match encoding {
        Some(encoding) => {
            let message: JointTrajectory = from_text(&text, encoding, &path.display().to_string())?;
            Ok(TrajectoryInput { samples: samples_from_message(&message, joint_names, path)?, base_start: None })
        }
        None => samples_from_csv(&text, joint_names.len(), path),
    }
}

/// The points of `message` in the order of `joint_names` (the robot's), checked: every robot
/// joint listed once and no other, 2 to [`MAX_POINTS`] points, each array empty or of one value
/// per joint (velocities and accelerations given at every point or at none, accelerations only
/// with velocities), values finite and bounded, `nanosec < 1e9`, times strictly increasing from
/// 0.
pub fn samples_from_message(
    message: &JointTrajectory,
    joint_names: &[String],
    path: &Path,
) -> Result<JointSamples, InputError> {
    let quote = |name: &str| format!("joint `{}`", crate::model::excerpt(name));
    let listed = &message.joint_names;
    let mut column = vec![usize::MAX; joint_names.len()];
    for (i, name) in listed.iter().enumerate() {
        let Some(j) = joint_names.iter().position(|r| r == name) else {
            let known = joint_names.join(", ");
            return Err(fail(path, quote(name), format!("is not a joint of the robot (its joints: {known})")));
        };
        if column[j] != usize::MAX {
            return Err(fail(path, quote(name), "is listed twice in joint_names"));
        }
        column[j] = i;
    }
    if let Some(j) = column.iter().position(|&c| c == usize::MAX) {
        return Err(fail(
            path,
            quote(&joint_names[j]),
            "is missing from joint_names: every joint of the robot must move",
        ));
    }
    let points = &message.points;
    check_count(points.len(), path)?;
    let m = listed.len();
    let has_velocities = !points[0].velocities.is_empty();
    let has_accelerations = !points[0].accelerations.is_empty();
    if has_accelerations && !has_velocities {
        return Err(fail(path, "point 0", "has accelerations without velocities: give both, or positions only"));
    }
    let mut samples = JointSamples {
        t: Vec::with_capacity(points.len()),
        positions: Vec::with_capacity(points.len()),
        velocities: has_velocities.then(|| Vec::with_capacity(points.len())),
        accelerations: has_accelerations.then(|| Vec::with_capacity(points.len())),
    };
    let reorder = |values: &[f64]| column.iter().map(|&c| values[c]).collect::<Vec<f64>>();
    for (k, point) in points.iter().enumerate() {
        let element = format!("point {k}");
        let arrays = [
            ("positions", &point.positions, true, MAX_POSITION),
            ("velocities", &point.velocities, has_velocities, MAX_RATE),
            ("accelerations", &point.accelerations, has_accelerations, MAX_RATE),
            ("effort", &point.effort, !point.effort.is_empty(), f64::MAX),
        ];
        for (field, values, expected, bound) in arrays {
            if values.len() != if expected { m } else { 0 } {
                let reason = match expected {
                    true => format!("{field} has {} values for {m} joint_names", values.len()),
                    false => format!("has {field}, point 0 has none: give them at every point or at none"),
                };
                return Err(fail(path, &element, reason));
            }
            if let Some((i, x)) = values.iter().enumerate().find(|(_, x)| !(x.is_finite() && x.abs() <= bound)) {
                let reason = format!(
                    "{field}[{i}] ({}) is {x}: every value must be finite{}",
                    quote(&listed[i]),
                    if bound < f64::MAX { format!(", |value| <= {bound:e}") } else { String::new() }
                );
                return Err(fail(path, &element, reason));
            }
        }
        let d = point.time_from_start;
        if d.nanosec >= 1_000_000_000 {
            return Err(fail(path, &element, format!("time_from_start.nanosec is {}: must be below 1e9", d.nanosec)));
        }
        samples.t.push(d.seconds());
        samples.positions.push(reorder(&point.positions));
        if let Some(v) = &mut samples.velocities {
            v.push(reorder(&point.velocities));
        }
        if let Some(a) = &mut samples.accelerations {
            a.push(reorder(&point.accelerations));
        }
    }
    check_times(&samples.t, path)?;
    Ok(samples)
}

fn check_count(count: usize, path: &Path) -> Result<(), InputError> {
    if count < 2 {
        return Err(fail(path, "points", format!("{count} point(s): at least 2 are needed (t = 0 and the end)")));
    }
    if count > MAX_POINTS {
        return Err(fail(path, "points", format!("{count} points: at most {MAX_POINTS} are read (docs/spec.md §3)")));
    }
    Ok(())
}

/// Times from exactly 0, strictly increasing, finite.
fn check_times(t: &[f64], path: &Path) -> Result<(), InputError> {
    if t[0] != 0.0 {
        return Err(fail(path, "point 0", format!("starts at {} s: the trajectory must start at t = 0", t[0])));
    }
    for (k, w) in t.windows(2).enumerate() {
        if !(w[1] > w[0] && w[1].is_finite()) {
            let reason = format!("at {} s is not after point {k} at {} s: times must increase strictly", w[1], w[0]);
            return Err(fail(path, format!("point {}", k + 1), reason));
        }
    }
    Ok(())
}

/// freefloat's plan CSV (`plan --out FILE.csv`, any arm): columns `t`, `theta1..thetan`, and
/// when present `phi` (the base's start), `dtheta1..n` and `ddtheta1..n` (all cells filled, or
/// the column is taken as absent); other columns are ignored.
pub fn samples_from_csv(text: &str, joints: usize, path: &Path) -> Result<TrajectoryInput, InputError> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| fail(path, "header", crate::model::excerpt(&e.to_string())))?
        .iter()
        .map(str::to_string)
        .collect();
    let find = |name: &str| header.iter().position(|h| h == name);
    let Some(t_col) = find("t") else { return Err(fail(path, "header", "has no `t` column")) };
    let thetas = (1..).take_while(|k| find(&format!("theta{k}")).is_some()).count();
    if thetas != joints {
        let reason = format!("has joint columns theta1..theta{thetas}; the robot has {joints} joints");
        return Err(fail(path, "header", reason));
    }
    let columns = |prefix: &str| (1..=joints).map(|k| find(&format!("{prefix}{k}"))).collect::<Option<Vec<_>>>();
    let positions_cols = columns("theta").unwrap_or_default();
    let (velocity_cols, acceleration_cols) = (columns("dtheta"), columns("ddtheta"));
    let phi_col = find("phi");
    let mut rows: Vec<Vec<String>> = Vec::new();
    for (k, record) in reader.records().enumerate() {
        let record = record.map_err(|e| fail(path, format!("point {k}"), crate::model::excerpt(&e.to_string())))?;
        if rows.len() == MAX_POINTS {
            return Err(fail(path, "points", format!("more than {MAX_POINTS} rows: at most {MAX_POINTS} are read")));
        }
        rows.push(record.iter().map(str::to_string).collect());
    }
    check_count(rows.len(), path)?;
    let filled = |cols: Option<Vec<usize>>| {
        cols.filter(|c| rows.iter().all(|r| c.iter().all(|&i| r.get(i).is_some_and(|s| !s.is_empty()))))
    };
    let (velocity_cols, acceleration_cols) = (filled(velocity_cols), filled(acceleration_cols));
    let acceleration_cols = if velocity_cols.is_some() { acceleration_cols } else { None };
    let cell = |k: usize, row: &[String], i: usize, bound: f64| -> Result<f64, InputError> {
        let name = header.get(i).map_or("?", String::as_str);
        let text = row.get(i).map_or("", String::as_str);
        let x: f64 = text.parse().map_err(|_| {
            fail(path, format!("point {k}"), format!("{name} `{}` is not a number", crate::model::excerpt(text)))
        })?;
        if !(x.is_finite() && x.abs() <= bound) {
            return Err(fail(
                path,
                format!("point {k}"),
                format!("{name} is {x}: must be finite, |value| <= {bound:e}"),
            ));
        }
        Ok(x)
    };
    let mut samples = JointSamples {
        t: Vec::with_capacity(rows.len()),
        positions: Vec::with_capacity(rows.len()),
        velocities: velocity_cols.as_ref().map(|_| Vec::with_capacity(rows.len())),
        accelerations: acceleration_cols.as_ref().map(|_| Vec::with_capacity(rows.len())),
    };
    for (k, row) in rows.iter().enumerate() {
        samples.t.push(cell(k, row, t_col, f64::MAX)?);
        let read = |cols: &[usize], bound| cols.iter().map(|&i| cell(k, row, i, bound)).collect::<Result<Vec<_>, _>>();
        samples.positions.push(read(&positions_cols, MAX_POSITION)?);
        if let (Some(v), Some(cols)) = (&mut samples.velocities, &velocity_cols) {
            v.push(read(cols, MAX_RATE)?);
        }
        if let (Some(a), Some(cols)) = (&mut samples.accelerations, &acceleration_cols) {
            a.push(read(cols, MAX_RATE)?);
        }
    }
    check_times(&samples.t, path)?;
    let base_start = match phi_col {
        Some(i) => Some(cell(0, &rows[0], i, MAX_POSITION)?),
        None => None,
    };
    Ok(TrajectoryInput { samples, base_start })
}
