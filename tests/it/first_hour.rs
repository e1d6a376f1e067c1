//! What a new user's first hour hit (issue 23, item 5), one test per finding: the help texts
//! that contradicted the README, `compare --torques` failing without naming the method, the
//! empty `numbers` of a JSON error, `track --plot` drawing one controller of several, and
//! `--urdf` reading TOML.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The four places where `--help` said otherwise than the README (README "Commands", "Angles
/// ...", "Transformations").
#[test]
fn help_agrees_with_the_readme() {
    let top = text(&run(&["--help"]).stdout);
    let first = top.lines().next().unwrap_or_default();
    assert!(first.contains("minimum-effort") && first.contains("Normal Form Approach"), "{first}");
    assert!(top.contains("Run the optimal planner, the NFA and the ECSA"), "{top}");
    let plan = text(&run(&["plan", "--help"]).stdout);
    assert!(!plan.contains("taken literally (not modulo 360)"), "{plan}");
    assert!(plan.contains("the optimal planner counts its angles modulo 360"), "{plan}");
    let auto = plan.lines().find(|l| l.contains("auto:")).unwrap_or_default();
    assert!(auto.contains("global"), "auto must name its fallback to the global form: {auto}");
    let compare = text(&run(&["compare", "--help"]).stdout);
    assert!(compare.starts_with("Run the optimal planner, the NFA and the ECSA"), "{compare}");
}

/// The paper's default problem: the ECSA's plain series does not start at rest (README), so its
/// torque level fails; the error names the method and the table has the torque rows.
#[test]
fn compare_torques_names_the_method_that_failed_and_shows_the_torque_level() {
    let o = run(&["compare", "--torques"]);
    let (out, err) = (text(&o.stdout), text(&o.stderr));
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("ecsa is not certified") && err.contains("torque level"), "{err}");
    assert!(err.contains("--window sin2"), "the remedy is named: {err}");
    let row = |label: &str| out.lines().find(|l| l.trim_start().starts_with(label)).map(str::to_string);
    let certified = row("torque level certified").unwrap_or_else(|| panic!("no torque row: {out}"));
    // optimal and NFA start at rest and are certified, the ECSA is not.
    assert_eq!(certified.split_whitespace().skip(3).collect::<Vec<_>>(), ["yes", "yes", "NO"], "{certified}");
    let errors = row("torque final error").unwrap_or_else(|| panic!("no torque error row: {out}"));
    assert_eq!(errors.split_whitespace().count(), 7, "{errors}");
}

/// An unreachable pose's JSON error object carries the numbers the message gives.
#[test]
fn json_error_of_an_unreachable_pose_has_its_numbers() {
    let o = run(&["plan", "--to-ee", "5,5,0", "--format", "json"]);
    assert_eq!(o.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    let numbers = &v["error"]["numbers"];
    let get = |k: &str| numbers[k].as_f64().unwrap_or_else(|| panic!("numbers.{k} missing: {v}"));
    assert!((get("x") - 5.0).abs() < 1e-12 && (get("y") - 5.0).abs() < 1e-12, "{v}");
    // out of reach: the wrist point's distance lies beyond the reachable range
    assert!(get("min") <= get("max") && get("max") < get("distance"), "{v}");
}

/// Every controller of `--controller` is drawn, each series named by its controller.
#[test]
fn track_plot_draws_every_controller() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("track.svg");
    let path_text = path.to_str().expect("utf-8 path");
    let o = run(&["track", "--controller", "open,ct,replan,adaptive", "--perturb", "0.02", "--plot", path_text]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let svg = std::fs::read_to_string(&path).expect("the picture");
    for controller in ["open", "ct", "replan", "adaptive"] {
        assert!(svg.contains(&format!("actual ({controller})")), "no series of {controller}");
        assert!(svg.contains(&format!("tau1 ({controller})")), "no torques of {controller}");
    }
}

/// `--urdf` with a TOML file is refused (exit 2), not read as TOML.
#[test]
fn urdf_flag_refuses_a_toml_file() {
    let toml = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml");
    let o = run(&["plan", "--urdf", toml]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--urdf") && err.contains(".urdf") && err.contains("--robot"), "{err}");
    // The same file by the flag of its kind is read.
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.urdf");
    let o = run(&["robot", "--urdf", urdf]);
    assert!(o.status.success(), "{}", text(&o.stderr));
}
