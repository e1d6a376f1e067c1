//! Runs the minimum-effort planner for `n` joints repeatedly (for profiling with perf):
//! `profile_chain CASE N` with CASE one of `src0.1` (the paper's problem at a = b = 0.1 on the
//! 2-link robot as an arm), `src1` (a = 1, b = -1), `3link`, `7link` (the criterion cases of
//! `benches/optimal.rs`).
use freefloat::model::arm::{Arm, Base, Link};
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use freefloat::{Mount, PlanningProblem, RobotParams};

fn links(spec: &[(f64, f64)]) -> Vec<Link> {
    spec.iter().map(|&(l, m)| Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 }).collect()
}

fn main() -> Result<(), freefloat::Error> {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("src0.1");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let (arm, problem) = match case {
        "src0.1" | "src1" => {
            let (a, b) = if case == "src1" { (1.0, -1.0) } else { (0.1, 0.1) };
            let robot = RobotParams::src().with_mount(Mount::new(a, b)?)?;
            let p = PlanningProblem::paper(robot);
            let q0 = [p.start.phi, p.start.theta1, p.start.theta2].to_vec();
            let q1 = [p.goal.phi, p.goal.theta1, p.goal.theta2].to_vec();
            (Arm::from_params(&robot), ChainProblem::rest_to_rest(q0, q1, p.horizon))
        }
        "3link" => (
            Arm {
                base: Base { mass: 15.0, inertia: 0.5 },
                mount: Mount { a: 0.2, b: 0.0 },
                links: links(&[(0.4, 2.0), (0.35, 1.5), (0.25, 0.8)]),
                limits: Default::default(),
                geometry: Default::default(),
            },
            ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0),
        ),
        _ => {
            let spec: Vec<(f64, f64)> = (0..7).map(|i| (0.3 - 0.025 * i as f64, 1.5 - 0.2 * i as f64)).collect();
            (
                Arm {
                    base: Base { mass: 20.0, inertia: 0.8 },
                    mount: Mount { a: 0.2, b: 0.1 },
                    links: links(&spec),
                    limits: Default::default(),
                    geometry: Default::default(),
                },
                ChainProblem::rest_to_rest(
                    vec![0.0, 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.6],
                    vec![0.4, -0.3, 0.5, 0.1, 0.7, 0.2, -0.5, 0.0],
                    10.0,
                ),
            )
        }
    };
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let start = std::time::Instant::now();
    let mut effort = 0.0;
    for _ in 0..n {
        let plan = planner.plan(&problem)?;
        effort = plan.stats.effort;
        if n == 1 {
            println!("{:?}", plan.stats);
        }
        std::hint::black_box(plan);
    }
    println!("{case}: effort {effort:.6}, {:.3} ms per plan", start.elapsed().as_secs_f64() * 1e3 / n as f64);
    Ok(())
}
