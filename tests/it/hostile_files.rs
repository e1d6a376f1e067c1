//! Hostile input, round two (issue 24 items 1, 3, 4, 6 and 9): deeply nested robot files, shard
//! counts that would allocate per shard, output paths that are not freefloat's to replace,
//! closed and full outputs, and messages that echo huge input. Each case must end in a clean,
//! typed error (exit 2, an `error:` line, no panic, no abort) or a documented success; nothing
//! freefloat did not write is removed.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use freefloat::model::InputError;
use freefloat::model::arm::Arm;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_freefloat"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit code 2, one `error:` message, no panic or abort.
#[track_caller]
fn refused(o: &Output, what: &str) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert!(err.starts_with("error"), "{what}: {err}");
    assert!(!err.contains("panicked") && !err.contains("overflow"), "{what}: {err}");
    err
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

// ---------------------------------------------------------------------------------------------
// Item 1: nesting depth of the robot files

/// A URDF whose `<link name="base">` (line 2) holds `depth` nested elements on line 3.
fn nested_urdf(depth: usize) -> String {
    format!(
        "<robot name=\"r\">\n<link name=\"base\">\n{}{}\n</link>\n</robot>\n",
        "<a>".repeat(depth),
        "</a>".repeat(depth)
    )
}

/// 15000 nested elements (105 KB) aborted the CLI with a stack overflow (exit 134): now exit 2,
/// naming the line and the bound, by the CLI (`--urdf`, `--robot`) and the library.
#[test]
fn deeply_nested_urdf_is_refused_before_parsing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("deep.urdf");
    let text = nested_urdf(15_000);
    assert!(text.len() > 100_000 && text.len() < 1 << 20);
    std::fs::write(&path, &text).expect("write");
    for command in [&["plan", "--urdf"][..], &["domain", "--grid", "16", "--robot"], &["track", "--robot"]] {
        let mut args = command.to_vec();
        args.push(s(&path));
        let e = refused(&run(&args), &format!("{command:?}"));
        assert!(e.contains("deep.urdf, line 3") && e.contains("nested deeper than 64 levels"), "{e}");
    }
    let e = Arm::from_urdf_str(&text, &path).expect_err("refused");
    assert!(matches!(e, InputError::NestedTooDeep { line: 3, limit: 64, .. }), "{e}");
}

/// The bound counts elements, not text: 65 levels are refused anywhere in the file (under the
/// robot, a joint, unclosed), 64 pass the scan, and `<a>` inside a comment or CDATA is no element.
#[test]
fn nesting_bound_counts_elements_only() {
    let p = Path::new("x.urdf");
    let deep = |e: &Result<Arm, InputError>| matches!(e, Err(InputError::NestedTooDeep { .. }));
    // `<robot>` and `<link>` are two levels: 62 more make 64, 63 more make 65.
    assert!(!deep(&Arm::from_urdf_str(&nested_urdf(62), p)));
    assert!(deep(&Arm::from_urdf_str(&nested_urdf(63), p)));
    let unclosed = format!("<robot name=\"r\">{}", "<a>".repeat(100_000));
    assert!(deep(&Arm::from_urdf_str(&unclosed, p)));
    let in_joint = format!("<robot name=\"r\"><joint name=\"j\" type=\"fixed\">{}</joint></robot>", "<b>".repeat(70));
    assert!(deep(&Arm::from_urdf_str(&in_joint, p)));
    let three_link = std::fs::read_to_string("examples/robots/three_link.urdf").expect("example");
    for hidden in [format!("<!-- {} -->", "<a>".repeat(20_000)), format!("<![CDATA[{}]]>", "<a>".repeat(20_000))] {
        let text = three_link.replacen("<link name=\"base\">", &format!("<link name=\"base\">{hidden}"), 1);
        let arm = Arm::from_urdf_str(&text, p).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(arm.joints(), 3);
    }
    // Malformed XML is a typed error too, not a panic.
    for bad in ["<robot><a></b></robot>", "<robot name=\"r\"><link name=\"x", "<<<<", "<robot>&undefined;</robot>"] {
        assert!(Arm::from_urdf_str(bad, p).is_err(), "{bad}");
    }
}

/// Deeply nested TOML (arrays, inline tables, dotted keys and table headers; up to 200 KB) is a
/// typed error from the TOML reader's own recursion bound, by the CLI and the library.
#[test]
fn deeply_nested_toml_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let base = "[robot]\nM = 12.9\nI = 0.208\n";
    let texts = [
        format!("{base}x = {}{}\n", "[".repeat(100_000), "]".repeat(100_000)),
        format!("{base}x = {}1{}\n", "{a=".repeat(50_000), "}".repeat(50_000)),
        format!("{base}{} = 1\n", vec!["a"; 100_000].join(".")),
        format!("[{}]\n", vec!["a"; 100_000].join(".")),
        format!("{base}x = {}\n", "[{a=".repeat(30_000)),
    ];
    for (k, text) in texts.iter().enumerate() {
        let path = dir.path().join(format!("deep{k}.toml"));
        std::fs::write(&path, text).expect("write");
        assert!(Arm::load(&path).is_err(), "{k}");
        assert!(freefloat::RobotParams::load(&path).is_err(), "{k}");
        let e = refused(&run(&["plan", "--robot", s(&path)]), &format!("toml {k}"));
        assert!(e.len() < 2000, "{k}: {} bytes", e.len());
    }
}

// ---------------------------------------------------------------------------------------------
// Item 3: shard counts

/// `--shard` takes at most 65536 shards, when written: `1/18446744073709551615` (which then
/// made `merge` panic) and `1/100000000` (4.4 GB) are exit 2, for `track` and `mount-sweep`.
#[test]
fn shard_count_is_bounded_when_written() {
    for shard in ["1/18446744073709551615", "1/100000000", "1/65537", "65537/65537"] {
        let o = run(&["track", "--trials", "1", "--shard", shard, "--out", "/tmp/never-written.csv"]);
        let e = refused(&o, shard);
        assert!(e.contains("--shard") && e.contains("65536"), "{e}");
        let o = run(&[
            "mount-sweep",
            "--steps",
            "1",
            "--a",
            "0,0",
            "--b",
            "0,0",
            "--shard",
            shard,
            "--out",
            "/tmp/never-written.csv",
        ]);
        assert!(refused(&o, shard).contains("65536"));
    }
}

/// FNV-1a of the parts, as the shard files hash them (docs/spec.md §3).
fn fnv(parts: &[&str]) -> u64 {
    use freefloat::analysis::shards::{FNV_OFFSET, fnv1a};
    parts.iter().fold(FNV_OFFSET, |h, p| fnv1a(fnv1a(h, p.as_bytes()), b"\x1f"))
}

/// `text` (a shard file) with its header's `shard=` set to `shard` and the checksum recomputed,
/// so that only the bound on `N` can refuse it.
fn reshard(text: &str, shard: &str) -> String {
    let (head, rest) = text.split_once('\n').expect("a header");
    let field = |key: &str| head.split_whitespace().find_map(|w| w.strip_prefix(key)).expect("field").to_string();
    let (run, rows) = (field("run="), field("rows="));
    let checks: Vec<&str> = rest.lines().skip(2).filter_map(|l| l.rsplit_once(',').map(|c| c.1)).collect();
    let start = fnv(&[&format!("{run} {shard} {rows}")]);
    let sum = checks.iter().fold(start, |h, c| freefloat::analysis::shards::fnv1a(h, c.as_bytes()));
    let magic = head.split(" run=").next().expect("magic");
    format!("{magic} run={run} shard={shard} rows={rows} checksum={sum:016x}\n{rest}")
}

/// When read: a file claiming 18446744073709551615 or 1e8 shards (checksum consistent) is a
/// damaged header, at once; a valid shard of 65536 is reported with its 65535 missing shards as
/// one range, at once and in one short line. For `track merge` and `mount-sweep merge`.
#[test]
fn shard_count_is_bounded_when_read() {
    let dir = tempfile::tempdir().expect("temp dir");
    let track = dir.path().join("t.csv");
    let o = run(&["track", "--trials", "1", "--controller", "ct", "--shard", "1/65536", "--quiet", "--out", s(&track)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let sweep = dir.path().join("s.csv");
    let o = run(&[
        "mount-sweep",
        "--steps",
        "1",
        "--a",
        "0,0",
        "--b",
        "0,0",
        "--grid",
        "16",
        "--trials",
        "1",
        "--quiet",
        "--shard",
        "1/65536",
        "--out",
        s(&sweep),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for (file, merge) in [(&track, &["track", "merge"][..]), (&sweep, &["mount-sweep", "merge", "--out"])] {
        let text = std::fs::read_to_string(file).expect("written");
        // The file as written: the reshard routine reproduces its checksum.
        assert_eq!(reshard(&text, "1/65536"), text);
        let merged = dir.path().join("merged.csv");
        let mut args = merge.to_vec();
        if merge.len() == 3 {
            args.push(s(&merged));
        }
        let clock = Instant::now();
        let mut with = args.clone();
        with.push(s(file));
        let e = refused(&run(&with), "missing");
        assert!(e.contains("shards missing from the merge: 2/65536 to 65536/65536") && e.len() < 400, "{e}");
        for shard in ["1/18446744073709551615", "1/100000000", "2/65537"] {
            let path = dir.path().join("tampered.csv");
            std::fs::write(&path, reshard(&text, shard)).expect("write");
            let mut with = args.clone();
            with.push(s(&path));
            let e = refused(&run(&with), shard);
            assert!(e.contains("tampered.csv, line 1: damaged header") && e.contains("65536"), "{e}");
        }
        assert!(clock.elapsed() < Duration::from_secs(10), "{:?}", clock.elapsed());
        assert!(!merged.exists());
    }
}

// ---------------------------------------------------------------------------------------------
// Item 4: output directories and files

/// `reproduce --out` refuses, before any work and changing nothing, a directory of other files
/// (the user's `thesis.tex` was deleted), a plain file (was moved aside), a FIFO and a device
/// node (was moved and deleted): exit 2 naming the path and what to do.
#[cfg(unix)]
#[test]
fn reproduce_refuses_what_it_did_not_write() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let thesis = dir.path().join("u");
    std::fs::create_dir(&thesis).expect("mkdir");
    std::fs::write(thesis.join("thesis.tex"), "x").expect("write");
    let plain = dir.path().join("f");
    std::fs::write(&plain, "mine").expect("write");
    let fifo = dir.path().join("fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    let device = dir.path().join("null");
    let made_device = Command::new("mknod").arg(&device).args(["c", "1", "3"]).stderr(Stdio::null()).status();
    let mut targets = vec![&thesis, &plain, &fifo];
    if made_device.is_ok_and(|s| s.success()) {
        targets.push(&device);
    }
    for out in targets {
        let clock = Instant::now();
        let e = refused(&run(&["reproduce", "--out", s(out)]), s(out));
        assert!(e.contains(s(out)) && e.contains("give `--out` a new or an empty directory"), "{e}");
        assert!(clock.elapsed() < Duration::from_secs(5), "checked before the run");
    }
    assert_eq!(std::fs::read_to_string(thesis.join("thesis.tex")).expect("kept"), "x");
    assert_eq!(std::fs::read_to_string(&plain).expect("kept"), "mine");
    assert!(std::fs::metadata(&fifo).expect("kept").file_type().is_fifo());
    if device.exists() {
        assert!(std::fs::metadata(&device).expect("kept").file_type().is_char_device());
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").flatten().map(|e| e.file_name()).collect();
    assert!(names.iter().all(|n| !n.to_string_lossy().starts_with('.')), "temporaries left: {names:?}");
}

/// Moving a run's files into its directory replaces only the files it writes, by name: a user's
/// file beside them stays, a file an earlier run listed and this one did not write goes, and a
/// name taken by a directory or a link is refused before anything moves.
#[cfg(unix)]
#[test]
fn reproduce_replaces_only_its_own_files() {
    use freefloat::report::out_dir::{MARKER, check_out_dir, move_into};
    let dir = tempfile::tempdir().expect("temp dir");
    let (fresh, out) = (dir.path().join("fresh"), dir.path().join("out"));
    let fill = |files: &[&str]| {
        std::fs::create_dir(&fresh).expect("mkdir");
        for f in files {
            std::fs::write(fresh.join(f), format!("new {f}")).expect("write");
        }
    };
    // A new directory, then the same directory again with a user's file in it.
    fill(&["a.svg", "old.gif"]);
    assert_eq!(move_into(&fresh, &out).expect("moved"), 2);
    std::fs::remove_dir(&fresh).expect("empty");
    std::fs::write(out.join("notes.txt"), "mine").expect("write");
    check_out_dir(&out).expect("a freefloat directory");
    fill(&["a.svg"]);
    move_into(&fresh, &out).expect("moved");
    std::fs::remove_dir(&fresh).expect("empty");
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).expect("kept"), "mine");
    assert!(!out.join("old.gif").exists(), "a file of the earlier run stayed");
    assert_eq!(
        std::fs::read_to_string(out.join(MARKER)).expect("marker").lines().skip(1).collect::<Vec<_>>(),
        ["a.svg"]
    );
    // A name that is a directory or a link is not replaced.
    std::fs::remove_file(out.join("a.svg")).expect("rm");
    std::fs::create_dir(out.join("a.svg")).expect("mkdir");
    std::fs::write(out.join("a.svg").join("inside"), "mine").expect("write");
    fill(&["a.svg", "b.svg"]);
    assert!(move_into(&fresh, &out).is_err());
    assert!(out.join("a.svg/inside").exists() && !out.join("b.svg").exists(), "something moved");
    std::fs::remove_dir_all(out.join("a.svg")).expect("rm");
    std::os::unix::fs::symlink(&fresh, out.join("a.svg")).expect("symlink");
    assert!(move_into(&fresh, &out).is_err());
    assert!(std::fs::symlink_metadata(out.join("a.svg")).expect("kept").is_symlink());
}

/// `--out`, `--plot` and `--gif` never replace what is not a regular file (a device, a FIFO, a
/// directory): exit 2 before any work, the node untouched. A link to a regular file writes its
/// target and stays a link.
#[cfg(unix)]
#[test]
fn outputs_replace_only_regular_files() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let fifo = dir.path().join("fifo.csv");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    let device = dir.path().join("null.csv");
    let has_device = Command::new("mknod")
        .arg(&device)
        .args(["c", "1", "3"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let mut kinds = vec!["fifo", "folder"];
    if has_device {
        kinds.push("null");
    }
    let node = |kind: &str, ext: &str| -> std::path::PathBuf {
        let path = dir.path().join(format!("{kind}.{ext}"));
        match kind {
            "fifo" => assert!(Command::new("mkfifo").arg(&path).status().expect("mkfifo").success()),
            "folder" => std::fs::create_dir(&path).expect("mkdir"),
            _ => assert!(Command::new("mknod").arg(&path).args(["c", "1", "3"]).status().expect("mknod").success()),
        }
        path
    };
    for kind in kinds {
        let (csv, svg) = if kind == "fifo" {
            (fifo.clone(), node(kind, "svg"))
        } else if kind == "null" {
            (device.clone(), node(kind, "svg"))
        } else {
            (node(kind, "csv"), node(kind, "svg"))
        };
        let cases: [Vec<&str>; 6] = [
            vec!["plan", "--samples", "101", "--out", s(&csv)],
            vec!["track", "--out", s(&csv)],
            vec!["track", "--trials", "1", "--out", s(&csv)],
            vec!["track", "--plot", s(&svg)],
            vec!["domain", "--grid", "16", "--plot", s(&svg)],
            vec!["mount-sweep", "--steps", "1", "--a", "0,0", "--b", "0,0", "--grid", "16", "--plot", s(&svg)],
        ];
        for args in cases {
            let clock = Instant::now();
            let o = run(&args);
            let e = refused(&o, &format!("{args:?}"));
            assert!(e.contains("regular file") || e.contains("is a directory"), "{args:?}: {e}");
            assert!(o.stdout.is_empty() && clock.elapsed() < Duration::from_secs(5), "{args:?}");
        }
        let file_type = |p: &Path| std::fs::symlink_metadata(p).expect("kept").file_type();
        for p in [&csv, &svg] {
            let t = file_type(p);
            assert!(t.is_fifo() || t.is_dir() || t.is_char_device(), "{} was replaced", p.display());
        }
    }
    let folder = dir.path().join("folder.csv");
    let gif = dir.path().join("fifo.gif");
    assert!(Command::new("mkfifo").arg(&gif).status().expect("mkfifo").success());
    refused(&run(&["plan", "--samples", "101", "--gif", s(&gif)]), "gif fifo");
    assert!(std::fs::metadata(&fifo).expect("kept").file_type().is_fifo());
    assert!(std::fs::metadata(&gif).expect("kept").file_type().is_fifo());
    assert!(folder.is_dir());
    if has_device {
        assert!(std::fs::metadata(&device).expect("kept").file_type().is_char_device());
    }
    // A link to a regular file: the target gets the plan, the link stays.
    let target = dir.path().join("target.json");
    std::fs::write(&target, "old").expect("write");
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&target, &link).expect("symlink");
    let o = run(&["plan", "--samples", "101", "--quiet", "--out", s(&link)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link).expect("link").is_symlink());
    assert!(std::fs::read_to_string(&target).expect("target").starts_with('{'));
    let dangling = dir.path().join("dangling.json");
    std::os::unix::fs::symlink(dir.path().join("nothing"), &dangling).expect("symlink");
    refused(&run(&["plan", "--samples", "101", "--out", s(&dangling)]), "dangling link");
}

// ---------------------------------------------------------------------------------------------
// Item 6: closed and full outputs

/// `track | true` and `track > /dev/full` panicked (exit 101, `println!`): a closed stdout ends
/// quietly with exit 0, a full one is exit 2 naming stdout; `2>/dev/full` is exit 2, not 101.
#[cfg(unix)]
#[test]
fn closed_and_full_outputs_are_not_panics() {
    let full = || Stdio::from(std::fs::OpenOptions::new().write(true).open("/dev/full").expect("/dev/full"));
    let track = ["track", "--controller", "ct", "--time", "2"];
    // stdout closed before the table is printed.
    let mut child = bin().args(track).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("ends");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"));
    for json in [false, true] {
        let mut args = track.to_vec();
        if json {
            args.extend(["--format", "json"]);
        }
        let o = bin().args(&args).stdout(full()).output().expect("runs");
        let e = refused(&o, "stdout full");
        assert!(e.contains("cannot write to stdout"), "{e}");
    }
    let o = bin().args(["plan", "--samples", "101", "--format", "csv"]).stdout(full()).output().expect("runs");
    assert!(refused(&o, "plan csv").contains("cannot write to stdout"));
    for args in
        [&["plan", "--time", "0"][..], &["track", "merge", "/no/such/x.csv"], &["reproduce", "--out", "/dev/null"]]
    {
        let o = bin().args(args).stderr(full()).output().expect("runs");
        assert_eq!(o.status.code(), Some(2), "{args:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Item 9: messages and contracts

/// `track --out nodir/r.csv` printed the whole table, then failed: every output is checked
/// before the run, so a bad one prints nothing (track, its Monte Carlo, domain, mount-sweep).
#[test]
fn outputs_are_checked_before_the_run() {
    let cases: [&[&str]; 6] = [
        &["track", "--out", "/no/such/dir/r.csv"],
        &["track", "--plot", "/no/such/dir/r.svg"],
        &["track", "--trials", "1", "--plot", "/no/such/dir/r.svg"],
        &["domain", "--grid", "16", "--plot", "/no/such/dir/d.svg"],
        &["mount-sweep", "--steps", "1", "--a", "0,0", "--b", "0,0", "--grid", "16", "--plot", "/no/such/dir/s.svg"],
        &["mount-sweep", "--steps", "1", "--a", "0,0", "--b", "0,0", "--grid", "16", "--out", "/no/such/dir/s.csv"],
    ];
    for args in cases {
        let clock = Instant::now();
        let o = run(args);
        let e = refused(&o, &format!("{args:?}"));
        assert!(e.contains("/no/such/dir"), "{e}");
        assert!(o.stdout.is_empty() && clock.elapsed() < Duration::from_secs(5), "{args:?}");
    }
}

/// An output onto one of the command's inputs replaced a file freefloat did not write: `check
/// --out` onto the trajectory it checks (another tool's plan), `merge --out` onto one of its
/// shards. Each is exit 2 naming the input, directly or through a symbolic link, and the input
/// is left byte for byte.
#[test]
fn outputs_never_replace_the_inputs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = |name: &str| dir.path().join(name);
    let o = run(&["plan", "--quiet", "--out", s(&path("traj.csv"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in ["1/2", "2/2"] {
        let out = path(&format!("t{}.csv", &k[..1]));
        let o = run(&["track", "--trials", "2", "--controller", "ct", "--shard", k, "--quiet", "--out", s(&out)]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = path(&format!("s{}.csv", &k[..1]));
        let sweep = ["mount-sweep", "--steps", "2,1", "--a", "0,0.1", "--b", "0,0", "--grid", "16", "--trials", "1"];
        let o = bin().args(sweep).args(["--quiet", "--shard", k, "--out", s(&out)]).output().expect("runs");
        assert!(o.status.success(), "{}", stderr(&o));
    }
    #[cfg(unix)]
    std::os::unix::fs::symlink(path("t1.csv"), path("alias.csv")).expect("symlink");
    let p = |name: &str| path(name).to_string_lossy().into_owned();
    let mut cases: Vec<([String; 6], &str, &str)> = vec![
        (
            ["check", "--trajectory", &p("traj.csv"), "--out", &p("traj.csv"), "-q"].map(String::from),
            "traj.csv",
            "--trajectory",
        ),
        (
            ["check", "--trajectory", &p("traj.csv"), "--out", "../x/../traj.csv", "-q"].map(String::from),
            "traj.csv",
            "--trajectory",
        ),
        (["track", "merge", &p("t1.csv"), &p("t2.csv"), "--out", &p("t2.csv")].map(String::from), "t2.csv", "shard"),
        (
            ["mount-sweep", "merge", &p("s1.csv"), &p("s2.csv"), "--out", &p("s1.csv")].map(String::from),
            "s1.csv",
            "shard",
        ),
    ];
    if cfg!(unix) {
        cases.push((
            ["track", "merge", &p("t1.csv"), &p("t2.csv"), "--out", &p("alias.csv")].map(String::from),
            "t1.csv",
            "shard",
        ));
    }
    for (args, input, what) in cases {
        let before = std::fs::read(path(input)).expect("the input");
        // `../x/../traj.csv` from inside the directory `x` is the input by another name.
        std::fs::create_dir_all(path("x")).expect("x");
        let o = bin().args(&args).current_dir(path("x")).output().expect("runs");
        let e = refused(&o, &format!("{args:?}"));
        assert!(e.contains("--out names an input") && e.contains(what), "{e}");
        assert_eq!(std::fs::read(path(input)).expect("the input"), before, "{args:?} changed {input}");
    }
}

/// A valid 254-character file name works: the temporary name stays within NAME_MAX = 255.
#[test]
fn long_output_names_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    let name = format!("{}.json", "p".repeat(249));
    assert_eq!(name.len(), 254);
    let path = dir.path().join(&name);
    let o = run(&["plan", "--samples", "101", "--quiet", "--out", s(&path)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&path).expect("written").starts_with('{'));
    let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").flatten().map(|e| e.file_name()).collect();
    assert_eq!(left.len(), 1, "{left:?}");
    let sweep = dir.path().join(format!("{}.csv", "s".repeat(250)));
    let o = run(&[
        "mount-sweep",
        "--steps",
        "1",
        "--a",
        "0,0",
        "--b",
        "0,0",
        "--grid",
        "16",
        "--trials",
        "1",
        "--quiet",
        "--out",
        s(&sweep),
    ]);
    assert!(o.status.success() && sweep.exists(), "{}", stderr(&o));
}

/// Names from a URDF are cut in messages: a 20,000-character joint name, 45,000 root links
/// (439 KB) give a message of a few hundred bytes.
#[test]
fn huge_names_are_cut_in_messages() {
    let dir = tempfile::tempdir().expect("temp dir");
    let three_link = std::fs::read_to_string("examples/robots/three_link.urdf").expect("example");
    let long = "j".repeat(20_000);
    // The long name on a joint that branches, on a prismatic joint, and on a child of two joints.
    let branch = format!(
        "<joint name=\"{long}\" type=\"continuous\"><parent link=\"link1\"/><child link=\"extra\"/><axis xyz=\"0 0 1\"/></joint>\
         <link name=\"extra\"><inertial><mass value=\"1\"/><inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0.1\"/></inertial></link></robot>"
    );
    let twice =
        format!("<joint name=\"{long}\" type=\"fixed\"><parent link=\"base\"/><child link=\"link2\"/></joint></robot>");
    let roots: String = (0..45_000).map(|k| format!("<link name=\"r{k}\"/>")).collect();
    let texts = [
        three_link.replace("</robot>", &branch),
        three_link.replace("name=\"joint2\" type=\"continuous\"", &format!("name=\"{long}\" type=\"prismatic\"")),
        three_link.replace("</robot>", &twice),
        three_link.replace("</robot>", &format!("{roots}</robot>")),
    ];
    for (k, text) in texts.iter().enumerate() {
        assert!(text.len() < 1 << 20);
        let path = dir.path().join(format!("names{k}.urdf"));
        std::fs::write(&path, text).expect("write");
        let e = refused(&run(&["plan", "--urdf", s(&path)]), &format!("names {k}"));
        assert!(e.len() < 600, "{k}: {} bytes: {}", e.len(), &e[..600.min(e.len())]);
    }
}

/// A 2-link `[[link]]` file with `com = 0` on link 1 said "an arm of 2 link(s); this command
/// serves 2-link arms": the real reason is named (the link's `com`), and `plan` and `compare`
/// (issue 19: every arm) still plan it.
#[test]
fn two_link_arm_off_the_paper_model_names_the_reason() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("two.toml");
    let link = |com: f64| format!("[[link]]\nlength = 0.5\ncom = {com}\nmass = 2.0\ninertia = 0.05\n");
    std::fs::write(&path, format!("[robot]\nM = 12.9\nI = 0.208\n{}{}", link(0.0), link(0.25))).expect("write");
    // `track`, `compare` and `mount-sweep` (the effort) serve this arm now (issue 19: every
    // arm through the n-joint pipeline); the domain of the paper's normal form does not.
    let e = refused(&run(&["domain", "--grid", "16", "--robot", s(&path)]), "domain");
    assert!(e.contains("link[1].com = 0") && !e.contains("an arm of 2 link(s)"), "{e}");
    for command in ["plan", "compare"] {
        let o = run(&[command, "--robot", s(&path), "--samples", "101", "--quiet"]);
        assert!(matches!(o.status.code(), Some(0 | 3)), "{command}: {}", stderr(&o));
    }
}

/// The n-link path names the flags (`--time`, `--from`, `--to`), not the planner's keys
/// (`horizon`, `start[1]`).
#[test]
fn n_link_errors_name_the_flags() {
    let arm = ["plan", "--robot", "examples/robots/three_link.toml", "--samples", "101"];
    let (from, to, time) = ("--from=0,30,60,45", "--to=30,75,20,90", "--time=10");
    let cases: [([&str; 3], &str); 5] = [
        ([from, to, "--time=0"], "--time"),
        ([from, to, "--time=1e300"], "--time"),
        (["--from=0,1e9,0,0", to, time], "--from"),
        ([from, "--to=0,0,-1e7,0", time], "--to"),
        (["--from=0,600000,0,0", to, time], "--from"),
    ];
    for (extra, flag) in cases {
        let mut args = arm.to_vec();
        args.extend(extra);
        let e = refused(&run(&args), &format!("{extra:?}"));
        assert!(
            e.contains(&format!("`{flag}`")) && !e.contains("`horizon`") && !e.contains("start["),
            "{extra:?}: {e}"
        );
    }
}

/// Text of a flag echoed in a message is cut.
#[test]
fn echoed_flags_are_cut() {
    let long = format!("1/{}", "9".repeat(10_000));
    let e = refused(&run(&["track", "--shard", &long]), "long shard");
    assert!(e.len() < 400, "{} bytes", e.len());
}
