//! Issue 22's hard sets of closed-loop problems, and their Monte Carlo.
//!
//! `cargo run --release --example hard_set > tests/fixtures/hard_set.csv` writes the 2-link set:
//! 20 problems of the paper's SRC robot with large mounts and large base turns, drawn by a
//! xorshift64* generator seeded with `0x5EED_0022`. Per problem, in this order: `|a|`, `|b|`
//! uniform in `[0.8, 1.5]` m, then their signs (each `+` with probability 1/2), then start and goal
//! `(phi, theta1, theta2)` uniform in `[-pi, pi)` rad, drawn again until the base turns by at
//! least 60 deg (`|wrap(phi_goal - phi_start)| >= pi/3`); rest to rest, `T = 10 s`. A problem
//! the minimum-effort planner does not plan is drawn again (none was, when the set was made).
//!
//! `cargo run --release --example hard_set -- --write --robot FILE --set OUT [--seed S]
//! [--min-turn 60] [--own-mount] [--note TEXT]` writes a set of the same kind for any arm of a robot file (TOML
//! or URDF, [`Arm::load`]) to `OUT`: the same draws with `n + 1` angles per end, the mount drawn as
//! above or, with `--own-mount`, the file's; the header names the robot and the command (and `TEXT`, one line). Each
//! plan's effort, largest joint rate and planning time go to stderr. The sets of the repository:
//! - `tests/fixtures/hard_set_3link.csv`: `examples/robots/three_link.toml` (the SRC base, three
//!   links), random mounts, turns >= 60 deg, seed `0x5EED_0322`.
//! - `tests/fixtures/hard_set_4link.csv`: `examples/robots/four_link.toml` (SPART's numbers, a
//!   300 kg base), its own mount (0.25, 0) m, seed `0x5EED_0422`; see that file's header for
//!   the base turns it asks for and why.
//!
//! `cargo run --release --example hard_set -- --trials 100 [--set FILE] [--robot FILE]
//! [--controller adaptive] [--replan-rate 50] [--final-window 0.3] [--forgetting 5]
//! [--torque-noise 0.01] [--kp 40000] [--kd 400]
//! [--rate 1000] [--only 0,3,9] [--detail] [--worst]`
//! runs each problem of a set (default `tests/fixtures/hard_set.csv`; the robot of its
//! `# robot:` line unless `--robot` names another, else the SRC robot) through `track`'s Monte
//! Carlo with the disturbances of the measurements (5 % parameters, 1 cm mount, 1 % torque
//! noise, 1e-5 rad and 1e-5 rad/s measurement noise, 1 kHz control, seed 1) and prints, per
//! problem, the success rate (final error <= 1e-3 rad), the median and largest final error, the
//! failed re-plans per run and the CPU time of one thread per run; `--detail` adds the failed
//! runs (and of them the limit failures) and the planning time, `--worst` the errors per
//! coordinate of the trial with the largest final error (run again).
use freefloat::model::arm::Arm;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::track::{Controller, Disturbances, MonteCarloOptions, Perturbation, TrackOptions, monte_carlo};
use freefloat::{Method, Mount, RobotParams};
use std::f64::consts::PI;
use std::path::Path;

/// A deterministic xorshift64* generator (no new dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(2.0 * PI) - PI
}

/// `base` with the mount `(a, b)` \[m\].
fn arm(base: &Arm, a: f64, b: f64) -> Arm {
    Arm { mount: Mount { a, b }, ..base.clone() }
}

/// What a set is drawn from.
struct Draw {
    /// The arm (its mount used with `own_mount`).
    base: Arm,
    seed: u64,
    /// Least base turn \[rad\].
    min_turn: f64,
    own_mount: bool,
}

/// Draws 20 problems that the minimum-effort planner plans, as rows of the set's CSV.
fn draw_rows(draw: &Draw) -> Vec<String> {
    let n = draw.base.joints();
    let mut rng = Rng(draw.seed);
    let mut rows = Vec::new();
    while rows.len() < 20 {
        let (a, b) = if draw.own_mount {
            (draw.base.mount.a, draw.base.mount.b)
        } else {
            let (a, b) = (rng.uniform(0.8, 1.5), rng.uniform(0.8, 1.5));
            (if rng.next() < 0.5 { -a } else { a }, if rng.next() < 0.5 { -b } else { b })
        };
        let q = loop {
            let q: Vec<f64> = (0..2 * (n + 1)).map(|_| rng.uniform(-PI, PI)).collect();
            if wrap(q[n + 1] - q[0]).abs() >= draw.min_turn {
                break q;
            }
        };
        let problem = ChainProblem::rest_to_rest(q[..=n].to_vec(), q[n + 1..].to_vec(), 10.0);
        let clock = std::time::Instant::now();
        let planned = plan_arm(&arm(&draw.base, a, b), Method::Optimal, &ArmRequest::new(problem));
        let seconds = clock.elapsed().as_secs_f64();
        let i = rows.len();
        let turn = wrap(q[n + 1] - q[0]).to_degrees();
        let Ok(planned) = planned else {
            eprintln!("# draw for {i}: turn {turn:.1} deg not planned ({seconds:.1} s), drawn again");
            continue;
        };
        let rate = planned.trajectory.iter().flat_map(|p| p.rate.iter()).fold(0.0_f64, |m, r| m.max(r.abs()));
        eprintln!(
            "# {i}: turn {turn:.1} deg, effort {:.3e} rad^2/s, max joint rate {rate:.2} rad/s, {seconds:.1} s",
            planned.plan.effort()
        );
        let q: Vec<String> = q.iter().map(|x| format!("{x:.17e}")).collect();
        rows.push(format!("{i},{a:.17e},{b:.17e},{},{:.9e}", q.join(","), planned.plan.effort()));
    }
    rows
}

/// The CSV header line for `n` joints.
fn columns(n: usize) -> String {
    let end = |s: &str| (1..=n).map(|k| format!(",theta{k}_{s}")).collect::<String>();
    format!("i,a,b,phi0{},phid{},effort", end("0"), end("d"))
}

/// The 2-link set of the SRC robot, as it was first written (to stdout).
fn write_src_set() {
    let draw =
        Draw { base: Arm::from_params(&RobotParams::src()), seed: 0x5EED_0022, min_turn: PI / 3.0, own_mount: false };
    println!("# issue 22 item 1: 20 hard closed-loop problems of the SRC robot (examples/hard_set.rs).");
    println!("# made by: cargo run --release --example hard_set > tests/fixtures/hard_set.csv");
    println!("# |a|, |b| ~ U[0.8, 1.5] m with random signs; start, goal ~ U[-pi, pi)^3 rad with a base turn");
    println!("# >= 60 deg; rest to rest, T = 10 s; xorshift64* seeded 0x5EED0022; effort of the plan in rad^2/s.");
    println!("{}", columns(2));
    for row in draw_rows(&draw) {
        println!("{row}");
    }
}

fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter().position(|a| a == name).and_then(|i| args.get(i + 1).cloned())
}

fn parse_seed(text: &str) -> Result<u64, std::num::ParseIntError> {
    match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(&hex.replace('_', ""), 16),
        None => text.parse(),
    }
}

/// `--write`: a set for the arm of `--robot`, to `--set`.
fn write_set(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let robot = flag(args, "--robot").ok_or("--write needs --robot FILE")?;
    let out = flag(args, "--set").ok_or("--write needs --set FILE")?;
    let seed = parse_seed(&flag(args, "--seed").unwrap_or_else(|| "0x5EED0022".into()))?;
    let min_turn_deg: f64 = flag(args, "--min-turn").map_or(Ok(60.0), |v| v.parse())?;
    let own_mount = args.iter().any(|a| a == "--own-mount");
    let base = Arm::load(Path::new(&robot))?;
    let n = base.joints();
    let draw = Draw { base, seed, min_turn: min_turn_deg.to_radians(), own_mount };
    let mount = if own_mount {
        format!("the file's mount a = {}, b = {} m", draw.base.mount.a, draw.base.mount.b)
    } else {
        "|a|, |b| ~ U[0.8, 1.5] m with random signs".into()
    };
    let mut text =
        format!("# issue 22 item 3: 20 hard closed-loop problems of a {n}-link arm (examples/hard_set.rs).\n");
    text += &format!("# robot: {robot}\n");
    let quoted: Vec<String> = args.iter().map(|a| if a.contains(' ') { format!("'{a}'") } else { a.clone() }).collect();
    text += &format!("# made by: cargo run --release --example hard_set -- {}\n", quoted.join(" "));
    text += &format!("# {mount}; start, goal ~ U[-pi, pi)^{} rad with a base turn >= {min_turn_deg} deg;\n", n + 1);
    text += &format!("# rest to rest, T = 10 s; xorshift64* seeded {seed:#X}; effort of the plan in rad^2/s.\n");
    if let Some(note) = flag(args, "--note") {
        text += &format!("# {note}\n");
    }
    text += &columns(n);
    text.push('\n');
    for row in draw_rows(&draw) {
        text += &row;
        text.push('\n');
    }
    std::fs::write(&out, text)?;
    Ok(())
}

/// The robot of a set: `--robot`, else its `# robot:` line, else the SRC robot.
fn set_robot(args: &[String], text: &str) -> Result<Arm, Box<dyn std::error::Error>> {
    let named = flag(args, "--robot")
        .or_else(|| text.lines().find_map(|l| l.strip_prefix("# robot: ")).map(|p| p.trim().to_string()));
    Ok(match named {
        Some(path) => Arm::load(Path::new(&path))?,
        None => Arm::from_params(&RobotParams::src()),
    })
}

fn run_set(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let trials: usize = flag(args, "--trials").map_or(Ok(100), |v| v.parse())?;
    let controller = flag(args, "--controller").unwrap_or_else(|| "adaptive".into());
    let controller = Controller::from_name(&controller).ok_or("--controller: open, ct, replan or adaptive")?;
    let mut options = TrackOptions {
        controller,
        disturbances: Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() },
        ..Default::default()
    };
    if let Some(rate) = flag(args, "--replan-rate") {
        options.replan.rate = rate.parse()?;
    }
    if let Some(window) = flag(args, "--final-window") {
        options.replan.final_window = window.parse()?;
    }
    if let Some(time) = flag(args, "--forgetting") {
        options.identify.forgetting_time = time.parse()?;
    }
    if let Some(noise) = flag(args, "--torque-noise") {
        options.disturbances.torque_noise = noise.parse()?;
    }
    if let Some(rate) = flag(args, "--rate") {
        options.rate = rate.parse()?;
    }
    let mut gains = options.gains();
    if let Some(kp) = flag(args, "--kp") {
        gains.kp = kp.parse()?;
    }
    if let Some(kd) = flag(args, "--kd") {
        gains.kd = kd.parse()?;
    }
    options.gains = Some(gains);
    let only: Option<Vec<usize>> = flag(args, "--only").map(|v| v.split(',').map(str::parse).collect()).transpose()?;
    let detail = args.iter().any(|a| a == "--detail");
    let worst = args.iter().any(|a| a == "--worst");
    let mc = MonteCarloOptions {
        trials,
        seed: 1,
        perturbation: Perturbation { relative: 0.05, mount: 0.01 },
        controllers: vec![controller],
        ..Default::default()
    };
    let text = std::fs::read_to_string(flag(args, "--set").unwrap_or_else(|| "tests/fixtures/hard_set.csv".into()))?;
    let base = set_robot(args, &text)?;
    let n = base.joints();
    println!("problem  a       b       base turn  success  median     max        failed re-plans/run  s/run");
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with('i')) {
        let v: Vec<f64> = line.split(',').map(str::parse).collect::<Result<_, _>>()?;
        if v.len() != 2 * n + 6 {
            return Err(format!("a row of {} numbers for an arm of {n} joints", v.len()).into());
        }
        if only.as_ref().is_some_and(|o| !o.contains(&(v[0] as usize))) {
            continue;
        }
        let model = arm(&base, v[1], v[2]);
        let problem = ChainProblem::rest_to_rest(v[3..n + 4].to_vec(), v[n + 4..2 * n + 5].to_vec(), 10.0);
        let clock = std::time::Instant::now();
        let planned = plan_arm(&model, Method::Optimal, &ArmRequest::new(problem.clone()))?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let clock = std::time::Instant::now();
        let (runs, summary) = monte_carlo(&model, &problem, &planned.plan, &options, &mc, &|| {})?;
        let per_run = clock.elapsed().as_secs_f64() * rayon::current_num_threads() as f64 / trials as f64;
        let s = &summary[0];
        let e = |x: Option<f64>| x.map_or("failed".to_string(), |x| format!("{x:.2e}"));
        print!(
            "{:>7}  {:>6.3}  {:>6.3}  {:>7.1}°  {:>6.1} %  {:<9}  {:<9}  {:>19.2}  {:.3}",
            v[0],
            v[1],
            v[2],
            wrap(v[n + 4] - v[3]).to_degrees(),
            100.0 * s.success_rate,
            e(s.median_error),
            e(s.max_error),
            s.replan_failures as f64 / trials as f64,
            per_run
        );
        if detail {
            print!("  failed runs {} (limits {}), plan {plan_seconds:.1} s", s.failed, s.limit_failures);
        }
        println!();
        if worst {
            print_worst(&model, &problem, &planned.plan, &options, &mc, &runs)?;
        }
    }
    Ok(())
}

/// `--worst`: the trial with the largest final error, run again: its error per coordinate
/// `(phi, theta1, ..)`, its final velocity, re-plans and the identified momentum map's error.
fn print_worst(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn freefloat::track::ArmMotion,
    options: &TrackOptions,
    mc: &MonteCarloOptions,
    runs: &[freefloat::track::Trial],
) -> Result<(), Box<dyn std::error::Error>> {
    let Some(w) = runs.iter().max_by(|a, b| a.final_error.total_cmp(&b.final_error)) else { return Ok(()) };
    let seed = freefloat::track::monte_carlo::trial_seed(mc.seed, w.trial as u64);
    let truth = mc.perturbation.apply(model, seed)?;
    let r = freefloat::track::track(model, problem, plan, &truth, options, seed)?;
    let list = |v: &[f64]| v.iter().map(|x| format!("{x:.2e}")).collect::<Vec<_>>().join(" ");
    let map = r.identification.as_ref().map(|i| (i.nominal_map_error, i.identified_map_error));
    println!(
        "         worst trial {}: errors [{}], final velocity [{}], re-plans {} (failed {}), map error (nominal, identified) {map:?}",
        w.trial,
        list(&r.final_errors),
        list(&r.final_velocity),
        r.replans,
        r.replan_failures
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        write_src_set();
        Ok(())
    } else if args.iter().any(|a| a == "--write") {
        write_set(args.as_slice())
    } else {
        run_set(&args)
    }
}
