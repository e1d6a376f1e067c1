//! Issue 22's hard set of closed-loop problems, and its Monte Carlo.
//!
//! `cargo run --release --example hard_set > tests/fixtures/hard_set.csv` writes the set: 20
//! problems of the paper's SRC robot with large mounts and large base turns, drawn by a
//! xorshift64* generator seeded with `0x5EED_0022`. Per problem, in this order: `|a|`, `|b|`
//! uniform in `[0.8, 1.5]` m, then their signs (each `+` with probability 1/2), then start and goal
//! `(phi, theta1, theta2)` uniform in `[-pi, pi)` rad, drawn again until the base turns by at
//! least 60 deg (`|wrap(phi_goal - phi_start)| >= pi/3`); rest to rest, `T = 10 s`. A problem
//! the minimum-effort planner does not plan is drawn again (none was, when the set was made).
//!
//! `cargo run --release --example hard_set -- --trials 100 [--controller adaptive] [--replan-rate 50]
//! [--torque-noise 0.01] [--kp 40000] [--kd 400] [--rate 1000] [--only 0,3,9]`
//! runs each problem of the fixture file through `track`'s Monte Carlo with the disturbances of
//! the measurements (5 % parameters, 1 cm mount, 1 % torque noise, 1e-5 rad and 1e-5
//! rad/s measurement noise, 1 kHz control, seed 1) and prints, per problem, the success rate
//! (final error <= 1e-3 rad), the median and largest final error, the failed re-plans per run
//! and the CPU time of one thread per run.
use freefloat::model::arm::Arm;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::track::{Controller, Disturbances, MonteCarloOptions, Perturbation, TrackOptions, monte_carlo};
use freefloat::{Method, Mount, RobotParams};
use std::f64::consts::PI;

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

fn arm(a: f64, b: f64) -> Arm {
    Arm { mount: Mount { a, b }, ..Arm::from_params(&RobotParams::src()) }
}

fn write_set() -> Result<(), Box<dyn std::error::Error>> {
    let mut rng = Rng(0x5EED_0022);
    println!("# issue 22 item 1: 20 hard closed-loop problems of the SRC robot (examples/hard_set.rs).");
    println!("# made by: cargo run --release --example hard_set > tests/fixtures/hard_set.csv");
    println!("# |a|, |b| ~ U[0.8, 1.5] m with random signs; start, goal ~ U[-pi, pi)^3 rad with a base turn");
    println!("# >= 60 deg; rest to rest, T = 10 s; xorshift64* seeded 0x5EED0022; effort of the plan in rad^2/s.");
    println!("i,a,b,phi0,theta1_0,theta2_0,phid,theta1_d,theta2_d,effort");
    let mut i = 0;
    while i < 20 {
        let (a, b) = (rng.uniform(0.8, 1.5), rng.uniform(0.8, 1.5));
        let a = if rng.next() < 0.5 { -a } else { a };
        let b = if rng.next() < 0.5 { -b } else { b };
        let q = loop {
            let q: Vec<f64> = (0..6).map(|_| rng.uniform(-PI, PI)).collect();
            if wrap(q[3] - q[0]).abs() >= PI / 3.0 {
                break q;
            }
        };
        let problem = ChainProblem::rest_to_rest(q[..3].to_vec(), q[3..].to_vec(), 10.0);
        let Ok(planned) = plan_arm(&arm(a, b), Method::Optimal, &ArmRequest::new(problem)) else { continue };
        let q: Vec<String> = q.iter().map(|x| format!("{x:.17e}")).collect();
        println!("{i},{a:.17e},{b:.17e},{},{:.9e}", q.join(","), planned.plan.effort());
        i += 1;
    }
    Ok(())
}

fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter().position(|a| a == name).and_then(|i| args.get(i + 1).cloned())
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
    let mc = MonteCarloOptions {
        trials,
        seed: 1,
        perturbation: Perturbation { relative: 0.05, mount: 0.01 },
        controllers: vec![controller],
        ..Default::default()
    };
    let text = std::fs::read_to_string("tests/fixtures/hard_set.csv")?;
    println!("problem  a       b       base turn  success  median     max        failed re-plans/run  s/run");
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with('i')) {
        let v: Vec<f64> = line.split(',').map(str::parse).collect::<Result<_, _>>()?;
        if only.as_ref().is_some_and(|o| !o.contains(&(v[0] as usize))) {
            continue;
        }
        let model = arm(v[1], v[2]);
        let problem = ChainProblem::rest_to_rest(v[3..6].to_vec(), v[6..9].to_vec(), 10.0);
        let planned = plan_arm(&model, Method::Optimal, &ArmRequest::new(problem.clone()))?;
        let clock = std::time::Instant::now();
        let (_, summary) = monte_carlo(&model, &problem, &planned.plan, &options, &mc, &|| {})?;
        let per_run = clock.elapsed().as_secs_f64() * rayon::current_num_threads() as f64 / trials as f64;
        let s = &summary[0];
        let e = |x: Option<f64>| x.map_or("failed".to_string(), |x| format!("{x:.2e}"));
        println!(
            "{:>7}  {:>6.3}  {:>6.3}  {:>7.1}°  {:>6.1} %  {:<9}  {:<9}  {:>19.2}  {:.3}",
            v[0],
            v[1],
            v[2],
            wrap(v[6] - v[3]).to_degrees(),
            100.0 * s.success_rate,
            e(s.median_error),
            e(s.max_error),
            s.replan_failures as f64 / trials as f64,
            per_run
        );
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() { write_set() } else { run_set(&args) }
}
