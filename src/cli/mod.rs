//! The command-line interface: flags ([`args`]) validated into library types, then run.

pub mod args;
mod domain;
mod plan;
mod reproduce;
mod sweep;
mod track;

use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::Parser;
use freefloat::{Configuration, Mount, RobotParams};

use args::{Cli, Command, CostArg, ProblemArgs, RobotArgs, TransformArg, WindowArg};

/// Parses the command line and runs the command.
pub fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Plan(args) => plan::run(&args),
        Command::Compare(args) => plan::compare(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Domain(args) => domain::run(&args),
        Command::MountSweep(args) => sweep::run(&args),
        Command::Track(args) => track::run(&args),
    }
}

/// Exit code of an error: 2 for bad input, 3 when the problem has no certified plan.
pub fn exit_code(err: &anyhow::Error) -> u8 {
    match err.downcast_ref::<freefloat::Error>() {
        Some(e) if !e.is_bad_input() => 3,
        _ => 2,
    }
}

/// Parses a comma-separated list of `N` finite numbers, naming the flag on error.
pub fn parse_list<const N: usize>(flag: &str, text: &str) -> anyhow::Result<[f64; N]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        bail!("{flag} takes {N} comma-separated numbers, got `{text}`");
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(parts) {
        let x: f64 = part.parse().with_context(|| format!("{flag}: `{part}` is not a number"))?;
        if !x.is_finite() {
            bail!("{flag}: `{part}` is not a finite number");
        }
        *slot = x;
    }
    Ok(out)
}

/// The robot of `--preset`/`--robot`, with `--mount` applied.
pub fn robot(args: &RobotArgs) -> anyhow::Result<RobotParams> {
    let robot = match &args.robot {
        Some(path) => RobotParams::load(path)?,
        None => RobotParams::src(),
    };
    Ok(match &args.mount {
        Some(text) => {
            let [a, b] = parse_list::<2>("--mount", text)?;
            robot.with_mount(Mount::new(a, b)?)?
        }
        None => robot,
    })
}

/// The planning problem of the flags.
pub fn problem(args: &ProblemArgs) -> anyhow::Result<freefloat::PlanningProblem> {
    let robot = robot(&args.robot)?;
    let [p0, a0, b0] = parse_list::<3>("--from", &args.ends.from)?;
    let [p1, a1, b1] = parse_list::<3>("--to", &args.ends.to)?;
    Ok(freefloat::PlanningProblem::new(
        robot,
        Configuration::from_degrees(p0, a0, b0),
        Configuration::from_degrees(p1, a1, b1),
        args.ends.time,
    )?)
}

/// The NFA options of the flags.
pub fn nfa_options(args: &ProblemArgs) -> freefloat::NfaOptions {
    use freefloat::Transform;
    freefloat::NfaOptions {
        transform: match args.transform {
            TransformArg::Auto => None,
            TransformArg::Eq11 => Some(Transform::Eq11),
            TransformArg::Eq12 => Some(Transform::Eq12),
            TransformArg::Eq14 => Some(Transform::Eq14),
            TransformArg::Global => Some(Transform::Global),
        },
        samples: args.samples,
        accelerations: true,
        tolerance: args.tolerance,
        ..Default::default()
    }
}

/// The optimal planner's options of the flags.
pub fn optimal_options(args: &ProblemArgs) -> anyhow::Result<freefloat::planners::optimal::OptimalOptions> {
    use freefloat::planners::optimal::{Cost, OptimalOptions};
    let [v1, v2] = parse_list::<2>("--from-velocity", &args.from_velocity)?;
    Ok(OptimalOptions {
        cost: match args.cost {
            CostArg::Effort => Cost::Effort,
            CostArg::Energy => Cost::Energy,
        },
        smooth_ends: args.smooth_ends,
        initial_velocity: [v1.to_radians(), v2.to_radians()],
        wrap: !args.no_wrap,
        samples: args.samples,
        tolerance: args.tolerance,
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
    let options = EcsaOptions { samples: args.samples, tolerance: args.tolerance, ..Default::default() }
        .with_window(window)
        .with_harmonics(args.harmonics)?;
    Ok(options)
}
