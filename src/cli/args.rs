//! Every command-line flag (clap), before validation: the one place that declares them.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Motion planning of free-floating space robots: minimum-effort plans (the default), the Normal
/// Form Approach and the ECSA, every plan verified.
#[derive(Debug, Parser)]
#[command(name = "freefloat", version, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// Print no notes, progress or summaries on stderr (errors are still printed).
    #[arg(long, short, global = true)]
    pub quiet: bool,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Plan a motion from --from to --to in --time seconds, verify it, report.
    Plan(PlanArgs),
    /// Run the optimal planner, the NFA and the ECSA on the same problem, side by side.
    Compare(CompareArgs),
    /// Regenerate the paper's results (Sec. 5) on the built-in defaults.
    Reproduce(super::reproduce::ReproduceArgs),
    /// Map the domain of existence of a feedback transformation on the joint torus (Figs. 13-14).
    Domain(DomainArgs),
    /// Sweep mounting points (a, b): domain of Eq. (14) and NFA success rate; shardable.
    MountSweep(SweepArgs),
    /// Track a plan in closed loop on a robot that is not the model (one run, or Monte Carlo).
    Track(TrackArgs),
    /// Check a joint trajectory from any tool (ROS 2 JointTrajectory YAML/JSON, or a plan CSV)
    /// on the free-floating robot: the base's attitude and position, the goal, the torques.
    Check(CheckArgs),
    /// Print what was read from a robot file: masses, lengths, centres of mass, inertias, the
    /// mount, the tool point, the joint names (docs/your-robot.md).
    Robot(RobotInfoArgs),
    /// Print a shell completion script (e.g. `freefloat completions bash > /etc/bash_completion.d/freefloat`).
    Completions(CompletionsArgs),
    /// Print the man page (roff; e.g. `freefloat man > freefloat.1`).
    Man,
}

/// Flags of `freefloat robot`.
#[derive(Debug, Args)]
pub struct RobotInfoArgs {
    /// The robot file: TOML, or URDF for a name ending in .urdf (or give --robot, --urdf).
    #[arg(value_name = "FILE", conflicts_with_all = ["robot", "urdf"])]
    pub file: Option<PathBuf>,
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = DomainFormat::Table)]
    pub format: DomainFormat,
}

/// Flags of `freefloat completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The robot: a preset or a TOML file, and the mounting point.
#[derive(Debug, Args, Clone)]
pub struct RobotArgs {
    /// Built-in robot (the paper's SRC manipulator).
    #[arg(long, value_enum, default_value_t = Preset::Src, conflicts_with_all = ["robot", "urdf"])]
    pub preset: Preset,
    /// Robot file (TOML, docs/spec.md §1: the 2-link keys, or [[link]] for any planar serial
    /// arm; a name ending in .urdf is read as URDF); its [mount] is overridden by --mount.
    #[arg(long, value_name = "FILE", conflicts_with = "urdf")]
    pub robot: Option<PathBuf>,
    /// Robot as a URDF file: a planar chain of revolute joints about z (docs/spec.md §1).
    #[arg(long, value_name = "FILE")]
    pub urdf: Option<PathBuf>,
    /// Mounting point of the arm in the base frame, A,B in m (default: the file's, else 0,0).
    #[arg(long, value_name = "A,B", allow_hyphen_values = true)]
    pub mount: Option<String>,
    #[command(flatten)]
    pub limits: super::limits::LimitArgs,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Preset {
    /// The SRC space manipulator of the paper.
    Src,
}

/// Start, goal and horizon of a planning problem (the paper's by default).
#[derive(Debug, Args, Clone)]
pub struct EndsArgs {
    /// Start configuration PHI,TH1,..,THn in deg: the base angle and the n joint angles of an
    /// n-link arm (n + 1 values; the default is the paper's 2-link problem).
    #[arg(long, value_name = "PHI,TH1,..,THn", default_value = "45,120,80", allow_hyphen_values = true)]
    pub from: String,
    /// Goal configuration PHI,TH1,..,THn in deg (n + 1 values): the optimal planner counts its
    /// angles modulo 360 (unless --no-wrap; a joint with a position range only to representatives
    /// inside it), the NFA and the ECSA take them literally.
    #[arg(long, value_name = "PHI,TH1,..,THn", default_value = "0,180,140", allow_hyphen_values = true)]
    pub to: String,
    /// Horizon T in s, from 1e-3 to 1e6; `plan` and `compare` of an arm with velocity,
    /// acceleration or torque limits (or `--max-velocity`) also take `auto`: the shortest horizon
    /// (to 1 %) in which the motion fits every limit, and the minimum-effort plan at it.
    #[arg(long, value_name = "T", default_value = "10", value_parser = super::config::parse_time, allow_hyphen_values = true)]
    pub time: f64,
}

/// The planning problem and the method.
#[derive(Debug, Args, Clone)]
pub struct ProblemArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    #[command(flatten)]
    pub ends: EndsArgs,
    /// Goal as an end-effector pose X,Y,PSI (m, m, deg; inertial frame, the system's centre of
    /// mass at the origin) instead of --to: solved by the free-floating inverse kinematics (both
    /// elbows planned, the certified plan of least effort kept, unless --elbow).
    #[arg(long, value_name = "X,Y,PSI", allow_hyphen_values = true, conflicts_with = "to")]
    pub to_ee: Option<String>,
    /// With --to-ee: the inverse-kinematics solution, by the sign of sin(theta1 - atan2(b, a)).
    #[arg(long, value_enum, requires = "to_ee")]
    pub elbow: Option<ElbowArg>,
    /// Feedback transformation of the NFA.
    #[arg(long, value_enum, default_value_t = TransformArg::Auto)]
    pub transform: TransformArg,
    /// Number of samples of the trajectory (both ends included), 2 to 1048576.
    #[arg(long, value_name = "N", default_value_t = 1001, allow_hyphen_values = true)]
    pub samples: u64,
    /// Also compute joint torques by inverse dynamics (Eq. 6) and certify them.
    #[arg(long)]
    pub torques: bool,
    /// Largest verified final error of a certified velocity plan in rad, positive, at most 1e-3.
    #[arg(long, value_name = "RAD", default_value = "1e-9", allow_hyphen_values = true)]
    pub tolerance: f64,
    /// Cap on the peak joint velocity |u| in rad/s, 1e-3 to 1000: a plan that exceeds it is planned
    /// again with the horizon stretched (velocities scale as 1/T); the report's `time` is the one used.
    #[arg(long, value_name = "RAD_PER_S", allow_hyphen_values = true)]
    pub max_velocity: Option<f64>,
    /// Optimal: joint velocities at t = 0, DTH1,..,DTHn in deg/s, one per joint (re-planning; the
    /// verification starts there).
    #[arg(long, value_name = "DTH1,..,DTHn", default_value = "0,0", allow_hyphen_values = true)]
    pub from_velocity: String,
    /// Optimal: also zero joint accelerations at both ends (quintic splines), so that the
    /// torques start and end at zero.
    #[arg(long)]
    pub smooth_ends: bool,
    /// Optimal: the cost minimised.
    #[arg(long, value_enum, default_value_t = CostArg::Effort)]
    pub cost: CostArg,
    /// Optimal: take the goal's angles literally (by default phi and the joint angles count
    /// modulo 360 deg: the nearby representatives are tried and the best certified plan kept).
    #[arg(long)]
    pub no_wrap: bool,
    /// ECSA: number of harmonics of the trigonometric controls, 1 to 4 (the paper: 1).
    #[arg(long, value_name = "H", default_value_t = 1, allow_hyphen_values = true)]
    pub harmonics: usize,
    /// ECSA: window of the controls.
    #[arg(long, value_enum, default_value_t = WindowArg::None)]
    pub window: WindowArg,
    #[command(flatten)]
    pub geometry: super::geometry::GeometryArgs,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum WindowArg {
    /// The plain series, as in the paper: joint velocities jump at t = 0 and t = T.
    None,
    /// The series times sin^2(pi t / T): the plan starts and ends at rest.
    Sin2,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ElbowArg {
    /// sin(theta1 - atan2(b, a)) >= 0.
    Up,
    /// sin(theta1 - atan2(b, a)) < 0.
    Down,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CostArg {
    /// The control effort, integral of |theta'|^2 dt.
    Effort,
    /// The robot's kinetic energy integrated over time (the natural metric of Eq. 3).
    Energy,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TransformArg {
    /// eq12 when a = b = 0, else eq14; the global form when their path does not exist.
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
    /// Minimum-effort steering of the joint path under the base's holonomy constraint (plans
    /// across sigma = 0; warm-started by the NFA).
    Optimal,
    /// Normal Form Approach (the paper).
    Nfa,
    /// Endogenous Configuration Space Approach (the paper's reference method).
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
    /// The joints' trajectory as a ROS 2 trajectory_msgs/JointTrajectory message (YAML).
    JointTrajectory,
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Planning method [default: optimal, or nfa when --transform names a transformation].
    #[arg(long, value_enum)]
    pub method: Option<MethodArg>,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Also write the result to FILE: .json (report with trajectory; with --format
    /// joint-trajectory the message), .csv (trajectory), .yaml/.yml (the JointTrajectory message).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Also write the base's trajectory, the companion of the JointTrajectory, to FILE.yaml|.json:
    /// a ROS 2 MultiDOFJointTrajectory (base position and attitude phi about z).
    #[arg(long, value_name = "FILE")]
    pub base_out: Option<PathBuf>,
    /// Also write an animated GIF of the motion to FILE.gif: the robot (any arm) as the report
    /// page draws it, the horizon played in 5 to 8 s (T clamped to that range), looping.
    #[arg(long, value_name = "FILE.gif")]
    pub gif: Option<PathBuf>,
    /// Also draw an arm's plan (--robot/--urdf) to FILE (.svg or .png), its limits dashed.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub gif_options: GifArgs,
}

/// Size and frame rate of `--gif` animations.
#[derive(Debug, Args, Clone)]
pub struct GifArgs {
    /// Width of the GIF in pixels, 240 to 1920.
    #[arg(long, value_name = "PX", default_value_t = 480, requires = "gif")]
    pub gif_width: u64,
    /// Height of the GIF in pixels, 240 to 1920.
    #[arg(long, value_name = "PX", default_value_t = 480, requires = "gif")]
    pub gif_height: u64,
    /// Frames per second of the GIF, 1 to 50.
    #[arg(long, value_name = "FPS", default_value_t = 25, requires = "gif")]
    pub gif_fps: u64,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub problem: ProblemArgs,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = CompareFormat::Table)]
    pub format: CompareFormat,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CompareFormat {
    /// A human-readable table.
    Table,
    /// One JSON object.
    Json,
}

/// Flags of `freefloat domain`.
#[derive(Debug, Args)]
pub struct DomainArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Feedback transformation whose domain is mapped.
    #[arg(long, value_enum, default_value_t = TransformArg::Auto)]
    pub transform: TransformArg,
    /// The map has GRID x GRID cells on the (theta1, theta2) torus, 3 to 8192.
    #[arg(long, value_name = "N", default_value_t = 720, allow_hyphen_values = true)]
    pub grid: usize,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = DomainFormat::Table)]
    pub format: DomainFormat,
    /// Also draw the map to FILE (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Start and goal of the NFA plan drawn on the map.
    #[command(flatten)]
    pub ends: EndsArgs,
    /// Samples of that plan, 2 to 1048576.
    #[arg(long, value_name = "N", default_value_t = 1001, allow_hyphen_values = true)]
    pub samples: u64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DomainFormat {
    /// A human-readable table.
    Table,
    /// One JSON object.
    Json,
}

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
    /// Number of values of a and of b (both ends included): NA or NA,NB, each 1 to 100000.
    #[arg(long, value_name = "NA[,NB]", default_value = "41", allow_hyphen_values = true)]
    pub steps: String,
    /// Grid size of each domain map, 3 to 8192 [default: 256] (the NFA's metric: 2-link arms).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub grid: Option<usize>,
    /// Random start/goal pairs per mounting point [default: 100] (the NFA's metric).
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub trials: Option<usize>,
    /// Seed of the random pairs, the same at every mounting point [default: 0] (NFA metric).
    #[arg(long, allow_hyphen_values = true)]
    pub seed: Option<u64>,
    /// NFA samples per plan, 2 to 1048576 (its verification is exact at any count) [default: 201].
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub samples: Option<u64>,
    /// The start whose component is measured, the goal checked for connection with it, and the
    /// horizon of every plan.
    #[command(flatten)]
    pub ends: EndsArgs,
    /// Run only part K of N (K from 1): every N-th point from the K-th. The file's first line
    /// names the run and the shard, for `merge` to check.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
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
    /// Also record the effort of the minimum-effort plan --from -> --to (for other arms than 2-link: always).
    #[arg(long)]
    pub effort: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ControllerArg {
    /// The planned torques alone.
    Open,
    /// Computed torque with PD on the joint angles around the plan.
    Ct,
    /// ct plus re-planning on the nominal model from the measured state.
    Replan,
    /// replan on a model whose momentum map is identified on line.
    Adaptive,
}

/// Flags of `freefloat track`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct TrackArgs {
    #[command(subcommand)]
    pub command: Option<TrackCommand>,
    /// The nominal robot (the planning model).
    #[command(flatten)]
    pub robot: RobotArgs,
    #[command(flatten)]
    pub ends: EndsArgs,
    #[command(flatten)]
    pub geometry: super::geometry::GeometryArgs,
    /// Controllers, comma-separated; several run side by side on the same robot and noise.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "adaptive")]
    pub controller: Vec<ControllerArg>,
    /// The true robot (TOML or URDF, docs/spec.md §1; the model's links) [default: the nominal
    /// robot, or --perturb].
    #[arg(long, value_name = "FILE", conflicts_with = "perturb")]
    pub true_robot: Option<PathBuf>,
    /// Perturb each mass, inertia, length and CoM distance by up to this fraction (seeded).
    #[arg(long, value_name = "P", default_value_t = 0.0, allow_hyphen_values = true)]
    pub perturb: f64,
    /// Move the mounting point by up to this many metres in a and in b (seeded).
    #[arg(long, value_name = "M", default_value_t = 0.0, allow_hyphen_values = true)]
    pub perturb_mount: f64,
    /// Seed of the true robot and of the noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Relative torque noise (standard deviation).
    #[arg(long, value_name = "REL", default_value_t = 0.0, allow_hyphen_values = true)]
    pub torque_noise: f64,
    /// Torque bias TAU1,..,TAUn in N m, one per joint [default: none].
    #[arg(long, value_name = "TAU1,..,TAUn", allow_hyphen_values = true)]
    pub torque_bias: Option<String>,
    /// Torque limit in N m for every joint (saturation; the robot's declared limits still apply) [default: none].
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    pub torque_limit: Option<f64>,
    /// Measurement noise on each angle, standard deviation in rad.
    #[arg(long, value_name = "RAD", default_value_t = 0.0, allow_hyphen_values = true)]
    pub noise_q: f64,
    /// Measurement noise on each velocity, standard deviation in rad/s.
    #[arg(long, value_name = "RAD_PER_S", default_value_t = 0.0, allow_hyphen_values = true)]
    pub noise_dq: f64,
    /// Control rate in Hz (zero-order hold).
    #[arg(long, value_name = "HZ", default_value_t = 1000.0, allow_hyphen_values = true)]
    pub rate: f64,
    /// Follow the plan's own feedforward: no correction for the zero-order hold on the nominal model
    /// (docs/spec.md §5).
    #[arg(long)]
    pub no_hold_correction: bool,
    /// Re-planning rate in Hz.
    #[arg(long, value_name = "HZ", default_value_t = 5.0, allow_hyphen_values = true)]
    pub replan_rate: f64,
    /// No re-plan starts in the last S seconds; the last one, the final correction, starts S seconds before the end.
    #[arg(long, value_name = "S", default_value_t = 0.25, allow_hyphen_values = true)]
    pub final_window: f64,
    /// Clearance in m that the plan and every re-plan keep beyond --clearance; a run fails only under --clearance [default: 0.02; above 0, refused for a robot without shapes or obstacles].
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub margin: Option<f64>,
    /// Fraction of every limit that the plan and every re-plan leave as headroom: velocity, acceleration, torque limits times 1 - F, ranges shrunk to 1 - F of their width about their centre; a run fails only outside the limits [default: 0.05; above 0, refused for a robot without limits].
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub limit_margin: Option<f64>,
    /// Joint-loop gains in 1/s^2 and 1/s [default: critically damped at min(200, rate/5) rad/s].
    #[arg(long, allow_hyphen_values = true)]
    pub kp: Option<f64>,
    /// Derivative gain (see --kp).
    #[arg(long, allow_hyphen_values = true)]
    pub kd: Option<f64>,
    /// Forgetting time of the identification in s.
    #[arg(long, value_name = "S", default_value_t = 5.0, allow_hyphen_values = true)]
    pub forgetting: f64,
    /// Monte Carlo: run N seeded trials in parallel and print success rates.
    #[arg(long, value_name = "N")]
    pub trials: Option<usize>,
    /// With --trials and --out: run only part K of N (K from 1), the trials i with
    /// i mod N = K - 1. The file's first line names the run and the shard, for `merge` to check.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = DomainFormat::Table)]
    pub format: DomainFormat,
    /// Write reference vs actual (and torques) to FILE.csv (single run, first controller); with
    /// --trials, one checked row per trial and controller.
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// Draw reference vs actual angles, torques and errors of every controller to FILE (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum TrackCommand {
    /// Merge the trial files of the shards of one Monte Carlo run and print its success rates.
    Merge(TrackMergeArgs),
}

#[derive(Debug, Args)]
pub struct TrackMergeArgs {
    /// The shards' CSV files (`track --trials N --shard K/N --out FILE.csv`).
    #[arg(required = true, value_name = "FILES")]
    pub files: Vec<PathBuf>,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = DomainFormat::Table)]
    pub format: DomainFormat,
    /// Also write the merged CSV file (equal to the unsharded run's).
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
}

/// Flags of `freefloat check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// The trajectory: a ROS 2 JointTrajectory (.yaml/.yml/.json; joints matched by name: the
    /// URDF's, else joint1..jointN) or freefloat's plan CSV (.csv).
    #[arg(long, value_name = "FILE")]
    pub trajectory: PathBuf,
    /// The base's start attitude PHI in deg (default: the CSV's phi, else 0), or the whole start
    /// PHI,TH1,..,THn, whose joints must be the trajectory's first point.
    #[arg(long, value_name = "PHI[,TH1,..]", allow_hyphen_values = true)]
    pub from: Option<String>,
    /// Goal PHI,TH1,..,THn in deg (angles modulo 360): exit 3 when it is missed.
    #[arg(long, value_name = "PHI,TH1,..", allow_hyphen_values = true)]
    pub to: Option<String>,
    /// Largest final error against --to in rad, positive, at most 1e-3.
    #[arg(long, value_name = "RAD", default_value = "1e-9", allow_hyphen_values = true)]
    pub tolerance: f64,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = DomainFormat::Table)]
    pub format: DomainFormat,
    /// Also write to FILE: .json (the report) or .csv (t, phi, xb, yb, the joints, one row per
    /// point).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub geometry: super::geometry::GeometryArgs,
}
