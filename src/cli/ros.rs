//! The ROS 2 outputs of `plan` (docs/spec.md §3, "ROS 2"): `--format joint-trajectory`,
//! `--out FILE.yaml|.json` as a JointTrajectory message, and `--base-out` for its companion.

use std::path::{Path, PathBuf};

use anyhow::bail;
use freefloat::model::arm::Arm;
use freefloat::model::arm::file::default_joint_names;
use freefloat::plan::ros::{Encoding, to_text};
use freefloat::report::ros::{MotionRows, base_trajectory, joint_trajectory};

use super::args::{Format, PlanArgs, RobotArgs};

/// What `plan --out FILE` writes, by the extension (any case) and `--format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutKind {
    /// `.json`: the JSON report with the trajectory.
    Report,
    /// `.csv`: the trajectory.
    Csv,
    /// `.yaml`/`.yml`, or `.json` with `--format joint-trajectory`: the JointTrajectory message.
    Message(Encoding),
}

/// The kind of `--out` (checked before planning; bad input for another extension).
pub fn out_kind(path: &Path, format: Format) -> anyhow::Result<OutKind> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    Ok(match (extension.as_deref(), Encoding::of_path(path)) {
        (Some("csv"), _) => OutKind::Csv,
        (Some("json"), _) if format != Format::JointTrajectory => OutKind::Report,
        (_, Some(encoding)) => OutKind::Message(encoding),
        _ => bail!("--out {}: the file name must end in .json, .csv, .yaml or .yml", path.display()),
    })
}

/// The checked `--base-out FILE.yaml|.yml|.json` (extension and place, before planning).
pub fn checked_base_out(args: &PlanArgs) -> anyhow::Result<Option<(&PathBuf, Encoding)>> {
    let Some(path) = &args.base_out else { return Ok(None) };
    let Some(encoding) = Encoding::of_path(path) else {
        bail!("--base-out {}: the file name must end in .yaml, .yml or .json", path.display())
    };
    freefloat::report::io::check_writable(path)?;
    Ok(Some((path, encoding)))
}

/// The joint names of the robot of the flags: a URDF's moving joints, else `joint1..jointN`.
pub fn joint_names(args: &RobotArgs, n: usize) -> anyhow::Result<Vec<String>> {
    match args.urdf.as_ref().or(args.robot.as_ref()) {
        Some(path) => Ok(Arm::load_named(path)?.1),
        None => Ok(default_joint_names(n)),
    }
}

/// Whether `plan` writes a ROS 2 message: `--format joint-trajectory`, `--out` of a message,
/// or `--base-out`.
pub fn wanted(format: Format, out: Option<(&PathBuf, OutKind)>, base_out: Option<(&PathBuf, Encoding)>) -> bool {
    format == Format::JointTrajectory || matches!(out, Some((_, OutKind::Message(_)))) || base_out.is_some()
}

/// The ROS 2 outputs of a plan's `rows`: the JointTrajectory YAML for stdout when `format` asks
/// for it, and the files of `out` (when a message) and `base_out`, written atomically.
pub fn messages(
    rows: &MotionRows,
    names: &[String],
    format: Format,
    out: Option<(&PathBuf, OutKind)>,
    base_out: Option<(&PathBuf, Encoding)>,
) -> anyhow::Result<Option<String>> {
    let message = joint_trajectory(rows, names)?;
    if let Some((path, OutKind::Message(encoding))) = out {
        freefloat::report::io::write_atomic(path, to_text(&message, encoding)?.as_bytes())?;
    }
    if let Some((path, encoding)) = base_out {
        freefloat::report::io::write_atomic(path, to_text(&base_trajectory(rows)?, encoding)?.as_bytes())?;
    }
    Ok(match format {
        Format::JointTrajectory => Some(to_text(&message, Encoding::Yaml)?),
        _ => None,
    })
}
