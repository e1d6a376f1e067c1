//! The model's error: bad input, i.e. a parameter out of range or a file that cannot be read.

use std::path::PathBuf;

/// Bad input (exit code 2 at the command line): every variant names what is wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// A parameter is out of range; `name` is the key as the user wrote it.
    #[error("invalid value {value} for `{name}`: expected {expected}")]
    InvalidParameter {
        /// The parameter's name, e.g. `robot.m1` or `--time`.
        name: String,
        /// The rejected value.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// A robot file could not be read or parsed.
    #[error("cannot read robot file {}: {reason}", path.display())]
    RobotFile {
        /// The file.
        path: PathBuf,
        /// What is wrong, e.g. the TOML parser's message naming an unknown key.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("cannot access {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// An end-effector goal out of the arm's reach.
    #[error(transparent)]
    Unreachable(#[from] super::kinematics::Unreachable),
}
