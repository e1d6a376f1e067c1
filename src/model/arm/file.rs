//! An arm's robot file (docs/spec.md §1): the TOML file with an `[[link]]` array, or the 2-link
//! SRC file (point-mass links), or a URDF (by the extension `.urdf`).
//!
//! ```toml
//! [robot]              # the base: both keys required
//! M = 15.0             # mass [kg]
//! I = 0.45             # moment of inertia about its centre of mass [kg m^2]
//! [mount]              # optional, default a = b = 0
//! a = 0.1
//! b = 0.0
//! [[link]]             # one per link, from the base outwards; every key required
//! length = 0.45        # joint to next joint [m]
//! com = 0.225          # joint to the link's centre of mass, along the link [m]
//! mass = 2.0           # [kg]
//! inertia = 0.03375    # about the link's centre of mass [kg m^2]; 0 = a point mass
//! ```

use std::path::Path;

use serde::Deserialize;

use super::file_limits::{BaseLimitTable, LinkLimitTable};
use super::{Arm, Base, Link};
use crate::model::robot_file::{MountTable, ROBOT_FILE_LIMIT, read_regular_file, short_reason};
use crate::model::{InputError, Mount, RobotParams};

/// The `[robot]` table of a file with `[[link]]`: the base only.
#[allow(non_snake_case)]
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BaseTable {
    M: f64,
    I: f64,
    /// The base angle's range (issue 20, [`super::file_limits`]).
    limit: Option<BaseLimitTable>,
    /// The base's shape(s) in its frame (issue 21; [`super::shapes`]).
    shape: Option<super::shapes::ShapeText>,
}

/// One `[[link]]` entry: every key required.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkTable {
    length: f64,
    com: f64,
    mass: f64,
    inertia: f64,
    /// The joint's limits (issue 20, [`super::file_limits`]).
    limit: Option<LinkLimitTable>,
    /// A capsule along the link of this width \[m\] (issue 21; [`super::shapes`]).
    width: Option<f64>,
    /// The link's shape(s) in its frame.
    shape: Option<super::shapes::ShapeText>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ArmFile {
    robot: BaseTable,
    mount: Option<MountTable>,
    link: Vec<LinkTable>,
}

impl Arm {
    /// Parses and validates a TOML robot file's text (docs/spec.md §1): with an `[[link]]`
    /// array, `[robot]` holds the base's `M` and `I` only and every `[[link]]` has `length`,
    /// `com`, `mass`, `inertia`; without one, it is the 2-link SRC file of
    /// [`RobotParams::from_toml`], whose links are point masses. Unknown keys are errors; a bad
    /// value is named as `link[k].mass` (`k` from 1), `robot.M`, `mount.a` (see [`Arm::new`]).
    ///
    /// ```
    /// use freefloat::model::arm::Arm;
    /// let text = "[robot]\nM = 15.0\nI = 0.45\n[[link]]\nlength = 0.45\ncom = 0.225\nmass = 2.0\ninertia = 0.03375\n";
    /// let arm = Arm::from_toml(text, "arm.toml".as_ref()).unwrap();
    /// assert_eq!(arm.joints(), 1);
    /// ```
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, InputError> {
        let bad_file = |e: toml::de::Error| InputError::RobotFile {
            path: path.to_path_buf(),
            reason: short_reason(&e.to_string()),
        };
        let table: toml::Table = toml::from_str(text).map_err(bad_file)?;
        if !table.contains_key("link") {
            return RobotParams::from_toml(text, path).map(|robot| Arm::from_params(&robot));
        }
        let file: ArmFile = toml::from_str(text).map_err(bad_file)?;
        let mount = file.mount.map(|m| Mount { a: m.a, b: m.b }).unwrap_or_default();
        let links =
            file.link.iter().map(|l| Link { length: l.length, com: l.com, mass: l.mass, inertia: l.inertia }).collect();
        let arm = Arm::new(Base { mass: file.robot.M, inertia: file.robot.I }, mount, links)?;
        let limit_tables: Vec<_> = file.link.iter().map(|l| l.limit).collect();
        let arm = arm.with_limits(super::file_limits::from_tables(file.robot.limit, &limit_tables)?)?;
        let shapes: Vec<_> = file.link.iter().map(|l| (l.width, l.shape.as_ref(), l.length)).collect();
        arm.with_geometry(super::shapes::toml_geometry(file.robot.shape.as_ref(), &shapes)?)
    }

    /// The arm as a TOML robot file with `[[link]]` (always that form, even for two point
    /// masses), which [`Arm::from_toml`] reads back to the same arm: every number is written in
    /// Rust's shortest round-trip form.
    pub fn to_toml(&self) -> String {
        let mut s = format!("[robot]\nM = {:?}\nI = {:?}\n", self.base.mass, self.base.inertia);
        s += &super::file_limits::base_line(&self.limits);
        s += &format!("\n[mount]\na = {:?}\nb = {:?}\n", self.mount.a, self.mount.b);
        for (k, link) in self.links.iter().enumerate() {
            s += &format!(
                "\n[[link]]\nlength = {:?}\ncom = {:?}\nmass = {:?}\ninertia = {:?}\n",
                link.length, link.com, link.mass, link.inertia
            );
            s += &super::file_limits::link_line(&self.limits, k);
        }
        s
    }

    /// Reads and validates a robot: a URDF when the file name ends in `.urdf` (any case; see
    /// [`Arm::from_urdf_str`]), else a TOML robot file (see [`Arm::from_toml`]). Either must be a
    /// regular file (a FIFO or a device is refused rather than waited on) of at most
    /// [`ROBOT_FILE_LIMIT`] bytes of UTF-8 text.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let bytes = read_regular_file(path, ROBOT_FILE_LIMIT)?;
        let text = String::from_utf8(bytes).map_err(|e| InputError::RobotFile {
            path: path.to_path_buf(),
            reason: format!("not UTF-8 text (invalid byte at offset {})", e.utf8_error().valid_up_to()),
        })?;
        let is_urdf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
        if is_urdf { Self::from_urdf_str(&text, path) } else { Self::from_toml(&text, path) }
    }

    /// The tool frame of a URDF file ([`Arm::from_urdf_str_described`]): `None` for a robot file
    /// or a URDF whose last link has no fixed child.
    pub fn load_tool_frame(path: &Path) -> Result<Option<String>, InputError> {
        if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf")) {
            return Ok(None);
        }
        let bytes = read_regular_file(path, ROBOT_FILE_LIMIT)?;
        let text = String::from_utf8_lossy(&bytes);
        Ok(Self::from_urdf_str_described(&text, path)?.2)
    }

    /// [`Arm::load`] with the joints' names: a URDF's moving joints as it names them
    /// ([`Arm::from_urdf_str_named`]), else [`default_joint_names`].
    pub fn load_named(path: &Path) -> Result<(Self, Vec<String>), InputError> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf")) {
            let bytes = read_regular_file(path, ROBOT_FILE_LIMIT)?;
            let text = String::from_utf8(bytes).map_err(|e| InputError::RobotFile {
                path: path.to_path_buf(),
                reason: format!("not UTF-8 text (invalid byte at offset {})", e.utf8_error().valid_up_to()),
            })?;
            return Self::from_urdf_str_named(&text, path);
        }
        let arm = Self::load(path)?;
        let names = default_joint_names(arm.joints());
        Ok((arm, names))
    }
}

/// The joint names of a robot without its own (a TOML robot file, the `src` preset):
/// `joint1`..`jointN` from the base outwards, as [`Arm::to_urdf`] names them.
pub fn default_joint_names(n: usize) -> Vec<String> {
    (1..=n).map(|k| format!("joint{k}")).collect()
}
