//! Runs the minimum-effort planner keeping a clearance repeatedly (for profiling with perf):
//! `profile_clearance CASE N [CLEARANCE]` with CASE `spart` (the SPART-like fixture with its base
//! box, `benches/clearance.rs`), `3link` (the 3-link example around an obstacle) or `random`
//! (N random problems on the SPART-like fixture; `FF_ONLY=K` runs problem K alone,
//! `FF_RATES=free` lifts the joints' velocity, acceleration and torque limits, `FF_CLEARANCES=0.02`
//! plans at the clearances listed only, 0, 0.02 and 0.04 m by default).
use freefloat::model::arm::Arm;
use freefloat::model::arm::collision::Body;
use freefloat::model::geometry::Shape;
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::path::Path;

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("spart");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let clearance: Option<f64> = args.get(3).and_then(|s| s.parse().ok());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (mut arm, problem) = if case == "spart" || case == "random" {
        let path = root.join("tests/fixtures/spart_like_4dof_geometry.urdf");
        let mut arm = Arm::from_urdf_str(&std::fs::read_to_string(&path)?, &path)?;
        arm.geometry.clearance = 0.02;
        let p = ChainProblem::rest_to_rest(
            deg(&[0.0, 30.0, -60.0, 45.0, -30.0]),
            deg(&[30.0, 60.0, -30.0, 20.0, -60.0]),
            10.0,
        );
        (arm, p)
    } else {
        let path = root.join("examples/robots/three_link.toml");
        let text = std::fs::read_to_string(&path)?
            .lines()
            .map(|l| if l.starts_with("inertia") { format!("{l}\nwidth = 0.04") } else { l.to_string() })
            .collect::<Vec<_>>()
            .join("\n");
        let mut arm = Arm::from_toml(&text, &path)?;
        arm.geometry.obstacles.push(Shape::circle([-0.4, 0.1], 0.05)?);
        arm.geometry.excluded.push((Body::Link(1), Body::Link(3)));
        let p = ChainProblem::rest_to_rest(deg(&[0.0, 0.0, 30.0, 30.0]), deg(&[20.0, 90.0, 30.0, -30.0]), 8.0);
        (arm, p)
    };
    if let Some(c) = clearance {
        arm.geometry.clearance = c;
    }
    if case == "random" {
        return random(arm, n);
    }
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    for _ in 0..n {
        let clock = std::time::Instant::now();
        let plan = planner.plan(&problem)?;
        let r_min = plan.verification.clearance.map_or(f64::NAN, |r| r.min);
        println!(
            "effort {:.10} clearance {:.5} certified {} collision-free {} seeds {} iterations {} spans {} in {:.1} ms",
            plan.stats.effort,
            r_min,
            plan.verification.certified,
            plan.verification.collision().is_ok(),
            plan.stats.seeds,
            plan.stats.iterations,
            plan.stats.spans,
            clock.elapsed().as_secs_f64() * 1e3
        );
    }
    Ok(())
}

/// `n` random problems on the SPART-like arm (base angles uniform in +-15 deg, joint angles in
/// +-90 deg, 10 s)
/// at clearances 0, 0.02 and 0.04 m: one line per plan, whether it is certified and clear.
fn random(arm: Arm, n: usize) -> Result<(), Box<dyn std::error::Error>> {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for k in 0..n {
        // The base within +-15 deg, the joints within +-90 deg.
        let angle = |j: usize, u: f64| if j == 0 { 30.0 * u - 15.0_f64 } else { 180.0 * u - 90.0 }.to_radians();
        let start: Vec<f64> = (0..5).map(|j| angle(j, uniform())).collect();
        let goal: Vec<f64> = (0..5).map(|j| angle(j, uniform())).collect();
        if std::env::var("FF_ONLY").is_ok_and(|v| v != k.to_string()) {
            continue;
        }
        let clearances: Vec<f64> = std::env::var("FF_CLEARANCES")
            .map(|v| v.split(',').filter_map(|x| x.parse().ok()).collect())
            .unwrap_or(vec![0.0, 0.02, 0.04]);
        for clearance in clearances {
            let mut arm = arm.clone();
            if std::env::var("FF_RATES").is_ok_and(|v| v == "free") {
                // The joints' rates unlimited (their ranges kept): SPART's own file declares
                // 100 rad/s and 1000 N m.
                for j in &mut arm.limits.joints {
                    (j.velocity, j.torque, j.acceleration) = (None, None, None);
                }
            }
            arm.geometry.clearance = clearance;
            let clock = std::time::Instant::now();
            let problem = ChainProblem::rest_to_rest(start.clone(), goal.clone(), 10.0);
            let at_ends = |q: &[f64]| arm.geometry.min_clearance(&arm, q).map_or(f64::INFINITY, |x| x.distance);
            if at_ends(&start) < clearance || at_ends(&goal) < clearance {
                println!("problem {k} clearance {clearance}: ends under the clearance");
                continue;
            }
            let outcome = match ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem) {
                Ok(plan) => {
                    let least = plan.verification.clearance.map_or(f64::NAN, |r| r.min);
                    let ok = plan.verification.certified && least >= clearance;
                    format!("{} effort {:.10} least {least:.5}", if ok { "clear" } else { "UNDER" }, plan.stats.effort)
                }
                Err(e) => format!("ERROR {e}"),
            };
            println!("problem {k} clearance {clearance}: {outcome} in {:.1} s", clock.elapsed().as_secs_f64());
        }
    }
    Ok(())
}
