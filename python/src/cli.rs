//! The `freefloat` command of the Python package: the library's command line
//! (`freefloat::cli`, the same code as the Rust binary's), run in this process.

use std::ffi::OsString;

use pyo3::prelude::*;

/// Runs the command line `argv` (the program's name first) with the GIL released and returns
/// its exit code (0 success, 2 bad input, 3 no certified plan); `--help`, `--version` and usage
/// errors end the process as the binary does. Called by `freefloat._cli.main`.
#[pyfunction]
pub fn _cli_main(py: Python<'_>, argv: Vec<OsString>) -> u8 {
    py.detach(|| freefloat::cli::main_from(argv))
}
