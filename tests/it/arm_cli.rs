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
    assert_eq!(r["torque_certificate"]["certified"], true, "{r}");
    assert_eq!(r["max_abs_torque"].as_array().unwrap().len(), 3);
    let urdf = example("three_link.urdf");
    let u = json(&freefloat(&["plan", "--urdf", &urdf, "--from", FROM, "--to", TO, "--format", "json"]));
    let (a, b) = (r["effort"].as_f64().unwrap(), u["effort"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-8 * a, "TOML {a}, URDF {b}");
}

/// `--method ecsa` plans the 3-link example arm (issue 14), certified at both levels (the
/// minimum-norm solution's torques: the pseudo-inverse iteration's large harmonics failed the
/// torque level), with the ECSA's account (solver, iterations, residual) in place of the optimal
/// planner's; the table names the iteration; a moving start is bad input (the ECSA plans from
/// rest).
#[test]
fn three_link_arm_plans_with_the_ecsa() {
    let toml = example("three_link.toml");
    let args =
        ["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--method", "ecsa", "--torques", "--format", "json"];
    let o = freefloat(&args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let r = json(&o);
    assert_eq!(r["method"], "ecsa");
    assert_eq!(r["joints"], 3);
    assert_eq!(r["certified"], true);
    assert!(r["final_error"].as_f64().unwrap() <= 1e-9, "{r}");
    assert!(r["optimal"].is_null(), "{r}");
    assert_eq!(r["torque_certificate"]["certified"], true, "{r}");
    let e = &r["ecsa"];
    assert_eq!(e["solver"], "minimum_norm", "{r}");
    assert!(e["continuation_steps"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(e["iteration"]["termination"], "converged", "{r}");
    assert!(e["iteration"]["residual"].as_f64().unwrap() <= 1e-10, "{r}");
    assert!(e["iteration"]["iterations"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(e["coefficients"].as_array().unwrap().len(), 9);
    let optimal = json(&freefloat(&["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--format", "json"]));
    assert!(optimal["ecsa"].is_null() && optimal["optimal"]["iterations"].is_u64(), "{optimal}");
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
    assert!(stderr(&o).contains("3 link") && stderr(&o).contains("freefloat plan"), "{}", stderr(&o));
    let o = freefloat(&["plan", "--robot", &toml, "--from", FROM, "--to", TO, "--smooth-ends"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
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
