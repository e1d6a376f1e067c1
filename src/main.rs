//! `freefloat`: the command-line shell over the library (docs/spec.md §3). Raw flags are parsed by clap
//! in `freefloat::cli::args`, validated into library types, run, and errors printed with their
//! cause chain; exit code 2 for bad input, 3 when the problem has no certified plan. The command
//! line lives in the library (`freefloat::cli`) so that the Python package's `freefloat` command
//! runs the same code.

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(freefloat::cli::main_from(std::env::args_os()))
}
