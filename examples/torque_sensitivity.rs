//! How much the open-loop forward dynamics of a torque plan amplify a small error: integrates
//! the dynamics with the planned torques from rest and from rest plus a 1e-9 rad/s joint velocity.
use freefloat::dynamics::{forward_dynamics, joint_torques};
use freefloat::numerics::ode::{OdeOptions, integrate};
use freefloat::plan::Motion;
use freefloat::{Configuration, Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams};
use nalgebra::Vector6;

fn main() -> Result<(), freefloat::Error> {
    let args: Vec<f64> = std::env::args().skip(1).filter_map(|s| s.parse().ok()).collect();
    let (a, b) = (args.first().copied().unwrap_or(1.0), args.get(1).copied().unwrap_or(-1.0));
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
