//! Writes `tests/fixtures/two_link_300.csv` (issue 19, item 2): 300 random problems of the
//! paper's SRC robot, each planned by the 2-joint minimum-effort planner (`planners::optimal`,
//! default options) and by the n-joint one (`planners::chain`, default options, on the same robot
//! as a 2-link `Arm`), with their efforts and certificates. Run from the repository root:
//!
//! `cargo run --release --example make_two_link_fixture > tests/fixtures/two_link_300.csv`
//!
//! With `--two-joint` it writes `tests/fixtures/two_link_300_two_joint.csv` instead: the same
//! 300 problems (read back from `tests/fixtures/two_link_300.csv`) planned by the 2-joint planner
//! of the day it is run, the planner that the n-joint one replaces (issue 19):
//!
//! `cargo run --release --example make_two_link_fixture -- --two-joint > tests/fixtures/two_link_300_two_joint.csv`
//!
//! Both fixtures record planners that no longer exist apart: since issue 19 merged them,
//! `OptimalPlanner` is the 2-link front-end of the one planner (`planners::chain`), so both modes
//! now print that planner's efforts. To remake the fixtures as recorded, run this at the commits
//! that made them: `two_link_300.csv` before issue 19's work began, `two_link_300_two_joint.csv`
//! at commit 7201eab (whose 2-joint planner is that of 83670d2).
//!
//! The distribution: a xorshift64* generator seeded with `0x5EED_0019`; per problem, in this
//! order, the mount `a`, `b` uniform in `[-1.5, 1.5]` \[m\], the start `(phi, theta1, theta2)`
//! and the goal `(phi, theta1, theta2)` each uniform in `[-pi, pi)` \[rad\]; rest to rest,
//! `T = 10 s`. Angles are printed with 17 significant digits, so the problems read back exactly.
use freefloat::Planner;
use freefloat::model::arm::Arm;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use freefloat::planners::optimal::OptimalPlanner;
use freefloat::{Configuration, Mount, PlanningProblem, RobotParams};
use rayon::prelude::*;
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

/// Effort, certified, milliseconds (NaN, false on an error).
type Outcome = (f64, bool, f64);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if std::env::args().any(|a| a == "--two-joint") {
        return two_joint_today();
    }
    let mut rng = Rng(0x5EED_0019);
    let mut problems = Vec::new();
    for _ in 0..300 {
        let (a, b) = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
        let q: Vec<f64> = (0..6).map(|_| rng.uniform(-PI, PI)).collect();
        problems.push((a, b, q));
    }
    let rows: Vec<(Outcome, Outcome)> = problems
        .par_iter()
        .map(|(a, b, q)| {
            let robot = RobotParams::src().with_mount(Mount { a: *a, b: *b }).expect("a mount in range");
            let start = Configuration { phi: q[0], theta1: q[1], theta2: q[2] };
            let goal = Configuration { phi: q[3], theta1: q[4], theta2: q[5] };
            let problem = PlanningProblem::new(robot, start, goal, 10.0).expect("a valid problem");
            let clock = std::time::Instant::now();
            let two = match OptimalPlanner::default().plan(&problem) {
                Ok(p) => (p.plan.effort, p.plan.verification.certified, clock.elapsed().as_secs_f64() * 1e3),
                Err(_) => (f64::NAN, false, clock.elapsed().as_secs_f64() * 1e3),
            };
            let chain = ChainPlanner::new(Arm::from_params(&robot), ChainOptions::default());
            let clock = std::time::Instant::now();
            let n = match chain.plan(&ChainProblem::rest_to_rest(q[0..3].to_vec(), q[3..6].to_vec(), 10.0)) {
                Ok(p) => (p.effort(), p.verification.certified, clock.elapsed().as_secs_f64() * 1e3),
                Err(_) => (f64::NAN, false, clock.elapsed().as_secs_f64() * 1e3),
            };
            (two, n)
        })
        .collect();
    println!("# issue 19 item 2: 300 random 2-link problems, both of today's minimum-effort planners.");
    println!("# made by: cargo run --release --example make_two_link_fixture > tests/fixtures/two_link_300.csv");
    println!("# SRC robot, mount a, b ~ U[-1.5, 1.5] m; start and goal (phi, theta1, theta2) ~ U[-pi, pi) rad;");
    println!("# rest to rest, T = 10 s; xorshift64* seeded 0x5EED0019 (see examples/make_two_link_fixture.rs).");
    println!("# effort in rad^2/s (NaN: no plan); certified: the velocity-level certificate at 1e-9 rad;");
    println!("# ms: wall time on a loaded machine, for orientation only.");
    println!(
        "i,a,b,phi0,theta1_0,theta2_0,phid,theta1_d,theta2_d,effort_2joint,certified_2joint,ms_2joint,effort_njoint,certified_njoint,ms_njoint"
    );
    let (mut two_wins, mut n_wins, mut ties) = (0, 0, 0);
    for (i, ((a, b, q), (two, n))) in problems.iter().zip(&rows).enumerate() {
        let value = |o: &Outcome| if o.1 { o.0 } else { f64::INFINITY };
        let (x, y) = (value(two), value(n));
        if x < y * (1.0 - 1e-6) {
            two_wins += 1;
        } else if y < x * (1.0 - 1e-6) {
            n_wins += 1;
        } else {
            ties += 1;
        }
        println!(
            "{i},{a:.17e},{b:.17e},{},{},{},{},{},{},{:.12e},{},{:.2},{:.12e},{},{:.2}",
            format_args!("{:.17e}", q[0]),
            format_args!("{:.17e}", q[1]),
            format_args!("{:.17e}", q[2]),
            format_args!("{:.17e}", q[3]),
            format_args!("{:.17e}", q[4]),
            format_args!("{:.17e}", q[5]),
            two.0,
            two.1,
            two.2,
            n.0,
            n.1,
            n.2
        );
    }
    eprintln!("2-joint better: {two_wins}, n-joint better: {n_wins}, equal within 1e-6: {ties}");
    Ok(())
}

/// The `--two-joint` table (module docs): index, effort, certified, for each recorded problem.
fn two_joint_today() -> Result<(), Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string("tests/fixtures/two_link_300.csv")?;
    let mut problems = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("i,")) {
        let f: Vec<f64> = line.split(',').skip(1).take(8).map(str::parse).collect::<Result<_, _>>()?;
        let robot = RobotParams::src().with_mount(Mount::new(f[0], f[1])?)?;
        let start = Configuration { phi: f[2], theta1: f[3], theta2: f[4] };
        let goal = Configuration { phi: f[5], theta1: f[6], theta2: f[7] };
        problems.push(PlanningProblem::new(robot, start, goal, 10.0)?);
    }
    let rows: Vec<(f64, bool)> = problems
        .par_iter()
        .map(|problem| match OptimalPlanner::default().plan(problem) {
            Ok(p) => (p.plan.effort, p.plan.verification.certified),
            Err(_) => (f64::NAN, false),
        })
        .collect();
    println!("# issue 19 item 2: the 300 problems of two_link_300.csv planned by the 2-joint planner as");
    println!("# it stands before the merge (default options), the planner the n-joint one replaces.");
    println!(
        "# made by: cargo run --release --example make_two_link_fixture -- --two-joint > tests/fixtures/two_link_300_two_joint.csv"
    );
    println!("# effort in rad^2/s (NaN: no plan); certified: the velocity-level certificate at 1e-9 rad.");
    println!("i,effort_2joint,certified_2joint");
    for (i, (effort, certified)) in rows.iter().enumerate() {
        println!("{i},{effort:.12e},{certified}");
    }
    Ok(())
}
