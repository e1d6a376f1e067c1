//! `freefloat mount-sweep`: the domain of Eq. (14) and the NFA's success rate over a grid of
//! mounting points, shardable for batch schedulers, and `mount-sweep merge`.

use std::io::IsTerminal;
use std::process::ExitCode;

use freefloat::analysis::shards::ShardFile;
use freefloat::analysis::sweep::{self, Shard, Span, SweepOptions, SweepRow, file};
use freefloat::report::io::write_atomic;
use freefloat::report::plot::{PictureFormat, sweep_picture};

use super::args::{MergeArgs, SweepArgs, SweepCommand, SweepRunArgs};

/// Runs `mount-sweep` or `mount-sweep merge`.
pub fn run(args: &SweepArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        Some(SweepCommand::Merge(m)) => merge(m),
        None => sweep(&args.run),
    }
}

fn options(args: &SweepRunArgs) -> anyhow::Result<SweepOptions> {
    let [a0, a1] = super::parse_list::<2>("--a", &args.a_range)?;
    let [b0, b1] = super::parse_list::<2>("--b", &args.b_range)?;
    let (na, nb) = super::config::steps(&args.steps)?;
    let single = |lo: f64, hi: f64, n: usize| if lo < hi { n } else { 1 };
    let (na, nb) = (single(a0, a1, na), single(b0, b1, nb));
    super::config::sweep_points(na, nb)?;
    let (start, goal, horizon) = super::ends(&args.ends)?;
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
        grid: args.grid,
        trials: args.trials,
        seed: args.seed,
        samples: super::config::samples(args.samples)?,
        horizon,
        tolerance: 1e-9,
        start,
        goal,
        global: args.global,
    })
}

fn sweep(args: &SweepRunArgs) -> anyhow::Result<ExitCode> {
    if args.robot.mount.is_some() {
        anyhow::bail!("mount-sweep chooses the mounting points itself: use --a, --b and --steps, not --mount");
    }
    let robot = super::robot(&args.robot)?;
    let options = options(args)?;
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
    let rows = sweep::run(&robot, &options, shard, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();
    let csv = file::write(&file::run_description(&robot, &options), shard, &rows)?;
    match &args.out {
        Some(path) => write_atomic(path, &csv)?,
        None => super::emit(&String::from_utf8(csv)?)?,
    }
    if let (Some(path), Some(format)) = (&args.plot, picture) {
        write_atomic(path, &sweep_picture(&rows, format, path)?)?;
    }
    let scope = if shard == Shard::ALL { String::new() } else { format!(" in shard {}/{}", shard.k, shard.n) };
    let summary = format!(
        "{} mounting points{scope}, grid {}, {} trials each, {:.1} s on {} threads\n{}",
        rows.len(),
        options.grid,
        options.trials,
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
    match sweep::best(rows) {
        Some(b) => format!(
            "best mounting point{scope}: a = {:.4} m, b = {:.4} m: NFA ({}) success rate {:.1} % ({} trials), start-component fraction {:.2} %, {} components\n",
            b.a,
            b.b,
            b.best_transform().name(),
            100.0 * b.best_rate(),
            b.trials,
            100.0 * b.start_component_fraction,
            b.components
        ),
        None => "no mounting points\n".into(),
    }
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

fn merge(args: &MergeArgs) -> anyhow::Result<ExitCode> {
    let picture = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    super::check_outputs(&[Some(&args.out), args.plot.as_ref()])?;
    super::config::distinct_outputs(&[("--out", Some(args.out.as_path())), ("--plot", args.plot.as_deref())])?;
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
