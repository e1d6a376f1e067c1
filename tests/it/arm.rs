//! The n-link arm model through the public API: the paper's five torque cases by the general
//! model, and robot files (TOML and URDF) read from disk.

use freefloat::dynamics::arm::inverse_dynamics;
use freefloat::model::InputError;
use freefloat::model::arm::Arm;
use freefloat::plan::Motion;
use freefloat::{Mount, NfaOptions, NormalFormPlanner, PlanningProblem, RobotParams, Transform};

/// The paper's five NFA cases (Figs. 4-8): the joint torques of the general n-link model
/// (`Arm::from_params`, n = 2 point masses) equal the SRC robot's hand-derived
/// `dynamics::joint_torques` at every sample, to 1e-12 relative to the case's peak torque.
#[test]
fn paper_cases_torques_by_the_general_model() {
    let cases = [
        (0.0, Transform::Eq11),
        (0.0, Transform::Eq12),
        (0.1, Transform::Eq14),
        (0.2, Transform::Eq14),
        (0.3, Transform::Eq14),
    ];
    for (a, transform) in cases {
        let robot = RobotParams::src().with_mount(Mount::new(a, a).unwrap()).unwrap();
        let options = NfaOptions { transform: Some(transform), accelerations: true, ..Default::default() };
        let (plan, motion) = NormalFormPlanner::new(options).plan_with_motion(&PlanningProblem::paper(robot)).unwrap();
        let arm = Arm::from_params(&robot);
        let k = robot.lumped();
        let points = motion.points(&plan.trajectory.t).unwrap();
        let (mut worst, mut peak) = (0.0_f64, 0.0_f64);
        for p in &points {
            let src = freefloat::dynamics::joint_torques(&k, p);
            let general = inverse_dynamics(&arm, &[p.q.theta1, p.q.theta2], &p.u, &p.du).tau;
            for i in 0..2 {
                worst = worst.max((general[i] - src[i]).abs());
                peak = peak.max(src[i].abs());
            }
        }
        eprintln!(
            "a = b = {a}, {transform:?}: {} samples, torques differ by {:.1e} of the peak",
            points.len(),
            worst / peak
        );
        assert!(worst <= 1e-12 * peak, "a = b = {a}, {transform:?}: torques differ by {worst:e} (peak {peak})");
    }
}

/// `Arm::load` picks the format by the extension (`.urdf` in any case), and a bad URDF's message
/// names the offending joint.
#[test]
fn arm_load_reads_toml_and_urdf_and_names_bad_joints() {
    let dir = tempfile::tempdir().unwrap();
    let arm = Arm::from_params(&RobotParams::src());
    let toml = dir.path().join("robot.toml");
    std::fs::write(&toml, arm.to_toml()).unwrap();
    assert_eq!(Arm::load(&toml).unwrap(), arm);
    let upper = dir.path().join("ROBOT.URDF");
    std::fs::write(&upper, arm.to_urdf()).unwrap();
    assert_eq!(Arm::load(&upper).unwrap().as_src(), Some(RobotParams::src()));
    let bad = dir.path().join("bad.urdf");
    std::fs::write(&bad, arm.to_urdf().replacen("continuous", "prismatic", 1)).unwrap();
    let e = Arm::load(&bad).unwrap_err();
    assert!(matches!(&e, InputError::Urdf { element, .. } if element == "joint `joint1`"), "{e}");
    let message = e.to_string();
    assert!(
        message.contains("bad.urdf") && message.contains("joint `joint1`") && message.contains("type prismatic"),
        "{message}"
    );
    assert!(matches!(Arm::load(dir.path()), Err(InputError::NotAFile { .. })));
}
