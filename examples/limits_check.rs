//! Plans on problems the limits benches do not tune on, for before/after comparisons of the
//! constrained planner: `limits_check [COUNT]` plans `COUNT` (10) random 3-link rest-to-rest
//! problems with velocity limits at 0.8 of the free plan's peak rates (then with torque limits
//! too at 0.8 of its peak torques), and prints each effort to 16 digits with its certificate's
//! verdict and the SQP iterations.
use freefloat::model::arm::{Arm, JointLimits, Limits};
use freefloat::planners::chain::{ChainOptions, ChainPlanner, ChainProblem};
use std::path::Path;

/// The arm with velocity (and with `torque`, torque) limits at `fraction` of `free`'s peaks.
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
    arm.clone().with_limits(Limits { joints, base: None }).ok()
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

/// Plans `problem` on `arm` and prints the effort and the verdict after `label`.
fn report(label: &str, arm: Arm, problem: &ChainProblem) {
    match ChainPlanner::new(arm, ChainOptions::default()).plan(problem) {
        Ok(p) => println!(
            "{label}: effort {:.16e} certified {} iterations {}",
            p.stats.effort, p.verification.certified, p.stats.iterations
        ),
        Err(e) => println!("{label}: error {e}"),
    }
}

fn main() {
    let count: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    let three = example("three_link.toml").with_limits(Limits::default()).expect("no limits");
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
            match binding(&three, &problem, 0.8, torque) {
                Some(arm) => report(&label, arm, &problem),
                None => println!("{label}: no free plan"),
            }
        }
    }
}
