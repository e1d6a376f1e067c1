//! `freefloat mount-sweep`: the domain of Eq. (14) and the NFA's success rate over a grid of
//! mounting points, shardable for batch schedulers, and `mount-sweep merge`.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use freefloat::Configuration;
use freefloat::analysis::sweep::{self, Shard, Span, SweepOptions, SweepRow};
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
    let steps: Vec<usize> = args
        .steps
        .split(',')
        .map(|s| s.trim().parse::<usize>().with_context(|| format!("--steps: `{s}` is not a count")))
        .collect::<anyhow::Result<_>>()?;
    let (na, nb) = match steps[..] {
        [n] => (n, n),
        [na, nb] => (na, nb),
        _ => anyhow::bail!("--steps takes NA or NA,NB"),
    };
    let single = |lo: f64, hi: f64, n: usize| if lo < hi { n } else { 1 };
    let [p0, s1, s2] = super::parse_list::<3>("--from", &args.ends.from)?;
    let [p1, g1, g2] = super::parse_list::<3>("--to", &args.ends.to)?;
    if !(args.ends.time.is_finite() && args.ends.time > 0.0) {
        anyhow::bail!("--time must be a positive number of seconds");
    }
    Ok(SweepOptions {
        a: Span::new("--a", a0, a1, single(a0, a1, na))?,
        b: Span::new("--b", b0, b1, single(b0, b1, nb))?,
        grid: args.grid,
        trials: args.trials,
        seed: args.seed,
        samples: args.samples,
        horizon: args.ends.time,
        tolerance: 1e-9,
        start: Configuration::from_degrees(p0, s1, s2),
        goal: Configuration::from_degrees(p1, g1, g2),
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
    let count = shard.indices(options.points()).count() as u64;
    let bar = if std::io::stderr().is_terminal() {
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
    let csv = sweep::to_csv(&rows)?;
    match &args.out {
        Some(path) => write_atomic(path, &csv)?,
        None => print!("{}", String::from_utf8(csv)?),
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
    if args.out.is_some() {
        print!("{summary}")
    } else {
        eprint!("{summary}")
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

fn read_rows(path: &Path) -> anyhow::Result<Vec<SweepRow>> {
    let bytes = std::fs::read(path).map_err(|source| {
        freefloat::Error::from(freefloat::model::InputError::Io { path: path.to_path_buf(), source })
    })?;
    Ok(sweep::from_csv(&bytes, path)?)
}

fn merge(args: &MergeArgs) -> anyhow::Result<ExitCode> {
    let picture = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    let mut all = Vec::new();
    for path in &args.files {
        all.extend(read_rows(path)?);
    }
    let rows = sweep::merge(all)?;
    write_atomic(&args.out, &sweep::to_csv(&rows)?)?;
    if let (Some(path), Some(format)) = (&args.plot, picture) {
        write_atomic(path, &sweep_picture(&rows, format, path)?)?;
    }
    print!("merged {} files, {} mounting points\n{}", args.files.len(), rows.len(), best_line(&rows, ""));
    Ok(ExitCode::SUCCESS)
}
