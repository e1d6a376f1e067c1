//! `freefloat plan` with any planar serial arm, as a user runs it: a robot file with
//! `[[link]]`, the same arm as URDF, a 2-link arm with link inertias through the whole 2-link
//! pipeline, its animated GIF, and the refusals.

use std::process::{Command, Output};

use freefloat::RobotParams;
use freefloat::model::arm::Arm;
use freefloat::report::plot::GifOptions;

use super::animation::decode;

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn example(name: &str) -> String {
    format!("{}/examples/robots/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

const FROM: &str = "0,60,-30,-30";
const TO: &str = "30,120,40,-60";

/// The 3-link example arm plans rest to rest, certified at both levels; the same arm read from
/// its URDF gives the same plan (the URDF round trip is exact to 1e-12, so the efforts agree far
/// below the planner's own tolerances).
#[test]
fn three_link_arm_plans_from_toml_and_urdf() {
    let toml = example("three_link.toml");
    let args = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--torques", "--format", "json"];
    let r = json(&freefloat(&args));
    assert_eq!(r["joints"], 3);
    assert_eq!(r["certified"], true);
    assert!(r["final_error"].as_f64().unwrap() <= 1e-9, "{r}");
    assert!(r["verification"]["max_abs_momentum"].as_f64().unwrap() <= 1e-12, "{r}");
    assert_eq!(r["torque_certificate"]["certificate"]["certified"], true, "{r}");
    assert_eq!(r["max_abs_torque"].as_array().unwrap().len(), 3);
    let urdf = example("three_link.urdf");
    let u = json(&freefloat(&["plan", "--urdf", &urdf, "--from", FROM, "--to", TO, "--format", "json"]));
    let (a, b) = (r["effort"].as_f64().unwrap(), u["effort"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-8 * a, "TOML {a}, URDF {b}");
}

/// `--method ecsa` plans the 3-link example arm (issue 14), with the sin^2 window certified at
/// both levels (the minimum-norm solution's torques: the pseudo-inverse iteration's large
/// harmonics failed the torque level; the plain series, which moves at t = 0, fails it from
/// rest), with the ECSA's account (solver, iterations, residual) in place of the optimal
/// planner's; the table names the iteration; a moving start is bad input (the ECSA plans from
/// rest).
#[test]
fn three_link_arm_plans_with_the_ecsa() {
    let toml = example("three_link.toml");
    // The sin^2 window starts and ends at rest, so its torques can be followed from rest.
    let args = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "ecsa", "--torques"];
    let o = freefloat(&[&args[..], &["--window", "sin2", "--format", "json"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let r = json(&o);
    assert_eq!(r["method"], "ecsa");
    assert_eq!(r["joints"], 3);
    assert_eq!(r["certified"], true);
    assert!(r["final_error"].as_f64().unwrap() <= 1e-9, "{r}");
    assert!(r["optimal"].is_null(), "{r}");
    assert_eq!(r["torque_certificate"]["certificate"]["certified"], true, "{r}");
    let e = &r["ecsa"];
    assert_eq!(e["solver"], "minimum_norm", "{r}");
    assert!(e["continuation_steps"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(e["iteration"]["termination"], "converged", "{r}");
    assert!(e["iteration"]["residual"].as_f64().unwrap() <= 1e-10, "{r}");
    assert!(e["iteration"]["iterations"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(e["coefficients"].as_array().unwrap().len(), 9);
    let optimal = json(&freefloat(&["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--format", "json"]));
    assert!(optimal["ecsa"].is_null() && optimal["optimal"]["iterations"].is_u64(), "{optimal}");
    // The plain series moves at t = 0: its torque level, started from the problem's state (at
    // rest), is not certified (exit 3, the level named), as the 2-link robot's.
    let plain = freefloat(&args);
    assert_eq!(plain.status.code(), Some(3), "{}", stderr(&plain));
    assert!(stderr(&plain).contains("torque level"), "{}", stderr(&plain));
    let table = freefloat(&["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "ecsa"]);
    assert_eq!(table.status.code(), Some(0), "{}", stderr(&table));
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("ecsa") && text.contains("CERTIFIED") && text.contains("iteration"), "{text}");
    // The ECSA's harmonics and window reach the n-joint ECSA (they were silently ignored).
    let sin2 = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "ecsa", "--harmonics", "2"];
    let sin2 = json(&freefloat(&[&sin2[..], &["--window", "sin2", "--format", "json"]].concat()));
    assert_eq!(sin2["certified"], true, "{sin2}");
    assert_eq!(
        (sin2["ecsa"]["harmonics"].as_u64(), sin2["ecsa"]["window"].as_str()),
        (Some(2), Some("sin_squared")),
        "{sin2}"
    );
    let moving = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "ecsa", "--from-velocity", "5,0,0"];
    let o = freefloat(&moving);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("from rest"), "{}", stderr(&o));
}

/// `--out FILE.csv` has one column per joint (and torque), and every row its n + 1 angles.
#[test]
fn arm_csv_has_a_column_per_joint() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("arm.csv");
    let toml = example("three_link.toml");
    let o = freefloat(&[
        "plan",
        "--robot",
        &toml,
        "--from",
        FROM,
        "--to",
        TO,
        "--torques",
        "--samples",
        "11",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert!(header.contains(&"theta3") && header.contains(&"tau3") && !header.contains(&"theta4"), "{header:?}");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 11);
    assert!(rows.iter().all(|r| r.len() == header.len() && r.iter().all(|x| x.is_finite())));
}

/// `plan --robot three_link.toml --gif` writes a GIF of the arm's motion that decodes: the size
/// asked, one frame per `1 / fps` of the loop and the last, an infinite loop, the motion shows
/// (the first and last frames differ); only the GIF is written. Bad `--gif` paths and sizes exit
/// 2 before planning, with the flag named, and write nothing.
#[test]
fn three_link_arm_writes_an_animated_gif() {
    let dir = tempfile::tempdir().unwrap();
    let toml = example("three_link.toml");
    let file = dir.path().join("arm.gif");
    let gif = file.to_str().unwrap();
    let base = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--samples", "201", "--quiet"];
    let size = ["--gif-width", "320", "--gif-height", "240", "--gif-fps", "5"];
    let o = freefloat(&[&base[..], &["--gif", gif], &size[..]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let decoded = decode(&std::fs::read(&file).expect("the GIF is written"));
    let options = GifOptions::new(320, 240, 5).unwrap();
    assert_eq!(decoded.size, (320, 240));
    assert_eq!(decoded.frames.len(), options.frame_count(10.0));
    assert_eq!(decoded.repeat, gif::Repeat::Infinite);
    assert_ne!(decoded.frames.first().map(|f| &f.1), decoded.frames.last().map(|f| &f.1), "no motion shows");
    let files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(files, vec![std::ffi::OsString::from("arm.gif")]);

    let bad = tempfile::tempdir().unwrap();
    let at = |name: &str| bad.path().join(name).to_str().unwrap().to_string();
    let cases: [(Vec<String>, &str); 5] = [
        (vec!["--gif".into(), at("arm.png")], "must end in .gif"),
        (vec!["--gif".into(), at("no/such/dir/arm.gif")], "no/such/dir/arm.gif"),
        (vec!["--gif".into(), at("arm.gif"), "--gif-width".into(), "100".into()], "--gif-width"),
        (vec!["--gif".into(), at("arm.gif"), "--gif-fps".into(), "51".into()], "--gif-fps"),
        (vec!["--gif-height".into(), "480".into()], "--gif"),
    ];
    for (extra, message) in cases {
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let o = freefloat(&[&base[..], &extra].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{extra:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{extra:?}");
    }
    assert_eq!(std::fs::read_dir(bad.path()).unwrap().count(), 0, "a refused run wrote a file");
}

/// What an n-link arm cannot take is refused (exit 2) with the reason: the NFA (its chained
/// form is the 2-link robot's), 3 angles for a 3-link arm, the 2-link commands.
#[test]
fn arm_refusals_name_the_reason() {
    let toml = example("three_link.toml");
    let o = freefloat(&["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "nfa"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("chained form"), "{}", stderr(&o));
    let o = freefloat(&["plan", "--robot", &toml]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--from takes 4"), "{}", stderr(&o));
    let o = freefloat(&["domain", "--robot", &toml]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("3 link") && stderr(&o).contains("two joints"), "{}", stderr(&o));
}

/// A 2-link arm with link inertias (from a URDF) takes the whole 2-link pipeline, the NFA
/// included; its plan differs from the point-mass robot's (the inertias matter).
#[test]
fn two_link_arm_with_inertia_takes_the_nfa() {
    let dir = tempfile::tempdir().unwrap();
    let mut arm = Arm::from_params(&RobotParams::src());
    arm.links[0].inertia = 4.5 * 0.619 * 0.619 / 12.0;
    arm.links[1].inertia = 1.5 * 0.6 * 0.6 / 12.0;
    let path = dir.path().join("two.urdf");
    std::fs::write(&path, arm.to_urdf()).unwrap();
    let path = path.to_str().unwrap();
    let with = json(&freefloat(&["plan", "--urdf", path, "--method", "nfa", "--torques", "--format", "json"]));
    assert_eq!(with["certified"], true, "{with}");
    let without = json(&freefloat(&["plan", "--method", "nfa", "--format", "json"]));
    let (a, b) = (with["max_abs_u"][0].as_f64().unwrap(), without["max_abs_u"][0].as_f64().unwrap());
    assert!((a - b).abs() > 1e-6 * b, "the link inertias changed nothing: {a} vs {b}");
}

// ---------------------------------------------------------------------------------------------
// Issue 19, items 4-6: every `plan` flag, `compare`, `--to-ee` and every output for any arm.

const FROM4: &str = "0,30,30,30,30";
/// The SPART-like arm without its limits (issue 20): these tests are not about limits.
const UNLIMITED4: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/spart_like_4dof_unlimited.urdf");
const TO4: &str = "20,60,-30,40,10";

/// The arms of the tests: the 3-link TOML and the SPART-like 4-link URDF, with their problems.
fn arms() -> [([String; 2], &'static str, &'static str); 2] {
    [(["--robot".into(), example("three_link.toml")], FROM, TO), (["--urdf".into(), UNLIMITED4.into()], FROM4, TO4)]
}

/// A free-floating forward kinematics of the test's own, from the robot's parameters alone:
/// every body's position relative to the base's centre of mass, then the whole shifted so that
/// the system's centre of mass is at the origin. Returns the base's centre of mass and the tool point `tool` m along the last link.
fn own_fk(arm: &Arm, q: &[f64], tool: f64) -> ([f64; 2], [f64; 2]) {
    let (sp, cp) = q[0].sin_cos();
    let mut joint = [cp * arm.mount.a - sp * arm.mount.b, sp * arm.mount.a + cp * arm.mount.b];
    let mut psi = q[0];
    let mut moment = [0.0, 0.0];
    let mut mass = arm.base.mass;
    let mut tip = joint;
    for (k, link) in arm.links.iter().enumerate() {
        psi += q[k + 1];
        let e = [psi.cos(), psi.sin()];
        moment = [
            moment[0] + link.mass * (joint[0] + link.com * e[0]),
            moment[1] + link.mass * (joint[1] + link.com * e[1]),
        ];
        mass += link.mass;
        if k + 1 == arm.links.len() {
            tip = [joint[0] + tool * e[0], joint[1] + tool * e[1]];
        }
        joint = [joint[0] + link.length * e[0], joint[1] + link.length * e[1]];
    }
    let base = [-moment[0] / mass, -moment[1] / mass];
    (base, [tip[0] + base[0], tip[1] + base[1]])
}

/// The CSV as a header and rows of numbers (empty cells as NaN).
fn csv_table(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines.next().expect("a header").split(',').map(String::from).collect();
    let rows = lines.map(|l| l.split(',').map(|x| x.parse().unwrap_or(f64::NAN)).collect()).collect();
    (header, rows)
}

/// The CSV of a 3-link and a 4-link arm has the base and end-effector columns of the 2-link CSV
/// (`xb, yb, xe, ye, psie, dxe, dye, dpsie`), `ddphi` and `n` torques; the end effector is the
/// tool point of the test's own forward kinematics at every sample (to 1e-12 m), its velocity
/// the central difference of the positions (to 1e-4 m/s at dt = 0.01 s: the difference's
/// truncation), and `ddphi` the central difference of `dphi`.
#[test]
fn arm_csv_has_base_and_end_effector_columns_checked_by_forward_kinematics() {
    for (robot, from, to) in arms() {
        let args = ["plan", &robot[0], &robot[1], "--from", from, "--to", to, "--torques", "--format", "csv"];
        let o = freefloat(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let (header, rows) = csv_table(&String::from_utf8_lossy(&o.stdout));
        let arm = Arm::load(robot[1].as_ref()).unwrap();
        let n = arm.joints();
        let col = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("{name} in {header:?}"));
        for name in ["xb", "yb", "xe", "ye", "psie", "dxe", "dye", "dpsie", "ddphi", &format!("tau{n}")] {
            col(name);
        }
        assert!(!header.iter().any(|h| h == "z1"), "{header:?}");
        assert!(rows.iter().all(|r| r.len() == header.len() && r.iter().all(|x| x.is_finite())));
        let tool = arm.links[n - 1].length;
        for r in rows.iter().step_by(97) {
            let q: Vec<f64> = (0..=n).map(|k| r[col("phi") + k]).collect();
            let (base, tip) = own_fk(&arm, &q, tool);
            assert!((r[col("xb")] - base[0]).abs() < 1e-12 && (r[col("yb")] - base[1]).abs() < 1e-12, "{r:?}");
            assert!((r[col("xe")] - tip[0]).abs() < 1e-12 && (r[col("ye")] - tip[1]).abs() < 1e-12, "{r:?}");
            assert!((r[col("psie")] - q.iter().sum::<f64>()).abs() < 1e-12);
        }
        let i = rows.len() / 2;
        let dt = rows[i + 1][0] - rows[i - 1][0];
        let miss = |x: &str, v: &str| ((rows[i + 1][col(x)] - rows[i - 1][col(x)]) / dt - rows[i][col(v)]).abs();
        for (x, v) in [("xe", "dxe"), ("ye", "dye")] {
            assert!(miss(x, v) < 1e-4, "{x}: {}", miss(x, v));
        }
        // The plan's splines have jumps of the jerk at their knots (t = T/2 among them), so the
        // joints' own accelerations miss their differences there by O(dt); ddphi, a combination of
        // them through Eq. 7, may miss by a few times theirs, not more.
        let joints = (1..=n).map(|k| miss(&format!("dtheta{k}"), &format!("ddtheta{k}"))).fold(0.0, f64::max);
        assert!(miss("dphi", "ddphi") <= 20.0 * joints + 1e-9, "ddphi: {} vs joints' {joints}", miss("dphi", "ddphi"));
    }
}

/// `--max-velocity` stretches the horizon until the peak joint velocity is the cap (velocities
/// scale as 1/T along the same path), says so in the notes, and the plan stays certified;
/// `--from-velocity` with `n` values starts there; `--format joint-trajectory` names the joints.
#[test]
fn arm_plan_takes_max_velocity_from_velocity_and_joint_trajectory() {
    for (robot, from, to) in arms() {
        let base = ["plan", &robot[0], &robot[1], "--from", from, "--to", to, "--quiet"];
        let free = json(&freefloat(&[&base[..], &["--format", "json"]].concat()));
        let peak = free["max_abs_u"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).fold(0.0, f64::max);
        let cap = 0.5 * peak;
        let capped = json(&freefloat(&[&base[..], &["--format", "json", "--max-velocity", &cap.to_string()]].concat()));
        assert_eq!(capped["certified"], true, "{capped}");
        let time = capped["time"].as_f64().unwrap();
        assert!(time > 1.9 * 10.0 && time < 2.1 * 10.0, "{time}");
        let peak2 = capped["max_abs_u"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).fold(0.0, f64::max);
        assert!(peak2 <= cap * (1.0 + 1e-6), "{peak2} > {cap}");
        assert!(capped["notes"].to_string().contains("--max-velocity"), "{capped}");
        let n = capped["joints"].as_u64().unwrap() as usize;
        let velocity = (1..=n).map(|k| (2 * k).to_string()).collect::<Vec<_>>().join(",");
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("moving.json");
        let moving = ["--from-velocity", &velocity, "--out", out.to_str().unwrap(), "--format", "json"];
        let m = json(&freefloat(&[&base[..], &moving[..]].concat()));
        assert_eq!(m["certified"], true, "{m}");
        let written: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        let dq0 = &written["trajectory"]["dq"][0];
        for k in 1..=n {
            let expected = (2.0 * k as f64).to_radians();
            assert!((dq0[k].as_f64().unwrap() - expected).abs() < 1e-9, "{dq0}");
        }
        let o = freefloat(&[&base[..], &["--format", "joint-trajectory"]].concat());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let yaml = String::from_utf8_lossy(&o.stdout);
        assert!(yaml.contains("joint_names") && yaml.contains("points"), "{yaml}");
    }
}

/// `compare` on a 3-link and a 4-link arm: the optimal planner and the ECSA, both certified, the
/// NFA listed as refused with the reason (its chained form is the 2-link robot's); exit 0.
#[test]
fn arm_compare_lists_every_method() {
    for (robot, from, to) in arms() {
        // The ECSA with the sin^2 window starts at rest: its torque level holds from rest.
        let base = ["compare", &robot[0], &robot[1], "--from", from, "--to", to, "--torques", "--window", "sin2"];
        let r = json(&freefloat(&[&base[..], &["--format", "json"]].concat()));
        for method in ["optimal", "ecsa"] {
            assert_eq!(r[method]["certified"], true, "{method}: {r}");
            assert_eq!(r[method]["torque_certificate"]["certificate"]["certified"], true, "{method}: {r}");
        }
        assert!(r["nfa"].is_null() && r["errors"]["nfa"].as_str().unwrap().contains("chained form"), "{r}");
        // The minimum-effort plan's effort is at most the ECSA's (same problem, same goal).
        assert!(r["optimal"]["effort"].as_f64() <= r["ecsa"]["effort"].as_f64(), "{r}");
        let o = freefloat(&base);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("(refused)") && text.contains("optimal") && text.contains("ECSA"), "{text}");
    }
}

/// The stdout of a run that must exit 0 (a table).
fn table(args: &[&str]) -> String {
    let o = freefloat(args);
    assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// One `compare` table for every robot (issue 19): the paper's robot with a joint limit, planned
/// by the n-joint pipeline (the NFA refused), has the rows of the paper's robot in the 2-link
/// pipeline, in the same order and columns.
#[test]
fn arm_compare_has_the_two_link_rows() {
    let labels = |args: &[&str]| {
        let text = table(args);
        let rows: Vec<String> = text
            .lines()
            .skip(2)
            .take_while(|line| !["optimal", "nfa", "ecsa"].iter().any(|m| line.starts_with(&format!("  {m}: "))))
            .map(|line| line[2..33].trim_end().to_string())
            .collect();
        (rows, text)
    };
    let (two_link, text) = labels(&["compare"]);
    let (arm, arm_text) = labels(&["compare", "--limit", "theta2.velocity=500"]);
    assert_eq!(two_link, arm, "{text}\n{arm_text}");
    assert!(two_link.len() == 18 && two_link.contains(&"min |sigma|, min |P|".to_string()), "{text}");
    assert!(arm_text.starts_with("freefloat compare: 2-link arm, "), "{arm_text}");
    // The NFA of the paper's model is planned for the arm too (as `plan --method nfa` plans it,
    // checked against the limit): the same closed-form plan, the same effort, inside the limit.
    let effort = |text: &str| text.lines().nth(2).and_then(|l| l.split_whitespace().nth(3)).map(str::to_string);
    assert!(!arm_text.contains("(refused)") && effort(&arm_text).is_some(), "{arm_text}");
    assert_eq!(effort(&text), effort(&arm_text), "{text}\n{arm_text}");
}

/// One `plan` table for every robot: the paper's robot as a 2-link arm (a limit sends it through
/// the `n`-joint planner) has the 2-link table's lines, with the same labels in the same order,
/// where both apply.
#[test]
fn arm_plan_has_the_two_link_lines() {
    let labels = |args: &[&str]| {
        let text = table(args);
        let rows: Vec<String> = text
            .lines()
            .skip(1)
            .filter(|line| line.len() > 27)
            .map(|line| line[2..27].trim_end().to_string())
            .collect();
        (rows, text)
    };
    let (two_link, text) = labels(&["plan", "--torques", "--samples", "201"]);
    let (arm, arm_text) = labels(&["plan", "--torques", "--samples", "201", "--limit", "theta2.velocity=500"]);
    let shared = [
        "start q0 [deg]",
        "goal  qd [deg]",
        "horizon",
        "reached q(T) [deg]",
        "verified final error",
        "effort",
        "max |u1|, |u2|",
        "optimality",
        "min |sigma|, |P|",
        "joint travel [deg]",
        "max |tau1|, |tau2|",
        "torque final error",
        "max |base row of (6)|",
        "time",
    ];
    let kept = |rows: &[String]| rows.iter().filter(|r| shared.contains(&r.as_str())).cloned().collect::<Vec<_>>();
    assert_eq!(kept(&two_link), shared, "{text}");
    assert_eq!(kept(&arm), shared, "{arm_text}");
    assert!(arm_text.starts_with("freefloat plan: optimal (minimum effort), 2-link arm, "), "{arm_text}");
    assert!(arm.iter().any(|r| r == "limits") && arm.iter().any(|r| r == "max |angular momentum|"), "{arm_text}");
    // Both levels' angular momentum lines, each naming its level (not told apart by position).
    let momentum: Vec<&str> = arm_text.lines().filter(|l| l.contains("max |angular momentum|")).collect();
    assert_eq!(momentum.len(), 2, "{arm_text}");
    assert!(momentum[0].ends_with("(velocity level)") && momentum[1].ends_with("(torque level)"), "{arm_text}");
}

/// `--to-ee` on the SPART-like 4-link URDF: the final sample's tool point (the test's own
/// forward kinematics) is the pose, every inverse-kinematics branch tried is listed with its
/// residual and effort, and the plan kept is the certified one of least effort; the notes name
/// the tool frame `EE`, 0.5 m along link 4. A pose out of reach exits 2 naming the reach.
#[test]
fn to_ee_on_the_four_link_urdf_reaches_the_pose() {
    let urdf = UNLIMITED4.to_string();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pose.json");
    let (x, y, psi) = (0.3, 1.5, 120.0_f64);
    let args = ["plan", "--urdf", &urdf, "--from", FROM4, "--to-ee", "0.3,1.5,120", "--format", "json"];
    let r = json(&freefloat(&[&args[..], &["--out", out.to_str().unwrap()]].concat()));
    assert_eq!(r["certified"], true, "{r}");
    let branches = r["to_ee"]["branches"].as_array().unwrap();
    assert!(branches.len() >= 2, "{r}");
    let efforts: Vec<f64> = branches.iter().filter_map(|b| b["effort"].as_f64()).collect();
    assert!(!efforts.is_empty());
    for b in branches {
        assert!(b["branch"].is_string() && b["residual"].is_f64() && b["reached"].is_boolean(), "{b}");
    }
    let kept: Vec<_> = branches.iter().filter(|b| b["kept"] == true).collect();
    assert_eq!(kept.len(), 1, "{r}");
    let least = efforts.iter().copied().fold(f64::INFINITY, f64::min);
    assert_eq!(kept[0]["effort"].as_f64(), Some(least));
    assert!((r["effort"].as_f64().unwrap() - least).abs() <= 1e-12 * least);
    assert!(r["notes"].to_string().contains("frame `EE`, 0.5 m along link 4"), "{}", r["notes"]);
    let written: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let q: Vec<f64> = written["trajectory"]["q"]
        .as_array()
        .unwrap()
        .last()
        .unwrap()
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let arm = Arm::load(urdf.as_ref()).unwrap();
    let (_, tip) = own_fk(&arm, &q, 0.5);
    assert!((tip[0] - x).abs() < 1e-8 && (tip[1] - y).abs() < 1e-8, "{tip:?}");
    let turn = (q.iter().sum::<f64>() - psi.to_radians()).rem_euclid(std::f64::consts::TAU);
    assert!(turn.min(std::f64::consts::TAU - turn) < 1e-9, "{q:?}");

    let far = freefloat(&["plan", "--urdf", &urdf, "--from", FROM4, "--to-ee", "5,1.5,120"]);
    assert_eq!(far.status.code(), Some(2), "{}", stderr(&far));
    assert!(stderr(&far).contains("out of reach") && stderr(&far).contains("reachable is"), "{}", stderr(&far));
    // `--elbow` picks one of a 2-link arm's two solutions: for 4 links it is refused.
    let elbow = freefloat(&["plan", "--urdf", &urdf, "--from", FROM4, "--to-ee", "0.3,1.5,120", "--elbow", "up"]);
    assert_eq!(elbow.status.code(), Some(2), "{}", stderr(&elbow));
    assert!(stderr(&elbow).contains("--elbow"), "{}", stderr(&elbow));
}

/// A URDF whose last link carries a massive end-effector link (2 kg) fixed 0.5 m along it: the
/// tool point is 0.5 m along the link (the test's own forward kinematics), not at the merged
/// centre of mass, and the notes name the frame (issue 19, item 6).
#[test]
fn a_massive_end_effector_link_puts_the_tool_at_half_a_metre() {
    let link = |name: &str, x: f64, mass: f64| {
        format!(
            "<link name=\"{name}\"><inertial><origin xyz=\"{x} 0 0\"/><mass value=\"{mass}\"/>\
             <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>"
        )
    };
    let joint = |name: &str, kind: &str, parent: &str, child: &str, x: f64| {
        format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/>\
             <origin xyz=\"{x} 0 0\" rpy=\"0 0 0\"/><axis xyz=\"0 0 1\"/></joint>"
        )
    };
    let urdf = format!(
        "<?xml version=\"1.0\"?><robot name=\"heavy_tool\">{}{}{}{}{}{}{}{}{}</robot>",
        link("base", 0.0, 40.0),
        link("l1", 0.2, 3.0),
        link("l2", 0.2, 3.0),
        link("l3", 0.25, 2.0),
        link("ee_link", 0.0, 2.0),
        joint("j1", "continuous", "base", "l1", 0.3),
        joint("j2", "continuous", "l1", "l2", 0.4),
        joint("j3", "continuous", "l2", "l3", 0.4),
        joint("tool", "fixed", "l3", "ee_link", 0.5),
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("heavy_tool.urdf");
    std::fs::write(&path, urdf).unwrap();
    let path = path.to_str().unwrap();
    let arm = Arm::load(path.as_ref()).unwrap();
    assert!((arm.links[2].length - 0.5).abs() < 1e-15, "{:?}", arm.links[2]);
    // The merged centre of mass: (2 * 0.25 + 2 * 0.5) / 4 = 0.375 m along link 3.
    assert!((arm.links[2].com - 0.375).abs() < 1e-12, "{:?}", arm.links[2]);
    let o = freefloat(&["plan", "--urdf", path, "--from", FROM, "--to", TO, "--format", "csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (header, rows) = csv_table(&String::from_utf8_lossy(&o.stdout));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    for r in rows.iter().step_by(250) {
        let q = &r[col("phi")..col("phi") + 4];
        let (_, tip) = own_fk(&arm, q, 0.5);
        assert!((r[col("xe")] - tip[0]).abs() < 1e-12 && (r[col("ye")] - tip[1]).abs() < 1e-12, "{r:?}");
        // The joint 3 to tool distance is 0.5 m, not the 0.375 m of the merged centre of mass.
        let (_, at_com) = own_fk(&arm, q, 0.375);
        assert!(((tip[0] - at_com[0]).hypot(tip[1] - at_com[1]) - 0.125).abs() < 1e-12);
    }
    let r = json(&freefloat(&["plan", "--urdf", path, "--from", FROM, "--to", TO, "--format", "json"]));
    assert!(r["notes"].to_string().contains("frame `ee_link`, 0.5 m along link 3"), "{}", r["notes"]);
    let toml = json(&freefloat(&[
        "plan",
        "--robot",
        &example("three_link.toml"),
        "--from",
        FROM,
        "--to",
        TO,
        "--format",
        "json",
    ]));
    assert!(toml["notes"].to_string().contains("the tip of link 3"), "{}", toml["notes"]);
}

/// `--smooth-ends` on the 3-link and 4-link arms: at rest with zero accelerations at both ends,
/// certified at both levels, effort at least the cubic ends' (a constrained problem).
#[test]
fn arm_plan_takes_smooth_ends() {
    for (robot, from, to) in arms() {
        let base = ["plan", &robot[0], &robot[1], "--from", from, "--to", to, "--torques", "--format", "csv"];
        let o = freefloat(&[&base[..], &["--smooth-ends"]].concat());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let (header, rows) = csv_table(&String::from_utf8_lossy(&o.stdout));
        let first = header.iter().position(|h| h == "ddtheta1").unwrap();
        let n = header.iter().filter(|h| h.starts_with("ddtheta")).count();
        for r in [&rows[0], &rows[rows.len() - 1]] {
            assert!(r[first..first + n].iter().all(|a| a.abs() < 1e-9), "{r:?}");
        }
    }
}

/// `--cost energy` on the 3-link and 4-link arms: certified, and its effort at least the
/// minimum-effort plan's (the effort plan minimises the effort).
#[test]
fn arm_plan_takes_cost_energy() {
    for (robot, from, to) in arms() {
        let base = ["plan", &robot[0], &robot[1], "--from", from, "--to", to, "--format", "json"];
        let effort = json(&freefloat(&base));
        let energy = json(&freefloat(&[&base[..], &["--cost", "energy"]].concat()));
        assert_eq!(energy["certified"], true, "{energy}");
        assert!(energy["effort"].as_f64().unwrap() >= effort["effort"].as_f64().unwrap() * (1.0 - 1e-9));
    }
}

/// `plan --robot three_link.toml --plot` draws the arm's plan (issue 20 item 7): with a
/// velocity limit the SVG has the dashed limits' legend and the caption's most-used limit; a
/// PNG renders too; a bad extension and the 2-link NFA's plan exit 2 before writing anything.
#[test]
fn three_link_arm_plot_draws_its_limits() {
    let dir = tempfile::tempdir().unwrap();
    let toml = example("three_link.toml");
    let svg = dir.path().join("arm.svg");
    let png = dir.path().join("arm.png");
    let base = ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--samples", "201", "--quiet"];
    let limited = ["--limit", "all.velocity=40", "--torques"];
    let o = freefloat(&[&base[..], &limited[..], &["--plot", svg.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&svg).expect("the SVG is written");
    for label in ["limits (dashed)", "rate [rad/s]", "the most used is theta", "velocity level"] {
        assert!(text.contains(label), "no `{label}` in the SVG");
    }
    let o = freefloat(&[&base[..], &["--plot", png.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(&std::fs::read(&png).expect("the PNG is written")[..8], b"\x89PNG\r\n\x1a\n");
    let bad = tempfile::tempdir().unwrap();
    let pdf = bad.path().join("arm.pdf");
    let o = freefloat(&[&base[..], &["--plot", pdf.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // The NFA's 2-link plan has no arm figure: refused, nothing written. The paper's robot's
    // minimum-effort plan goes through the one pipeline of every arm, and draws (issue 19).
    let two = bad.path().join("two.svg");
    let o = freefloat(&["plan", "--quiet", "--method", "nfa", "--plot", two.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--plot"), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(bad.path()).unwrap().count(), 0, "a refused run wrote a file");
    let o = freefloat(&["plan", "--quiet", "--plot", two.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&two).expect("the SVG is written");
    assert!(text.contains("2-link arm"), "the 2-link robot's figure");
}

/// One report for every arm and method (issue 19, item 5): the JSON of the 2-link robot's three
/// methods, of the same robot with a limit (planned as an arm), of a 3-link and of a 4-link arm
/// have the same top-level keys (docs/spec.md §3's required keys among them), `joints` counts the
/// joints and the per-joint arrays have `n` (or `n + 1`) entries.
#[test]
fn every_arm_and_method_reports_the_same_keys() {
    let keys = |r: &serde_json::Value| {
        let mut k: Vec<String> = r.as_object().expect("an object").keys().cloned().collect();
        k.retain(|k| !["optimal", "ecsa", "limits", "clearance", "closed_loop", "to_ee"].contains(&k.as_str()));
        k.sort();
        k
    };
    let three = example("three_link.toml");
    let four = example("four_link.toml");
    let runs: [(usize, Vec<&str>); 6] = [
        (2, vec!["plan", "--format", "json"]),
        (2, vec!["plan", "--method", "nfa", "--format", "json"]),
        (2, vec!["plan", "--method", "ecsa", "--format", "json"]),
        (2, vec!["plan", "--limit", "theta2.position=-170:170", "--format", "json"]),
        (3, vec!["plan", "--robot", &three, "--from", FROM, "--to", TO, "--format", "json"]),
        (4, vec!["plan", "--robot", &four, "--from", "0,10,20,30,40", "--to", "20,40,-10,30,10", "--format", "json"]),
    ];
    let reports: Vec<(usize, serde_json::Value)> = runs.iter().map(|(n, args)| (*n, json(&freefloat(args)))).collect();
    let first = keys(&reports[0].1);
    for required in ["method", "transform", "mount", "time", "samples", "z0", "zd", "final_error", "max_abs_u"] {
        assert!(first.iter().any(|k| k == required), "{required} missing: {first:?}");
    }
    for (n, r) in &reports {
        assert_eq!(keys(r), first, "{}", r["method"]);
        assert_eq!(r["joints"].as_u64(), Some(*n as u64));
        assert_eq!(r["max_abs_u"].as_array().map(Vec::len), Some(*n));
        assert_eq!(r["joint_travel"].as_array().map(Vec::len), Some(n + 1));
        assert_eq!(r["start"].as_array().map(Vec::len), Some(n + 1));
        assert_eq!(r["controls_at_ends"][1].as_array().map(Vec::len), Some(*n));
        assert_eq!(r["robot"]["links"].as_array().map(Vec::len), Some(*n));
        // The domain margins of Eqs. 9 and 13 are the 2-link robot's.
        assert_eq!(r["min_abs_sigma"].is_number(), *n == 2, "{}", r["min_abs_sigma"]);
        assert!(r["notes"][0].as_str().is_some_and(|s| s.starts_with("end effector:")), "{}", r["notes"]);
    }
}

/// `--torques` gives every arm the closed-loop certificate (issue 19, item 4: what the 2-link
/// robot has, every arm has): the nominal 3-link arm tracking its plan with computed torque at
/// 1 kHz reaches the goal within the certificate's 1e-6 rad; without `--torques` there is none.
#[test]
fn an_arms_torques_report_the_closed_loop_certificate() {
    let three = example("three_link.toml");
    let base = ["plan", "--robot", &three, "--from", FROM, "--to", TO, "--format", "json"];
    let v = json(&freefloat(&[&base[..], &["--torques"]].concat()));
    let c = &v["closed_loop"];
    assert_eq!(c["controller"], "ct", "{c}");
    assert!(c["final_error"].as_f64().expect("number") <= 1e-6 && c["certified"] == true, "{c}");
    assert!(json(&freefloat(&base)).get("closed_loop").is_none(), "only with --torques");
}

/// The torque level is reported with the same keys for every arm (issue 19, item 5): the 2-link
/// robot's `torque_certificate` (peaks, base row of Eq. 6, the nested forward-dynamics
/// certificate) and a 3-link arm's have the same keys, and the certificate's own keys too (but
/// the path deviation, which a motion that cannot evaluate its configuration leaves out).
#[test]
fn the_torque_level_has_the_same_keys_for_every_arm() {
    let keys = |v: &serde_json::Value| {
        let mut k: Vec<String> = v.as_object().expect("an object").keys().cloned().collect();
        k.retain(|k| k != "seconds" && k != "max_path_deviation");
        k.sort();
        k
    };
    let three = example("three_link.toml");
    let two = json(&freefloat(&["plan", "--torques", "--format", "json"]));
    let arm =
        json(&freefloat(&["plan", "--robot", &three, "--from", FROM, "--to", TO, "--torques", "--format", "json"]));
    let (t2, t3) = (&two["torque_certificate"], &arm["torque_certificate"]);
    assert_eq!(keys(t2), keys(t3), "{t2}\n{t3}");
    assert_eq!(keys(&t2["certificate"]), keys(&t3["certificate"]), "{t2}\n{t3}");
    assert_eq!(t3["max_abs_torque"].as_array().map(Vec::len), Some(3), "{t3}");
    assert_eq!(t3["certificate"]["certified"], true, "{t3}");
}
