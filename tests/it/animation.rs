//! `--gif`: an animated GIF of a plan's motion that decodes (frames, size, infinite loop, frame
//! delays), whose frames show the robot where the kinematics puts it, written atomically; bad
//! paths and sizes are refused (exit 2).

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use freefloat::model::arm::Arm;
use freefloat::model::kinematics::pose;
use freefloat::planners::arm::{ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::{PlannerOptions, planner};
use freefloat::report::plot::{GifOptions, GifView, LINK_COLOURS, animation_gif, arm_animation_gif};
use freefloat::{Configuration, Method, Mount, PlanningProblem, RobotParams};

fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).current_dir(dir).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A decoded GIF: size, loop, and each frame's delay \[1/100 s\] and RGBA pixels.
pub(crate) struct Decoded {
    pub(crate) size: (u16, u16),
    pub(crate) repeat: gif::Repeat,
    pub(crate) frames: Vec<(u16, Vec<u8>)>,
}

/// The frames of a GIF composed as a viewer shows them (each over the previous one kept).
pub(crate) fn decode(bytes: &[u8]) -> Decoded {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(bytes).expect("a GIF header");
    let (width, height) = (decoder.width(), decoder.height());
    let mut frames: Vec<(u16, Vec<u8>)> = Vec::new();
    while let Some(frame) = decoder.read_next_frame().expect("the frame decodes") {
        assert_eq!((frame.left, frame.top, frame.width, frame.height), (0, 0, width, height));
        // Transparent pixels show the previous frame (kept): compose as a viewer does.
        let mut canvas = frames.last().map(|f| f.1.clone()).unwrap_or_else(|| frame.buffer.to_vec());
        for (pixel, new) in canvas.chunks_exact_mut(4).zip(frame.buffer.chunks_exact(4)) {
            if new[3] != 0 {
                pixel.copy_from_slice(new);
            }
        }
        assert!(canvas.chunks_exact(4).all(|p| p[3] == 255), "a pixel is never drawn");
        frames.push((frame.delay, canvas));
    }
    Decoded { size: (width, height), repeat: decoder.repeat(), frames }
}

/// `plan --gif` writes a GIF that decodes: the frames of the options' rate over the loop (the
/// 10 s horizon played in 8 s), the size asked, an infinite loop, each frame's delay, a hold on
/// the last; the motion shows (the first and last frames differ).
#[test]
fn plan_writes_a_looping_gif_of_the_motion() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = ["plan", "--samples", "201", "--quiet", "--gif", "anim.gif"];
    let o =
        run_in(dir.path(), &[&args[..], &["--gif-width", "320", "--gif-height", "240", "--gif-fps", "10"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let gif = decode(&std::fs::read(dir.path().join("anim.gif")).expect("written"));
    let options = GifOptions::new(320, 240, 10).expect("valid");
    assert_eq!(options.frame_count(10.0), 81);
    assert_eq!(gif.frames.len(), 81);
    assert_eq!(gif.size, (320, 240));
    assert_eq!(gif.repeat, gif::Repeat::Infinite);
    assert!(gif.frames[..80].iter().all(|(delay, _)| *delay == 10));
    assert_eq!(gif.frames[80].0, 100);
    assert_ne!(gif.frames[0].1, gif.frames[80].1, "the first and last frames are the same");
    // Only the GIF was written: no temporary file is left.
    let files: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").flatten().map(|e| e.file_name()).collect();
    assert_eq!(files, vec![std::ffi::OsString::from("anim.gif")]);
}

/// Colour distance (largest channel difference) of pixel `(x, y)` of an RGBA frame from `rgb`.
fn distance(frame: &[u8], width: usize, (x, y): (f64, f64), rgb: [u8; 3]) -> u8 {
    let i = 4 * (y.floor() as usize * width + x.floor() as usize);
    (0..3).map(|k| frame[i + k].abs_diff(rgb[k])).max().unwrap_or(u8::MAX)
}

/// Every frame draws the robot where `model::kinematics::pose` puts it at the frame's
/// configuration: the base's centre of mass in the base's colour, the elbow black, the
/// end-effector orange and the middle of link 2 green (within the palette's rounding); the
/// frames run from the plan's start to the configuration it reached.
#[test]
fn frames_show_the_robot_where_the_kinematics_puts_it() {
    // A mounting point off the base's centre of mass, so that joint 1 does not cover it.
    let robot = RobotParams::src().with_mount(Mount::new(0.2, 0.1).expect("mount")).expect("robot");
    let problem = PlanningProblem::paper(robot);
    let planned = planner(Method::Optimal, &PlannerOptions::default()).plan(&problem).expect("a plan");
    let plan = &planned.plan;
    let options = GifOptions::new(480, 480, 4).expect("valid");
    let clock = Instant::now();
    let bytes = animation_gif(plan, "test", &options, Path::new("test.gif")).expect("encodes");
    let seconds = clock.elapsed().as_secs_f64();
    let gif = decode(&bytes);
    let view = GifView::new(plan, &options);
    assert_eq!(gif.frames.len(), view.frames().len());
    assert_eq!(view.frames()[0], (plan.trajectory.t[0], &plan.trajectory.q[0][..]));
    assert_eq!(view.frames().last().map(|f| f.1.to_vec()), plan.trajectory.q.last().map(|q| q.to_vec()));
    let base = [0x44, 0x44, 0x44];
    let (black, orange, green) = ([0, 0, 0], [0xd5, 0x5e, 0x00], [0x00, 0x9e, 0x73]);
    for ((_, frame), &(t, q)) in gif.frames.iter().zip(&view.frames()) {
        let p = pose(&robot, &Configuration::from_array([q[0], q[1], q[2]]));
        let middle = [(p.joint2[0] + p.tip[0]) / 2.0, (p.joint2[1] + p.tip[1]) / 2.0];
        for (what, point, colour) in
            [("base", p.base, base), ("elbow", p.joint2, black), ("tip", p.tip, orange), ("link 2", middle, green)]
        {
            let (x, y) = view.pixel(point);
            let d = distance(frame, 480, (x, y), colour);
            let i = 4 * (y.floor() as usize * 480 + x.floor() as usize);
            assert!(
                d <= 40,
                "t = {t} s: the {what} pixel at ({x:.1}, {y:.1}) is {:?}, off its colour by {d}",
                &frame[i..i + 3]
            );
        }
    }
    eprintln!("{} frames at 480 x 480 px: {} bytes in {seconds:.2} s", gif.frames.len(), bytes.len());
}

/// Distance \[px\] from `p` to the segment `a`-`b`.
fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let length2 = dx * dx + dy * dy;
    let s = if length2 > 0.0 { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (p.0 - a.0 - s * dx).hypot(p.1 - a.1 - s * dy)
}

/// A body to find on a frame: its name, its counter, its pixel, its colour, and whether nothing
/// drawn after it comes near.
type Check<'a> = (&'a str, usize, (f64, f64), [u8; 3], bool);

/// A 3-link arm's GIF shows, on every frame, the arm where `Arm::joint_positions` puts it at the
/// frame's configuration: the base's centre of mass grey, joints 2 and 3 black, the end effector
/// orange and the middle of each link in that link's colour (`LINK_COLOURS`). A body is checked
/// where nothing drawn after it comes near (links are drawn from the base outwards, then the
/// joints, then the end effector), and each is checked on most frames.
#[test]
fn arm_frames_show_every_link_where_the_joint_positions_put_it() {
    let toml = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml"))
        .expect("the example");
    let mut arm = Arm::from_toml(&toml, Path::new("three_link.toml")).expect("a 3-link arm");
    // A mounting point off the base's centre of mass, so that joint 1 does not cover it.
    arm.mount = Mount::new(0.2, 0.1).expect("mount");
    let rad = |v: [f64; 4]| v.iter().map(|x: &f64| x.to_radians()).collect::<Vec<_>>();
    let problem = ChainProblem::rest_to_rest(rad([0.0, 60.0, -30.0, -30.0]), rad([30.0, 120.0, 40.0, -60.0]), 10.0);
    let request = ArmRequest { samples: 401, ..ArmRequest::new(problem) };
    let planned = plan_arm(&arm, Method::Optimal, &request).expect("a plan");
    let options = GifOptions::new(480, 480, 4).expect("valid");
    let clock = Instant::now();
    let bytes = arm_animation_gif(&planned, "test", &options, Path::new("test.gif")).expect("encodes");
    let seconds = clock.elapsed().as_secs_f64();
    let gif = decode(&bytes);
    let view = GifView::arm(&planned, &options);
    let frames = view.frames();
    assert_eq!(gif.frames.len(), frames.len());
    assert_eq!(gif.frames.len(), options.frame_count(10.0));
    let last = planned.trajectory.last().expect("samples");
    let end: Vec<f64> = std::iter::once(last.phi).chain(last.theta.iter().copied()).collect();
    assert_eq!(frames.last().map(|f| f.1.to_vec()), Some(end));
    let rgb = |hex: &str| -> [u8; 3] {
        std::array::from_fn(|k| u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).expect("hex"))
    };
    let mut checked = [0usize; 7];
    for ((_, frame), &(t, q)) in gif.frames.iter().zip(&frames) {
        let points: Vec<(f64, f64)> = arm.joint_positions(q).into_iter().map(|p| view.pixel(p)).collect();
        assert_eq!(points.len(), 5);
        let middle = |k: usize| ((points[k + 1].0 + points[k + 2].0) / 2.0, (points[k + 1].1 + points[k + 2].1) / 2.0);
        let near = |p: (f64, f64), q: (f64, f64), r: f64| (p.0 - q.0).hypot(p.1 - q.1) < r;
        // What is drawn after a body: the later links (6 px wide), the joints and the tip (5 px).
        let after_link = |k: usize, p: (f64, f64)| {
            (k + 1..3).any(|j| to_segment(p, points[j + 1], points[j + 2]) < 6.0)
                || points.iter().any(|&d| near(p, d, 8.0))
        };
        let mut bodies: Vec<Check> = Vec::new();
        let free_base = !points[1..].iter().any(|&d| near(points[0], d, 8.0));
        bodies.push(("base", 0, points[0], [0x44; 3], free_base));
        for j in [2, 3] {
            bodies.push(("joint", j - 1, points[j], [0, 0, 0], !near(points[j], points[4], 11.0)));
        }
        bodies.push(("tip", 3, points[4], rgb("#d55e00"), true));
        for (k, colour) in LINK_COLOURS.iter().take(3).enumerate() {
            bodies.push(("link", 4 + k, middle(k), rgb(colour), !after_link(k, middle(k))));
        }
        for (what, slot, (x, y), colour, free) in bodies {
            if !free {
                continue;
            }
            checked[slot] += 1;
            let d = distance(frame, 480, (x, y), colour);
            assert!(d <= 40, "t = {t} s: the {what} ({slot}) pixel at ({x:.1}, {y:.1}) is off its colour by {d}");
        }
    }
    // Bodies hidden on a frame are few: each is checked on at least half of them.
    assert!(checked.iter().all(|&c| 2 * c >= frames.len()), "checked {checked:?} of {} frames", frames.len());
    eprintln!("3-link arm: {} frames at 480 x 480 px: {} bytes in {seconds:.2} s", frames.len(), bytes.len());
}

/// Refused with exit 2 before planning, nothing written: a name not ending in .gif, a missing
/// directory, sizes and rates out of range, the size flags without `--gif`. `.GIF` is a GIF.
#[test]
fn bad_gif_paths_and_sizes_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases: [(&[&str], &str); 7] = [
        (&["--gif", "anim.png"], "must end in .gif"),
        (&["--gif", "anim"], "must end in .gif"),
        (&["--gif", "no/such/dir/anim.gif"], "no/such/dir/anim.gif"),
        (&["--gif", "anim.gif", "--gif-width", "100"], "--gif-width"),
        (&["--gif", "anim.gif", "--gif-height", "5000"], "--gif-height"),
        (&["--gif", "anim.gif", "--gif-fps", "0"], "--gif-fps"),
        (&["--gif-fps", "10"], "--gif"),
    ];
    for (extra, message) in cases {
        let o = run_in(dir.path(), &[&["plan", "--samples", "101"], extra].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{extra:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{extra:?}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 0);
    let o = run_in(dir.path(), &["plan", "--samples", "101", "--quiet", "--gif", "anim.GIF", "--gif-fps", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("anim.GIF").exists());
}

/// A stale temporary of a killed run is removed by the next write of the GIF; SIGTERM while a
/// GIF is being made leaves neither the GIF nor a temporary.
#[cfg(unix)]
#[test]
fn interrupted_gif_writes_leave_no_temporary() {
    let dir = tempfile::tempdir().expect("temp dir");
    let stale = dir.path().join(".anim.gif.999999999.tmp");
    std::fs::write(&stale, "half").expect("write");
    let o = run_in(dir.path(), &["plan", "--samples", "101", "--quiet", "--gif", "anim.gif", "--gif-fps", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists() && dir.path().join("anim.gif").exists());

    let dir = tempfile::tempdir().expect("temp dir");
    let mut child = Command::new(env!("CARGO_BIN_EXE_freefloat"))
        .current_dir(dir.path())
        .args(["plan", "--gif", "big.gif", "--gif-width", "1920", "--gif-height", "1920", "--gif-fps", "50"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn");
    std::thread::sleep(Duration::from_millis(1000));
    let killed = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().expect("kill runs");
    assert!(killed.success());
    let clock = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        assert!(clock.elapsed() < Duration::from_secs(30), "the run does not stop");
        std::thread::sleep(Duration::from_millis(20));
    }
    let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").flatten().map(|e| e.file_name()).collect();
    assert!(left.is_empty(), "{left:?}");
}

/// `reproduce --gif` writes `anim-CASE.gif` for every plan of the 2-link robot and
/// `anim-arm3.gif` for the 3-link arm, lists them in summary.md, and the self-contained page
/// links none of them.
#[test]
fn reproduce_writes_one_gif_per_case() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let args = ["reproduce", "--gif", "--gif-width", "240", "--gif-height", "240", "--gif-fps", "2", "--out"];
    let o = Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).arg(&out).output().expect("runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary.md")).expect("summary.md");
    let html = std::fs::read_to_string(out.join("report.html")).expect("report.html");
    assert!(!html.contains("anim-"), "the page links a GIF");
    let mut gifs = 0;
    for case in freefloat::report::cases() {
        let name = format!("anim-{}.gif", case.id);
        let gif = decode(&std::fs::read(out.join(&name)).unwrap_or_else(|e| panic!("{name}: {e}")));
        assert_eq!((gif.size, gif.frames.len()), ((240, 240), 17), "{name}");
        assert!(summary.contains(&name), "summary.md does not list {name}");
        gifs += 1;
    }
    assert!(gifs >= 10);
    // The 3-link arm's plan (Fig. 18) has its animation too.
    let arm3 = decode(&std::fs::read(out.join("anim-arm3.gif")).expect("anim-arm3.gif"));
    let options = GifOptions::new(240, 240, 2).expect("valid");
    let horizon = freefloat::report::arm3::ARM3_HORIZON;
    assert_eq!((arm3.size, arm3.frames.len()), ((240, 240), options.frame_count(horizon)));
    assert!(summary.contains("anim-arm3.gif"), "summary.md does not list anim-arm3.gif");
    // And its plan inside a velocity limit (Fig. 19).
    let limited = decode(&std::fs::read(out.join("anim-arm3-limits.gif")).expect("anim-arm3-limits.gif"));
    assert_eq!((limited.size, limited.frames.len()), ((240, 240), options.frame_count(horizon)));
    assert!(summary.contains("anim-arm3-limits.gif"));
}
