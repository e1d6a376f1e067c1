//! `freefloat`: the command-line shell over the library (docs/spec.md §3). Raw flags are parsed by clap
//! in [`cli::args`], validated into library types, run, and errors printed with their cause
//! chain; exit code 2 for bad input, 3 when the problem has no certified plan.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    match cli::run() {
        Ok(code) => code,
        Err(err) if err.downcast_ref::<cli::ClosedPipe>().is_some() => ExitCode::SUCCESS,
        Err(err) => {
            cli::report_error(&format!("error: {err:#}\n"));
            ExitCode::from(cli::exit_code(&err))
        }
    }
}
