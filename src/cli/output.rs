//! What the binary prints: stdout that tolerates a closed pipe, notes on stderr that `--quiet`
//! silences, the JSON error object of `--format json`, the signal handler that removes
//! temporary files, shell completions and the man page.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::CommandFactory;

use super::args::Cli;

static QUIET: AtomicBool = AtomicBool::new(false);

/// Silences [`note`] (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// True under `--quiet`.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// A spinner on stderr with `message` and the time elapsed while long work runs (a plan that
/// keeps a clearance, `--time auto`'s search), cleared when dropped; drawn only on a terminal
/// and not under `--quiet`, so that nothing of it reaches a pipe or a file.
pub struct Spinner(indicatif::ProgressBar);

impl Spinner {
    /// Starts the spinner (hidden off a terminal or under `--quiet`).
    pub fn start(message: &'static str) -> Self {
        use std::io::IsTerminal;
        if !std::io::stderr().is_terminal() || quiet() {
            return Self(indicatif::ProgressBar::hidden());
        }
        let bar = indicatif::ProgressBar::new_spinner().with_message(message);
        if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {msg}, {elapsed} elapsed") {
            bar.set_style(style);
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        Self(bar)
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

/// Prints a note (progress, summaries, hints) on stderr, unless `--quiet`.
pub fn note(text: &str) {
    if !quiet() {
        let mut err = std::io::stderr().lock();
        let _ignored = err.write_all(text.as_bytes()); // stderr closed: nothing else to tell
    }
}

/// Stdout was closed by its reader (`freefloat plan --format csv | head -3`): the run stops
/// quietly with exit code 0, as Unix tools do.
#[derive(Debug, thiserror::Error)]
#[error("stdout was closed")]
pub struct ClosedPipe;

static WROTE: AtomicBool = AtomicBool::new(false);

/// True once [`emit`] has written something.
pub fn wrote_stdout() -> bool {
    WROTE.load(Ordering::Relaxed)
}

/// Writes `text` to stdout; a closed pipe becomes [`ClosedPipe`] (exit 0), any other failure
/// (a full disk) an error naming stdout (exit 2), never a panic. Every line the binary prints
/// goes through here or through [`note`] / [`report_error`]: `tests/it/layout.rs` refuses the
/// `print` macros, which panic on such outputs.
pub fn emit(text: &str) -> anyhow::Result<()> {
    WROTE.store(true, Ordering::Relaxed);
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(ClosedPipe.into()),
        result => Ok(result.map_err(|e| anyhow::Error::new(e).context("cannot write to stdout"))?),
    }
}

/// Prints a line on stderr that `--quiet` does not silence (an error, a failed case); a closed
/// or full stderr is ignored: there is nowhere left to tell, and the exit code still says it.
pub fn report_error(text: &str) {
    let mut err = std::io::stderr().lock();
    let _ignored = err.write_all(text.as_bytes()).and_then(|()| err.flush());
}

/// On SIGINT, SIGTERM or SIGHUP: removes the temporary files and directories of writes in
/// progress, then exits with code 130. (The `ctrlc` crate with its `termination` feature: one
/// portable handler thread, no unsafe code here.)
pub fn install_signal_handler() {
    let installed = ctrlc::set_handler(|| {
        freefloat::report::io::remove_temporaries();
        std::process::exit(130);
    });
    if let Err(e) = installed {
        note(&format!("note: no signal handler ({e}): an interrupted run may leave a temporary file\n"));
    }
}

/// `freefloat completions SHELL`.
pub fn completions(shell: clap_complete::Shell) -> anyhow::Result<std::process::ExitCode> {
    let mut buf = Vec::new();
    clap_complete::generate(shell, &mut Cli::command(), "freefloat", &mut buf);
    emit(&String::from_utf8(buf)?)?;
    Ok(std::process::ExitCode::SUCCESS)
}

/// `freefloat man`: the man page (roff) on stdout.
pub fn man() -> anyhow::Result<std::process::ExitCode> {
    let mut buf = Vec::new();
    clap_mangen::Man::new(Cli::command()).render(&mut buf)?;
    emit(&String::from_utf8(buf)?)?;
    Ok(std::process::ExitCode::SUCCESS)
}

/// The JSON error object printed on stdout under `--format json` (docs/spec.md §3):
/// `{"error": {"kind", "exit_code", "message", "numbers"}}`, the numbers those of
/// [`freefloat::Error::numbers`] (the same as the Python exceptions' `numbers`).
pub fn error_json(err: &anyhow::Error) -> String {
    use freefloat::Error as E;
    use freefloat::model::InputError as I;
    use serde_json::json;
    let kind = match err.downcast_ref::<E>() {
        Some(E::Input(I::InvalidParameter { .. })) => "invalid_parameter",
        Some(E::Input(I::TooMuchMemory { .. })) => "too_much_memory",
        Some(E::Input(I::TooLarge { .. })) => "too_large",
        Some(E::Input(_)) => "bad_input",
        Some(E::NotCertified { .. }) => "not_certified",
        Some(E::Singular { .. }) => "singular",
        Some(E::NewtonFailed { .. }) => "newton_failed",
        Some(E::GoalMissed { .. }) => "goal_missed",
        Some(E::Collision { .. }) => "collision",
        Some(E::LimitExceeded { .. }) => "limit_exceeded",
        Some(E::HorizonTooShort { .. }) => "horizon_too_short",
        Some(e) if e.is_bad_input() => "bad_input",
        Some(_) => "no_certified_plan",
        None => "bad_input",
    };
    let numbers = err.downcast_ref::<E>().map(E::numbers).unwrap_or_else(|| json!({}));
    let object = json!({"error": {
        "kind": kind,
        "exit_code": super::exit_code(err),
        "message": format!("{err:#}"),
        "numbers": numbers,
    }});
    object.to_string()
}
