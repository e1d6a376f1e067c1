//! Raw command-line flags (clap), before validation.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Motion planning of free-floating space robots with the Normal Form Approach, verified.
#[derive(Debug, Parser)]
#[command(name = "freefloat", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Plan a motion from --from to --to in --time seconds, verify it, report.
    Plan(PlanArgs),
    /// Run NFA and ECSA on the same problem, side by side.
    Compare(CompareArgs),
    /// Regenerate the paper's results (Sec. 5) on the built-in defaults.
    Reproduce(ReproduceArgs),
    /// Map the domain of existence of a feedback transformation on the joint torus (Figs. 13-14).
    Domain(super::domain::DomainArgs),
    /// Sweep mounting points (a, b): domain of Eq. (14) and NFA success rate; shardable.
    MountSweep(super::sweep::SweepArgs),
}

/// The robot: a preset or a TOML file, and the mounting point.
#[derive(Debug, Args, Clone)]
pub struct RobotArgs {
    /// Built-in robot (the paper's SRC manipulator).
    #[arg(long, value_enum, default_value_t = Preset::Src, conflicts_with = "robot")]
    pub preset: Preset,
    /// Robot file (TOML, SPEC §1); its [mount] is overridden by --mount.
    #[arg(long, value_name = "FILE")]
    pub robot: Option<PathBuf>,
    /// Mounting point of the arm in the base frame, A,B in m (default: the file's, else 0,0).
    #[arg(long, value_name = "A,B", allow_hyphen_values = true)]
    pub mount: Option<String>,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Preset {
    /// The SRC space manipulator of the paper.
    Src,
}

/// The planning problem and the method.
#[derive(Debug, Args, Clone)]
pub struct ProblemArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Start configuration PHI,TH1,TH2 in deg.
    #[arg(long, value_name = "PHI,TH1,TH2", default_value = "45,120,80", allow_hyphen_values = true)]
    pub from: String,
    /// Goal configuration PHI,TH1,TH2 in deg, taken literally (not modulo 360).
    #[arg(long, value_name = "PHI,TH1,TH2", default_value = "0,180,140", allow_hyphen_values = true)]
    pub to: String,
    /// Horizon T in s.
    #[arg(long, value_name = "T", default_value_t = 10.0)]
    pub time: f64,
    /// Feedback transformation of the NFA.
    #[arg(long, value_enum, default_value_t = TransformArg::Auto)]
    pub transform: TransformArg,
    /// Number of samples of the trajectory (both ends included).
    #[arg(long, value_name = "N", default_value_t = 1001)]
    pub samples: usize,
    /// Also compute joint torques by inverse dynamics (Eq. 6) and certify them.
    #[arg(long)]
    pub torques: bool,
    /// Largest verified final error of a certified velocity plan in rad.
    #[arg(long, value_name = "RAD", default_value_t = 1e-9)]
    pub tolerance: f64,
    /// Cap on the peak joint velocity |u| in rad/s: a plan that exceeds it is planned again with
    /// the horizon stretched (velocities scale as 1/T along the same path); the report's `time`
    /// says which horizon was used.
    #[arg(long, value_name = "RAD_PER_S")]
    pub max_velocity: Option<f64>,
    /// ECSA: number of harmonics of the trigonometric controls, 1 to 4 (the paper: 1).
    #[arg(long, value_name = "H", default_value_t = 1)]
    pub harmonics: usize,
    /// ECSA: window of the controls.
    #[arg(long, value_enum, default_value_t = WindowArg::None)]
    pub window: WindowArg,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum WindowArg {
    /// The plain series, as in the paper: joint velocities jump at t = 0 and t = T.
    None,
    /// The series times sin^2(pi t / T): the plan starts and ends at rest.
    Sin2,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TransformArg {
    /// eq12 when a = b = 0, else eq14.
    Auto,
    /// Eq. (11), a = b = 0 only.
    Eq11,
    /// Eq. (12), a = b = 0 only.
    Eq12,
    /// Eq. (14), any mounting point.
    Eq14,
    /// The global normal form (beyond the paper): any mounting point, singular only at sigma = 0.
    Global,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Normal Form Approach.
    Nfa,
    /// Endogenous Configuration Space Approach.
    Ecsa,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// A human-readable table.
    Table,
    /// One JSON object.
    Json,
    /// The trajectory, one row per sample.
    Csv,
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Planning method.
    #[arg(long, value_enum, default_value_t = MethodArg::Nfa)]
    pub method: MethodArg,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Also write the result to FILE: .json (report with trajectory) or .csv (trajectory).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Output format on stdout (table or json).
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,
}
