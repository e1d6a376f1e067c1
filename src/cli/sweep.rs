//! `freefloat mount-sweep`: the domain of Eq. (14) and the NFA's success rate over a grid of
//! mounting points, shardable for batch schedulers, and `mount-sweep merge`.

use freefloat::model::InputError;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Subcommand};
use freefloat::Configuration;
use freefloat::analysis::sweep::{self, Shard, Span, SweepOptions, SweepRow};
use freefloat::report::io::write_atomic;
use freefloat::report::plot::{PictureFormat, sweep_picture};

use super::args::RobotArgs;

/// Flags of `freefloat mount-sweep`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub command: Option<SweepCommand>,
    #[command(flatten)]
    pub run: SweepRunArgs,
}

#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// Merge the CSV files of the shards of one sweep into the whole.
    Merge(MergeArgs),
}

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' CSV files.
    #[arg(required = true, value_name = "FILES")]
    pub files: Vec<PathBuf>,
    /// The merged CSV file.
    #[arg(long, value_name = "FILE.csv")]
    pub out: PathBuf,
    /// Also draw the heat maps to FILE (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct SweepRunArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Range of a, MIN,MAX in m.
    #[arg(long = "a", value_name = "MIN,MAX", default_value = "-0.3,0.3", allow_hyphen_values = true)]
    pub a_range: String,
    /// Range of b, MIN,MAX in m.
    #[arg(long = "b", value_name = "MIN,MAX", default_value = "-0.3,0.3", allow_hyphen_values = true)]
    pub b_range: String,
    /// Number of values of a and of b (both ends included): NA or NA,NB.
    #[arg(long, value_name = "NA[,NB]", default_value = "41")]
    pub steps: String,
    /// Grid size of each domain map.
    #[arg(long, value_name = "N", default_value_t = 256)]
    pub grid: usize,
    /// Random start/goal pairs per mounting point.
    #[arg(long, value_name = "K", default_value_t = 100)]
    pub trials: usize,
    /// Seed of the random pairs (the same pairs at every mounting point).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// NFA samples per plan (the verification is exact at any sample count).
    #[arg(long, value_name = "N", default_value_t = 201)]
    pub samples: usize,
    /// Horizon T in s of every plan.
    #[arg(long, value_name = "T", default_value_t = 10.0)]
    pub time: f64,
    /// Start configuration whose component is measured, PHI,TH1,TH2 [deg].
    #[arg(long, value_name = "PHI,TH1,TH2", default_value = "45,120,80", allow_hyphen_values = true)]
    pub from: String,
    /// Goal checked for connection with --from, PHI,TH1,TH2 [deg].
    #[arg(long, value_name = "PHI,TH1,TH2", default_value = "0,180,140", allow_hyphen_values = true)]
    pub to: String,
    /// Run only part K of N (K from 1): every N-th point from the K-th.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Write the CSV to FILE (default: stdout).
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Also draw the heat maps to FILE (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Also rate the global normal form (beyond the paper; its band-steered plans cost
    /// milliseconds more each: use fewer points or trials).
    #[arg(long)]
    pub global: bool,
}

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
    let [p0, s1, s2] = super::parse_list::<3>("--from", &args.from)?;
    let [p1, g1, g2] = super::parse_list::<3>("--to", &args.to)?;
    if !(args.time.is_finite() && args.time > 0.0) {
        anyhow::bail!("--time must be a positive number of seconds");
    }
    Ok(SweepOptions {
        a: Span::new("--a", a0, a1, single(a0, a1, na))?,
        b: Span::new("--b", b0, b1, single(b0, b1, nb))?,
        grid: args.grid,
        trials: args.trials,
        seed: args.seed,
        samples: args.samples,
        horizon: args.time,
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
    let bytes = std::fs::read(path)
        .map_err(|source| freefloat::Error::from(InputError::Io { path: path.to_path_buf(), source }))?;
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
