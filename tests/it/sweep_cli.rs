//! `freefloat mount-sweep` for any arm, as a user runs it: the effort metric of a 3-link arm
//! (CSV, shards, merge, picture), the NFA's flags refused for it, and the effort beside the NFA's
//! metric for the paper's robot.

use std::process::{Command, Output};

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The CSV rows of a sweep file as maps from column to cell (comment lines skipped).
fn rows(bytes: &[u8]) -> Vec<std::collections::HashMap<String, String>> {
    let text = String::from_utf8(bytes.to_vec()).unwrap();
    let body: String = text.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect();
    let mut r = csv::Reader::from_reader(body.as_bytes());
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records().map(|rec| header.iter().cloned().zip(rec.unwrap().iter().map(String::from)).collect()).collect()
}

/// A 3-link arm's sweep: every point planned and certified with a positive finite effort, the
/// NFA's cells empty; two shards merge into the whole byte for byte; the picture is drawn; the
/// summary names the mount of least effort, which is the row of least effort.
#[test]
fn a_three_link_arm_sweeps_the_effort() {
    let dir = tempfile::tempdir().unwrap();
    let robot = format!("{}/examples/robots/three_link.toml", env!("CARGO_MANIFEST_DIR"));
    let (whole, svg) = (dir.path().join("s.csv"), dir.path().join("s.svg"));
    let s = |p: &std::path::Path| p.display().to_string();
    let base = ["mount-sweep", "--robot", &robot, "--a", "-0.2,0.2", "--b", "0,0", "--steps", "3,1"];
    let ends = ["--from", "0,30,60,45", "--to", "30,75,20,90"];
    let run = |extra: &[&str]| freefloat(&[&base[..], &ends[..], extra].concat());
    let o = run(&["--out", &s(&whole), "--plot", &s(&svg)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = rows(&std::fs::read(&whole).unwrap());
    assert_eq!(table.len(), 3);
    let mut least = (f64::INFINITY, String::new());
    for r in &table {
        assert_eq!(r["planned"], "true", "{r:?}");
        let effort: f64 = r["effort"].parse().unwrap();
        assert!(effort.is_finite() && effort > 0.0);
        assert!(r["eq14_rate"].is_empty() && r["components"].is_empty(), "{r:?}");
        if effort < least.0 {
            least = (effort, r["a"].clone());
        }
    }
    let summary = String::from_utf8_lossy(&o.stdout);
    let a: f64 = least.1.parse().unwrap();
    assert!(summary.contains(&format!("least effort: a = {a:.4} m")), "{summary}");
    assert!(std::fs::read_to_string(&svg).unwrap().contains("Effort of the minimum-effort plan"));
    let parts: Vec<_> = (1..=2).map(|k| dir.path().join(format!("p{k}.csv"))).collect();
    for (k, part) in parts.iter().enumerate() {
        let o = run(&["--shard", &format!("{}/2", k + 1), "--out", &s(part)]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let merged = dir.path().join("m.csv");
    let o = freefloat(&["mount-sweep", "merge", "--out", &s(&merged), &s(&parts[0]), &s(&parts[1])]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&merged).unwrap(), std::fs::read(&whole).unwrap());
}

/// For a 3-link arm the NFA's flags are exit 2 naming the reason, not ignored, and so are
/// `--from`/`--to` of the wrong length (the paper's 2-link default among them).
#[test]
fn a_three_link_sweep_refuses_what_it_cannot_honour() {
    let robot = format!("{}/examples/robots/three_link.toml", env!("CARGO_MANIFEST_DIR"));
    let base = ["mount-sweep", "--robot", &robot, "--a", "0,0", "--b", "0,0", "--steps", "1"];
    let ends = ["--from", "0,30,60,45", "--to", "30,75,20,90"];
    for flag in [&["--trials", "5"][..], &["--grid", "32"], &["--global"], &["--seed", "3"], &["--samples", "11"]] {
        let o = freefloat(&[&base[..], &ends[..], flag].concat());
        assert_eq!(o.status.code(), Some(2), "{flag:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("two joints"), "{flag:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty());
    }
    let o = freefloat(&base);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("takes 4 comma-separated angles"), "{}", stderr(&o));
}

/// The paper's robot with `--effort`: the NFA's cells as without it, and the effort cells of a
/// certified plan at every point.
#[test]
fn the_paper_robot_sweeps_the_effort_beside_the_nfa() {
    let base = ["mount-sweep", "--a", "-0.1,0.1", "--b", "0,0", "--steps", "2,1", "--grid", "16", "--trials", "3"];
    let nfa = freefloat(&base);
    let both = freefloat(&[&base[..], &["--effort"]].concat());
    assert!(nfa.status.success() && both.status.success(), "{}{}", stderr(&nfa), stderr(&both));
    let (nfa, both) = (rows(&nfa.stdout), rows(&both.stdout));
    assert_eq!(nfa.len(), 2);
    for (x, y) in nfa.iter().zip(&both) {
        for (k, v) in x {
            if k != "planned" && k != "effort" && k != "check" {
                assert_eq!(&y[k], v, "{k}");
            }
        }
        assert!(x["planned"].is_empty() && y["planned"] == "true");
        assert!(y["effort"].parse::<f64>().unwrap() > 0.0);
    }
}
