//! How much the open-loop forward dynamics of a torque plan amplify a small error: integrates
//! the dynamics with the planned torques from rest and from rest plus a 1e-9 rad/s joint velocity.
//!
//! ```text
//! cargo run --release --example torque_sensitivity            # a, b = (1, -1) and (0.2, 0.2) m
//! cargo run --release --example torque_sensitivity -- 0.1 0.1 # one mounting point a, b [m]
//! ```
use freefloat::dynamics::{forward_dynamics, joint_torques};
use freefloat::numerics::ode::{OdeOptions, integrate};
use freefloat::plan::Motion;
use freefloat::{Configuration, Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams};
use nalgebra::Vector6;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mounts: Vec<(f64, f64)> = match args.as_slice() {
        // The README's two mounting points: the paper's impossible case and an ordinary one.
        [] => vec![(1.0, -1.0), (0.2, 0.2)],
        [a, b] => vec![(a.parse()?, b.parse()?)],
        _ => return Err("usage: torque_sensitivity [A B] (the mounting point [m]; default: 1 -1 and 0.2 0.2)".into()),
    };
    for (a, b) in mounts {
        sensitivity(a, b)?;
    }
    Ok(())
}

/// Prints how far a 1e-9 rad/s error in `theta1'(0)` takes the torque plan's motion by `T`.
fn sensitivity(a: f64, b: f64) -> Result<(), freefloat::Error> {
    let p = PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b)?)?);
    let k = p.robot.lumped();
    let (_, motion) = NormalFormPlanner::new(NfaOptions::default()).plan_with_motion(&p)?;
    let run = |dv: f64| -> Result<Vector6<f64>, freefloat::Error> {
        let q0 = p.start.to_array();
        let y0 = Vector6::new(q0[0], q0[1], q0[2], 0.0, dv, 0.0);
        let f = |t: f64, y: &Vector6<f64>| {
            let tau = joint_torques(&k, &motion.at(t)?);
            let ddq =
                forward_dynamics(&k, &Configuration::new(y[0], y[1], y[2]), [y[3], y[4], y[5]], [0.0, tau[0], tau[1]]);
            Ok::<_, freefloat::Error>(Vector6::new(y[3], y[4], y[5], ddq[0], ddq[1], ddq[2]))
        };
        Ok(integrate(f, 0.0, y0, p.horizon, &OdeOptions::default(), |_, _| {})?.0)
    };
    let base = run(0.0)?;
    let pert = run(1e-9)?;
    println!(
        "mount ({a}, {b}): d theta1'(0) = 1e-9 rad/s -> |dq(T)| = {:.3e} rad",
        (pert - base).fixed_rows::<3>(0).abs().max()
    );
    Ok(())
}
