//! `freefloat mount-sweep`: over a grid of mounting points, the domain of Eq. (14) and the NFA's
//! success rate (2-link arms), and with `--effort` (always for another arm) the effort of the
//! minimum-effort plan `--from -> --to`; shardable for batch schedulers, and `mount-sweep merge`.

use std::io::IsTerminal;
use std::process::ExitCode;

use freefloat::analysis::shards::ShardFile;
use freefloat::analysis::sweep::{self, Shard, Span, SweepOptions, SweepRow, file};
use freefloat::report::io::write_atomic;
use freefloat::report::plot::{PictureFormat, sweep_picture};

use freefloat::model::arm::Arm;

use super::args::{MergeArgs, SweepArgs, SweepCommand, SweepRunArgs};

/// Runs `mount-sweep` or `mount-sweep merge`.
pub fn run(args: &SweepArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        Some(SweepCommand::Merge(m)) => merge(m),
        None => sweep(&args.run),
    }
}

/// The swept arm: the 2-link robot of the flags (the paper's SRC by default), or the arm of the
/// robot file.
fn arm(args: &SweepRunArgs) -> anyhow::Result<Arm> {
    Ok(match super::any_robot(&args.robot)? {
        super::Robot::TwoLink => Arm::from_params(&super::robot(&args.robot)?),
        super::Robot::Arm(arm) => arm,
    })
}

/// `--from`, `--to` of `n + 1` angles (deg -> rad) and `--time`; the defaults (the paper's
/// 2-link problem) only for a 2-link arm.
fn ends(args: &super::args::EndsArgs, n: usize) -> anyhow::Result<(Vec<f64>, Vec<f64>, f64)> {
    if n == 2 {
        let (start, goal, horizon) = super::ends(args)?;
        return Ok((start.to_array().to_vec(), goal.to_array().to_vec(), horizon));
    }
    let angles = |flag: &str, text: &str| super::config::arm_angles(flag, text, n + 1);
    Ok((angles("--from", &args.from)?, angles("--to", &args.to)?, super::config::time(args.time)?))
}

fn options(args: &SweepRunArgs, arm: &Arm) -> anyhow::Result<SweepOptions> {
    let two_link = arm.as_src().is_some();
    // The NFA's flags for an arm it cannot serve: refused with the reason, not ignored.
    let nfa_flags =
        args.global || args.grid.is_some() || args.trials.is_some() || args.seed.is_some() || args.samples.is_some();
    if !two_link && nfa_flags {
        sweep::nfa_robot(arm)?;
    }
    let defaults = SweepOptions::default();
    let [a0, a1] = super::parse_list::<2>("--a", &args.a_range)?;
    let [b0, b1] = super::parse_list::<2>("--b", &args.b_range)?;
    let (na, nb) = super::config::steps(&args.steps)?;
    let single = |lo: f64, hi: f64, n: usize| if lo < hi { n } else { 1 };
    let (na, nb) = (single(a0, a1, na), single(b0, b1, nb));
    super::config::sweep_points(na, nb)?;
    let (start, goal, horizon) = ends(&args.ends, arm.joints())?;
    for (flag, x) in [("--a", a0), ("--a", a1), ("--b", b0), ("--b", b1)] {
        if x.abs() > freefloat::model::MAX_MOUNT {
            return Err(freefloat::Error::from(freefloat::model::InputError::InvalidParameter {
                name: flag.into(),
                value: x,
                expected: "mounting coordinates with |a|, |b| <= 1e3 m (docs/spec.md §1)",
            })
            .into());
        }
    }
    Ok(SweepOptions {
        a: Span::new("--a", a0, a1, na)?,
        b: Span::new("--b", b0, b1, nb)?,
        grid: args.grid.unwrap_or(defaults.grid),
        trials: args.trials.unwrap_or(defaults.trials),
        seed: args.seed.unwrap_or(defaults.seed),
        samples: super::config::samples(args.samples.unwrap_or(defaults.samples as u64))?,
        horizon,
        tolerance: 1e-9,
        start,
        goal,
        global: args.global,
        nfa: two_link,
        effort: args.effort || !two_link,
    })
}

fn sweep(args: &SweepRunArgs) -> anyhow::Result<ExitCode> {
    if args.robot.mount.is_some() {
        anyhow::bail!("mount-sweep chooses the mounting points itself: use --a, --b and --steps, not --mount");
    }
    let arm = arm(args)?;
    let options = options(args, &arm)?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?.unwrap_or(Shard::ALL);
    let picture = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    super::check_outputs(&[args.out.as_ref(), args.plot.as_ref()])?;
    super::config::distinct_outputs(&[("--out", args.out.as_deref()), ("--plot", args.plot.as_deref())])?;
    if let Some(path) = &args.out {
        super::config::csv_out("mount-sweep", path)?;
    }
    options.validate()?;
    let count = shard.indices(options.points()).count() as u64;
    let bar = if std::io::stderr().is_terminal() && !super::output::quiet() {
        indicatif::ProgressBar::new(count)
    } else {
        indicatif::ProgressBar::hidden()
    };
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} points, {elapsed} elapsed, eta {eta}")
    {
        bar.set_style(style);
    }
    let clock = std::time::Instant::now();
    let rows = sweep::run(&arm, &options, shard, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();
    let csv = file::write(&file::run_description(&arm, &options), shard, &rows)?;
    match &args.out {
        Some(path) => write_atomic(path, &csv)?,
        None => super::emit(&String::from_utf8(csv)?)?,
    }
    if let (Some(path), Some(format)) = (&args.plot, picture) {
        write_atomic(path, &sweep_picture(&rows, format, path)?)?;
    }
    let scope = if shard == Shard::ALL { String::new() } else { format!(" in shard {}/{}", shard.k, shard.n) };
    let what = match (options.nfa, options.effort) {
        (true, true) => format!("grid {}, {} trials each, the effort", options.grid, options.trials),
        (true, false) => format!("grid {}, {} trials each", options.grid, options.trials),
        _ => format!("the effort of the {}-link arm's plan", arm.joints()),
    };
    let summary = format!(
        "{} mounting points{scope}, {what}, {:.1} s on {} threads\n{}",
        rows.len(),
        seconds,
        rayon::current_num_threads(),
        best_line(&rows, &scope)
    );
    // The CSV may be on stdout: the summary then goes to stderr.
    if args.out.is_some() && !super::output::quiet() {
        super::emit(&summary)?
    } else {
        super::note(&summary)
    }
    Ok(ExitCode::SUCCESS)
}

fn best_line(rows: &[SweepRow], scope: &str) -> String {
    let mut text = String::new();
    if let Some(b) = sweep::best(rows) {
        text += &format!(
            "best mounting point{scope}: a = {:.4} m, b = {:.4} m: NFA ({}) success rate {:.1} % ({} trials), start-component fraction {:.2} %, {} components\n",
            b.a,
            b.b,
            b.best_transform().name(),
            100.0 * b.best_rate().unwrap_or(0.0),
            b.trials,
            100.0 * b.start_component_fraction.unwrap_or(0.0),
            b.components.unwrap_or(0)
        );
    }
    if rows.iter().any(|r| r.planned.is_some()) {
        let failed = rows.iter().filter(|r| r.planned == Some(false)).count();
        let without = if failed > 0 { format!(" ({failed} points without a certified plan)") } else { String::new() };
        text += &match sweep::least_effort(rows) {
            Some(b) => format!(
                "least effort{scope}: a = {:.4} m, b = {:.4} m: {} rad^2/s{without}\n",
                b.a,
                b.b,
                freefloat::report::numbers::number(b.effort.unwrap_or(f64::NAN))
            ),
            None => format!("no certified plan at any mounting point{scope}\n"),
        };
    }
    if text.is_empty() {
        text = "no mounting points\n".into();
    }
    text
}

/// The largest shard file read \[bytes\] (a million sweep points take about 250 MiB).
const SHARD_FILE_LIMIT: u64 = 1 << 30;

/// Reads and checks the shard files of a merge with `read` (each up to [`SHARD_FILE_LIMIT`]).
pub(super) fn read_shard_files<R>(
    paths: &[std::path::PathBuf],
    read: impl Fn(&[u8], &std::path::Path) -> Result<ShardFile<R>, freefloat::Error>,
) -> anyhow::Result<Vec<(std::path::PathBuf, ShardFile<R>)>> {
    let mut files = Vec::new();
    for path in paths {
        let bytes = freefloat::model::read_regular_file(path, SHARD_FILE_LIMIT).map_err(freefloat::Error::from)?;
        files.push((path.clone(), read(&bytes, path)?));
    }
    Ok(files)
}

/// The shard files of a merge as inputs that no output may replace (`FILES`).
pub(super) fn shard_inputs(files: &[std::path::PathBuf]) -> Vec<(&str, &std::path::Path)> {
    files.iter().map(|f| ("FILES, a shard", f.as_path())).collect()
}

fn merge(args: &MergeArgs) -> anyhow::Result<ExitCode> {
    let picture = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    super::check_outputs(&[Some(&args.out), args.plot.as_ref()])?;
    let outputs = [("--out", Some(args.out.as_path())), ("--plot", args.plot.as_deref())];
    super::config::distinct_outputs(&outputs)?;
    super::config::outputs_apart_from_inputs(&outputs, &shard_inputs(&args.files))?;
    super::config::csv_out("mount-sweep merge", &args.out)?;
    let merged = file::merge_files(read_shard_files(&args.files, file::read)?)?;
    write_atomic(&args.out, &file::write(&merged.run, merged.shard, &merged.rows)?)?;
    if let (Some(path), Some(format)) = (&args.plot, picture) {
        write_atomic(path, &sweep_picture(&merged.rows, format, path)?)?;
    }
    super::emit(&format!(
        "merged {} files, {} mounting points\n{}",
        args.files.len(),
        merged.rows.len(),
        best_line(&merged.rows, "")
    ))?;
    Ok(ExitCode::SUCCESS)
}
