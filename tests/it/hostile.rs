//! What freefloat refuses (issue 15): hostile or careless input gets a clear error with exit code
//! 2 (or 3 for a problem without a certified plan), never a silent wrong result, a panic, a hang,
//! a runaway allocation, a half-written file or a non-finite number in an output. Each test is
//! one item of the list; read the names.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

mod inputs;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_freefloat"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Exit code 2, an `error:` line, no panic.
#[track_caller]
fn refused(o: &Output, what: &str) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert!(err.starts_with("error"), "{what}: {err}");
    assert!(!err.contains("panicked"), "{what}: {err}");
    err
}

/// Waits for `child` at most `limit`, killing it after.
fn wait_at_most(child: &mut Child, limit: Duration) -> Option<std::process::ExitStatus> {
    let clock = Instant::now();
    while clock.elapsed() < limit {
        if let Some(status) = child.try_wait().expect("wait") {
            return Some(status);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _killed = child.kill();
    let _reaped = child.wait();
    None
}

const ROBOT: &str = "[robot]\nl1 = 0.619\nl2 = 0.6\nd1 = 0.313\nd2 = 0.287\nM = 12.9\nI = 0.208\nm1 = 4.5\nm2 = 1.5\n";

/// A small sweep: 9 points, coarse maps, two trials each.
const SMALL: [&str; 10] =
    ["mount-sweep", "--steps", "3", "--grid", "16", "--trials", "2", "--quiet", "--a", "-0.2,0.2"];

fn sweep(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let path = dir.join(name);
    let mut args: Vec<&str> = SMALL.to_vec();
    args.extend(extra);
    args.extend(["--out", path.to_str().expect("utf-8")]);
    let o = run(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    path
}

fn merge(dir: &Path, files: &[&Path]) -> Output {
    let out = dir.join("merged.csv");
    let mut args = vec!["mount-sweep", "merge", "--out", out.to_str().expect("utf-8")];
    args.extend(files.iter().map(|p| p.to_str().expect("utf-8")));
    run(&args)
}

// ---------------------------------------------------------------------------------------------
// Silent wrong results

/// Shards of one sweep merge into exactly the unsharded file, an empty shard included.
#[test]
fn merge_of_all_shards_equals_the_unsharded_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let whole = sweep(dir.path(), "whole.csv", &[]);
    let shards: Vec<PathBuf> =
        (1..=10).map(|k| sweep(dir.path(), &format!("s{k}.csv"), &["--shard", &format!("{k}/10")])).collect();
    let refs: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let o = merge(dir.path(), &refs);
    assert!(o.status.success(), "{}", stderr(&o));
    let merged = std::fs::read(dir.path().join("merged.csv")).expect("merged");
    assert_eq!(merged, std::fs::read(&whole).expect("whole"));
}

/// An empty shard (`--shard 10/10` of a 9-point sweep) still writes its header lines.
#[test]
fn empty_shard_writes_its_header() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = sweep(dir.path(), "empty.csv", &["--shard", "10/10"]);
    let text = std::fs::read_to_string(path).expect("written");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    assert!(lines[0].starts_with("# freefloat-sweep v2 ") && lines[0].contains("shard=10/10 rows=0"), "{text}");
    assert!(lines[2].starts_with("index,points,a,b,"), "{text}");
}

/// Shards of different runs (other --time, --from, robot, --samples, --global, a-range) are
/// refused, naming the file.
#[test]
fn merge_refuses_shards_of_other_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let first = sweep(dir.path(), "first.csv", &["--shard", "1/2"]);
    let robot = dir.path().join("robot.toml");
    std::fs::write(&robot, ROBOT.replace("m2 = 1.5", "m2 = 1.6")).expect("write");
    let others: [&[&str]; 6] = [
        &["--time", "11"],
        &["--from", "45,120,81"],
        &["--robot", robot.to_str().expect("utf-8")],
        &["--samples", "31"],
        &["--global"],
        &["--b", "-0.2,0.3"],
    ];
    for (k, other) in others.iter().enumerate() {
        let mut extra = other.to_vec();
        extra.extend(["--shard", "2/2"]);
        let second = sweep(dir.path(), &format!("other{k}.csv"), &extra);
        let o = merge(dir.path(), &[&first, &second]);
        let err = refused(&o, &format!("{other:?}"));
        assert!(err.contains(&format!("other{k}.csv")) && err.contains("another run"), "{other:?}: {err}");
        assert!(!dir.path().join("merged.csv").exists());
    }
}

/// Edited rates, counts, components, and NaN / inf / 1e309 are refused, naming file and line;
/// `--plot` draws nothing then.
#[test]
fn merge_refuses_tampered_rows() {
    let dir = tempfile::tempdir().expect("temp dir");
    let good = sweep(dir.path(), "good.csv", &[]);
    let text = std::fs::read_to_string(&good).expect("written");
    let row = text.lines().nth(4).expect("a row").to_string(); // line 5: index 1
    let cells: Vec<&str> = row.split(',').collect();
    let edit = |column: usize, value: &str| {
        let mut c = cells.clone();
        c[column] = value;
        c.join(",")
    };
    // Columns: index 0, components 7, start_component_fraction 8, eq14_successes 10, eq14_rate 11.
    let tampered =
        [edit(11, "0.99"), edit(10, "2"), edit(7, "5"), edit(8, "NaN"), edit(8, "inf"), edit(2, "1e309"), edit(0, "7")];
    for (k, bad_row) in tampered.iter().enumerate() {
        let path = dir.path().join(format!("bad{k}.csv"));
        std::fs::write(&path, text.replace(&row, bad_row)).expect("write");
        let plot = dir.path().join("plot.svg");
        let out = dir.path().join("merged.csv");
        let o = run(&[
            "mount-sweep",
            "merge",
            "--out",
            out.to_str().expect("utf-8"),
            "--plot",
            plot.to_str().expect("utf-8"),
            path.to_str().expect("utf-8"),
        ]);
        let err = refused(&o, bad_row);
        assert!(err.contains(&format!("bad{k}.csv, line 5")), "{bad_row}: {err}");
        assert!(!plot.exists() && !out.exists());
    }
    // A lost row, and an edited header.
    let lost = dir.path().join("lost.csv");
    std::fs::write(&lost, text.replace(&format!("{row}\n"), "")).expect("write");
    assert!(refused(&merge(dir.path(), &[&lost]), "lost row").contains("lost.csv"));
    let head = dir.path().join("head.csv");
    std::fs::write(&head, text.replace("shard=1/1", "shard=1/2")).expect("write");
    assert!(refused(&merge(dir.path(), &[&head]), "header").contains("head.csv"));
    // A file that is not a sweep at all.
    let plain = dir.path().join("plain.csv");
    std::fs::write(&plain, "index,points\n0,1\n").expect("write");
    assert!(refused(&merge(dir.path(), &[&plain]), "plain").contains("not a freefloat sweep file"));
}

/// A shard given twice or a missing shard is refused, with words, not `invalid value 2`.
#[test]
fn merge_refuses_duplicate_and_missing_shards() {
    let dir = tempfile::tempdir().expect("temp dir");
    let one = sweep(dir.path(), "one.csv", &["--shard", "1/3"]);
    let two = sweep(dir.path(), "two.csv", &["--shard", "2/3"]);
    let err = refused(&merge(dir.path(), &[&one, &two]), "missing");
    assert!(err.contains("shards missing from the merge: 3/3"), "{err}");
    let err = refused(&merge(dir.path(), &[&one, &two, &one]), "duplicate");
    assert!(err.contains("given twice"), "{err}");
}

/// A tolerance must be finite, positive and at most 1e-3 rad: `inf` is not "certified".
#[test]
fn tolerance_must_be_finite_positive_and_small() {
    for t in ["inf", "1e300", "0.01", "0", "-1e-9", "NaN"] {
        let o = run(&["plan", "--samples", "101", "--format", "json", &format!("--tolerance={t}")]);
        let err = refused(&o, t);
        assert!(err.contains("--tolerance") && err.contains("1e-3"), "{t}: {err}");
        assert!(!stdout(&o).contains("\"certified\""), "{t}");
    }
}

/// Counts parse into checked types with upper bounds: no wrap-around, no panic.
#[test]
fn counts_do_not_wrap_or_panic() {
    let cases: [&[&str]; 5] = [
        &["mount-sweep", "--steps", "4294967296"],
        &["mount-sweep", "--steps", "4294967297,4294967295"],
        &["mount-sweep", "--steps", "0"],
        &["plan", "--samples", "18446744073709551615"],
        &["plan", "--samples", "18446744073709551616"],
    ];
    for args in cases {
        refused(&run(args), &format!("{args:?}"));
    }
}

/// `domain` and `mount-sweep` refuse `--samples 0` and `1` instead of reporting from them.
#[test]
fn too_few_samples_are_refused() {
    for n in ["0", "1"] {
        let e = refused(&run(&["domain", "--grid", "16", "--samples", n]), n);
        assert!(e.contains("--samples"), "{e}");
        refused(&run(&["mount-sweep", "--steps", "1", "--grid", "16", "--samples", n]), n);
    }
}

/// Physical ranges are checked up front: no NaN or inf is ever printed.
#[test]
fn huge_physical_values_are_refused() {
    let e = refused(&run(&["domain", "--mount=1e300,0"]), "mount");
    assert!(e.contains("--mount") && e.contains("1e300"), "{e}");
    let dir = tempfile::tempdir().expect("temp dir");
    for (from, to) in [("l1 = 0.619", "l1 = 1e300"), ("M = 12.9", "M = 1e300"), ("d1 = 0.313", "d1 = 1e-300")] {
        let path = dir.path().join("robot.toml");
        std::fs::write(&path, ROBOT.replace(from, to)).expect("write");
        let o = run(&["domain", "--grid", "16", "--robot", path.to_str().expect("utf-8"), "--format", "json"]);
        let e = refused(&o, to);
        assert!(e.contains("physical range"), "{e}");
        let all = format!("{}{e}", stdout(&o)).to_lowercase();
        assert!(!all.contains("nan") && !all.contains("inf,") && !all.contains(": inf"), "{all}");
    }
}

// ---------------------------------------------------------------------------------------------
// Resources

/// The memory of a request is checked before anything is allocated, and the message gives the
/// size it would take and the limit.
#[test]
fn memory_is_checked_before_allocating() {
    let cases: [&[&str]; 3] = [
        &["plan", "--samples", "100000000"],
        &["plan", "--samples", "1000000000"],
        &["mount-sweep", "--steps", "100000"],
    ];
    for args in cases {
        let clock = Instant::now();
        let e = refused(&run(args), &format!("{args:?}"));
        assert!(e.contains("would need about") && e.contains("the limit is 1.0 GiB"), "{e}");
        assert!(clock.elapsed() < Duration::from_secs(5));
    }
}

/// A robot file that is a FIFO (or a directory) is refused instead of waited on.
#[cfg(unix)]
#[test]
fn robot_file_must_be_a_regular_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let fifo = dir.path().join("fifo.toml");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success());
    let mut child = bin()
        .args(["plan", "--robot", fifo.to_str().expect("utf-8")])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let status = wait_at_most(&mut child, Duration::from_secs(10)).expect("no hang on a FIFO");
    assert_eq!(status.code(), Some(2));
    let mut err = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut err).expect("read");
    assert!(err.contains("not a regular file"), "{err}");
    let e = refused(&run(&["plan", "--robot", dir.path().to_str().expect("utf-8")]), "directory");
    assert!(e.contains("not a regular file"), "{e}");
}

/// Horizons are bounded up front: a denormal horizon fails at once, not after minutes, and a
/// tiny velocity cap cannot stretch the horizon to infinity.
#[test]
fn horizons_are_bounded_up_front() {
    for args in [
        &["plan", "--time=5e-324"][..],
        &["plan", "--time=1e-310"],
        &["plan", "--time=1e300"],
        &["plan", "--max-velocity=1e-320"],
        &["plan", "--max-velocity=1e300"],
    ] {
        let clock = Instant::now();
        let e = refused(&run(args), &format!("{args:?}"));
        assert!(e.contains("--time") || e.contains("--max-velocity") || e.contains("horizon"), "{e}");
        assert!(clock.elapsed() < Duration::from_secs(20), "{args:?} took {:?}", clock.elapsed());
    }
}

/// Messages echo at most a few dozen characters of the input.
#[test]
fn messages_do_not_echo_huge_input() {
    let dir = tempfile::tempdir().expect("temp dir");
    let big = dir.path().join("big.toml");
    std::fs::write(&big, "x".repeat(2 << 20)).expect("write");
    let e = refused(&run(&["plan", "--robot", big.to_str().expect("utf-8")]), "big file");
    assert!(e.len() < 500 && e.contains("limit"), "{e}");
    let line = dir.path().join("line.toml");
    std::fs::write(&line, format!("[robot]\nl1 = {}\n", "9".repeat(500_000))).expect("write");
    let e = refused(&run(&["plan", "--robot", line.to_str().expect("utf-8")]), "long line");
    assert!(e.len() < 2000, "{} bytes on stderr", e.len());
    let digits = format!("45,1{},80", "0".repeat(300));
    let e = refused(&run(&["plan", &format!("--from={digits}")]), "300 digits");
    assert!(e.len() < 300, "{e}");
    let e = refused(&run(&["plan", &format!("--from={}", "x".repeat(100_000))]), "long text");
    assert!(e.len() < 500, "{} bytes", e.len());
}

// ---------------------------------------------------------------------------------------------
// Files

/// `--out` into a missing directory is refused before anything is printed or planned.
#[test]
fn out_into_a_missing_directory_prints_nothing() {
    let o = run(&["plan", "--samples", "101", "--out", "/no/such/dir/plan.json"]);
    refused(&o, "missing dir");
    assert!(o.stdout.is_empty(), "{}", stdout(&o));
}

/// `--out x.JSON` is a JSON file: extensions are case-insensitive.
#[test]
fn out_extensions_are_case_insensitive() {
    let dir = tempfile::tempdir().expect("temp dir");
    for name in ["plan.JSON", "plan.Csv"] {
        let o = run_in(dir.path(), &["plan", "--samples", "101", "--quiet", "--out", name]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert!(dir.path().join(name).exists());
    }
    let json = std::fs::read_to_string(dir.path().join("plan.JSON")).expect("written");
    assert!(json.trim_start().starts_with('{'));
}

/// A temporary file left by a killed run (`.NAME.PID.tmp`, PID no longer running) is removed by
/// the next write of that file; nothing else is touched.
#[test]
fn stale_temporaries_of_killed_runs_are_removed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let stale = dir.path().join(".plan.json.999999999.tmp");
    let other = dir.path().join(".other.json.999999999.tmp");
    std::fs::write(&stale, "half").expect("write");
    std::fs::write(&other, "not ours").expect("write");
    let o = run_in(dir.path(), &["plan", "--samples", "101", "--quiet", "--out", "plan.json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists() && other.exists());
}

/// SIGTERM or SIGKILL during `reproduce` leaves the old directory whole (never a mix of old and
/// new files), and SIGTERM leaves no temporary directory behind.
#[cfg(unix)]
#[test]
fn interrupted_reproduce_leaves_the_old_directory() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).expect("mkdir");
    // A directory of an earlier run: its marker lists what it wrote (issue 24 item 4).
    std::fs::write(out.join(".freefloat-out"), "# written by freefloat reproduce\nold.txt\n").expect("write");
    std::fs::write(out.join("old.txt"), "old").expect("write");
    for signal in ["-TERM", "-KILL"] {
        let mut child = bin()
            .current_dir(dir.path())
            .args(["reproduce", "--out", "out"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn");
        std::thread::sleep(Duration::from_millis(1500));
        let killed = Command::new("kill").args([signal, &child.id().to_string()]).status().expect("kill runs");
        assert!(killed.success());
        let status = wait_at_most(&mut child, Duration::from_secs(30)).expect("stops");
        if signal == "-TERM" {
            assert_eq!(status.code(), Some(130), "{status:?}");
            let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").flatten().map(|e| e.file_name()).collect();
            assert_eq!(left, vec![std::ffi::OsString::from("out")], "{left:?}");
        }
        let mut files: Vec<_> = std::fs::read_dir(&out).expect("out").flatten().map(|e| e.file_name()).collect();
        files.sort();
        assert_eq!(files, [".freefloat-out", "old.txt"].map(std::ffi::OsString::from), "{signal}: {files:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// A newcomer's first hour

/// `plan --format csv | head -3`: a closed pipe ends the run quietly with exit code 0.
#[test]
fn closed_stdout_is_not_a_panic() {
    let mut child = bin()
        .args(["plan", "--format", "csv", "--samples", "20001", "--method", "nfa"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let mut head = [0u8; 64];
    child.stdout.take().expect("stdout").read_exact(&mut head).expect("some output");
    // stdout is dropped here: the reader is gone.
    let status = wait_at_most(&mut child, Duration::from_secs(60)).expect("ends");
    let mut err = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut err).expect("read");
    assert_eq!(status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
}

/// Each level shows its own verdict: a failed torque level does not mark the velocity line.
#[test]
fn each_level_shows_its_own_verdict() {
    let o = run(&["plan", "--method", "nfa", "--mount", "1,-1", "--torques", "--samples", "201"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let text = stdout(&o);
    let line = |key: &str| text.lines().find(|l| l.trim_start().starts_with(key)).unwrap_or_default().to_string();
    assert!(line("verified final error").ends_with(" CERTIFIED"), "{text}");
    assert!(line("torque final error").ends_with("NOT CERTIFIED"), "{text}");
}

/// With `--format json`, a failure prints one JSON error object on stdout (docs/spec.md §3).
#[test]
fn json_failure_prints_one_error_object() {
    for (args, code, kind) in [
        (&["plan", "--format", "json", "--tolerance", "inf"][..], 2, "invalid_parameter"),
        (&["plan", "--format", "json", "--method", "nfa", "--from", "45,120,0"], 3, "singular"),
        (&["domain", "--format", "json", "--samples", "1"], 2, "invalid_parameter"),
        (&["compare", "--format", "json", "--time", "0"], 2, "invalid_parameter"),
    ] {
        let o = run(args);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
        assert_eq!(v["error"]["kind"], kind, "{v}");
        assert_eq!(v["error"]["exit_code"], code);
        assert!(v["error"]["message"].as_str().is_some_and(|m| !m.is_empty()));
        assert!(v["error"]["numbers"].is_object());
    }
}

/// Messages say what is wrong in words, once, naming the flag as the user wrote it.
#[test]
fn messages_are_clear() {
    let e = refused(&run(&["mount-sweep", "--shard", "0/8"]), "shard");
    assert!(e.contains("--shard `0/8`") && !e.contains("NaN"), "{e}");
    let e = refused(&run(&["plan", "--robot", "/no/such/robot.toml"]), "missing");
    assert_eq!(e.matches("No such file").count(), 1, "{e}");
    let e = refused(&run(&["domain", "--plot", "x.gif"]), "plot");
    assert_eq!(e.matches(".svg or .png").count(), 1, "{e}");
    let e = refused(&run(&["plan", "--time", "-1"]), "negative time");
    assert!(e.contains("--time") && !e.contains("unexpected argument"), "{e}");
    let e = refused(&run(&["plan", "--mount", "1e9,0"]), "mount");
    assert!(e.contains("`--mount`"), "{e}");
    let help = stdout(&run(&["compare", "--help"]));
    assert!(!help.contains("csv"), "{help}");
    let help = stdout(&run(&["plan", "--help"]));
    assert!(help.contains("[default: 1e-9]") && !help.contains("0.000000001"), "{help}");
}

/// Numbers in tables have sensible precision.
#[test]
fn numbers_are_printed_with_sensible_precision() {
    let o = run(&["plan", "--samples", "101", "--time", "53.58170147727351", "--method", "nfa"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("horizon                  53.5817 s"), "{}", stdout(&o));
}

/// Shell completions, a man page, and `--quiet`.
#[test]
fn completions_man_page_and_quiet() {
    for shell in ["bash", "zsh", "fish"] {
        let o = run(&["completions", shell]);
        assert!(o.status.success() && stdout(&o).contains("mount-sweep"), "{shell}");
    }
    let o = run(&["man"]);
    assert!(o.status.success() && stdout(&o).contains(".TH"), "{}", stderr(&o));
    let o = run(&["plan", "--quiet", "--samples", "101", "--mount", "1,-1", "--max-velocity", "2"]);
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
}

/// `domain` says what components and slivers are.
#[test]
fn domain_explains_its_words() {
    let o = run(&["domain", "--grid", "64"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("singular curves cut") && text.contains("components (numbered 0, 1"), "{text}");
}

// ---------------------------------------------------------------------------------------------
// Random input

/// Every number in `text`, as the JSON or the table prints it, is finite.
fn no_non_finite(text: &str) -> bool {
    let lower = text.to_lowercase();
    !["nan", "inf,", "inf ", "inf\n", "infinity"].iter().any(|w| lower.contains(w))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// Random bytes are never a robot, and never a panic.
    #[test]
    fn random_bytes_are_not_a_robot(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        prop_assert!(freefloat::RobotParams::from_toml(&text, Path::new("r.toml")).is_err());
    }

    /// Random TOML robot documents: accepted robots are physical and give finite constants.
    #[test]
    fn random_robot_documents(
        values in proptest::collection::vec(prop_oneof![
            Just("0".to_string()), Just("-1".to_string()), Just("nan".to_string()), Just("inf".to_string()),
            Just("1e309".to_string()), Just("1e-300".to_string()), Just("\"x\"".to_string()),
            (1e-4f64..1e4).prop_map(|x| format!("{x}")),
        ], 10),
        drop_key in 0usize..12,
        extra in prop_oneof![Just(""), Just("m3 = 1\n"), Just("[mount]\na = 1e300\nb = 0\n"), Just("[mount]\na = 0.1\nb = 0.1\n")],
    ) {
        let keys = ["l1", "l2", "d1", "d2", "M", "I", "m1", "m2"];
        let mut text = String::from("[robot]\n");
        for (k, (key, value)) in keys.iter().zip(&values).enumerate() {
            if k != drop_key {
                text += &format!("{key} = {value}\n");
            }
        }
        text += extra;
        if let Ok(robot) = freefloat::RobotParams::from_toml(&text, Path::new("r.toml")) {
            let k = robot.lumped();
            prop_assert!([k.mc, k.A, k.B, k.C, k.D, k.E, k.IP].iter().all(|x| x.is_finite()));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    /// Random argument vectors: exit 0, 2 or 3 only, no panic, no non-finite number printed.
    #[test]
    fn random_command_lines(
        command in prop_oneof![Just("plan"), Just("domain"), Just("compare"), Just("mount-sweep")],
        flags in proptest::collection::vec((
            prop_oneof![
                Just("--time"), Just("--samples"), Just("--tolerance"), Just("--mount"), Just("--from"),
                Just("--to"), Just("--grid"), Just("--steps"), Just("--max-velocity"), Just("--format"),
                Just("--shard"), Just("--harmonics"), Just("--trials"),
            ],
            prop_oneof![
                Just("0"), Just("1"), Just("-1"), Just("nan"), Just("inf"), Just("1e309"), Just("5e-324"),
                Just("18446744073709551616"), Just("0.5"), Just("3"), Just("json"), Just("1,2"), Just("1,2,3"),
                Just("1/2"), Just("x"), Just(""), Just("0.1,0.1"),
            ],
        ), 0..4),
    ) {
        let mut args = vec![command.to_string(), "--samples".into(), "21".into()];
        if command != "plan" && command != "compare" {
            args.extend(["--grid".into(), "16".into()]);
        }
        if command == "mount-sweep" {
            args.extend(["--steps".into(), "1".into(), "--trials".into(), "1".into()]);
        }
        for (flag, value) in flags {
            args.push(format!("{flag}={value}"));
        }
        let o = bin().args(&args).output().expect("the binary runs");
        let code = o.status.code();
        prop_assert!(matches!(code, Some(0 | 2 | 3)), "{args:?}: {code:?} {}", stderr(&o));
        prop_assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
        prop_assert!(no_non_finite(&stdout(&o)), "{args:?}: {}", stdout(&o));
    }
}
