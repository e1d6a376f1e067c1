//! ROS 2 trajectories and `freefloat check` (issue 23, docs/spec.md §3 "ROS 2"): messages written
//! and read back with ROS's field names and units, `check` of freefloat's own exported plans
//! reproducing their certificates (2-link and 3-link), a missed goal (exit 3 naming the
//! coordinate), and hostile trajectory files (exit 2 naming the point or joint).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use freefloat::model::arm::Arm;
use freefloat::model::arm::file::default_joint_names;
use freefloat::plan::Method;
use freefloat::plan::ros::{Encoding, JointTrajectory, MultiDOFJointTrajectory, from_text, to_text};
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::report::ros::{MotionRows, base_trajectory, joint_trajectory};

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("one JSON object ({e}): {}", stderr(o)))
}

fn example(name: &str) -> String {
    format!("{}/examples/robots/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temporary path")
}

/// A certified plan of the 3-link example arm with torques, 101 samples.
fn three_link_plan() -> (Arm, freefloat::planners::arm::ArmPlanned) {
    let arm = Arm::load(Path::new(&example("three_link.toml"))).expect("the example arm");
    let deg = |v: &[f64]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    let problem = ChainProblem::rest_to_rest(deg(&[0.0, 30.0, 60.0, 45.0]), deg(&[30.0, 75.0, 20.0, 90.0]), 7.3);
    let request = ArmRequest { samples: 101, torques: true, ..ArmRequest::new(problem) };
    let planned = plan_arm(&arm, Method::Optimal, &request).expect("certified");
    (arm, planned)
}

/// A JointTrajectory and its base companion, written as YAML and as JSON, read back equal
/// (every f64 round trips exactly); the fields carry ROS 2's names and units: `time_from_start`
/// as whole seconds and nanoseconds below 1e9 within 0.5 ns of the sample time, positions and
/// velocities in rad and rad/s as the plan has them, efforts the plan's torques in N m, the
/// base's rotation the quaternion about z of phi.
#[test]
fn joint_trajectory_written_and_read_back() {
    let (arm, planned) = three_link_plan();
    let names = default_joint_names(3);
    let rows = MotionRows::from_arm(&planned);
    let message = joint_trajectory(&rows, &names).expect("a message");
    let base = base_trajectory(&rows).expect("a message");
    for encoding in [Encoding::Yaml, Encoding::Json] {
        let text = to_text(&message, encoding).expect("encodes");
        for field in ["joint_names", "points", "positions", "velocities", "accelerations", "effort", "time_from_start"]
        {
            assert!(text.contains(field), "{encoding:?}: no `{field}`");
        }
        assert!(text.contains("sec") && text.contains("nanosec") && text.contains("joint3"), "{encoding:?}");
        let back: JointTrajectory = from_text(&text, encoding, "test").expect("decodes");
        assert_eq!(back, message, "{encoding:?}");
        let base_text = to_text(&base, encoding).expect("encodes");
        let back: MultiDOFJointTrajectory = from_text(&base_text, encoding, "test").expect("decodes");
        assert_eq!(back, base, "{encoding:?}");
    }
    for (i, point) in message.points.iter().enumerate() {
        let sample = &planned.trajectory[i];
        let d = point.time_from_start;
        assert!(d.nanosec < 1_000_000_000);
        assert!((d.seconds() - sample.t).abs() <= 0.5e-9 + 1e-15, "point {i}: {d:?}");
        assert_eq!(point.positions, sample.theta, "positions in rad");
        assert_eq!(point.velocities, sample.rate, "velocities in rad/s");
        assert_eq!(point.accelerations, sample.acceleration, "accelerations in rad/s^2");
        assert_eq!(point.effort, planned.torques.as_ref().expect("torques").tau[i], "effort in N m");
        let transform = base.points[i].transforms[0];
        assert!((transform.rotation.yaw() - freefloat::model::wrap_angle(sample.phi)).abs() < 1e-12, "point {i}");
        let position = arm.bodies(&rows.q[i]).base;
        assert!(
            (transform.translation.x - position[0]).abs() < 1e-15 && transform.translation.z.abs() < f64::MIN_POSITIVE
        );
    }
    assert_eq!(
        message.points.last().expect("points").time_from_start,
        freefloat::plan::ros::Duration { sec: 7, nanosec: 300_000_000 }
    );
}

/// A JointTrajectory as `ros2 topic echo` prints it (fields in ROS's order, a stamp and a frame
/// id, the document end `---`), with fields left out as `ros2 topic pub` allows (their defaults),
/// is read; an unknown field is refused.
#[test]
fn reads_the_ros2_echo_layout() {
    let text = "header:\n  stamp:\n    sec: 1700000000\n    nanosec: 5\n  frame_id: base_link\njoint_names:\n- joint1\n- joint2\n\
                points:\n- positions:\n  - 0.1\n  - -0.2\n  velocities: []\n  accelerations: []\n  effort: []\n  time_from_start:\n    sec: 0\n    nanosec: 0\n\
                - positions: [0.3, 0.4]\n  time_from_start:\n    sec: 2\n    nanosec: 500000000\n---\n";
    let m: JointTrajectory = from_text(text, Encoding::Yaml, "echo").expect("the echo layout");
    assert_eq!(m.header.frame_id, "base_link");
    assert_eq!(m.points[1].positions, vec![0.3, 0.4]);
    assert!(m.points[1].velocities.is_empty());
    assert!((m.points[1].time_from_start.seconds() - 2.5).abs() < 1e-15);
    let typo = text.replace("positions: [0.3", "position: [0.3");
    let e = from_text::<JointTrajectory>(&typo, Encoding::Yaml, "echo").expect_err("unknown field");
    assert!(e.to_string().contains("position"), "{e}");
}

/// `plan` exports the paper's problem (2-link robot) as YAML and as CSV, the 3-link example arm
/// as YAML and as JSON; `check` of each, from the plan's start to its goal, reproduces the
/// plan's certificate: its final error within 1e-9 rad of the plan's verified final error (both
/// integrate the same system at 1e-12; the check's motion is the quintic through the samples).
#[test]
fn check_of_an_exported_plan_equals_its_certificate() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let three = example("three_link.toml");
    type Case<'a> = (&'a str, Vec<&'a str>, &'a str, &'a str, &'a str);
    let cases: Vec<Case> = vec![
        ("src.yaml", vec![], "45,120,80", "0,180,140", "--format=joint-trajectory"),
        ("src.csv", vec![], "45,120,80", "0,180,140", "--format=table"),
        ("three.yaml", vec!["--robot", &three], "0,30,60,45", "30,75,20,90", "--format=table"),
        ("three.json", vec!["--robot", &three], "0,30,60,45", "30,75,20,90", "--format=joint-trajectory"),
    ];
    for (file, robot, from, to, format) in cases {
        let out = dir.path().join(file);
        let mut plan = vec!["plan", "--from", from, "--to", to, "--out", path_str(&out), format];
        plan.extend(&robot);
        let o = freefloat(&plan);
        assert!(o.status.success(), "{file}: {}", stderr(&o));
        let mut report = vec!["plan", "--from", from, "--to", to, "--format", "json"];
        report.extend(&robot);
        let planned = json(&freefloat(&report));
        let plan_error = planned["final_error"].as_f64().expect("final_error");
        let mut check = vec!["check", "--trajectory", path_str(&out), "--from", from, "--to", to, "--format", "json"];
        check.extend(&robot);
        let o = freefloat(&check);
        assert!(o.status.success(), "{file}: {}", stderr(&o));
        let r = json(&o);
        let error = r["final_error"].as_f64().expect("final_error");
        assert!((error - plan_error).abs() <= 1e-9, "{file}: check {error}, plan {plan_error}");
        assert_eq!(r["interpolation"], "quintic", "{file}");
        assert_eq!(r["holds"], true);
        for key in ["base", "max_abs_torque", "reached", "final_errors", "limits", "clearance"] {
            assert!(r.get(key).is_some(), "{file}: {key}");
        }
        assert!(r["limits"].is_null() && r["clearance"].is_null(), "no limits, no shapes: nothing to check");
    }
}

/// Another tool's trajectory is checked against the robot's limits and shapes (issues 20, 21:
/// the certificate's checks). Before, `check --limit all.velocity=5` accepted the flag, printed
/// "not checked" and exited 0 on a trajectory at 41 deg/s. Now a limit it leaves is exit 3 naming
/// the joint, the quantity and the numbers; a limit it keeps is in the JSON `limits` block; the
/// robot file's shapes and `--obstacle` are checked along the same integrated motion.
#[test]
fn a_trajectory_is_checked_against_the_limits_and_the_shapes() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let three = example("three_link.toml");
    let out = dir.path().join("three.csv");
    let ends = ["--from", "0,0,0,0", "--to", "30,10,10,10"];
    let o = freefloat(&[&["plan", "--robot", &three, "--out", path_str(&out)][..], &ends].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let check = ["check", "--robot", &three, "--trajectory", path_str(&out), "--to", "30,10,10,10"];
    let o = freefloat(&[&check[..], &["--limit", "all.velocity=5"]].concat());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("theta1's velocity") && stderr(&o).contains("(5 deg/s)"), "{}", stderr(&o));
    let o = freefloat(&[&check[..], &["--limit", "all.velocity=50", "--format", "json"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let r = json(&o);
    assert_eq!(r["limits"]["inside"], true, "{}", r["limits"]);
    let used = r["limits"]["uses"].as_array().unwrap().iter().map(|u| u["use"].as_f64().unwrap()).fold(0.0, f64::max);
    // 41.05 deg/s of 50 at its peak (between the points).
    assert!(used > 0.8 && used < 1.0, "{used}");
    // The SPART-like arm's plan that ignored the base: link 4 passes through it.
    let spart = format!("{}/tests/fixtures/spart_like_4dof_geometry.urdf", env!("CARGO_MANIFEST_DIR"));
    let through = dir.path().join("spart.csv");
    let no_base = ["--no-collide", "base,link2", "--no-collide", "base,link3", "--no-collide", "base,link4"];
    let plan = ["plan", "--urdf", &spart, "--from", "0,30,-60,45,-30", "--to", "30,60,-30,20,-60"];
    let o = freefloat(&[&plan[..], &no_base, &["--out", path_str(&through)]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let check = ["check", "--urdf", &spart, "--trajectory", path_str(&through)];
    let o = freefloat(&check);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("base and link 4"), "{}", stderr(&o));
    let o = freefloat(&[&check[..], &no_base, &["--format", "json"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&o)["clearance"]["holds"], true);
    let o = freefloat(&[&check[..], &no_base, &["--obstacle", "circle:1,1,0.2"]].concat());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("obstacle 1"), "{}", stderr(&o));
}

/// A goal the trajectory misses is exit 3, with the coordinate and its error on stderr: a joint
/// moved by 2 deg names that joint (2 deg = 0.0349 rad), the base moved by 3 deg names the base.
#[test]
fn a_missed_goal_exits_3_naming_the_joint_or_the_base() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let out = dir.path().join("p.yaml");
    assert!(freefloat(&["plan", "--out", path_str(&out)]).status.success());
    let check = |to: &str| freefloat(&["check", "--trajectory", path_str(&out), "--from", "45", "--to", to]);
    let o = check("0,180,142");
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("joint `joint2`") && e.contains("0.0349"), "{e}");
    assert!(String::from_utf8_lossy(&o.stdout).contains("MISSED"), "the table is still printed");
    let o = check("3,180,140");
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("base phi"), "{}", stderr(&o));
    let o =
        freefloat(&["check", "--trajectory", path_str(&out), "--from", "45", "--to", "0,180,142", "--format", "json"]);
    assert_eq!(json(&o)["holds"], false);
}

/// A two-point, two-joint message for the `src` preset, with `edit` applied to its JSON.
fn hostile(dir: &Path, name: &str, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let mut v = serde_json::json!({
        "joint_names": ["joint1", "joint2"],
        "points": [
            {"positions": [2.0, 1.4], "velocities": [0.0, 0.0], "time_from_start": {"sec": 0, "nanosec": 0}},
            {"positions": [2.5, 1.0], "velocities": [0.0, 0.0], "time_from_start": {"sec": 1, "nanosec": 0}},
            {"positions": [3.1, 2.4], "velocities": [0.0, 0.0], "time_from_start": {"sec": 2, "nanosec": 0}}
        ]
    });
    edit(&mut v);
    let path = dir.join(name);
    std::fs::write(&path, v.to_string()).expect("writable");
    path
}

/// Hostile trajectory files are bad input (exit 2, no panic), each message naming what is wrong:
/// times not increasing, not starting at 0, nanosec >= 1e9, a non-finite value (JSON's 1e999
/// is out of range; YAML's .nan), an unknown, a duplicate or a missing joint, arrays of the
/// wrong length, velocities on some points only, accelerations without velocities, more points
/// than MAX_POINTS, one point, an unknown field, a directory, and a file of another type.
#[test]
fn hostile_trajectory_files_exit_2() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let d = dir.path();
    let time = |k: usize, sec: i64, nanosec: i64| {
        move |v: &mut serde_json::Value| {
            v["points"][k]["time_from_start"] = serde_json::json!({"sec": sec, "nanosec": nanosec})
        }
    };
    let many = {
        let points: Vec<serde_json::Value> = (0..=freefloat::analysis::check::MAX_POINTS)
            .map(|k| serde_json::json!({"positions": [0.0, 1.0], "time_from_start": {"sec": k, "nanosec": 0}}))
            .collect();
        move |v: &mut serde_json::Value| v["points"] = serde_json::Value::Array(points.clone())
    };
    let cases: Vec<(PathBuf, &str)> = vec![
        (hostile(d, "unsorted.json", time(2, 0, 500_000_000)), "point 2"),
        (hostile(d, "late.json", time(0, 0, 1)), "point 0"),
        (hostile(d, "nanosec.json", time(1, 0, 1_000_000_000)), "nanosec"),
        (hostile(d, "negative.json", time(1, -1, 0)), "point 1"),
        (hostile(d, "unknown.json", |v| v["joint_names"][1] = "elbow".into()), "joint `elbow`"),
        (hostile(d, "duplicate.json", |v| v["joint_names"][1] = "joint1".into()), "twice"),
        (
            hostile(d, "missing.json", |v| {
                v["joint_names"] = serde_json::json!(["joint1"]);
                for p in v["points"].as_array_mut().expect("points") {
                    p["positions"] = serde_json::json!([1.0]);
                    p["velocities"] = serde_json::json!([0.0]);
                }
            }),
            "joint `joint2`",
        ),
        (hostile(d, "short.json", |v| v["points"][1]["positions"] = serde_json::json!([1.0])), "point 1"),
        (hostile(d, "some_velocities.json", |v| v["points"][1]["velocities"] = serde_json::json!([])), "point 1"),
        (
            hostile(d, "accelerations.json", |v| {
                for p in v["points"].as_array_mut().expect("points") {
                    p["velocities"] = serde_json::json!([]);
                    p["accelerations"] = serde_json::json!([0.0, 0.0]);
                }
            }),
            "without velocities",
        ),
        (hostile(d, "one.json", |v| v["points"] = serde_json::json!([v["points"][0].clone()])), "at least 2"),
        (hostile(d, "field.json", |v| v["points"][0]["positons"] = serde_json::json!([1.0, 2.0])), "positons"),
        (hostile(d, "many.json", many), "at most 100000"),
    ];
    let mut cases = cases;
    let inf = d.join("inf.json");
    let text = std::fs::read_to_string(&cases[0].0).expect("readable").replace("2.5,1.0", "2.5,1e999");
    std::fs::write(&inf, text).expect("writable");
    cases.push((inf, "number out of range"));
    let nan = d.join("nan.yaml");
    std::fs::write(&nan, "joint_names: [joint1, joint2]\npoints:\n- positions: [0.0, 1.0]\n- positions: [.nan, 1.0]\n  time_from_start: {sec: 1}\n").expect("writable");
    cases.push((nan, "NaN"));
    let other = d.join("plan.txt");
    std::fs::write(&other, "t\n").expect("writable");
    cases.push((other, ".yaml"));
    let folder = d.join("folder.yaml");
    std::fs::create_dir(&folder).expect("a directory");
    cases.push((folder, "not a regular file"));
    for (path, needle) in &cases {
        let o = freefloat(&["check", "--trajectory", path_str(path)]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{}: {e}", path.display());
        assert!(e.contains(needle), "{}: `{needle}` not in: {e}", path.display());
        assert!(!e.contains("panicked"), "{e}");
    }
    // The valid message itself checks (exit 0): each case fails by its edit alone.
    let ok = hostile(d, "ok.json", |_| {});
    let o = freefloat(&["check", "--trajectory", path_str(&ok)]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `--from` with the joints of another start than the trajectory's first point is bad input
/// naming the joint; a 3-link trajectory checked on the 2-link robot names the unknown joint.
#[test]
fn start_and_robot_must_fit_the_trajectory() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let out = dir.path().join("p.json");
    let three = example("three_link.toml");
    let plan = [
        "plan",
        "--robot",
        &three,
        "--from",
        "0,30,60,45",
        "--to",
        "30,75,20,90",
        "--format",
        "joint-trajectory",
        "--out",
        path_str(&out),
    ];
    assert!(freefloat(&plan).status.success());
    let o = freefloat(&["check", "--robot", &three, "--trajectory", path_str(&out), "--from", "0,30,61,45"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("joint `joint2`"), "{}", stderr(&o));
    let o = freefloat(&["check", "--trajectory", path_str(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("joint `joint3`"), "{}", stderr(&o));
}
