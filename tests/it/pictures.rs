//! Pictures of a plan with shapes and obstacles (issue 21 item 7; docs/spec.md §3): the GIF, the
//! report page's animation and the figure draw the obstacles where they are and mark the moment
//! of least clearance of the verified motion (red when it collides); a robot without shapes draws
//! exactly as before.

use std::path::Path;
use std::process::Command;

use freefloat::Method;
use freefloat::model::arm::Arm;
use freefloat::model::geometry::Shape;
use freefloat::plan::clearance::ClearanceReport;
use freefloat::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::report::plot::scene::{CLEAR_COLOUR, COLLISION_COLOUR};
use freefloat::report::plot::{GifOptions, GifView, LEAST_HOLD, PictureFormat, arm_animation_gif, plan_picture};
use freefloat::report::{arm_animation, arm_plan_figure};

use super::animation::decode;

/// The obstacle of issue 21's 3-link case: 5 cm about (-0.4, 0.1) m.
const CENTRE: [f64; 2] = [-0.4, 0.1];
const RADIUS: f64 = 0.05;

/// The 3-link example arm with capsule links 4 cm wide, links 1 and 3 not checked against each
/// other (as `tests/it/geometry.rs` plans it), and `obstacles`.
fn three_link(obstacles: Vec<Shape>) -> Arm {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml"))
        .expect("the example")
        .lines()
        .map(|l| if l.starts_with("inertia") { format!("{l}\nwidth = 0.04") } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let mut arm = Arm::from_toml(&text, Path::new("three_link_widths.toml")).expect("a 3-link arm");
    arm.geometry.obstacles = obstacles;
    arm.geometry.excluded.push(("link1".parse().expect("a body"), "link3".parse().expect("a body")));
    arm
}

fn plan(arm: &Arm, method: Method, from: [f64; 4], to: [f64; 4], horizon: f64) -> ArmPlanned {
    let rad = |v: [f64; 4]| v.iter().map(|x: &f64| x.to_radians()).collect::<Vec<_>>();
    let request =
        ArmRequest { samples: 401, ..ArmRequest::new(ChainProblem::rest_to_rest(rad(from), rad(to), horizon)) };
    plan_arm(arm, method, &request).expect("a plan")
}

/// Issue 21's 3-link plan around its obstacle (certified, the clearance holding at about 1 mm).
fn around_the_obstacle() -> ArmPlanned {
    let arm = three_link(vec![Shape::circle(CENTRE, RADIUS).expect("a circle")]);
    plan(&arm, Method::Optimal, [0.0, 0.0, 30.0, 30.0], [20.0, 90.0, 30.0, -30.0], 8.0)
}

/// The least clearance of a plan (it has shapes, so it has one).
fn least(p: &ArmPlanned) -> ClearanceReport {
    p.verification().clearance.expect("the certificate checks the clearance")
}

/// The index of the instant of `ts` nearest to `t`, found here by a scan of its own.
fn nearest(ts: &[f64], t: f64) -> usize {
    let mut best = 0;
    for (k, s) in ts.iter().enumerate() {
        if (s - t).abs() < (ts[best] - t).abs() {
            best = k;
        }
    }
    best
}

/// The number after `name="` in `element` (an SVG element's attribute).
fn attribute(element: &str, name: &str) -> f64 {
    let key = format!(" {name}=\"");
    let start = element.find(&key).map(|i| i + key.len()).expect("the attribute");
    let end = element[start..].find('"').expect("closed") + start;
    element[start..end].parse().expect("a number")
}

/// The GIF draws the obstacle where it is with its radius (as an SVG circle, and in grey on the
/// decoded frames: inside at 60 % of the radius, not at 160 %), the links' capsules, and marks
/// the least clearance on the frame nearest its time (held `LEAST_HOLD`), in purple since it
/// holds, with its caption in mm on every frame.
#[test]
fn the_gif_draws_the_obstacle_and_marks_the_least_clearance() {
    let planned = around_the_obstacle();
    let c = least(&planned);
    assert!(c.holds(), "{c:?}");
    let options = GifOptions::new(480, 480, 10).expect("valid");
    let view = GifView::arm(&planned, &options);
    let frames = view.frames();
    // The obstacle's circle, at its centre and radius in pixels (y down).
    let scale = view.scale();
    let (ox, oy) = view.pixel(CENTRE);
    let (ex, ey) = view.pixel([CENTRE[0] + RADIUS, CENTRE[1]]);
    assert!((ex - ox - RADIUS * scale).abs() < 1e-9 && (ey - oy).abs() < 1e-9);
    let svg = view.svg("test", 0);
    let circle = svg.lines().find(|l| l.contains("id=\"obstacle1\"")).expect("the obstacle is drawn");
    assert!((attribute(circle, "cx") - ox).abs() < 0.01 && (attribute(circle, "cy") - oy).abs() < 0.01, "{circle}");
    assert!((attribute(circle, "r") - RADIUS * scale).abs() < 0.01, "{circle}: {} px/m", scale);
    // Each link's capsule is an outline (the base has no shape: its illustrative box stays).
    assert_eq!(svg.matches("<polygon").count(), 3, "three capsules");
    // The marked frame: nearest the certificate's time, held, purple, with the pair.
    let times: Vec<f64> = frames.iter().map(|f| f.0).collect();
    let m = nearest(&times, c.time);
    assert_eq!(view.marked(), Some(m));
    assert!(m + 1 < frames.len(), "the least clearance is not at the end here (t = {} s)", c.time);
    let marked = view.svg("test", m);
    assert!(marked.contains(&format!("<g id=\"least-clearance\" stroke=\"{CLEAR_COLOUR}\"")));
    assert!(!view.svg("test", m + 1).contains("id=\"least-clearance\""), "only the marked frame");
    let caption = format!("least clearance {:.1} mm, link 3 / obstacle 1, t = {:.2} s", c.min * 1e3, c.time);
    assert!(svg.contains(&caption) && marked.contains(&caption), "{caption}");
    // The decoded GIF: the hold, and the obstacle's grey disc where the view puts it.
    let gif = decode(&arm_animation_gif(&planned, "test", &options, Path::new("t.gif")).expect("encodes"));
    assert_eq!(gif.frames.len(), frames.len());
    for (k, (delay, _)) in gif.frames.iter().enumerate() {
        let expected = if k == m || k + 1 == frames.len() { LEAST_HOLD } else { options.delay() };
        assert_eq!(*delay, expected, "frame {k}");
    }
    // 45 % of #5f5f5f over white is 183: a grey (no colour) darker than the faint paths (217)
    // and the base's box (208), lighter than the edges (as the 255-colour palette renders it).
    let is_grey = |frame: &[u8], r: f64, angle: f64| {
        let (x, y) = (ox + r * scale * angle.cos(), oy - r * scale * angle.sin());
        let i = 4 * (y.floor() as usize * 480 + x.floor() as usize);
        let p = &frame[i..i + 3];
        p[0].abs_diff(p[1]) <= 3 && p[1].abs_diff(p[2]) <= 3 && (140..=200).contains(&p[0])
    };
    let first = &gif.frames[0].1;
    let angles: Vec<f64> = (0..16).map(|k| std::f64::consts::TAU * k as f64 / 16.0).collect();
    let inside = angles.iter().filter(|&&a| is_grey(first, 0.6 * RADIUS, a)).count();
    let outside = angles.iter().filter(|&&a| is_grey(first, 1.6 * RADIUS, a)).count();
    assert!(inside >= 12 && outside <= 2, "grey inside {inside}/16, outside {outside}/16");
}

/// A plan that goes through an obstacle (the ECSA does not see it: an obstacle on the tip's
/// start) is marked in red in the GIF, on the page and on the figure, at the certificate's time;
/// the base's box, when it has one, is drawn as its shape.
#[test]
fn a_colliding_plan_is_marked_red_everywhere() {
    let mut arm = three_link(vec![]);
    let (from, to) = ([0.0, 0.0, 30.0, 30.0], [20.0, 90.0, 30.0, -30.0]);
    arm.geometry.base.push(Shape::rectangle([0.0, 0.0], [0.3, 0.2]).expect("a box"));
    // An obstacle where the ECSA's tip passes at mid-motion (the ECSA does not avoid it), clear
    // of both ends (an end inside an obstacle is refused before any plan).
    let free = plan(&arm, Method::Ecsa, from, to, 8.0);
    let mid = &free.trajectory[free.trajectory.len() / 2];
    let q: Vec<f64> = std::iter::once(mid.phi).chain(mid.theta.iter().copied()).collect();
    let tip = *arm.joint_positions(&q).last().expect("a tip");
    arm.geometry.obstacles.push(Shape::circle(tip, 0.05).expect("a circle"));
    let planned = plan(&arm, Method::Ecsa, from, to, 8.0);
    let c = least(&planned);
    assert!(!c.holds() && c.min < 0.0, "{c:?}");
    // The GIF.
    let options = GifOptions::new(480, 480, 10).expect("valid");
    let view = GifView::arm(&planned, &options);
    let times: Vec<f64> = view.frames().iter().map(|f| f.0).collect();
    let m = nearest(&times, c.time);
    assert_eq!(view.marked(), Some(m));
    let svg = view.svg("test", m);
    assert!(svg.contains(&format!("<g id=\"least-clearance\" stroke=\"{COLLISION_COLOUR}\"")), "red marker");
    assert!(svg.contains(&format!("fill=\"{COLLISION_COLOUR}\" id=\"least-caption\"")), "red caption");
    // The base's box and the three capsules, outside the marker's group.
    let unmarked = svg.split("<g id=\"least-clearance\"").next().unwrap_or_default();
    assert_eq!(unmarked.matches("<polygon").count(), 4);
    // The page: the same time, its nearest sample, red.
    let anim = arm_animation(&planned, "collide", "colliding");
    let scene = anim.scene.as_ref().expect("a scene");
    let l = scene.least.as_ref().expect("the least clearance");
    assert_eq!((l.t, l.min, l.holds), (c.time, c.min, false));
    assert_eq!(l.sample, nearest(&anim.t, c.time));
    assert_eq!(l.colour, COLLISION_COLOUR);
    assert_eq!(l.between, [c.a.to_string(), c.b.to_string()]);
    // The figure: a red vertical line at the time on the three charts.
    let figure = arm_plan_figure(&planned, "colliding".into(), "test");
    for panel in figure.panels.iter().filter(|p| !p.series.is_empty()) {
        let mark = panel.marks.first().expect("a mark");
        assert_eq!((mark.x, mark.colour), (c.time, (0xe8, 0x00, 0x0b)), "{}", panel.title);
    }
    assert!(figure.caption.iter().any(|l| l.contains("COLLIDES")), "{:?}", figure.caption);
    // Within its tolerance, the velocity level is still not called certified.
    let velocity = figure.caption.iter().find(|l| l.starts_with("velocity level")).expect("a velocity line");
    assert!(velocity.contains("NOT certified (it collides"), "{velocity}");
}

/// The page's animation of a plan with an obstacle holds the obstacle's outline on its circle
/// and the least clearance at the certificate's time and its nearest sample, purple (it holds);
/// the figure marks the same time on its charts with the clearance in mm and the pair, and the
/// picture shows the label.
#[test]
fn the_page_and_the_figure_mark_the_least_clearance() {
    let planned = around_the_obstacle();
    let c = least(&planned);
    let anim = arm_animation(&planned, "around", "around the obstacle");
    let scene = anim.scene.as_ref().expect("a scene");
    assert_eq!(scene.obstacles.len(), 1);
    for p in &scene.obstacles[0] {
        let r = (p[0] - CENTRE[0]).hypot(p[1] - CENTRE[1]);
        assert!((r - RADIUS).abs() < 2e-5, "{p:?} at {r} m from the centre");
    }
    assert_eq!(scene.bodies.len(), 4, "the base and three links");
    assert!(scene.bodies[0].is_empty() && scene.bodies[1..].iter().all(|b| b.len() == 1));
    let l = scene.least.as_ref().expect("the least clearance");
    assert_eq!((l.t, l.min, l.holds), (c.time, c.min, true));
    assert_eq!(l.sample, nearest(&anim.t, c.time));
    assert_eq!(l.colour, CLEAR_COLOUR);
    assert_eq!(l.between, ["link 3".to_string(), "obstacle 1".to_string()]);
    let json = serde_json::to_value(&anim).expect("serialises");
    assert_eq!(json["scene"]["least"]["t"].as_f64(), Some(c.time));
    // The figure.
    let figure = arm_plan_figure(&planned, "around".into(), "test");
    let label = format!("least clearance {:.1} mm, link 3 / obstacle 1", c.min * 1e3);
    let charts: Vec<_> = figure.panels.iter().filter(|p| !p.series.is_empty()).collect();
    assert_eq!(charts.len(), 2, "angles and rates (no torques asked)");
    for panel in &charts {
        assert_eq!(panel.marks.len(), 1);
        assert_eq!(
            (panel.marks[0].x, &panel.marks[0].label, panel.marks[0].colour),
            (c.time, &label, (0x7b, 0x32, 0x94))
        );
    }
    assert!(figure.caption.iter().any(|l| l.contains("CLEAR") && l.contains("link 3 and obstacle 1")));
    let svg = plan_picture(&figure, PictureFormat::Svg, Path::new("f.svg")).expect("draws");
    assert_eq!(String::from_utf8_lossy(&svg).matches(&label).count(), 2, "one label per chart");
}

/// 64-bit FNV-1a: a fingerprint of a file's bytes.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3))
}

/// Robots without shapes draw exactly as before issue 21's pictures: the GIFs of the 2-link
/// robot and of the 3-link example arm have the bytes (length and fingerprint) that commit
/// 83670d2 wrote for the same commands; their page animation has no scene and the figure no
/// mark. Since the 2-link robot's minimum-effort plan went through the one pipeline of every arm
/// (issue 19), its GIF is the arm's: the title says "2-link arm", and the frames are 83670d2's
/// (compared frame by frame: the title's pixels differ, elsewhere at most 1 in 255 of a colour
/// channel, the palette quantised for the new title).
#[test]
fn a_robot_without_shapes_draws_as_before() {
    let dir = tempfile::tempdir().expect("temp dir");
    let robot = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml");
    let runs: [(&[&str], usize, u64); 2] = [
        (&["plan", "--quiet", "--samples", "201", "--gif-fps", "10", "--gif", "a.gif"], 403_076, 0x59ee_8d02_72ec_f608),
        (
            &[
                "plan",
                "--robot",
                robot,
                "--from",
                "0,0,30,30",
                "--to",
                "20,90,30,-30",
                "--time",
                "8",
                "--gif-fps",
                "10",
                "--quiet",
                "--gif",
                "a.gif",
            ],
            312_496,
            0xe074_45a3_16e7_a74d,
        ),
    ];
    for (args, length, print) in runs {
        let o = Command::new(env!("CARGO_BIN_EXE_freefloat"))
            .current_dir(dir.path())
            .args(args)
            .output()
            .expect("the binary runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let bytes = std::fs::read(dir.path().join("a.gif")).expect("written");
        assert_eq!((bytes.len(), fnv(&bytes)), (length, print), "{args:?}");
    }
    let arm = Arm::load(Path::new(robot)).expect("the example");
    let planned = plan(&arm, Method::Optimal, [0.0, 0.0, 30.0, 30.0], [20.0, 90.0, 30.0, -30.0], 8.0);
    assert!(planned.verification().clearance.is_none());
    let json = serde_json::to_value(arm_animation(&planned, "plain", "plain")).expect("serialises");
    assert!(json.get("scene").is_none(), "no scene key");
    let figure = arm_plan_figure(&planned, "plain".into(), "test");
    assert!(figure.panels.iter().all(|p| p.marks.is_empty()));
    assert!(GifView::arm(&planned, &GifOptions::default()).marked().is_none());
}

/// `plan --gif` of the 2-link robot (the NFA's path) with a robot file's shapes: the plan folds
/// link 2 into the base's box at T (exit 3, as `tests/it/geometry.rs` measures), and the GIF,
/// still written, marks it in red on its last frame; the same robot without shapes has no red.
#[test]
fn the_two_link_gif_marks_its_collision_in_red() {
    let dir = tempfile::tempdir().expect("temp dir");
    let link = |l: f64, d: f64, m: f64, shape: &str| {
        format!("[[link]]\nlength = {l}\ncom = {d}\nmass = {m}\ninertia = 0.0\n{shape}")
    };
    let robot = |shapes: bool| {
        let (base, width) = if shapes { ("shape = \"box:0,0,0.6,0.5\"\n", "width = 0.04\n") } else { ("", "") };
        format!(
            "[robot]\nM = 12.9\nI = 0.208\n{base}{}{}",
            link(0.619, 0.313, 4.5, width),
            link(0.6, 0.287, 1.5, width)
        )
    };
    let mut reds = Vec::new();
    for shapes in [true, false] {
        let path = dir.path().join(format!("two_{shapes}.toml"));
        std::fs::write(&path, robot(shapes)).expect("written");
        let args = ["plan", "--robot", path.to_str().expect("utf-8"), "--method", "nfa", "--gif", "a.gif", "--quiet"];
        let o =
            Command::new(env!("CARGO_BIN_EXE_freefloat")).current_dir(dir.path()).args(args).output().expect("runs");
        assert_eq!(o.status.code(), Some(if shapes { 3 } else { 0 }), "{}", String::from_utf8_lossy(&o.stderr));
        let gif = decode(&std::fs::read(dir.path().join("a.gif")).expect("written"));
        let last = &gif.frames.last().expect("frames").1;
        // Pixels of the collision's red (#e8000b), within the palette's rounding.
        let red = last.chunks_exact(4).filter(|p| p[0] >= 200 && p[1] <= 40 && p[2] <= 50).count();
        reds.push(red);
    }
    assert!(reds[0] > 200 && reds[1] == 0, "red pixels with shapes {}, without {}", reds[0], reds[1]);
}
