//! The TOML robot file (docs/spec.md, Sec. 1): `[robot]` with every key required, `[mount]`
//! optional; unknown keys are errors, so that typos never pass silently.

use std::path::Path;

use serde::Deserialize;

use super::{InputError, Mount, RobotParams};

/// The `[robot]` table: every key required.
#[allow(non_snake_case)]
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotTable {
    l1: f64,
    l2: f64,
    d1: f64,
    d2: f64,
    M: f64,
    I: f64,
    m1: f64,
    m2: f64,
}

/// The `[mount]` table: optional, default `a = b = 0`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MountTable {
    pub(super) a: f64,
    pub(super) b: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotFile {
    robot: RobotTable,
    mount: Option<MountTable>,
}

impl RobotParams {
    /// Parses and validates a robot file's text (docs/spec.md §1). Unknown keys are errors.
    ///
    /// ```
    /// let text = "[robot]\nl1 = 0.619\nl2 = 0.6\nd1 = 0.313\nd2 = 0.287\nM = 12.9\nI = 0.208\nm1 = 4.5\nm2 = 1.5\n[mount]\na = 0.1\nb = 0.1\n";
    /// let robot = freefloat::RobotParams::from_toml(text, "robot.toml".as_ref()).unwrap();
    /// assert_eq!(robot.mount.a, 0.1);
    /// ```
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, InputError> {
        let file: RobotFile = toml::from_str(text)
            .map_err(|e| InputError::RobotFile { path: path.to_path_buf(), reason: short_reason(&e.to_string()) })?;
        let r = file.robot;
        let mount = file.mount.map(|m| Mount { a: m.a, b: m.b }).unwrap_or_default();
        RobotParams::new(RobotParams {
            l1: r.l1,
            l2: r.l2,
            d1: r.d1,
            d2: r.d2,
            base_mass: r.M,
            base_inertia: r.I,
            m1: r.m1,
            m2: r.m2,
            i1: 0.0,
            i2: 0.0,
            mount,
        })
    }

    /// Reads and validates a robot file: a regular file of at most [`ROBOT_FILE_LIMIT`] bytes
    /// (a FIFO or a device is refused rather than waited on), UTF-8 TOML.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let bytes = read_regular_file(path, ROBOT_FILE_LIMIT)?;
        let text = String::from_utf8(bytes).map_err(|e| InputError::RobotFile {
            path: path.to_path_buf(),
            reason: format!("not UTF-8 text (invalid byte at offset {})", e.utf8_error().valid_up_to()),
        })?;
        Self::from_toml(&text, path)
    }
}

/// The largest robot file read \[bytes\]: a robot file is a dozen lines.
pub const ROBOT_FILE_LIMIT: u64 = 1 << 20;

/// Reads a whole input file of at most `limit` bytes. Only regular files are read: the type is
/// checked before the file is opened (opening a FIFO without a writer blocks forever) and again
/// on the open handle; the size is checked before reading, and the read stops at `limit + 1`.
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    use std::io::Read;
    let io = |source| InputError::Io { path: path.to_path_buf(), source };
    let not_a_file = || InputError::NotAFile { path: path.to_path_buf() };
    if !std::fs::metadata(path).map_err(io)?.is_file() {
        return Err(not_a_file());
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(not_a_file());
    }
    if meta.len() > limit {
        return Err(InputError::TooLarge { path: path.to_path_buf(), bytes: meta.len(), limit });
    }
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(InputError::TooLarge { path: path.to_path_buf(), bytes: bytes.len() as u64, limit });
    }
    Ok(bytes)
}

/// A parser's message with every line cut to [`super::ECHO_LIMIT`] characters and at most
/// eight lines: the TOML parser quotes the offending line, which may be megabytes long.
pub(super) fn short_reason(reason: &str) -> String {
    let mut lines: Vec<String> = reason.lines().take(8).map(super::excerpt).collect();
    if reason.lines().count() > 8 {
        lines.push("...".into());
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str =
        "[robot]\nl1 = 0.619\nl2 = 0.6\nd1 = 0.313\nd2 = 0.287\nM = 12.9\nI = 0.208\nm1 = 4.5\nm2 = 1.5\n";

    #[test]
    fn robot_file_round_trip_and_errors() {
        let p = Path::new("r.toml");
        assert_eq!(RobotParams::from_toml(GOOD, p).unwrap(), RobotParams::src());
        let unknown = format!("{GOOD}m3 = 1.0\n");
        let e = RobotParams::from_toml(&unknown, p).unwrap_err().to_string();
        assert!(e.contains("m3"), "{e}");
        let missing = GOOD.replace("m2 = 1.5\n", "");
        assert!(RobotParams::from_toml(&missing, p).unwrap_err().to_string().contains("m2"));
        for (key, bad) in [("M", "-12.9"), ("I", "nan"), ("l1", "inf"), ("d1", "0.0"), ("m1", "0")] {
            let text = GOOD.replace(&format!("{key} = "), &format!("{key} = {bad} #"));
            let e = RobotParams::from_toml(&text, p).unwrap_err();
            assert!(
                matches!(&e, InputError::InvalidParameter { name, .. } if name == &format!("robot.{key}")),
                "{key}: {e}"
            );
        }
        let mount = format!("{GOOD}[mount]\na = 0.1\nc = 0.2\n");
        assert!(RobotParams::from_toml(&mount, p).unwrap_err().to_string().contains('c'));
    }
}
