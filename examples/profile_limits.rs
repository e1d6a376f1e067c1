//! Runs the limits bench's cases repeatedly (for profiling with perf): `profile_limits CASE N`
//! with CASE one of `3v`, `3vt`, `2v`, `4s`, `auto` (the cases of `benches/limits.rs`).
use freefloat::model::arm::{Arm, JointLimits, Limits};
use freefloat::planners::chain::horizon::uses;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::path::Path;
use std::time::Instant;

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

fn binding(arm: &Arm, problem: &ChainProblem, fraction: f64, torque: bool) -> Arm {
    let free = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(problem).expect("the free plan");
    let n = arm.joints();
    let mut peak = vec![[0.0_f64; 2]; n];
    for p in free.sample(2001) {
        let tau = freefloat::dynamics::arm::inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
        for j in 0..n {
            peak[j] = [peak[j][0].max(p.rate[j].abs()), peak[j][1].max(tau[j].abs())];
        }
    }
    let joints = (0..n)
        .map(|j| JointLimits {
            velocity: Some(fraction * peak[j][0]),
            torque: torque.then(|| fraction * peak[j][1]),
            position: None,
            acceleration: None,
        })
        .collect();
    let limited = arm.clone().with_limits(Limits { joints, base: None }).expect("valid limits");
    let (most, _) = uses(&ChainPlanner::new(limited.clone(), ChainOptions::default()), &free);
    assert!(most.expect("limits").used > 1.0, "the free plan breaks a limit");
    limited
}

fn example(name: &str) -> Arm {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots").join(name);
    let text = std::fs::read_to_string(&path).expect("the example");
    if name.ends_with(".urdf") {
        Arm::from_urdf_str(&text, &path).expect("the URDF")
    } else {
        Arm::from_toml(&text, &path).expect("the TOML")
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("3v");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let three = example("three_link.toml").with_limits(Limits::default()).expect("no limits");
    let problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0]), 10.0)
    };
    let (arm, problem) = match case {
        "3v" | "auto" => (binding(&three, &problem, 0.8, false), problem),
        "3vt" => (binding(&three, &problem, 0.8, true), problem),
        "2v" => {
            let src = Arm::from_params(&freefloat::RobotParams::src());
            let (q0, qd, horizon) = freefloat::model::paper_problem();
            let paper = ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon);
            (binding(&src, &paper, 0.8, false), paper)
        }
        _ => {
            let mut spart = example("spart_like_4dof.urdf");
            spart.geometry = Default::default();
            let p = ChainProblem {
                wrap: false,
                ..ChainProblem::rest_to_rest(
                    deg(&[0.0, 20.0, -30.0, 40.0, 10.0]),
                    deg(&[30.0, 60.0, 30.0, -20.0, 40.0]),
                    30.0,
                )
            };
            (spart, p)
        }
    };
    let arm = if std::env::var_os("FREE").is_some() { arm.with_limits(Limits::default()).expect("none") } else { arm };
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let clock = Instant::now();
    for _ in 0..n {
        if case == "auto" {
            let s = planner.shortest_horizon(&problem).expect("a horizon");
            eprintln!(
                "T {:.4} probes {} effort {:.10} spans {}",
                s.horizon, s.probes, s.plan.stats.effort, s.plan.stats.spans
            );
        } else {
            let p = planner.plan(&problem).expect("plans");
            let s = &p.stats;
            eprintln!(
                "effort {:.10} seeds {} iterations {} final {} spans {} nodes {}",
                s.effort, s.seeds, s.iterations, s.final_iterations, s.spans, s.quadrature_nodes
            );
        }
    }
    eprintln!("{:.2} ms per run", clock.elapsed().as_secs_f64() * 1e3 / n as f64);
}
