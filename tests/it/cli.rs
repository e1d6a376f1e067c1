//! `freefloat` as a user runs it: outputs, exit codes (0 ok, 2 bad input, 3 no certified plan),
//! and error messages that name what is wrong.

use std::process::{Command, Output};

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const ROBOT: &str = "[robot]\nl1 = 0.619\nl2 = 0.6\nd1 = 0.313\nd2 = 0.287\nM = 12.9\nI = 0.208\nm1 = 4.5\nm2 = 1.5\n";

#[test]
fn plan_json_has_the_required_keys_and_a_certificate() {
    let o = freefloat(&["plan", "--method", "nfa", "--mount", "0.2,0.2", "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    for key in [
        "method",
        "transform",
        "mount",
        "time",
        "samples",
        "z0",
        "zd",
        "final_error",
        "max_abs_u",
        "min_abs_sigma",
        "min_abs_p",
        "max_abs_torque",
        "torque_final_error",
        "seconds",
        "iterations",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    assert_eq!(v["method"], "nfa");
    assert_eq!(v["transform"], "eq14");
    assert_eq!(v["samples"], 1001);
    assert!(v["final_error"].as_f64().expect("a number") <= 1e-9);
    for stage in ["plan", "verify"] {
        assert!(v["seconds"][stage].as_f64().expect("seconds") > 0.0);
    }
}

#[test]
fn plan_writes_csv_and_json_files_whole() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("plan.csv");
    let json = dir.path().join("plan.json");
    for out in [&csv, &json] {
        let o = freefloat(&["plan", "--transform", "eq11", "--samples", "101", "--out", out.to_str().expect("utf-8")]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let text = std::fs::read_to_string(&csv).expect("csv written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t,phi,theta1,theta2,dphi,dtheta1,dtheta2,ddphi,ddtheta1,ddtheta2,z1,z2,z3,tau1,tau2,xb,yb,xe,ye,psie,dxe,dye,dpsie"
        )
    );
    assert_eq!(lines.clone().count(), 101);
    assert!(!text.to_lowercase().contains("nan"));
    // Joint velocities vanish at both ends.
    for row in [lines.clone().next().expect("first row"), lines.last().expect("last row")] {
        let cells: Vec<&str> = row.split(',').collect();
        for c in &cells[5..7] {
            assert!(c.parse::<f64>().expect("number").abs() < 1e-12, "{row}");
        }
    }
    // Task space: psie = phi + theta1 + theta2, and the end-effector velocity is the derivative
    // of its position (central differences over the 0.1 s samples, O(dt^2)).
    let rows: Vec<Vec<f64>> =
        text.lines().skip(1).map(|r| r.split(',').map(|c| c.parse::<f64>().unwrap_or(f64::NAN)).collect()).collect();
    for (i, r) in rows.iter().enumerate() {
        assert!((r[19] - (r[1] + r[2] + r[3])).abs() < 1e-12, "psie at row {i}");
        if i > 0 && i + 1 < rows.len() {
            for (x, dx) in [(17, 20), (18, 21)] {
                let fd = (rows[i + 1][x] - rows[i - 1][x]) / (rows[i + 1][0] - rows[i - 1][0]);
                assert!((fd - r[dx]).abs() < 1e-3, "row {i}: {fd} vs {}", r[dx]);
            }
        }
    }
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("valid");
    assert_eq!(v["trajectory"]["t"].as_array().expect("t column").len(), 101);
    assert_eq!(v["trajectory"]["end_effector"].as_array().expect("end-effector column").len(), 101);
}

#[test]
fn invalid_robot_file_values_are_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases = [
        ("M = 12.9", "M = -12.9", "robot.M"),
        ("I = 0.208", "I = nan", "robot.I"),
        ("l1 = 0.619", "l1 = inf", "robot.l1"),
        ("d2 = 0.287", "d2 = 0.9", "robot.d2"),
        ("m1 = 4.5", "m1 = 0.0", "robot.m1"),
        ("m2 = 1.5", "m2 = 1.5\nm3 = 2.0", "m3"),
        ("m2 = 1.5\n", "", "m2"),
    ];
    for (from, to, name) in cases {
        let path = dir.path().join("robot.toml");
        std::fs::write(&path, ROBOT.replace(from, to)).expect("write");
        let o = freefloat(&["plan", "--robot", path.to_str().expect("utf-8")]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(name), "{name} not named in: {}", stderr(&o));
    }
    let o = freefloat(&["plan", "--robot", "/no/such/robot.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("/no/such/robot.toml"));
}

#[test]
fn a_valid_robot_file_with_a_mount_plans() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("robot.toml");
    std::fs::write(&path, format!("{ROBOT}[mount]\na = 0.1\nb = 0.1\n")).expect("write");
    let o = freefloat(&["plan", "--robot", path.to_str().expect("utf-8"), "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(v["mount"], serde_json::json!([0.1, 0.1]));
}

#[test]
fn bad_flags_exit_2() {
    for args in [
        &["plan", "--mount", "0.1"][..],
        &["plan", "--from", "1,2,x"],
        &["plan", "--time", "-1"],
        &["plan", "--samples", "1"],
        &["plan", "--mount", "0.1,0.1", "--transform", "eq11"],
        &["plan", "--out", "plan.txt"],
        &["plan", "--method", "optimal", "--transform", "eq14"],
        &["plan", "--method", "nfa", "--window", "sin2"],
        &["plan", "--method", "ecsa", "--smooth-ends"],
    ] {
        let o = freefloat(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).starts_with("error"), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn problems_without_a_plan_exit_3_with_the_reason() {
    let cases: [(&[&str], &str); 5] = [
        (&["plan", "--from", "45,120,0", "--transform", "eq12"], "sin(theta2) = 0"),
        (&["plan", "--method", "nfa", "--from", "45,120,0"], "sigma = 0"),
        (&["plan", "--mount", "0.1,0.1", "--from", "45,120,0", "--transform", "eq14"], "leaves the domain"),
        (&["plan", "--method", "nfa", "--to", "0,180,-140"], "different components"),
        (&["plan", "--mount", "1,-1", "--transform", "eq14"], "eq14"),
    ];
    for (args, reason) in cases {
        let o = freefloat(args);
        assert_eq!(o.status.code(), Some(3), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(reason), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "no output on failure");
    }
}

#[test]
fn failed_certificate_exits_3_but_writes_the_report_when_asked() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("report.json");
    let o = freefloat(&["plan", "--tolerance", "1e-18", "--format", "json", "--out", out.to_str().expect("utf-8")]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("not certified"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("json");
    assert_eq!(v["certified"], false);
    assert!(v["final_error"].as_f64().is_some_and(|e| e > 1e-18 && e <= 1e-9), "{}", v["final_error"]);
    // Any arm alike: the plan at the default tolerance, judged at the one asked for.
    let arm = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml");
    let out = dir.path().join("arm.json");
    let args = ["plan", "--robot", arm, "--from", "0,0,30,30", "--to", "20,90,30,-30", "--samples", "101"];
    let o = freefloat(&[&args[..], &["--tolerance", "1e-18", "--out", out.to_str().expect("utf-8")]].concat());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("not certified"), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("json");
    assert_eq!((v["certified"].clone(), v["joints"].clone()), (false.into(), 3.into()));
    assert_eq!(v["tolerance"], 1e-18);
}

/// `--max-velocity` stretches the horizon so that the peak joint velocity stays under the cap,
/// and the plan stays certified (here the global normal form's band steering at a = 1, b = -1).
#[test]
fn max_velocity_stretches_the_horizon() {
    let o = freefloat(&["plan", "--mount", "1,-1", "--max-velocity", "2", "--samples", "201", "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("horizon stretched"), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let peak =
        v["max_abs_u"].as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).fold(0.0, f64::max);
    assert!(peak <= 2.0 * (1.0 + 1e-9), "peak |u| {peak}");
    assert!(v["time"].as_f64().expect("time") > 10.0);
    assert!(v["final_error"].as_f64().expect("number") <= 1e-9);
    let bad = freefloat(&["plan", "--max-velocity", "0"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// A goal on another piece of the domain with the same normal-form coordinates (theta2 whole
/// turns away across sin(theta2) = 0) is a clear error, not a plan that ends elsewhere.
#[test]
fn goal_on_another_sheet_is_named() {
    let o = freefloat(&["plan", "--method", "nfa", "--from", "45,120,80000"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("instead of the goal"), "{}", stderr(&o));
}

/// The default method is the optimal planner, and it plans what the normal form refuses: a start
/// on sigma = 0, and a goal across sigma = 0 (docs/spec.md §2).
#[test]
fn default_plans_across_sigma_zero() {
    for args in
        [&["plan", "--from", "45,120,0", "--format", "json"][..], &["plan", "--to", "0,180,-140", "--format", "json"]]
    {
        let o = freefloat(args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
        assert_eq!(v["method"], "optimal");
        assert!(v["final_error"].as_f64().expect("number") <= 1e-9);
        assert!(v["optimal"]["kkt_residual"].as_f64().expect("number") < 1e-6);
    }
}

/// `--to-ee` plans to an end-effector pose: the plan ends there (task-space columns of the last
/// sample), and an unreachable pose is bad input naming the reachable range.
#[test]
fn plans_to_an_end_effector_pose() {
    let o = freefloat(&["plan", "--mount", "0.1,0.1", "--to-ee", "0.5,0.3,90", "--samples", "201", "--format", "csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).expect("utf-8");
    let last: Vec<f64> = text.lines().last().expect("rows").split(',').map(|c| c.parse().unwrap_or(f64::NAN)).collect();
    assert!((last[17] - 0.5).abs() < 1e-9 && (last[18] - 0.3).abs() < 1e-9, "{last:?}");
    let psi = (last[19] - 90f64.to_radians()).rem_euclid(std::f64::consts::TAU);
    assert!(!(1e-9..=std::f64::consts::TAU - 1e-9).contains(&psi), "psie {}", last[19]);
    let far = freefloat(&["plan", "--to-ee", "5,0,0"]);
    assert_eq!(far.status.code(), Some(2), "{}", stderr(&far));
    assert!(stderr(&far).contains("out of reach"), "{}", stderr(&far));
}

/// Issue 11, item 5.1: a band plan whose `kappa` came from a coarse quadrature left the band
/// ("leaves the band", exit 3); now it is certified and `band.lambda_range` is the final path's.
#[test]
fn band_plan_with_a_fine_kappa_is_certified() {
    let o = freefloat(&[
        "plan",
        "--method",
        "nfa",
        "--mount=-0.6806,-0.0684",
        "--from=-161.452,-132.37,122.396",
        "--to=130.052,-72.462,82.138",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let band = &v["band"];
    let (margin, range) = (band["margin"].as_f64().expect("margin"), &band["lambda_range"]);
    let (lo, hi) = (range[0].as_f64().expect("number"), range[1].as_f64().expect("number"));
    assert!(margin <= lo && lo < hi && hi <= 1.0 - margin, "{band}");
    assert!(v["final_error"].as_f64().expect("number") <= 1e-9);
}

/// Issue 11, item 5.2: whether the global normal form takes the polynomial path or the band
/// steering does not depend on `--samples` (at 20001 samples it was a polynomial plan with
/// peak |u2| 1676 rad/s, not certified; at 1001 a band plan).
#[test]
fn band_or_polynomial_does_not_depend_on_samples() {
    for samples in ["1001", "20001"] {
        let o = freefloat(&[
            "plan",
            "--method",
            "nfa",
            "--mount=-0.3022,-0.3933",
            "--from=-116.871,-144.801,-25.144",
            "--to=160.882,171.748,-23.402",
            "--samples",
            samples,
            "--format",
            "json",
        ]);
        assert!(o.status.success(), "{samples}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
        assert_eq!(v["steering"], "band", "{samples}");
        assert!(v["final_error"].as_f64().expect("number") <= 1e-9);
    }
}

/// Issue 11, item 5.3: the stretch for `--max-velocity` is decided on the velocity plan, before
/// and whatever the torque level (a failing torque level used to skip it); the torques are those
/// of the stretched plan.
#[test]
fn max_velocity_stretches_before_the_torque_level() {
    let o = freefloat(&[
        "plan",
        "--method",
        "nfa",
        "--mount",
        "1,-1",
        "--max-velocity",
        "2",
        "--samples",
        "201",
        "--torques",
        "--format",
        "json",
    ]);
    assert!(stderr(&o).contains("horizon stretched"), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap_or_else(|_| panic!("json: {}", stderr(&o)));
    assert!(v["time"].as_f64().expect("time") > 10.0);
    let peak =
        v["max_abs_u"].as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).fold(0.0, f64::max);
    assert!(peak <= 2.0 * (1.0 + 1e-9), "peak |u| {peak}");
    assert!(v["max_abs_torque"].is_array() && v["torque_final_error"].is_number(), "{v}");
}

/// `--torques` also reports the closed-loop certificate: the nominal robot tracking the plan with
/// computed torque at 1 kHz reaches the goal within 1e-6 rad (docs/spec.md §2).
#[test]
fn torques_report_the_closed_loop_certificate() {
    let o = freefloat(&["plan", "--method", "nfa", "--mount", "0.2,0.2", "--torques", "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let c = &v["closed_loop"];
    assert_eq!(c["controller"], "ct", "{c}");
    assert!(c["final_error"].as_f64().expect("number") <= 1e-6 && c["certified"] == true, "{c}");
    let plain = freefloat(&["plan", "--method", "nfa", "--mount", "0.2,0.2", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&plain.stdout).expect("json");
    assert!(v.get("closed_loop").is_none(), "only with --torques");
}

/// `--from-velocity` starts the torque certificate and the closed-loop one from that velocity
/// (both used to start from rest and fail), and a method that plans from rest refuses it.
#[test]
fn a_moving_start_is_certified_at_the_torque_level() {
    let o = freefloat(&["plan", "--from-velocity", "5,-5", "--torques", "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(report["torque_certificate"]["certificate"]["certified"], serde_json::Value::Bool(true), "{report}");
    assert_eq!(report["closed_loop"]["certified"], serde_json::Value::Bool(true), "{report}");
    let o = freefloat(&["plan", "--from-velocity", "5,-5", "--method", "nfa"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// The paper's ECSA through the command line's one pipeline (issue 19): `plan --method ecsa` on
/// the paper's robot is the 2-link arm's ECSA with the paper's damped pseudo-inverse iteration,
/// and takes the paper reproduction's iterations at a = b = 0, 0.1, 0.2, 0.3: 4, 2, 5, 4 (the
/// library's `paper_reproduction_is_unchanged`, from the 2-joint ECSA before the merge).
#[test]
fn the_paper_ecsa_through_the_command_line() {
    for (a, iterations) in [("0", 4), ("0.1", 2), ("0.2", 5), ("0.3", 4)] {
        let mount = format!("{a},{a}");
        let o = freefloat(&["plan", "--method", "ecsa", "--mount", &mount, "--samples", "101", "--format", "json"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
        assert_eq!(v["ecsa"]["solver"], "pseudo_inverse", "a = b = {a}");
        assert_eq!(v["ecsa"]["iteration"]["iterations"], iterations, "a = b = {a}: {}", v["ecsa"]);
        assert_eq!(v["certified"], true);
    }
}
