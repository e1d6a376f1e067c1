//! Hostile input, round two (issue 24, items 2, 5, 7 and 8): bounds that hold for every front
//! end, flags that are honoured or refused (never ignored), outputs free of non-finite numbers,
//! and time and memory estimated before the run.

use std::path::Path;
use std::time::{Duration, Instant};

use super::{refused, run, stderr, stdout};

const THREE_LINK: &str = "examples/robots/three_link.toml";
const THREE_LINK_URDF: &str = "examples/robots/three_link.urdf";
/// A 3-link problem (`--from`/`--to` with 4 angles).
const P3: [&str; 4] = ["--from", "0,60,-30,-30", "--to", "30,120,40,-60"];

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path).display().to_string()
}

/// `plan` on the 3-link arm with `extra` flags (few samples: a plan takes a fraction of a second).
fn plan3(robot: &[&str], extra: &[&str]) -> std::process::Output {
    let mut args = vec!["plan", "--samples", "11"];
    args.extend(robot);
    args.extend(P3);
    args.extend(extra);
    run(&args)
}

/// No `nan` or `inf` word in an output (stdout, a CSV, a JSON or SVG file).
#[track_caller]
fn finite_text(what: &str, text: &str) {
    let lower = text.to_lowercase();
    for word in ["nan", "inf"] {
        let hit = lower.match_indices(word).find(|(i, _)| {
            // A word, not part of one ("information", "infinity" counts: it starts with inf).
            let before = lower[..*i].chars().next_back().is_none_or(|c| !c.is_ascii_alphabetic());
            let after = lower[i + word.len()..].chars().next();
            before && (word == "inf" || after.is_none_or(|c| !c.is_ascii_alphabetic()))
        });
        if let Some((i, _)) = hit {
            let from = lower[..i].char_indices().rev().nth(60).map_or(0, |(j, _)| j);
            panic!("{what}: `{word}` in the output: ...{}...", &text[from..(i + 20).min(text.len())]);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Item 2: one validation layer (the library's), so that every front end has the CLI's bounds.

/// The sample, tolerance and memory bounds are the library's: a planner's options, an arm's
/// request and a domain map refuse what the command line refuses, before allocating.
#[test]
fn library_options_carry_the_command_lines_bounds() {
    use freefloat::planners::arm::{ArmRequest, plan_arm};
    use freefloat::planners::chain::ChainProblem;
    use freefloat::planners::{PlannerOptions, planner};
    use freefloat::{Method, PlanningProblem, RobotParams};
    let problem = PlanningProblem::paper(RobotParams::src());
    let huge = 1_000_000_000;
    let clock = Instant::now();
    for method in [Method::Optimal, Method::Nfa, Method::Ecsa] {
        let mut options = PlannerOptions::default();
        (options.nfa.samples, options.ecsa.samples, options.optimal.samples) = (huge, huge, huge);
        let e = planner(method, &options).plan(&problem).map(drop).expect_err("refused");
        assert!(e.is_bad_input() && e.to_string().contains("memory"), "{}: {e}", method.name());
        let mut options = PlannerOptions::default();
        (options.nfa.tolerance, options.ecsa.tolerance, options.optimal.tolerance) = (0.5, 0.5, 0.5);
        let e = planner(method, &options).plan(&problem).map(drop).expect_err("refused");
        assert!(e.is_bad_input() && e.to_string().contains("tolerance"), "{}: {e}", method.name());
    }
    let arm = freefloat::Arm::load(Path::new(&repo(THREE_LINK))).expect("the example arm");
    let chain = ChainProblem {
        start: vec![0.0, 1.0, -0.5, -0.5],
        goal: vec![0.5, 2.0, 0.7, -1.0],
        horizon: 10.0,
        initial_velocity: vec![0.0; 3],
        wrap: true,
    };
    let request = ArmRequest {
        problem: chain,
        samples: huge,
        tolerance: 1e-9,
        torques: false,
        ecsa: freefloat::EcsaOptions::default(),
        cost: Default::default(),
        smooth_ends: false,
        shortest_horizon: false,
    };
    let e = plan_arm(&arm, Method::Optimal, &request).map(drop).expect_err("refused");
    assert!(e.is_bad_input() && e.to_string().contains("memory"), "{e}");
    // Harmonics shape the ECSA's controls only: with the optimal planner they are refused.
    let ecsa = freefloat::EcsaOptions::default().with_harmonics(3).expect("3 harmonics");
    let request = ArmRequest { samples: 11, ecsa, ..request };
    let e = plan_arm(&arm, Method::Optimal, &request).map(drop).expect_err("refused");
    assert!(e.is_bad_input() && e.to_string().contains("harmonics"), "{e}");
    let e = freefloat::analysis::domain::DomainMap::new(&RobotParams::src(), freefloat::Transform::Eq12, 8192)
        .map(drop)
        .expect_err("refused");
    assert!(e.to_string().contains("memory") && e.to_string().contains("6192"), "{e}");
    // Refused up front: nothing of the 1e9 samples (24 GB) was allocated or computed.
    assert!(clock.elapsed() < Duration::from_secs(20), "{:?}", clock.elapsed());
}

// ---------------------------------------------------------------------------------------------
// Item 5: ignored input is a silent wrong answer.

/// Every flag of `plan` on an arm of 3 links is honoured or refused: the refused ones exit 2
/// naming the flag, from the TOML file and from the URDF alike (`--max-velocity` is honoured
/// since issue 19, and so are `--smooth-ends` and `--cost energy`: tests/it/arm_cli.rs).
#[test]
fn n_link_plan_refuses_every_flag_it_cannot_honour() {
    let refused_flags: [(&[&str], &str); 7] = [
        (&["--transform", "eq14"], "--transform"),
        (&["--transform", "global"], "--transform"),
        (&["--method", "ecsa", "--transform", "eq11"], "--transform"),
        (&["--harmonics", "3"], "harmonics"),
        (&["--window", "sin2"], "window"),
        (&["--elbow", "up"], "--elbow"),
        (&["--method", "nfa"], "method"),
    ];
    for robot in [["--robot", THREE_LINK], ["--urdf", THREE_LINK_URDF]] {
        let robot = [robot[0], &repo(robot[1])];
        for (flags, named) in refused_flags {
            let o = plan3(&robot, flags);
            let err = refused(&o, &format!("{flags:?}"));
            assert!(err.contains(named), "{flags:?}: {err}");
            assert!(stdout(&o).is_empty(), "{flags:?}: printed a result");
        }
    }
    // `--from-velocity` takes n = 3 joint velocities (or the default `0,0`, rest).
    for velocity in ["0,0,0,0,0,0,0", "1,2", "1,2,3,4"] {
        let err = refused(&plan3(&["--robot", &repo(THREE_LINK)], &["--from-velocity", velocity]), velocity);
        assert!(err.contains("--from-velocity"), "{err}");
    }
}

/// `--elbow` without `--to-ee` chooses nothing: refused for the 2-link robot too (clap's
/// `requires` lets it through when `--to` is given).
#[test]
fn elbow_without_a_pose_is_refused() {
    for command in ["plan", "compare"] {
        let o = run(&[command, "--to", "0,180,140", "--elbow", "up", "--samples", "11"]);
        assert!(refused(&o, command).contains("--elbow"));
        assert!(stdout(&o).is_empty(), "{command} printed a result");
    }
}

/// The honoured flags of the 3-link `plan` change the report as asked.
#[test]
fn n_link_plan_honours_the_flags_it_takes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("p.json");
    let o = plan3(
        &["--robot", &repo(THREE_LINK), "--mount", "0.05,0.02"],
        &[
            "--tolerance",
            "1e-8",
            "--torques",
            "--no-wrap",
            "--from-velocity",
            "0,0,0",
            "--format",
            "json",
            "--out",
            out.to_str().expect("utf-8"),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    assert_eq!(r["samples"], 11, "--samples");
    assert_eq!(r["verification"]["tolerance"], 1e-8, "--tolerance");
    assert_eq!(r["robot"]["mount"]["a"], 0.05, "--mount");
    assert!(r["torques"].is_object() || r["torque_certificate"].is_object(), "--torques: {r}");
    assert!(out.exists(), "--out");
    let ecsa = plan3(&["--robot", &repo(THREE_LINK)], &["--method", "ecsa", "--harmonics", "2", "--window", "sin2"]);
    assert!(matches!(ecsa.status.code(), Some(0 | 3)), "{}", stderr(&ecsa));
    if ecsa.status.success() {
        assert!(stdout(&ecsa).contains("2 harmonic(s), window sin2"), "{}", stdout(&ecsa));
    }
}

/// Two outputs on one path are refused before any work, however the path is spelt (a `..`, a
/// symbolic link to the directory).
#[test]
fn two_outputs_on_one_path_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    std::fs::create_dir(d.join("sub")).expect("sub");
    std::os::unix::fs::symlink(d.join("sub"), d.join("link")).expect("symlink");
    let a = d.join("sub/r.svg");
    let spellings = [a.clone(), d.join("sub/../sub/r.svg"), d.join("link/r.svg")];
    for other in &spellings {
        let o = run(&[
            "track",
            "--controller",
            "ct",
            "--out",
            a.to_str().expect("utf-8"),
            "--plot",
            other.to_str().expect("utf-8"),
        ]);
        let err = refused(&o, &other.display().to_string());
        assert!(err.contains("same file"), "{err}");
        assert!(!a.exists(), "nothing written");
    }
}

/// `mount-sweep` refuses no trials (a success rate of nothing) and output names that are not
/// CSV, for a run and a merge.
#[test]
fn sweep_refuses_no_trials_and_other_extensions() {
    let err = refused(&run(&["mount-sweep", "--steps", "2", "--grid", "16", "--trials", "0"]), "--trials 0");
    assert!(err.contains("trial"), "{err}");
    let dir = tempfile::tempdir().expect("temp dir");
    let txt = dir.path().join("s.txt");
    let o =
        run(&["mount-sweep", "--steps", "2", "--grid", "16", "--trials", "1", "--out", txt.to_str().expect("utf-8")]);
    assert!(refused(&o, "--out s.txt").contains(".csv"));
    assert!(!txt.exists());
    let o = run(&["mount-sweep", "merge", "--out", txt.to_str().expect("utf-8"), "x.csv"]);
    assert!(refused(&o, "merge --out s.txt").contains(".csv"));
}

/// URDF input that the reader would take and freefloat would misread: a `<mimic>` joint, a root
/// element other than `<robot>`, an axis that is not finite. Each names what is wrong.
#[test]
fn urdf_mimic_foreign_root_and_infinite_axis_are_refused() {
    let text = std::fs::read_to_string(repo(THREE_LINK_URDF)).expect("the example URDF");
    let dir = tempfile::tempdir().expect("temp dir");
    let cases = [
        (
            text.replacen(
                "<axis xyz=\"0 0 1\"/>\n  </joint>",
                "<axis xyz=\"0 0 1\"/>\n    <mimic joint=\"joint1\" multiplier=\"2\"/>\n  </joint>",
                2,
            ),
            "mimic",
        ),
        (text.replacen("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 1\"/><mimic joint=\"nowhere\"/>", 1), "nowhere"),
        (text.replacen("<robot", "<robo", 1).replacen("</robot>", "</robo>", 1), "<robot>"),
        (text.replacen("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 inf\"/>", 1), "not finite"),
    ];
    for (i, (urdf, named)) in cases.iter().enumerate() {
        assert_ne!(urdf, &text, "case {i} changed the file");
        let path = dir.path().join(format!("r{i}.urdf"));
        std::fs::write(&path, urdf).expect("write");
        let o = plan3(&["--urdf", path.to_str().expect("utf-8")], &[]);
        let err = refused(&o, named);
        assert!(err.contains(named), "case {i}: {err}");
    }
}

// ---------------------------------------------------------------------------------------------
// Item 7: no output holds a non-finite number; a diverged run is a verdict with a reason.

/// Gains and rates outside the sampled loop's stable range are refused with the reason, before
/// the run (they printed inf, 300-digit torques and NaN rows).
#[test]
fn unstable_gains_and_rates_are_refused() {
    let cases: [&[&str]; 5] = [
        &["--kp", "1e300", "--controller", "ct"],
        &["--rate", "1", "--replan-rate", "1", "--kp", "2500"],
        &["--kd", "1e300", "--controller", "ct"],
        &["--kp", "1e6", "--controller", "ct", "--rate", "100"],
        &["--kd", "2000", "--controller", "replan"],
    ];
    for flags in cases {
        let mut args = vec!["track"];
        args.extend(flags);
        let err = refused(&run(&args), &format!("{flags:?}"));
        assert!(err.contains("kp") || err.contains("kd"), "{flags:?}: {err}");
        assert!(err.contains("stable") || err.contains("at most"), "{flags:?}: {err}");
    }
}

/// Every output of the cases that printed NaN or inf is finite now: an empty shard's statistics,
/// a run at the edge of the stable gains, a run on a robot far from the model.
#[test]
fn track_outputs_hold_no_non_finite_number() {
    let dir = tempfile::tempdir().expect("temp dir");
    let far = dir.path().join("far.toml");
    std::fs::write(&far, super::ROBOT.replace("M = 12.9", "M = 1e6").replace("I = 0.208", "I = 1e9")).expect("far");
    let csv = dir.path().join("e.csv");
    let svg = dir.path().join("e.svg");
    let (csv_s, svg_s, far_s) =
        (csv.to_str().expect("utf-8"), svg.to_str().expect("utf-8"), far.to_str().expect("utf-8"));
    let cases: Vec<Vec<&str>> = vec![
        vec!["--trials", "1", "--shard", "2/2", "--out", csv_s],
        vec!["--trials", "1", "--shard", "2/2", "--out", csv_s, "--format", "json"],
        vec!["--controller", "ct", "--kp", "1e5", "--kd", "400", "--rate", "1000", "--out", csv_s, "--plot", svg_s],
        vec!["--controller", "open,ct", "--rate", "200", "--replan-rate", "10", "--format", "json"],
        vec!["--true-robot", far_s, "--controller", "ct", "--rate", "200", "--out", csv_s, "--plot", svg_s],
        vec!["--true-robot", far_s, "--controller", "ct", "--rate", "200", "--format", "json"],
    ];
    for flags in cases {
        let _absent = std::fs::remove_file(&csv);
        let _also_absent = std::fs::remove_file(&svg);
        let mut args = vec!["track", "--quiet"];
        args.extend(&flags);
        let o = run(&args);
        assert!(o.status.success(), "{flags:?}: {}", stderr(&o));
        finite_text(&format!("{flags:?} stdout"), &stdout(&o));
        for file in [&csv, &svg] {
            if let Ok(text) = std::fs::read_to_string(file) {
                finite_text(&format!("{flags:?} {}", file.display()), &text);
            }
        }
    }
}

/// A run that diverges reports the verdict (the word and the time), never a number: the library's
/// result names the failure, the JSON has no number where the error was.
#[test]
fn a_diverged_run_is_a_verdict_with_a_reason() {
    use freefloat::planners::{PlannerOptions, planner};
    use freefloat::track::{Controller, Disturbances, TrackOptions, TwoLinkMotion, track, two_link};
    use freefloat::{Method, PlanningProblem, RobotParams};
    let problem = PlanningProblem::paper(RobotParams::src());
    let planned = planner(Method::Optimal, &PlannerOptions::default()).plan(&problem).expect("plan");
    // A torque bias beyond any this arm can take drives the plant out of the finite numbers.
    let options = TrackOptions {
        controller: Controller::Open,
        rate: 100.0,
        disturbances: Disturbances { torque_bias: vec![1e150, -1e150], ..Default::default() },
        record: true,
        ..Default::default()
    };
    let (arm, chain) = two_link(&problem);
    match track(&arm, &chain, &TwoLinkMotion(planned.motion.as_ref()), &arm, &options, 0) {
        Ok(run) => {
            let failure = run.failure.expect("a bias of 1e150 N m diverges");
            assert_eq!(failure.reason, "diverged");
            assert!(failure.t > 0.0 && failure.t <= problem.horizon, "{failure:?}");
            let json = serde_json::to_string(&run).expect("json");
            finite_text("diverged run's JSON", &json);
            let h = run.history.expect("recorded");
            assert!(h.actual.iter().flatten().chain(h.tau.iter().flatten()).all(|x| x.is_finite()), "NaN rows");
        }
        // A bias this large may as well be refused as bad input: either is a clean answer.
        Err(e) => assert!(e.is_bad_input(), "{e}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Item 8: time and memory estimated from the request before the run.

/// Requests whose time or memory exceeds the documented budgets are refused at once (exit 2),
/// with the estimate in the message.
#[test]
fn budgets_are_checked_before_the_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases: [(&[&str], &str); 7] = [
        (&["track", "--rate", "1e6", "--time", "1e6", "--controller", "ct"], "control ticks"),
        (&["track", "--time", "1e5"], "re-plans"),
        (&["track", "--rate", "1e5", "--time", "100", "--controller", "ct", "--plot", "never.svg"], "memory"),
        (&["track", "--trials", "1000000", "--time", "1000", "--controller", "ct"], "control ticks"),
        (&["mount-sweep", "--grid", "8192", "--steps", "2", "--trials", "1"], "memory"),
        (&["domain", "--grid", "8192"], "memory"),
        (&["mount-sweep", "--trials", "1000000000", "--grid", "16"], "NFA plans"),
    ];
    for (args, named) in cases {
        let clock = Instant::now();
        let o = super::run_in(dir.path(), args);
        assert!(!dir.path().join("never.svg").exists(), "{args:?} wrote its output");
        let err = refused(&o, &format!("{args:?}"));
        // The estimate against the budget: "would need about 1.9 GiB ...; the limit is 1 GiB" or
        // "would take about 1.00e12 control ticks; the budget is 1.00e8".
        assert!(err.contains(named) && (err.contains("budget") || err.contains("limit")), "{args:?}: {err}");
        assert!(err.contains("about"), "{args:?}: no estimate: {err}");
        assert!(clock.elapsed() < Duration::from_secs(20), "{args:?} took {:?}", clock.elapsed());
    }
}
