//! `freefloat track`: closed-loop runs from the command line, their outputs and exit codes.

use std::process::{Command, Output};

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Controllers at a coarse rate, to keep the test fast.
const FAST: [&str; 4] = ["--rate", "200", "--replan-rate", "10"];

#[test]
fn single_run_json_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("run.csv");
    let mut args = vec!["track", "--mount", "0.1,0.1", "--controller", "open,ct", "--format", "json"];
    args.extend(FAST);
    args.extend(["--out", csv.to_str().unwrap()]);
    let o = freefloat(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let runs = v.as_array().expect("one object per controller");
    assert_eq!(runs.len(), 2);
    for key in ["controller", "final_error", "final_errors", "peak_torque", "replans", "saturated_fraction"] {
        assert!(runs[0].get(key).is_some(), "missing key {key}");
    }
    assert!(runs[1]["final_error"].as_f64().unwrap() < 1e-4);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("t_s,phi_ref,theta1_ref,theta2_ref,phi,theta1,theta2,tau1_Nm,tau2_Nm"));
    assert_eq!(text.lines().count(), 1 + 2001);
}

#[test]
fn monte_carlo_prints_success_rates() {
    let mut args =
        vec!["track", "--mount", "0.1,0.1", "--controller", "ct,replan", "--trials", "3", "--perturb", "0.05"];
    args.extend(FAST);
    let o = freefloat(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("3 trials") && out.contains("replan") && out.contains('%'), "{out}");
}

#[test]
fn invalid_options_exit_2_with_the_flag_named() {
    let dir = tempfile::tempdir().unwrap();
    let bad_robot = dir.path().join("bad.toml");
    std::fs::write(&bad_robot, "[robot]\nl1 = 0.6\n").unwrap();
    for (args, name) in [
        (vec!["--rate", "0"], "rate"),
        (vec!["--rate", "inf"], "rate"),
        (vec!["--replan-rate", "5000"], "replan-rate"),
        (vec!["--kp", "-1"], "kp"),
        (vec!["--kd", "nan"], "kd"),
        (vec!["--torque-noise", "-0.1"], "torque-noise"),
        (vec!["--noise-q", "2"], "noise-q"),
        (vec!["--torque-limit", "0"], "torque-limit"),
        (vec!["--torque-bias", "1"], "--torque-bias"),
        (vec!["--perturb", "0.9"], "perturb"),
        (vec!["--true-robot", bad_robot.to_str().unwrap()], "bad.toml"),
        (vec!["--true-robot", "/no/such/robot.toml"], "robot.toml"),
    ] {
        let mut all = vec!["track"];
        all.extend(args.iter().copied());
        let o = freefloat(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(name), "{args:?}: {}", stderr(&o));
    }
}
