//! The limits of URDF and TOML robot files read, refused and round-tripped (issue 20).

use std::path::Path;

use super::*;

fn urdf(text: &str) -> Result<Arm, InputError> {
    Arm::from_urdf_str(text, Path::new("robot.urdf"))
}

const LINK: &str = r#"<inertial><origin xyz="0.2 0 0"/><mass value="2"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0.03"/></inertial>"#;

/// A 2-joint URDF: joint `shoulder` of `kind1` with `extra1` inside, `elbow` continuous with
/// `extra2` inside, and a `<transmission>` whose `<joint>` must not be read as a joint.
fn two_joints(kind1: &str, extra1: &str, extra2: &str) -> String {
    let z = r#"<axis xyz="0 0 1"/>"#;
    format!(
        r#"<robot name="r">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="0.5"/></inertial></link>
  <link name="upper">{LINK}</link>
  <link name="fore">{LINK}</link>
  <joint name="shoulder" type="{kind1}"><parent link="base"/><child link="upper"/><origin xyz="0.3 0 0"/>{z}{extra1}</joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/>{z}{extra2}</joint>
  <transmission name="t"><joint name="elbow"><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></transmission>
</robot>"#
    )
}

#[test]
fn urdf_limits_are_read_for_revolute_and_continuous_joints() {
    let arm = urdf(&two_joints(
        "revolute",
        r#"<limit lower="-2" upper="1.5" effort="50" velocity="0.3"/>"#,
        r#"<limit lower="-9" upper="9" effort="7" velocity="2"/>"#,
    ))
    .unwrap();
    let j = arm.limits.joint(0);
    assert_eq!(j.position, Some([-2.0, 1.5]));
    assert_eq!(j.velocity, Some(0.3));
    assert_eq!(j.torque, Some(50.0));
    assert_eq!(j.acceleration, None);
    // Continuous: velocity and effort only.
    assert_eq!(
        arm.limits.joint(1),
        JointLimits { position: None, velocity: Some(2.0), torque: Some(7.0), acceleration: None }
    );
    assert_eq!(arm.limits.base, None);
    // A continuous joint without <limit> is unlimited; the transmission's <joint> is not read.
    let arm = urdf(&two_joints("continuous", "", "")).unwrap();
    assert!(arm.limits.is_empty(), "{:?}", arm.limits);
}

#[test]
fn a_revolute_joint_without_limit_is_refused_by_name() {
    let Err(InputError::Urdf { element, reason, .. }) = urdf(&two_joints("revolute", "", "")) else {
        panic!("refused")
    };
    assert!(element.contains("shoulder"), "{element}");
    assert!(reason.contains("<limit"), "{reason}");
}

#[test]
fn bad_urdf_limits_name_the_joint_and_the_attribute() {
    for (limit, attribute) in [
        (r#"<limit lower="-2" upper="2" effort="50" velocity="0"/>"#, "limit.velocity"),
        (r#"<limit lower="-2" upper="2" effort="-1" velocity="1"/>"#, "limit.effort"),
        (r#"<limit lower="2" upper="-2" effort="50" velocity="1"/>"#, "limit.upper"),
        (r#"<limit lower="-inf" upper="2" effort="50" velocity="1"/>"#, "limit.lower"),
        (r#"<limit lower="-2" upper="NaN" effort="50" velocity="1"/>"#, "limit.upper"),
    ] {
        let e = urdf(&two_joints("revolute", limit, "")).expect_err(limit);
        let message = e.to_string();
        assert!(message.contains(attribute) && message.contains("shoulder"), "{limit}: {message}");
    }
}

#[test]
#[allow(clippy::approx_constant)] // the file's 3.1416
fn the_spart_like_files_carry_their_limits() {
    let arm = Arm::load(Path::new("examples/robots/spart_like_4dof.urdf")).unwrap();
    assert_eq!(arm.limits.joints.len(), 4);
    for j in &arm.limits.joints {
        assert_eq!(
            *j,
            JointLimits {
                position: Some([-3.1416, 3.1416]),
                velocity: Some(1.0),
                torque: Some(20.0),
                acceleration: None
            }
        );
    }
    let tight = Arm::load(Path::new("tests/fixtures/spart_like_4dof_tight.urdf")).unwrap();
    for j in &tight.limits.joints {
        assert_eq!(
            *j,
            JointLimits { position: Some([-2.0, 2.0]), velocity: Some(0.3), torque: Some(50.0), acceleration: None }
        );
    }
    // The same arm otherwise.
    assert_eq!(Arm { limits: Limits::default(), ..tight }, Arm { limits: Limits::default(), ..arm });
}

const TOML: &str = "[robot]\nM = 12.9\nI = 0.208\nlimit = { lower = -0.5, upper = 1.0 }\n\
    [[link]]\nlength = 0.45\ncom = 0.225\nmass = 3.0\ninertia = 0.05\n\
    limit = { lower = -2.0, upper = 2.0, velocity = 0.3, effort = 50.0, acceleration = 1.5 }\n\
    [[link]]\nlength = 0.4\ncom = 0.2\nmass = 2.0\ninertia = 0.02\n\
    [[link]]\nlength = 0.35\ncom = 0.175\nmass = 1.0\ninertia = 0.01\nlimit = { velocity = 0.1 }\n";

#[test]
fn toml_limits_are_read_and_round_trip() {
    let arm = Arm::from_toml(TOML, Path::new("arm.toml")).unwrap();
    assert_eq!(arm.limits.base, Some([-0.5, 1.0]));
    assert_eq!(
        arm.limits.joints,
        vec![
            JointLimits {
                position: Some([-2.0, 2.0]),
                velocity: Some(0.3),
                torque: Some(50.0),
                acceleration: Some(1.5)
            },
            JointLimits::default(),
            JointLimits { velocity: Some(0.1), ..JointLimits::default() },
        ]
    );
    let text = arm.to_toml();
    let back = Arm::from_toml(&text, Path::new("back.toml")).unwrap();
    assert_eq!(back, arm, "{text}");
    // The JSON robot block shows them too, and reads back.
    let json = serde_json::to_string(&arm).unwrap();
    assert!(json.contains("\"limits\""), "{json}");
    assert_eq!(serde_json::from_str::<Arm>(&json).unwrap(), arm);
    // Without limits: nothing written, nothing read.
    let plain = Arm { limits: Limits::default(), ..arm };
    assert!(!plain.to_toml().contains("limit"));
    assert!(!serde_json::to_string(&plain).unwrap().contains("limits"));
}

#[test]
fn bad_toml_limits_are_refused_by_key() {
    for (from, to, key) in [
        ("velocity = 0.3", "velocity = 0.0", "link[1].limit.velocity"),
        ("velocity = 0.3", "speed = 0.3", "speed"),
        ("lower = -2.0, ", "", "link[1].limit.lower"),
        ("upper = 2.0", "upper = -3.0", "link[1].limit.upper"),
        ("lower = -0.5, upper = 1.0", "lower = 1.0, upper = 0.5", "robot.limit.upper"),
        ("effort = 50.0", "effort = nan", "link[1].limit.effort"),
    ] {
        let text = TOML.replacen(from, to, 1);
        let e = Arm::from_toml(&text, Path::new("arm.toml")).expect_err(to);
        assert!(e.to_string().contains(key), "{to}: {e}");
    }
}
