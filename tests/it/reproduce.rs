//! `freefloat reproduce`: every file written whole, pictures that decode and parse, a summary
//! holding the numbers the planners compute, and a report page that runs in a headless browser.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use approx::assert_relative_eq;
use freefloat::model::arm::Arm;
use freefloat::plan::{TorqueOptions, torque_plan};
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::report::plot::{DOMAIN_PAIR_SIZE, METHODS_SIZE, PLAN_FIGURE_SIZE, SWEEP_SIZE};
use freefloat::{
    EcsaOptions, EcsaPlanner, Method, Mount, NfaOptions, NormalFormPlanner, Planned, Planner, PlanningProblem,
    RobotParams, Transform,
};
use serde_json::Value;

fn reproduce(dir: &Path) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_freefloat"))
        .args(["reproduce", "--out"])
        .arg(dir)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// The figures and the size of their PNGs.
fn figures() -> Vec<(String, (u32, u32))> {
    let mut figures: Vec<(String, (u32, u32))> = (4..=15).map(|k| (format!("fig{k:02}"), PLAN_FIGURE_SIZE)).collect();
    for (name, size) in &mut figures {
        if name == "fig13" || name == "fig14" {
            *size = DOMAIN_PAIR_SIZE;
        }
    }
    figures.push(("fig16".into(), SWEEP_SIZE));
    figures.push(("fig17".into(), METHODS_SIZE));
    // The 3-link arm (issue 14), beyond the paper.
    figures.push(("fig18".into(), PLAN_FIGURE_SIZE));
    // The 3-link arm inside a velocity limit (issue 20 item 7).
    figures.push(("fig19".into(), PLAN_FIGURE_SIZE));
    // The closed loop's Monte Carlo (issue 22 items 4 and 5).
    figures.push(("fig20".into(), PLAN_FIGURE_SIZE));
    // The sin²-windowed ECSA, beyond the paper: plan pictures named by their case.
    for a in ["0.0", "0.1", "0.2", "0.3"] {
        figures.push((format!("ecsa-sin2-{a}"), PLAN_FIGURE_SIZE));
    }
    figures
}

/// Decodes a PNG: its size and the number of distinct first-channel values (a blank picture
/// has one).
fn decode_png(path: &Path) -> ((u32, u32), usize) {
    let file = std::fs::File::open(path).expect("png exists");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png decodes");
    let channels = info.color_type.samples();
    let mut seen = [false; 256];
    for px in buf[..info.buffer_size()].chunks(channels) {
        seen[px[0] as usize] = true;
    }
    ((info.width, info.height), seen.iter().filter(|&&s| s).count())
}

fn row<'a>(summary: &'a Value, id: &str) -> &'a Value {
    summary["cases"].as_array().expect("cases").iter().find(|r| r["id"] == id).expect("the case's row")
}

fn f64_at(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} is a number: {v}"))
}

fn pair_at(v: &Value, key: &str) -> [f64; 2] {
    [v[key][0].as_f64().expect("a number"), v[key][1].as_f64().expect("a number")]
}

fn close(a: f64, b: f64) {
    assert_relative_eq!(a, b, max_relative = 1e-9, epsilon = 1e-300);
}

fn robot_at(a: f64, b: f64) -> RobotParams {
    RobotParams::src().with_mount(Mount::new(a, b).expect("mount")).expect("robot")
}

#[test]
fn reproduce_writes_every_file_whole_and_the_planners_numbers() {
    let dir = tempfile::tempdir().expect("temp dir");
    let o = reproduce(dir.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("wrote 45 files"), "{stdout}");

    // Every file exists and is not empty; nothing else (no temporary files) is left.
    let mut expected: Vec<String> = ["report.html", "summary.json", "summary.md"].map(String::from).to_vec();
    for (name, size) in figures() {
        expected.push(format!("{name}.png"));
        expected.push(format!("{name}.svg"));
        let (decoded, levels) = decode_png(&dir.path().join(format!("{name}.png")));
        assert_eq!(decoded, size, "{name}.png");
        assert!(levels > 10, "{name}.png looks blank");
        let text = std::fs::read_to_string(dir.path().join(format!("{name}.svg"))).expect("svg is UTF-8");
        let doc = roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{name}.svg parses: {e}"));
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg", "{name}.svg");
        assert_eq!(root.attribute("width"), Some(size.0.to_string().as_str()), "{name}.svg");
        assert!(root.descendants().filter(|n| n.has_tag_name("text")).count() > 10, "{name}.svg has labels");
        if name == "fig18" || name == "fig19" {
            for label in
                ["t [s]", "angle [deg]", "rate [rad/s]", "τ [N m]", "θ3", "τ3", "velocity level", "torque level"]
            {
                assert!(text.contains(label), "{name}.svg has no `{label}`");
            }
        } else if name == "fig20" {
            for label in ["log10 final error [rad]", "share of the trials [%]", "success: 1e-3 rad", "adaptive", "open"]
            {
                assert!(text.contains(label), "{name}.svg has no `{label}`");
            }
        } else if size == PLAN_FIGURE_SIZE {
            for label in ["t [s]", "angle [deg]", "u [rad/s]", "τ [N m]", "θ1", "velocity level", "torque level"] {
                assert!(text.contains(label), "{name}.svg has no `{label}`");
            }
        }
    }
    // Labels of issue 15: z's units, the ECSA's residual history, θ in the domain maps, Fig. 16's
    // title and colour bars.
    let svg = |name: &str| std::fs::read_to_string(dir.path().join(format!("{name}.svg"))).expect("svg");
    assert!(svg("fig04").contains("z (rad, mixed units)"));
    assert!(svg("fig10").contains("log10 of the end-point residual [rad]"));
    for name in ["fig13", "fig14"] {
        assert!(svg(name).contains("θ1 [deg]") && !svg(name).contains("theta"), "{name}");
    }
    for label in ["Fig. 16", "fraction of the torus", "success rate"] {
        assert!(svg("fig16").contains(label), "fig16 has no `{label}`");
    }
    let mut found: Vec<String> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    found.sort();
    // The marker of a directory freefloat wrote (issue 24 item 4), listing every file.
    let marker = std::fs::read_to_string(dir.path().join(".freefloat-out")).expect("the marker");
    assert_eq!(found.first().map(String::as_str), Some(".freefloat-out"));
    found.remove(0);
    expected.sort();
    assert_eq!(marker.lines().skip(1).collect::<Vec<_>>(), expected);
    assert_eq!(found, expected);
    for name in &expected {
        let len = std::fs::metadata(dir.path().join(name)).expect("exists").len();
        assert!(len > 1000, "{name} has {len} bytes");
    }

    // The summary: no NaN anywhere, one row per case, the paper's times for the paper's cases.
    let md = std::fs::read_to_string(dir.path().join("summary.md")).expect("summary.md");
    let html = std::fs::read_to_string(dir.path().join("report.html")).expect("report.html");
    let json = std::fs::read_to_string(dir.path().join("summary.json")).expect("summary.json");
    // Text without the pictures' base64 payloads (which may spell anything).
    let words: String = html.split("base64,").map(|part| part.split_once('"').map_or(part, |(_, rest)| rest)).collect();
    for text in [&md, &words, &json] {
        assert!(!text.contains("NaN") && !text.contains("inf ") && !text.contains("Infinity"), "a NaN in the output");
    }
    // Self-contained: no external resources.
    assert!(!html.contains("http://") && !html.contains("https://") && !html.contains("src=\"/"));
    assert_eq!(html.matches("data:image/png;base64,").count(), 21, "a picture for every figure");
    // Self-contained: no link to a file beside the page, only to anchors on it.
    for link in words.split("href=\"").skip(1) {
        assert!(link.starts_with('#'), "a link off the page: {}", &link[..link.len().min(40)]);
    }
    // Narrow screens: every table scrolls inside its own wrapper; symbols in headers do not break.
    assert_eq!(html.matches("<table>").count(), html.matches("<div class=\"scroll\"><table>").count());
    assert!(html.contains("<span class=\"nb\">|τ1|,</span>"));
    let summary: Value = serde_json::from_str(&json).expect("summary.json parses");
    let rows = summary["cases"].as_array().expect("cases");
    assert_eq!(rows.len(), 14);
    for r in rows {
        let id = r["id"].as_str().expect("id");
        assert!(md.contains(id) && html.contains(id), "{id} missing from summary.md or report.html");
        assert!(r["error"].is_null(), "{id}: {}", r["error"]);
        for key in ["final_error", "torque_final_error"] {
            assert!(f64_at(r, key).is_finite(), "{id}: {key}");
        }
        for stage in ["plan", "torques", "verify", "torque_verify"] {
            assert!(f64_at(&r["seconds"], stage) > 0.0, "{id}: seconds.{stage}");
        }
        let paper = r["figure"].as_str().is_some_and(|f| f != "fig15");
        assert_eq!(!r["paper_seconds"].is_null(), paper, "{id}: paper's times");
        assert_eq!(r["certified"], true, "{id}: every case is certified at the velocity level");
    }
    assert_eq!(summary["domains"].as_array().expect("domains").len(), 4);
    assert_eq!(summary["sweep"]["points"], 121);

    // The three methods (Fig. 17): five mounting points by three methods, every one planned and
    // certified at the velocity level, in summary.md and on the page; one row recomputed here.
    let methods = summary["methods"].as_array().expect("methods");
    assert_eq!(methods.len(), 15);
    assert!(md.contains("## Three methods") && html.contains("Three methods"));
    for r in methods {
        assert!(r["error"].is_null(), "{r}");
        assert_eq!(r["certified"], true, "{r}");
        for key in ["effort", "final_error", "torque_final_error"] {
            assert!(f64_at(r, key).is_finite(), "{key}: {r}");
        }
    }
    let options = freefloat::planners::PlannerOptions::default();
    for (method, name) in [(freefloat::Method::Optimal, "optimal"), (freefloat::Method::Nfa, "nfa")] {
        let planned = freefloat::planners::planner(method, &options).plan(&PlanningProblem::paper(robot_at(1.0, -1.0)));
        let plan = planned.expect("a plan").plan;
        let r = methods.iter().find(|r| r["method"] == name && r["mount"][0] == 1.0).expect("the row");
        close(f64_at(r, "effort"), plan.effort);
        close(pair_at(r, "max_abs_u")[0], plan.max_abs_u[0]);
        close(pair_at(r, "max_abs_u")[1], plan.max_abs_u[1]);
    }

    // The 3-link arm (Fig. 18): planned, certified at both levels, in summary.md and on the page;
    // its numbers are the planner's, recomputed here.
    let arm3 = &summary["arm3"];
    assert!(arm3["error"].is_null(), "{arm3}");
    assert_eq!(arm3["certified"], true, "{arm3}");
    assert_eq!(arm3["torque_certified"], true, "{arm3}");
    assert!(f64_at(arm3, "final_error") <= 1e-9 && f64_at(arm3, "torque_final_error") <= 1e-6, "{arm3}");
    assert_eq!(arm3["max_abs_torque"].as_array().map(Vec::len), Some(3));
    assert_eq!(arm3["arm"]["links"].as_array().map(Vec::len), Some(3));
    assert!(md.contains("## A 3-link arm (Fig. 18)") && html.contains("A 3-link arm"));
    let planned = freefloat::report::plan_arm3().expect("the 3-link plan");
    close(f64_at(arm3, "effort"), planned.effort());
    close(f64_at(arm3, "final_error"), planned.verification().final_error);
    let tau = &planned.torques.as_ref().expect("torques").max_abs_torque;
    for (k, t) in tau.iter().enumerate() {
        close(arm3["max_abs_torque"][k].as_f64().expect("a number"), *t);
    }

    // Fig. 19: the 3-link arm inside a velocity limit that binds, certified, its limits' use listed.
    let limited = &summary["arm3_limited"];
    assert_eq!(
        (limited["figure"].as_str(), &limited["certified"], &limited["torque_certified"]),
        (Some("fig19"), &true.into(), &true.into()),
        "{limited}"
    );
    let uses = limited["limits"]["uses"].as_array().expect("the limits' use");
    assert_eq!(uses.len(), 3, "one velocity limit per joint");
    let most = uses.iter().map(|u| f64_at(u, "use")).fold(0.0, f64::max);
    assert!(most > 0.99 && most <= 1.0 + 1e-9, "the limit binds: {most}");
    assert_eq!(limited["limits"]["inside"], true);

    // Fig. 20: every controller on the same 20 perturbed trials per problem, adaptive's success
    // as a torque limit tightens; the tracked plans are the minimum-effort planner's.
    let closed = &summary["closed_loop"];
    assert_eq!((closed["trials"].as_u64(), closed["curve_trials"].as_u64()), (Some(20), Some(10)), "{closed}");
    let cases = closed["cases"].as_array().expect("the closed loop's cases");
    assert_eq!(cases.len(), 2);
    for case in cases {
        let rate = |name: &str| {
            let s = case["controllers"].as_array().expect("summaries").iter().find(|s| s["controller"] == name);
            let s = s.unwrap_or_else(|| panic!("{name} in {case}"));
            assert_eq!(s["trials"].as_u64(), Some(20));
            f64_at(s, "success_rate")
        };
        // Issue 22: adaptive holds >= 95 % on hard problems and at the paper's mounts, and no
        // controller with less feedback does better on the same trials.
        assert!(rate("adaptive") >= 0.95, "{case}");
        for other in ["open", "ct", "replan"] {
            assert!(rate(other) <= rate("adaptive"), "{other} beats adaptive: {case}");
        }
        let mount = pair_at(case, "mount");
        let deg = |key: &str| case[key].as_array().expect("angles").iter().map(|x| x.as_f64().unwrap().to_radians());
        let problem = ChainProblem::rest_to_rest(deg("start_deg").collect(), deg("goal_deg").collect(), 10.0);
        let arm =
            Arm { mount: Mount::new(mount[0], mount[1]).expect("mount"), ..Arm::from_params(&RobotParams::src()) };
        let request = ArmRequest { torques: true, ..ArmRequest::new(problem) };
        let planned = plan_arm(&arm, Method::Optimal, &request).expect("the tracked plan");
        close(f64_at(case, "effort"), planned.effort());
        let peak = planned.torques.as_ref().expect("torques").max_abs_torque.iter().copied().fold(0.0, f64::max);
        close(f64_at(case, "peak_torque"), peak);
    }
    let curve = closed["torque_curve"].as_array().expect("the torque curve");
    let peak = f64_at(&cases[0], "peak_torque");
    for p in curve {
        close(f64_at(p, "limit"), f64_at(p, "fraction") * peak);
    }
    let success = |p: &Value| f64_at(&p["adaptive"], "success_rate");
    let (tightest, loosest) = (curve.first().expect("points"), curve.last().expect("points"));
    // A tenth of the plan's peak torque cannot follow the plan; the plan's own peak can.
    assert!(f64_at(tightest, "fraction") <= 0.1 && f64_at(loosest, "fraction") >= 1.0);
    assert!(success(tightest) < success(loosest) && success(loosest) >= 0.95, "{closed}");

    // The values are the planners': recompute an NFA case, an ECSA case and Fig. 15 here.
    let robot = |a: f64, b: f64| RobotParams::src().with_mount(Mount::new(a, b).expect("mount")).expect("robot");
    let nfa = |a: f64, b: f64, transform| {
        let problem = PlanningProblem::paper(robot(a, b));
        let options = NfaOptions { transform: Some(transform), accelerations: true, ..Default::default() };
        let (plan, motion) = NormalFormPlanner::new(options).plan_with_motion(&problem).expect("plan");
        let tp = torque_plan(&motion, &problem, &plan.trajectory.t, &TorqueOptions::default()).expect("torques");
        (plan, tp.report)
    };
    for (id, a, b, transform) in [("fig06", 0.1, 0.1, Transform::Eq14), ("fig15", 1.0, -1.0, Transform::Global)] {
        let (plan, torques) = nfa(a, b, transform);
        let r = row(&summary, id);
        close(f64_at(r, "final_error"), plan.verification.final_error);
        close(f64_at(r, "torque_final_error"), torques.certificate.final_error);
        assert_eq!(r["torque_certified"], torques.certificate.certified, "{id}");
        for k in 0..2 {
            close(pair_at(r, "max_abs_u")[k], plan.max_abs_u[k]);
            close(pair_at(r, "max_abs_torque")[k], torques.max_abs_torque[k]);
        }
        assert!(r["iterations"].is_null());
    }
    // Fig. 15 is honest: certified at the velocity level, not at the torque level.
    assert_eq!(row(&summary, "fig15")["torque_certified"], false);
    assert!(f64_at(row(&summary, "fig15"), "torque_final_error") > 1e-6);

    let problem = PlanningProblem::paper(robot(0.2, 0.2));
    let ecsa = EcsaPlanner::new(EcsaOptions::default());
    let Planned { plan, motion, .. } = ecsa.plan(&problem).expect("ecsa plan");
    let torques =
        torque_plan(motion.as_ref(), &problem, &plan.trajectory.t, &TorqueOptions::default()).expect("torques").report;
    let r = row(&summary, "fig11");
    assert_eq!(r["iterations"].as_u64(), plan.iterations.map(|i| i as u64));
    close(f64_at(r, "final_error"), plan.verification.final_error);
    close(f64_at(r, "torque_final_error"), torques.certificate.final_error);
    // The plain series does not start at rest: its torque plan from rest is not certified.
    assert_eq!(r["torque_certified"], false);
    assert!(pair_at(r, "u_start")[0].abs() > 1e-3);
}

/// The chromium binary, if installed.
fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"].into_iter().find_map(|name| {
        let ok = Command::new(name).arg("--version").stdout(Stdio::null()).stderr(Stdio::null()).status();
        ok.is_ok_and(|s| s.success()).then(|| PathBuf::from(name))
    })
}

/// Runs headless chromium with `args`, killed after 120 s; returns its stdout and stderr (through
/// files: the DOM of the page is larger than a pipe's buffer).
fn headless(browser: &Path, dir: &Path, name: &str, args: &[String]) -> (String, String) {
    let (out, err) = (dir.join(format!("{name}.out")), dir.join(format!("{name}.err")));
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", dir.join(format!("{name}.profile")).display()))
        .args(args)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).expect("stdout file"))
        .stderr(std::fs::File::create(&err).expect("stderr file"))
        .spawn()
        .expect("chromium starts");
    let clock = Instant::now();
    while child.try_wait().expect("chromium runs").is_none() {
        if clock.elapsed() > Duration::from_secs(120) {
            let _killed = child.kill();
            panic!("chromium did not finish in 120 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into_owned();
    (read(&out), read(&err))
}

/// The page in a headless browser: its script runs without error, every animation canvas is
/// drawn (not blank), and a screenshot shows the page. Fails when chromium is missing in CI
/// (`CI` or `FREEFLOAT_REQUIRE_BROWSER` set; `.ci/run` installs it), else skips with a message.
#[test]
fn report_page_runs_in_a_headless_browser() {
    let Some(browser) = chromium() else {
        let required = std::env::var_os("CI").is_some() || std::env::var_os("FREEFLOAT_REQUIRE_BROWSER").is_some();
        assert!(!required, "chromium is required in CI (apt-get install -y chromium) but not installed");
        eprintln!("SKIPPED report_page_runs_in_a_headless_browser: chromium is not installed");
        return;
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    reproduce(&out);
    let url = format!("file://{}", out.join("report.html").display());

    // The DOM after the script ran: status and painted pixels, written by the page's script.
    let (text, log) = headless(
        &browser,
        dir.path(),
        "dom",
        &[
            "--enable-logging=stderr".into(),
            "--v=0".into(),
            "--virtual-time-budget=3000".into(),
            "--dump-dom".into(),
            url.clone(),
        ],
    );
    let body = text.split("<body").nth(1).and_then(|b| b.split('>').next()).unwrap_or_else(|| panic!("no body: {log}"));
    let attribute = |name: &str| {
        body.split(&format!("{name}=\"")).nth(1).and_then(|v| v.split('"').next()).unwrap_or_default().to_string()
    };
    assert_eq!(attribute("data-status"), "ok", "the page's script failed: {body}\n{log}");
    assert!(!log.contains("Uncaught"), "console errors: {log}");
    assert_eq!(
        attribute("data-canvases"),
        "16",
        "one animation per plan (the 3-link arm's, free and inside its velocity limits, among them)"
    );
    let painted: usize = attribute("data-painted").parse().expect("a pixel count");
    assert!(painted > 2000, "an animation canvas is (nearly) blank: {painted} pixels drawn");

    // A phone's width (390 px): nothing wider than the screen (tables scroll in their wrappers).
    let (text, log) = headless(
        &browser,
        dir.path(),
        "narrow",
        &["--window-size=390,800".into(), "--virtual-time-budget=3000".into(), "--dump-dom".into(), url.clone()],
    );
    let number = |name: &str| -> u32 {
        text.split(&format!("{name}=\""))
            .nth(1)
            .and_then(|v| v.split('"').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no {name}: {log}"))
    };
    // Headless chromium keeps a minimum window width (about 500 px), so the screen is what the
    // page measures (clientWidth), at most a little over 390 px.
    let (width, screen) = (number("data-width"), number("data-viewport"));
    assert!(screen < 600, "the window is {screen} px wide, not a phone's");
    assert!(width <= screen, "the page is {width} px wide on a {screen} px screen");

    // A screenshot of Fig. 15 with its animation at t = 4.3 s, kept for a human to look at.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-fig15.png");
    let _stale = std::fs::remove_file(&shot);
    let (_, log) = headless(
        &browser,
        dir.path(),
        "shot",
        &[
            "--window-size=1400,1700".into(),
            format!("--screenshot={}", shot.display()),
            format!("{url}#only=fig15&t=4.3"),
        ],
    );
    assert!(shot.exists(), "no screenshot: {log}");
    let (size, levels) = decode_png(&shot);
    assert_eq!(size, (1400, 1700));
    assert!(levels > 20, "the screenshot looks blank");
    eprintln!("screenshot: {}", shot.display());

    // The 3-link arm's animation at t = 2.5 s, kept for a human to look at.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-fig18.png");
    let _stale = std::fs::remove_file(&shot);
    let (_, log) = headless(
        &browser,
        dir.path(),
        "shot18",
        &[
            "--window-size=1400,1700".into(),
            format!("--screenshot={}", shot.display()),
            format!("{url}#only=fig18&t=2.5"),
        ],
    );
    assert!(shot.exists(), "no screenshot: {log}");
    assert!(decode_png(&shot).1 > 20, "the screenshot looks blank");
    eprintln!("screenshot: {}", shot.display());
}

/// `reproduce --trials 0` (or above the Monte Carlo's bound) is refused before any work, exit
/// 2 naming the flag's quantity, and writes nothing.
#[test]
fn reproduce_refuses_a_bad_trial_count_before_any_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    for trials in ["0", "1000001"] {
        let o = Command::new(env!("CARGO_BIN_EXE_freefloat"))
            .args(["reproduce", "--trials", trials, "--out"])
            .arg(dir.path().join("out"))
            .output()
            .expect("the binary runs");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("trials"), "{stderr}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 0, "nothing is written");
}
