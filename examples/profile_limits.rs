//! Runs the limits bench's cases repeatedly (for profiling with perf): `profile_limits CASE N`
//! with CASE one of `3v`, `3vt`, `2v`, `4s`, `auto` (the cases of `benches/limits.rs`), or `4t`
//! (SPART's example with tight limits at a horizon `HORIZON`), or `random COUNT` (problems the
//! benches do not tune on, see [`random`]). `USES=1` prints the uses of the
//! torque and base limits; `GRADING=k` sets the end grading.
use freefloat::model::arm::{Arm, JointLimits, Limits};
use freefloat::planners::chain::horizon::uses;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::path::Path;
use std::time::Instant;

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// The arm with velocity (and with `torque`, torque) limits at `fraction` of its free plan's
/// peaks; `None` without a free plan.
fn binding(arm: &Arm, problem: &ChainProblem, fraction: f64, torque: bool) -> Option<Arm> {
    let free = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(problem).ok()?;
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
    Some(limited)
}

/// `random COUNT`: problems the benches do not tune on, for before/after comparisons: `COUNT`
/// random 3-link rest-to-rest problems with velocity limits at 0.8 of the free plan's peak rates
/// (then with torque limits too), each effort printed to 16 digits with its certificate's
/// verdict and the SQP iterations.
fn random(three: &Arm, count: usize) {
    // A linear congruential generator (Knuth's MMIX constants): the same problems every run.
    let mut state: u64 = 20;
    let mut uniform = move |lo: f64, hi: f64| {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
    };
    for k in 0..count {
        let start: Vec<f64> = (0..4).map(|_| uniform(-60.0, 60.0).to_radians()).collect();
        let goal: Vec<f64> = (0..4).map(|_| uniform(-60.0, 60.0).to_radians()).collect();
        let problem = ChainProblem { wrap: false, ..ChainProblem::rest_to_rest(start, goal, uniform(6.0, 14.0)) };
        for torque in [false, true] {
            let label = format!("random {k} {}", if torque { "vt" } else { "v" });
            let Some(arm) = binding(three, &problem, 0.8, torque) else {
                println!("{label}: no free plan");
                continue;
            };
            match ChainPlanner::new(arm, ChainOptions::default()).plan(&problem) {
                Ok(p) => println!(
                    "{label}: effort {:.16e} certified {} iterations {}",
                    p.stats.effort, p.verification.certified, p.stats.iterations
                ),
                Err(e) => println!("{label}: error {e}"),
            }
        }
    }
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

/// Each declared torque and base-range limit's largest use on the plan (`USES=1`): the
/// certificate's (integrated motion) and the plan's own sampled at 1024 points per knot span.
fn report_uses(arm: &Arm, plan: &freefloat::planners::chain::ChainPlan) {
    eprintln!("certified {}", plan.verification.certified);
    for u in plan.verification.limits.iter().flat_map(|r| &r.uses) {
        eprintln!(
            "  certificate {} {}: use - 1 = {:.3e} at t {:.6} (value {:.12})",
            u.name,
            u.quantity.name(),
            u.used - 1.0,
            u.time,
            u.value
        );
    }
    let n = arm.joints();
    let mut peak = vec![(f64::NEG_INFINITY, 0.0); n + 1];
    for w in plan.basis().breakpoints().windows(2) {
        for k in 0..=1024 {
            let t = w[0] + (w[1] - w[0]) * k as f64 / 1024.0;
            let p = plan.at(t);
            let tau = freefloat::dynamics::arm::inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
            for j in 0..n {
                if let Some(l) = arm.limits.joint(j).torque {
                    let used = tau[j].abs() / l;
                    if used > peak[j + 1].0 {
                        peak[j + 1] = (used, t);
                    }
                }
            }
            if let Some([lo, hi]) = arm.limits.base {
                let used = ((p.phi - 0.5 * (lo + hi)) / (0.5 * (hi - lo))).abs();
                if used > peak[0].0 {
                    peak[0] = (used, t);
                }
            }
        }
    }
    for (j, (used, t)) in peak.iter().enumerate() {
        if used.is_finite() {
            eprintln!(
                "  dense {}: use - 1 = {:.3e} at t {:.6}",
                if j == 0 { "phi".into() } else { format!("tau{j}") },
                used - 1.0,
                t
            );
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("3v");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let three = example("three_link.toml").with_limits(Limits::default()).expect("no limits");
    if case == "random" {
        return random(&three, args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10));
    }
    let problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0]), 10.0)
    };
    let (arm, problem) = match case {
        "3v" | "auto" => (binding(&three, &problem, 0.8, false).expect("the free plan"), problem),
        "3vt" => (binding(&three, &problem, 0.8, true).expect("the free plan"), problem),
        "2v" => {
            let src = Arm::from_params(&freefloat::RobotParams::src());
            let (q0, qd, horizon) = freefloat::model::paper_problem();
            let paper = ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon);
            (binding(&src, &paper, 0.8, false).expect("the free plan"), paper)
        }
        "4t" => {
            // SPART's example with tight limits (+-2 rad, 0.3 rad/s, 50 N m), the horizon
            // `HORIZON` s (13.5 by default; `--time auto` finds 13.24): the torque binds.
            let mut spart = example("spart_like_4dof.urdf");
            spart.geometry = Default::default();
            let joint = JointLimits {
                position: Some([-2.0, 2.0]),
                velocity: Some(0.3),
                torque: Some(50.0),
                acceleration: None,
            };
            let n = spart.joints();
            let spart = spart.with_limits(Limits { joints: vec![joint; n], base: None }).expect("valid limits");
            let horizon = std::env::var("HORIZON").ok().and_then(|h| h.parse().ok()).unwrap_or(13.5);
            let p = ChainProblem::rest_to_rest(
                deg(&[0.0, 20.0, -30.0, 40.0, 10.0]),
                deg(&[30.0, 60.0, 30.0, -20.0, 40.0]),
                horizon,
            );
            (spart, p)
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
    let mut options = ChainOptions::default();
    if let Some(g) = std::env::var("GRADING").ok().and_then(|g| g.parse().ok()) {
        options.grading = g;
    }
    let planner = ChainPlanner::new(arm, options);
    let clock = Instant::now();
    for _ in 0..n {
        if case == "auto" {
            let s = planner.shortest_horizon(&problem).expect("a horizon");
            eprintln!(
                "T {:.4} probes {} effort {:.10} spans {}",
                s.horizon, s.probes, s.plan.stats.effort, s.plan.stats.spans
            );
            if std::env::var_os("USES").is_some() {
                report_uses(planner.arm(), &s.plan);
            }
        } else {
            let p = planner.plan(&problem).expect("plans");
            let s = &p.stats;
            eprintln!(
                "effort {:.10} seeds {} iterations {} final {} spans {} nodes {}",
                s.effort, s.seeds, s.iterations, s.final_iterations, s.spans, s.quadrature_nodes
            );
            if std::env::var_os("USES").is_some() {
                report_uses(planner.arm(), &p);
            }
        }
    }
    eprintln!("{:.2} ms per run", clock.elapsed().as_secs_f64() * 1e3 / n as f64);
}
