//! The model's error: bad input, i.e. a parameter out of range or a file that cannot be read.

use std::path::PathBuf;

/// Bad input (exit code 2 at the command line): every variant names what is wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// A parameter is out of range; `name` is the key as the user wrote it.
    #[error("invalid value {} for `{name}`: expected {expected}", fmt_value(*value))]
    InvalidParameter {
        /// The parameter's name, e.g. `robot.m1` or `--time`.
        name: String,
        /// The rejected value.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// A parameter given as text does not parse or is out of range; `text` is cut to
    /// [`ECHO_LIMIT`] characters.
    #[error("invalid {name} `{}`: expected {expected}", excerpt(text))]
    InvalidText {
        /// The parameter's name, e.g. `--shard`.
        name: String,
        /// The text given.
        text: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// A robot file could not be read or parsed.
    #[error("cannot read robot file {}: {reason}", path.display())]
    RobotFile {
        /// The file.
        path: PathBuf,
        /// What is wrong, e.g. the TOML parser's message naming an unknown key (cut to a few
        /// lines of at most [`ECHO_LIMIT`] characters: the input is never echoed whole).
        reason: String,
    },
    /// A URDF file that parses but describes no planar serial arm (docs/spec.md §1, URDF):
    /// `element` names the offending joint or link.
    #[error("URDF {}: {element}: {reason}", path.display())]
    Urdf {
        /// The file.
        path: PathBuf,
        /// The offending element, e.g. ``joint `elbow` `` or ``link `forearm` ``.
        element: String,
        /// What is wrong and what is accepted.
        reason: String,
    },
    /// A file could not be read or written. The message names the file; the operating system's
    /// reason is the error's source (printed once, after it, by a cause chain).
    #[error("cannot access {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A trajectory file (`freefloat check`, docs/spec.md §3) that cannot be parsed or does not
    /// fit the robot: `element` names the point (counted from 0, as ROS indexes `points`), the
    /// joint or the field at fault.
    #[error("trajectory {}: {element}: {reason}", path.display())]
    Trajectory {
        /// The file.
        path: PathBuf,
        /// The offending element, e.g. `point 3` or ``joint `elbow` ``.
        element: String,
        /// What is wrong and what is accepted.
        reason: String,
    },
    /// An end-effector goal out of the arm's reach.
    #[error(transparent)]
    Unreachable(#[from] super::kinematics::Unreachable),
    /// An input file is not a regular file (a directory, a FIFO, a device): reading it could
    /// block forever or never end.
    #[error("{} is not a regular file", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
    },
    /// An input file is larger than what freefloat reads.
    #[error("{} is {bytes} bytes long; the limit for this file is {limit} bytes", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size \[bytes\].
        bytes: u64,
        /// The largest size read \[bytes\].
        limit: u64,
    },
    /// A request would take more memory than freefloat allows itself.
    #[error(
        "{what} would need about {} of memory; the limit is {} ({hint})",
        fmt_bytes(*bytes),
        fmt_bytes(*limit)
    )]
    TooMuchMemory {
        /// What was asked, e.g. `--samples 100000000`.
        what: String,
        /// The estimated need \[bytes\].
        bytes: u128,
        /// The limit \[bytes\].
        limit: u128,
        /// What is accepted, e.g. `at most 1048576 samples`.
        hint: String,
    },
    /// A request would take more time than freefloat allows itself (docs/spec.md §3,
    /// "Budgets"): `work` units of `unit` (e.g. control ticks) against the budget `limit`.
    #[error("{what} would take about {} {unit}; the budget is {} {unit} ({hint})", fmt_count(*work), fmt_count(*limit))]
    TooMuchWork {
        /// What was asked, e.g. `--time 1e6 at --rate 1e6`.
        what: String,
        /// The estimated work, in `unit`.
        work: f64,
        /// The budget, in `unit`.
        limit: f64,
        /// The unit of work, e.g. `control ticks`.
        unit: &'static str,
        /// What is accepted.
        hint: String,
    },
    /// A shard file (of `mount-sweep` or `track --trials`) is damaged, from another run, or does
    /// not fit with the other shards.
    #[error("{}{}: {reason}", path.display(), line.map(|l| format!(", line {l}")).unwrap_or_default())]
    ShardFile {
        /// The file.
        path: PathBuf,
        /// The line (from 1), when one line is at fault.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },
    /// An input file nests deeper than freefloat reads (elements of a URDF): refused before any
    /// recursive parser sees it, which could overflow its stack.
    #[error("{}, line {line}: elements nested deeper than {limit} levels; a robot file needs a handful", path.display())]
    NestedTooDeep {
        /// The file.
        path: PathBuf,
        /// The line (from 1) of the element that passes the limit.
        line: usize,
        /// The deepest nesting read.
        limit: usize,
    },
    /// Obstacles or a clearance were given for a robot whose bodies have no shapes: nothing
    /// would be checked, so a plan through an obstacle would pass as clear.
    #[error("{}", nothing_to_check_message(*obstacles, *clearance))]
    NothingToCheck {
        /// The obstacles given.
        obstacles: usize,
        /// The clearance given \[m\].
        clearance: f64,
    },
    /// A tool-pose goal inside the reach that no inverse-kinematics branch plans to: either
    /// `branch` was asked for and no branch of that name reaches the pose, or no branch reached
    /// it at all (the pose at the edge of the reach or at a singular configuration).
    #[error("{}", pose_branch_message(branch.as_deref(), reaching, *tried, *residual))]
    PoseBranch {
        /// The branch asked for (`up`, `down`, ...), when that is what is wrong.
        branch: Option<String>,
        /// The branches that reach the pose.
        reaching: Vec<String>,
        /// How many branches the inverse kinematics tried.
        tried: usize,
        /// The least distance of a branch's tool point from the pose \[m\].
        residual: f64,
    },
}

fn nothing_to_check_message(obstacles: usize, clearance: f64) -> String {
    let given = match (obstacles, clearance > 0.0) {
        (0, _) => format!("a clearance of {} m was given", fmt_value(clearance)),
        (n, false) => format!("{n} obstacle(s) were given"),
        (n, true) => format!("{n} obstacle(s) and a clearance of {} m were given", fmt_value(clearance)),
    };
    format!(
        "{given}, but the robot's bodies have no shapes, so nothing would be checked: give them shapes (TOML link \
         `width` or `shape`, base `shape`; URDF <collision>), or drop the obstacles and the clearance"
    )
}

fn pose_branch_message(branch: Option<&str>, reaching: &[String], tried: usize, residual: f64) -> String {
    match branch {
        Some(branch) => format!(
            "no inverse-kinematics branch `{}` reaches the pose (those that do: {}); drop the branch choice to plan \
             them all",
            excerpt(branch),
            reaching.join(", ")
        ),
        None => format!(
            "none of the {tried} inverse-kinematics branch(es) reached the pose (best residual {residual:.2e} m): \
             the pose is inside the reach but at its edge or at a singular configuration; move it inwards"
        ),
    }
}

/// The most characters of user input that a message repeats.
pub const ECHO_LIMIT: usize = 80;

/// `text` cut to [`ECHO_LIMIT`] characters, with its length when cut: messages never echo a
/// whole (possibly huge) input.
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(ECHO_LIMIT) {
        Some((cut, _)) => format!("{}... ({} bytes in all)", &text[..cut], text.len()),
        None => text.to_string(),
    }
}

/// A number as a message shows it: plain when moderate, else in scientific notation (`1e300`,
/// not 301 digits).
pub fn fmt_value(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e9).contains(&a) || !x.is_finite() { format!("{x}") } else { format!("{x:e}") }
}

/// A count of work (ticks, plans) as people read it: whole below a million, else `1.00e12`.
pub fn fmt_count(x: f64) -> String {
    if x.is_finite() && x.abs() < 1e6 { format!("{}", x.round()) } else { format!("{x:.2e}") }
}

/// A size in bytes in binary units (KiB to EiB).
pub fn fmt_bytes(bytes: u128) -> String {
    const UNITS: [&str; 7] = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = bytes as f64;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    if unit == 0 { format!("{bytes} bytes") } else { format!("{x:.1} {}", UNITS[unit]) }
}
