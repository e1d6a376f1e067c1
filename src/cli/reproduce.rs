//! `freefloat reproduce`: writes the paper's results (see [`freefloat::report::reproduce`]),
//! with a progress line per job on a terminal.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};

use clap::Args;
use freefloat::report::closed_loop::CLOSED_LOOP_TRIALS;
use freefloat::report::reproduce::{job_count, reproduce};

use super::args::GifArgs;

/// Flags of `freefloat reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,
    /// Also write an animated GIF of every plan, `anim-CASE.gif` (e.g. `anim-fig06.gif`), into DIR.
    #[arg(long)]
    pub gif: bool,
    #[command(flatten)]
    pub gif_options: GifArgs,
    /// Closed-loop trials of Fig. 20 per controller and problem (half as many per point of its
    /// torque curve), 1 to 1000000; 1000 is the full version (about half an hour on 2 cores).
    #[arg(long, value_name = "N", default_value_t = CLOSED_LOOP_TRIALS)]
    pub trials: usize,
}

/// Runs `reproduce`: exit 0 when every figure's case has a plan, the paper's NFA cases
/// (Figs. 4-8) are certified at both levels and Fig. 20's Monte Carlo runs; 3 otherwise
/// (everything is still written).
pub fn run(args: &ReproduceArgs) -> anyhow::Result<ExitCode> {
    let (total, done, on) =
        (job_count(args.gif), AtomicUsize::new(0), std::io::stderr().is_terminal() && !super::output::quiet());
    let progress = |what: &str, seconds: f64, status: &str| {
        let k = done.fetch_add(1, Ordering::Relaxed) + 1;
        if on {
            super::note(&format!("[{k:>2}/{total}] {what:<46} {status:<58} {:>7.1} ms\n", seconds * 1e3));
        }
    };
    let gif = if args.gif { Some(super::gif_options(&args.gif_options)?) } else { None };
    let r = reproduce(&args.out, gif.as_ref(), args.trials, &progress)?;
    super::emit(&format!("{}\nwrote {} files to {} in {:.2} s\n", r.markdown, r.files, args.out.display(), r.seconds))?;
    for failure in &r.failures {
        super::report_error(&format!("{failure}\n"));
    }
    Ok(if r.failures.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(3) })
}
