//! The command-line interface: flags ([`args`]) validated into library types, then run.

pub mod args;
mod check;
mod compare;
pub mod config;
mod domain;
mod geometry;
mod limits;
mod output;
mod plan;
mod reproduce;
mod robot;
mod ros;
mod sweep;
mod track;

use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::Parser;
use freefloat::model::arm::Arm;
use freefloat::{Configuration, Mount, RobotParams};

use args::{Cli, Command, CostArg, ProblemArgs, RobotArgs, TransformArg, WindowArg};

pub use output::{ClosedPipe, emit, note, report_error};

/// Runs the command line `args` (the program's name first) as the `freefloat` binary does and
/// returns its exit code: 0 success (or a closed stdout), 2 bad input, 3 no certified plan; an
/// error is printed on stderr with its cause chain. Usage errors, `--help` and `--version` are
/// clap's: printed, then the process exits (code 2, resp. 0).
pub fn main_from<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    match run(Cli::parse_from(args)) {
        Ok(code) => (0..=u8::MAX).find(|&c| ExitCode::from(c) == code).unwrap_or(1),
        Err(err) if err.downcast_ref::<ClosedPipe>().is_some() => 0,
        Err(err) => {
            report_error(&format!("error: {err:#}\n"));
            exit_code(&err)
        }
    }
}

/// Runs the parsed command. With `--format json`, a failure also prints one JSON error object on
/// stdout (docs/spec.md §3).
pub fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    output::set_quiet(cli.quiet);
    output::install_signal_handler();
    let json = match &cli.command {
        Command::Plan(a) => a.format == args::Format::Json,
        Command::Compare(a) => a.format == args::CompareFormat::Json,
        Command::Domain(a) => a.format == args::DomainFormat::Json,
        Command::Check(a) => a.format == args::DomainFormat::Json,
        Command::Robot(a) => a.format == args::DomainFormat::Json,
        _ => false,
    };
    let result = match cli.command {
        Command::Plan(args) => plan::run(&args),
        Command::Compare(args) => compare::compare(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Domain(args) => domain::run(&args),
        Command::MountSweep(args) => sweep::run(&args),
        Command::Track(args) => track::run(&args),
        Command::Check(args) => check::run(&args),
        Command::Robot(args) => robot::run(&args),
        Command::Completions(args) => output::completions(args.shell),
        Command::Man => output::man(),
    };
    match result {
        Err(err) if json && !output::wrote_stdout() && err.downcast_ref::<ClosedPipe>().is_none() => {
            // The script reading stdout gets the error as its one JSON object (a report already
            // printed, e.g. `"certified": false`, is that object); a closed stdout is no news.
            let _ignored_closed_pipe = emit(&format!("{}\n", output::error_json(&err)));
            Err(err)
        }
        result => result,
    }
}

/// Exit code of an error: 0 for a closed stdout (the reader has what it wanted, as with Unix
/// tools), 2 for bad input, 3 when the problem has no certified plan.
pub fn exit_code(err: &anyhow::Error) -> u8 {
    if err.downcast_ref::<ClosedPipe>().is_some() {
        return 0;
    }
    match err.downcast_ref::<freefloat::Error>() {
        Some(e) if !e.is_bad_input() => 3,
        _ => 2,
    }
}

/// Parses a comma-separated list of `N` finite numbers, naming the flag on error.
pub fn parse_list<const N: usize>(flag: &str, text: &str) -> anyhow::Result<[f64; N]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        bail!("{flag} takes {N} comma-separated numbers, got `{}`", config::quote(text));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(parts) {
        let x: f64 = part.parse().with_context(|| format!("{flag}: `{}` is not a number", config::quote(part)))?;
        if !x.is_finite() {
            bail!("{flag}: `{}` is not a finite number", config::quote(part));
        }
        *slot = x;
    }
    Ok(out)
}

/// Parses a comma-separated list of finite numbers (at most 64), naming the flag on error.
pub fn parse_numbers(flag: &str, text: &str) -> anyhow::Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() > 64 {
        bail!("{flag} takes at most 64 numbers, got {}", parts.len());
    }
    parts
        .iter()
        .map(|part| {
            let x: f64 =
                part.parse().map_err(|_| anyhow::anyhow!("{flag}: `{}` is not a number", config::quote(part)))?;
            if !x.is_finite() {
                bail!("{flag}: `{}` is not a finite number", config::quote(part));
            }
            Ok(x)
        })
        .collect()
}

/// What `--preset`/`--robot`/`--urdf` name: a 2-link arm (the paper's model, link inertias
/// included; see [`robot()`]), or any other planar serial arm.
#[allow(clippy::large_enum_variant, reason = "one value per command, moved once")]
pub enum Robot {
    /// The paper's 2-link model: two links, no limits, no shapes of its own.
    TwoLink,
    /// Any other arm (docs/spec.md §1), and a 2-link one with limits or shapes: the arm
    /// pipeline, where the planners honour them (the NFA's 2-link plan checked against them).
    Arm(Arm),
}

/// The robot of the flags (see [`Robot`]).
pub fn any_robot(args: &RobotArgs) -> anyhow::Result<Robot> {
    // Issue 20: a 2-link arm with declared limits (file or --limit) is planned as any arm.
    let arm = match robot_file(args)? {
        Some(path) => Arm::load(path)?,
        None if args.limits.limit.is_empty() => return Ok(Robot::TwoLink),
        None => Arm::from_params(&RobotParams::src()),
    };
    let arm = limits::with_flags(arm, &args.limits)?;
    // Issue 21 likewise: a 2-link arm with shapes, so that the minimum-effort planner keeps its
    // clearance (the 2-link pipeline's parameters carry no geometry: it only checks it), as
    // Python's `plan` does for a `constrained` arm.
    if arm.as_src().is_some() && arm.limits.is_empty() && arm.geometry.is_empty() {
        return Ok(Robot::TwoLink);
    }
    let mount = match &args.mount {
        Some(text) => {
            let [a, b] = parse_list::<2>("--mount", text)?;
            Mount::new(a, b)?
        }
        None => arm.mount,
    };
    Ok(Robot::Arm(Arm::new(arm.base, mount, arm.links)?.with_limits(arm.limits)?.with_geometry(arm.geometry)?))
}

/// The file of `--robot` or `--urdf`; `--urdf` with a name that does not end in `.urdf` is bad
/// input (the file would be read by its name's kind, TOML, not as the flag says).
pub fn robot_file(args: &RobotArgs) -> anyhow::Result<Option<&std::path::PathBuf>> {
    if let Some(path) = &args.urdf
        && !path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
    {
        return Err(freefloat::Error::from(freefloat::model::InputError::InvalidText {
            name: "--urdf".into(),
            text: path.display().to_string(),
            expected: "a URDF file whose name ends in .urdf (for a TOML robot file use --robot)",
        })
        .into());
    }
    Ok(args.urdf.as_ref().or(args.robot.as_ref()))
}

/// The 2-link robot of `--preset`/`--robot`/`--urdf`, with `--mount` applied; an arm of another
/// number of links is bad input here (only `plan` serves it).
pub fn robot(args: &RobotArgs) -> anyhow::Result<RobotParams> {
    let robot = match robot_file(args)? {
        Some(path) => {
            let arm = Arm::load(path)?;
            match arm.as_src() {
                Some(robot) => robot,
                // A valid 2-link arm is the paper's model unless a centre of mass sits on its joint.
                None if arm.joints() == 2 => bail!(
                    "{}: link[{}].com = 0: this command's 2-link model (the paper's d1, d2) needs the centre of mass \
                     of each link off its joint, 0 < com <= length (docs/spec.md §1); `freefloat plan` plans this \
                     arm as a general serial arm",
                    path.display(),
                    arm.links.iter().position(|l| l.com <= 0.0).map_or(1, |k| k + 1)
                ),
                None => bail!(
                    "{}: an arm of {} link(s); this command needs the paper's 2-link model (its normal form, Eq. 10, is for two joints; docs/spec.md §1); `freefloat plan`, `compare`, `track` and `mount-sweep` serve any planar serial arm",
                    path.display(),
                    arm.joints()
                ),
            }
        }
        None => RobotParams::src(),
    };
    Ok(match &args.mount {
        Some(text) => {
            let [a, b] = parse_list::<2>("--mount", text)?;
            if let Some(x) = [a, b].into_iter().find(|x| x.abs() > freefloat::model::MAX_MOUNT) {
                return Err(freefloat::Error::from(freefloat::model::InputError::InvalidParameter {
                    name: "--mount".into(),
                    value: x,
                    expected: "a mounting point with |a|, |b| <= 1e3 m (docs/spec.md §1)",
                })
                .into());
            }
            robot.with_mount(Mount::new(a, b)?)?
        }
        None => robot,
    })
}

/// The planning problem of the flags.
pub fn problem(args: &ProblemArgs) -> anyhow::Result<freefloat::PlanningProblem> {
    let robot = robot(&args.robot)?;
    let (start, goal, time) = ends(&args.ends)?;
    let [v1, v2] = parse_list::<2>("--from-velocity", &args.from_velocity)?;
    let problem = freefloat::PlanningProblem::new(robot, start, goal, time)?;
    Ok(problem.with_start_velocity([v1.to_radians(), v2.to_radians()])?)
}

/// `--from`, `--to` and `--time`, checked.
pub fn ends(args: &args::EndsArgs) -> anyhow::Result<(Configuration, Configuration, f64)> {
    Ok((config::angles("--from", &args.from)?, config::angles("--to", &args.to)?, config::time(args.time)?))
}

/// The NFA options of the flags (samples and tolerance checked).
pub fn nfa_options(args: &ProblemArgs) -> anyhow::Result<freefloat::NfaOptions> {
    use freefloat::Transform;
    Ok(freefloat::NfaOptions {
        transform: match args.transform {
            TransformArg::Auto => None,
            TransformArg::Eq11 => Some(Transform::Eq11),
            TransformArg::Eq12 => Some(Transform::Eq12),
            TransformArg::Eq14 => Some(Transform::Eq14),
            TransformArg::Global => Some(Transform::Global),
        },
        samples: config::samples(args.samples)?,
        accelerations: true,
        tolerance: config::tolerance(args.tolerance)?,
        ..Default::default()
    })
}

/// The optimal planner's options of the flags.
pub fn optimal_options(args: &ProblemArgs) -> anyhow::Result<freefloat::planners::optimal::OptimalOptions> {
    use freefloat::planners::optimal::{Cost, OptimalOptions};
    Ok(OptimalOptions {
        cost: match args.cost {
            CostArg::Effort => Cost::Effort,
            CostArg::Energy => Cost::Energy,
        },
        smooth_ends: args.smooth_ends,
        wrap: !args.no_wrap,
        samples: config::samples(args.samples)?,
        tolerance: config::tolerance(args.tolerance)?,
        ..Default::default()
    })
}

/// The ECSA options of the flags (harmonics checked: exit 2 when out of range).
pub fn ecsa_options(args: &ProblemArgs) -> anyhow::Result<freefloat::EcsaOptions> {
    use freefloat::{EcsaOptions, Window};
    let window = match args.window {
        WindowArg::None => Window::None,
        WindowArg::Sin2 => Window::SinSquared,
    };
    let options = EcsaOptions {
        samples: config::samples(args.samples)?,
        tolerance: config::tolerance(args.tolerance)?,
        ..Default::default()
    }
    .with_window(window)
    .with_harmonics(args.harmonics)?;
    Ok(options)
}

/// Checks every output file given (`--out`, `--plot`, ...) before any work: its directory exists
/// and takes a file, and it is nothing yet or a regular file (docs/spec.md §3).
pub fn check_outputs(paths: &[Option<&std::path::PathBuf>]) -> anyhow::Result<()> {
    for path in paths.iter().flatten() {
        freefloat::report::io::check_writable(path)?;
    }
    Ok(())
}

/// The validated size and frame rate of `--gif` (bad input, exit 2, out of range).
pub fn gif_options(args: &args::GifArgs) -> anyhow::Result<freefloat::report::plot::GifOptions> {
    Ok(freefloat::report::plot::GifOptions::new(args.gif_width, args.gif_height, args.gif_fps)?)
}

/// The checked `plan --gif FILE.gif` with its options, before anything is planned (exit 2 on a
/// bad name, an unwritable place or bad options); `None` without `--gif`.
pub fn checked_gif(
    args: &args::PlanArgs,
) -> anyhow::Result<Option<(&std::path::PathBuf, freefloat::report::plot::GifOptions)>> {
    let Some(path) = &args.gif else { return Ok(None) };
    freefloat::report::plot::check_gif_path(path)?;
    freefloat::report::io::check_writable(path)?;
    Ok(Some((path, gif_options(&args.gif_options)?)))
}
