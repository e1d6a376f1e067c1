//! The robot's shapes, the obstacles and the clearance (issue 21; docs/spec.md §1, §3): URDF and
//! TOML geometry read into freefloat's frames, bad geometry refused (exit 2), and a plan that
//! collides never certified (exit 3 naming the bodies), whatever the method.

use std::path::Path;
use std::process::{Command, Output};

use freefloat::model::arm::Arm;
use freefloat::model::geometry::Shape;
use freefloat::planners::chain::ChainProblem;

fn freefloat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn fixture() -> String {
    format!("{}/tests/fixtures/spart_like_4dof_geometry.urdf", env!("CARGO_MANIFEST_DIR"))
}

/// The SPART-like plan of issue 21.
const FROM: &str = "0,30,-60,45,-30";
const TO: &str = "30,60,-30,20,-60";
/// Every pair with the base left out: the links against each other only.
const NO_BASE: [&str; 6] = ["--no-collide", "base,link2", "--no-collide", "base,link3", "--no-collide", "base,link4"];

/// The JSON report of a `plan` that must succeed.
fn planned(args: &[&str]) -> serde_json::Value {
    let o = freefloat(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn close(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
}

/// The fixture's shapes in freefloat's frames, by hand: the base's visual box (no `<collision>`)
/// about the base's centre of mass, which the 2 kg camera at y = 0.2 m moves to
/// y = 2 * 0.2 / 62 m; each link's five spheres on its axis from joint k; the end-effector
/// frame's sphere (a fixed child 0.5 m along link 4) in link 4's frame.
#[test]
fn urdf_collision_spheres_and_the_visual_base_box_land_in_freefloats_frames() {
    let text = std::fs::read_to_string(fixture()).unwrap();
    let (arm, _, _, notes) = Arm::from_urdf_str_noted(&text, Path::new("f.urdf")).unwrap();
    let g = &arm.geometry;
    let y = 2.0 * 0.2 / 62.0;
    assert_eq!(g.base.len(), 1);
    for corner in [[-0.25, -0.25 - y], [0.25, -0.25 - y], [0.25, 0.25 - y], [-0.25, 0.25 - y]] {
        assert!(g.base[0].points.iter().any(|p| close(*p, corner)), "{corner:?} in {:?}", g.base[0]);
    }
    assert_eq!(g.links.len(), 4);
    for (k, shapes) in g.links.iter().enumerate() {
        let mut xs: Vec<f64> = vec![0.05, 0.15, 0.25, 0.35, 0.45];
        if k == 3 {
            xs.push(0.5);
        }
        assert_eq!(shapes.len(), xs.len(), "link {}", k + 1);
        for (s, x) in shapes.iter().zip(xs) {
            assert!(close(s.points[0], [x, 0.0]) && (s.radius - 0.03).abs() < 1e-15, "link {}: {s:?}", k + 1);
        }
    }
    assert!(notes.iter().any(|n| n.contains("`Base`") && n.contains("<visual>")), "{notes:?}");
}

/// A URDF of one link with each solid: a cylinder along z (a circle), one turned into the plane
/// (a rectangle), a box turned by yaw, a sphere on a fixed child link, and a mesh (skipped with
/// a note).
#[test]
fn urdf_cylinders_boxes_spheres_project_and_meshes_are_skipped() {
    let text = r#"<robot name="r">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><cylinder radius="0.3" length="0.2"/></geometry></collision>
    <collision><geometry><mesh filename="package://r/base.stl"/></geometry></collision></link>
  <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><origin xyz="0.5 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.05" length="1.0"/></geometry></collision>
    <collision><origin xyz="0.2 0.1 0" rpy="0 0 1.5707963267948966"/><geometry><box size="0.4 0.2 0.1"/></geometry></collision></link>
  <link name="tip"><collision><geometry><sphere radius="0.04"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0.4 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j_tip" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="1.0 0 0"/></joint>
</robot>"#;
    let (arm, _, _, notes) = Arm::from_urdf_str_noted(text, Path::new("r.urdf")).unwrap();
    let g = &arm.geometry;
    assert_eq!(g.base, vec![Shape::circle([0.0, 0.0], 0.3).unwrap()]);
    assert!(notes.iter().any(|n| n.contains("base.stl") && n.contains("skipped")), "{notes:?}");
    let link = &g.links[0];
    assert_eq!(link.len(), 3);
    // The cylinder along x: the rectangle from joint 1 to x = 1 m, 0.1 m wide.
    for corner in [[0.0, -0.05], [1.0, -0.05], [1.0, 0.05], [0.0, 0.05]] {
        assert!(link[0].points.iter().any(|p| close(*p, corner)), "{corner:?} in {:?}", link[0]);
    }
    // The box turned by 90 deg about its centre (0.2, 0.1): 0.2 m along x, 0.4 m along y.
    for corner in [[0.1, -0.1], [0.3, -0.1], [0.3, 0.3], [0.1, 0.3]] {
        assert!(link[1].points.iter().any(|p| close(*p, corner)), "{corner:?} in {:?}", link[1]);
    }
    // The tip's sphere, 1 m along the link (its fixed joint's offset).
    assert!(close(link[2].points[0], [1.0, 0.0]) && (link[2].radius - 0.04).abs() < 1e-15);
}

/// Bad geometry is bad input (exit 2) naming the link: a negative sphere radius, a box side that
/// is not a number.
#[test]
fn bad_urdf_geometry_is_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(fixture()).unwrap();
    for (bad, what) in
        [(r#"<sphere radius="-0.03"/>"#, "sphere radius"), (r#"<sphere radius="nan"/>"#, "sphere radius")]
    {
        let text = good.replacen(r#"<sphere radius="0.03"/>"#, bad, 1);
        let path = dir.path().join("bad.urdf");
        std::fs::write(&path, text).unwrap();
        let o = freefloat(&["plan", "--urdf", path.to_str().unwrap(), "--from", FROM, "--to", TO]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains("Link_1") && stderr(&o).contains(what), "{}", stderr(&o));
    }
}

/// A TOML robot's `width` is a capsule along the link, `shape` adds shapes in the link's (or
/// the base's) frame; a misspelt key and a bad shape are refused naming the key.
#[test]
fn toml_width_and_shape_keys() {
    let base = "[robot]\nM = 20.0\nI = 1.0\nshape = \"box:0,0,0.5,0.4\"\n[mount]\na = 0.25\nb = 0.0\n";
    let link = "[[link]]\nlength = 0.5\ncom = 0.25\nmass = 2.0\ninertia = 0.04\n";
    let text = format!("{base}{link}width = 0.06\n{link}shape = [\"circle:0.5,0,0.05\", \"capsule:0,0,0.5,0,0.02\"]\n");
    let arm = Arm::from_toml(&text, Path::new("a.toml")).unwrap();
    let g = &arm.geometry;
    assert_eq!(g.base, vec![Shape::rectangle([0.0, 0.0], [0.5, 0.4]).unwrap()]);
    assert_eq!(g.links[0], vec![Shape::capsule([0.0, 0.0], [0.5, 0.0], 0.03).unwrap()]);
    assert_eq!(
        g.links[1],
        vec![Shape::circle([0.5, 0.0], 0.05).unwrap(), Shape::capsule([0.0, 0.0], [0.5, 0.0], 0.02).unwrap()]
    );
    let typo = format!("{base}{link}widht = 0.06\n");
    assert!(Arm::from_toml(&typo, Path::new("a.toml")).unwrap_err().to_string().contains("widht"));
    let bad = format!("{base}{link}shape = \"circle:0,0,-1\"\n");
    let e = Arm::from_toml(&bad, Path::new("a.toml")).unwrap_err().to_string();
    assert!(e.contains("link[1].shape"), "{e}");
}

/// The SPART-like fixture's plan (its own limits): the unconstrained minimum passes link 4
/// through the base (measured -0.279 m at t = 6.4 s without clearance rows, issue 21); the
/// planner keeps the clearance asked for as a constraint, so the plan with `--clearance 0.02` is
/// certified on the integrated motion with at least 0.02 m between every pair, and costs more
/// than the plan that ignores the base (which clears the links among themselves, > 0.1 m, and is
/// certified with its clearance block).
#[test]
fn the_spart_like_plan_keeps_its_clearance_from_the_base() {
    let f = fixture();
    let plan = ["plan", "--urdf", &f, "--from", FROM, "--to", TO, "--format", "json"];
    let r = planned(&[&plan[..], &["--clearance", "0.02"]].concat());
    assert_eq!(r["certified"], true);
    let c = &r["clearance"];
    assert!(c["min"].as_f64().unwrap() >= 0.02 && c["holds"] == true, "{c}");
    let kept = r["effort"].as_f64().unwrap();

    let r = planned(&[&plan[..], &NO_BASE[..]].concat());
    let c = &r["clearance"];
    assert_eq!((&r["certified"], &c["between"]), (&serde_json::json!(true), &serde_json::json!(["link 1", "link 3"])));
    assert!(c["min"].as_f64().unwrap() > 0.1 && c["holds"] == true, "{c}");
    let free = r["effort"].as_f64().unwrap();
    assert!(kept > free, "kept clear {kept} against {free} ignoring the base");
}

/// The example SPART-like robot (its torque limits of 20 N m, its visual shapes) with
/// `--smooth-ends`: the plan rides the base's edge, its clearance re-solve was not held between
/// the torque rows' points, and the plan was refused (exit 3) with joint 1's torque at 103 % of
/// its limit. The re-solve is held as the refined plan is: certified, clear, inside every limit
/// (the certificate reads the integrated motion between its steps).
#[test]
fn smooth_ends_clear_of_the_base_hold_the_torque_limits() {
    let f = format!("{}/examples/robots/spart_like_4dof.urdf", env!("CARGO_MANIFEST_DIR"));
    let r = planned(&["plan", "--urdf", &f, "--from", FROM, "--to", TO, "--smooth-ends", "--format", "json"]);
    assert_eq!(r["certified"], true);
    assert_eq!(
        (&r["clearance"]["holds"], &r["limits"]["inside"]),
        (&serde_json::json!(true), &serde_json::json!(true))
    );
    let uses = r["limits"]["uses"].as_array().unwrap();
    assert!(uses.iter().all(|u| u["use"].as_f64().unwrap() <= 1.0), "{uses:?}");
}

/// An obstacle out of every body's reach (`Geometry::pairs_within`) changes nothing of the plan:
/// the same effort to the last digit, and the certificate still measures it (before, its pairs'
/// dense rows through `phi(t)` doubled the time of this plan, 3.4 to 7.0 s, for the same plan).
#[test]
fn an_obstacle_out_of_reach_leaves_the_plan_as_it_is() {
    let f = fixture();
    let plan = ["plan", "--urdf", &f, "--from", FROM, "--to", TO, "--format", "json"];
    let free = planned(&plan);
    let far = planned(&[&plan[..], &["--obstacle", "circle:10,10,0.1"]].concat());
    assert_eq!(far["certified"], true);
    assert_eq!(free["effort"], far["effort"], "the same plan");
    assert_eq!(free["clearance"]["min"], far["clearance"]["min"], "its least clearance between the robot's bodies");
}

/// The same plan at 0.03 and 0.035 m, between the clearances the search was first tried at (0.02
/// above, 0.04): both exited 3 with the least bad plan (0.013 m and the base crossed), their
/// coarse finalists stalled or came under the clearance, and the line's solution on the finest
/// basis, converged at 7.53 and 7.57 rad^2/s, had been dropped as 20 % above them. Where no
/// finalist is certified and clear, the candidates set aside are tried next.
#[test]
fn the_spart_like_plan_keeps_clearances_between_those_tried() {
    let f = fixture();
    let plan = ["plan", "--urdf", &f, "--from", FROM, "--to", TO, "--format", "json"];
    for clearance in ["0.03", "0.035"] {
        let r = planned(&[&plan[..], &["--clearance", clearance]].concat());
        assert_eq!(r["certified"], true, "{clearance}");
        let c = &r["clearance"];
        let wanted: f64 = clearance.parse().unwrap();
        assert!(c["min"].as_f64().unwrap() >= wanted && c["holds"] == true, "{clearance}: {c}");
    }
}

/// An obstacle where the unconstrained plan's end effector arrives: every motion ends inside it,
/// so `plan` and `compare` refuse the goal at once (exit 2), naming the end, the pair and the
/// depth, instead of searching every seed for a plan that cannot be certified. An obstacle on the
/// ECSA's path but clear of both ends (where its end effector passes at t = 5 s, measured at
/// (-0.608, -0.019) m): the ECSA does not avoid it, and its plan is never certified (exit 3,
/// naming the obstacle).
#[test]
fn an_obstacle_on_the_path_is_never_certified() {
    let f = fixture();
    let mut args = vec![
        "plan",
        "--urdf",
        &f,
        "--from",
        FROM,
        "--to",
        TO,
        "--limit",
        "all=none",
        "--obstacle",
        "circle:0.95,1.55,0.1",
    ];
    args.extend(NO_BASE);
    for command in ["plan", "compare"] {
        args[0] = command;
        let o = freefloat(&args);
        assert_eq!(o.status.code(), Some(2), "{command}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains("goal (--to)") && e.contains("link 4 and obstacle 1"), "{command}: {e}");
    }
    args[0] = "plan";
    args[10] = "circle:-0.61,-0.02,0.05";
    args.extend(["--method", "ecsa", "--format", "json"]);
    let o = freefloat(&args);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("link 4 and obstacle 1"), "{}", stderr(&o));
    // Bad flags are bad input.
    let bad_flags = [
        ["--obstacle", "circle:1,1"],
        ["--clearance", "-1"],
        ["--no-collide", "base,link9"],
        ["--no-collide", "link2,link2"],
    ];
    for bad in bad_flags {
        let o = freefloat(&[&["plan", "--urdf", &f, "--from", FROM, "--to", TO][..], &bad[..]].concat());
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", stderr(&o));
    }
}

/// Obstacles or a clearance for a robot without shapes would check nothing, so a plan through
/// the obstacle would pass as clear: they are refused (exit 2) on the paper's robot and on an
/// arm without shapes, for every command that takes them; an exclusion alone is a note.
#[test]
fn obstacles_for_a_robot_without_shapes_are_refused() {
    let three = "examples/robots/three_link.toml";
    let arm = ["--robot", three, "--from", "0,0,0,0", "--to", "30,10,10,10"];
    let cases: [(&str, &[&str], &[&str]); 5] = [
        ("plan", &[], &["--obstacle", "circle:0,0,0.1"]),
        ("plan", &[], &["--clearance", "0.01"]),
        ("plan", &arm, &["--obstacle", "circle:0,0,0.1"]),
        ("compare", &arm, &["--clearance", "0.01"]),
        ("track", &[], &["--obstacle", "circle:0.3,0.3,0.1"]),
    ];
    for (command, robot, flags) in cases {
        let o = freefloat(&[&[command][..], robot, flags].concat());
        assert_eq!(o.status.code(), Some(2), "{command} {flags:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("no shapes"), "{command} {flags:?}: {}", stderr(&o));
    }
    let o = freefloat(&[&["plan"][..], &arm, &["--no-collide", "base,link2"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("--no-collide: the robot has no shapes"), "{}", stderr(&o));
}

/// A start or goal closer than `--clearance` to a pair that is checked is refused at once
/// (exit 2), naming the end and the pair, and the JSON error carries the distance. The SPART-like
/// arm's start has link 2 within 0.5 m of the base (measured 0.446 m).
#[test]
fn ends_under_the_clearance_are_refused_at_once() {
    let f = fixture();
    let o = freefloat(&["plan", "--urdf", &f, "--from", FROM, "--to", TO, "--clearance", "0.5", "--format", "json"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let numbers = &r["error"]["numbers"];
    let name = numbers["name"].as_str().unwrap();
    assert!(name.starts_with("start (--from)") && name.contains("under the clearance 0.5 m"), "{r}");
    // The distance reported is the least over the pairs at the start, by the library's geometry.
    let d = numbers["value"].as_f64().unwrap();
    let path = Path::new(&f);
    let mut arm = Arm::from_urdf_str(&std::fs::read_to_string(path).unwrap(), path).unwrap();
    let deg = |s: &str| s.split(',').map(|x| x.parse::<f64>().unwrap().to_radians()).collect::<Vec<_>>();
    let least = arm.geometry.min_clearance(&arm, &deg(FROM)).unwrap();
    assert_eq!((least.a.to_string(), least.b.to_string()), ("base".into(), "link 2".into()));
    assert!((least.distance - d).abs() < 1e-12 && d < 0.5, "{d} against {least:?}");
    // At a clearance both ends keep, the problem is not refused.
    let goal_least = arm.geometry.min_clearance(&arm, &deg(TO)).unwrap().distance;
    arm.geometry.clearance = 0.99 * d.min(goal_least);
    ChainProblem::rest_to_rest(deg(FROM), deg(TO), 10.0).validate(&arm).unwrap();
}

/// A 2-link arm with shapes: the minimum-effort planner keeps its clearance as for any arm, and
/// the NFA's plan is checked. Ends that collide are refused before any plan (exit 2): an obstacle
/// at the system's centre of mass lies inside the heavy base's box at the start, and the paper's
/// goal, theta2 = 140 deg, folds link 2 back into this base's 0.6 m x 0.5 m box (measured 6.5 mm
/// deep); the NFA, which does not take the robot's shapes, reports that collision at t = 10 s
/// (exit 3).
#[test]
fn two_link_plans_of_every_method_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("src_shapes.toml");
    let link = |l: f64, d: f64, m: f64| {
        format!("[[link]]\nlength = {l}\ncom = {d}\nmass = {m}\ninertia = 0.0\nwidth = 0.04\n")
    };
    let text = format!(
        "[robot]\nM = 12.9\nI = 0.208\nshape = \"box:0,0,0.6,0.5\"\n{}{}",
        link(0.619, 0.313, 4.5),
        link(0.6, 0.287, 1.5)
    );
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap();
    let o = freefloat(&["compare", "--robot", p, "--obstacle", "circle:0,0,0.05", "--format", "json"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("start (--from)") && stderr(&o).contains("base and obstacle 1"), "{}", stderr(&o));
    let o = freefloat(&["plan", "--robot", p]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("goal (--to)") && stderr(&o).contains("base and link 2"), "{}", stderr(&o));
    let o = freefloat(&["plan", "--robot", p, "--method", "nfa"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("min clearance"));
    assert!(stderr(&o).contains("base and link 2 come") && stderr(&o).contains("t = 10 s"), "{}", stderr(&o));
    // A goal clear of the base, theta2 = 90 deg: the 2-link pipeline's plan (without the rows)
    // passed link 2 0.273 m through the base at t = 2.95 s; the arm's planner keeps it clear.
    let r = planned(&["plan", "--robot", p, "--to", "0,120,90", "--format", "json"]);
    let c = &r["clearance"];
    assert!(r["certified"] == true && c["holds"] == true && c["min"].as_f64().unwrap() >= 0.0, "{c}");
}

/// The 3-link example arm with capsule links 4 cm wide (`examples/robots/three_link.toml` and a
/// `width` per link), written to `dir`.
fn three_link_with_widths(dir: &Path) -> String {
    let text = std::fs::read_to_string(format!("{}/examples/robots/three_link.toml", env!("CARGO_MANIFEST_DIR")))
        .unwrap()
        .lines()
        .map(|l| if l.starts_with("inertia") { format!("{l}\nwidth = 0.04") } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let path = dir.join("three_link_widths.toml");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Issue 21's 3-link case: a circular obstacle (5 cm at (-0.4, 0.1) m) that the unconstrained
/// plan's end effector passes through (its tip 2.5 cm from the centre at t = 5.1 s, measured),
/// links 1 and 3 not checked against each other (stacked in different planes). No other
/// candidate of the search clears it (before the obstacle rows: exit 3); the rows through
/// `phi(t)` push that plan clear, certified on the integrated motion with the clearance holding
/// at the rows' 1 mm margin (the row binds), at a higher effort than through the obstacle.
#[test]
fn a_three_link_arm_reaches_around_an_obstacle_that_its_free_plan_crosses() {
    let dir = tempfile::tempdir().unwrap();
    let robot = three_link_with_widths(dir.path());
    let csv = dir.path().join("free.csv");
    let plan = [
        "plan",
        "--robot",
        &robot,
        "--from",
        "0,0,30,30",
        "--to",
        "20,90,30,-30",
        "--time",
        "8",
        "--no-collide",
        "link1,link3",
        "--format",
        "json",
    ];
    let o = freefloat(&[&plan[..], &["--out", csv.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let free: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // The free plan's end effector comes inside the obstacle.
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let nearest = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap_or(f64::NAN)).collect::<Vec<_>>())
        .map(|r| (r[col("xe")] + 0.4).hypot(r[col("ye")] - 0.1))
        .fold(f64::INFINITY, f64::min);
    assert!(nearest < 0.05, "the free plan's tip stays {nearest} m from the obstacle's centre");
    let o = freefloat(&[&plan[..], &["--obstacle", "circle:-0.4,0.1,0.05"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let kept: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let c = &kept["clearance"];
    assert_eq!(kept["certified"], true, "{kept}");
    assert_eq!(c["between"][1], "obstacle 1", "{c}");
    let min = c["min"].as_f64().unwrap();
    assert!(c["holds"] == true && (0.0..0.01).contains(&min), "{c}");
    let (with, without) = (kept["effort"].as_f64().unwrap(), free["effort"].as_f64().unwrap());
    assert!(with > without, "around the obstacle {with} against {without} through it");
}

/// Issue 21's SPART-like example (`examples/robots/spart_like_4dof.urdf`: 1 rad/s, 20 N m) at a
/// clearance of 0.02 m in 4.3 s: every plan the search finds inside the limits passes through the
/// base (stop 61: exit 3, base and link 3 0.317 m into each other), while the plan without the
/// rate limits clears. The answer is the horizon too short (exit 3, `horizon_too_short`, not
/// searched) at a longer horizon, at which the plan is then certified, clear and inside every
/// limit. Ignored: the two searches at 4.3 s and the one at the horizon named take about 51 s of
/// CPU in release (`cargo test --release -- --ignored`).
#[test]
#[ignore = "about 50 s of CPU in release: three clearance searches of the SPART-like arm"]
fn the_spart_like_horizon_too_short_is_told_with_one_that_fits() {
    let f = format!("{}/examples/robots/spart_like_4dof.urdf", env!("CARGO_MANIFEST_DIR"));
    let problem = ["--from=-41,-9.7,-14.9,31.2,69.3", "--to=53.9,6.2,-7.7,-32.4,-65.0", "--clearance", "0.02"];
    let args = [&["plan", "--urdf", &f, "--format", "json"][..], &problem, &["--time", "4.3"]].concat();
    let o = freefloat(&args);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let (kind, numbers) = (&r["error"]["kind"], &r["error"]["numbers"]);
    assert_eq!((kind.as_str(), &numbers["searched"]), (Some("horizon_too_short"), &serde_json::json!(false)), "{r}");
    let fits = numbers["shortest"].as_f64().unwrap();
    assert!(fits > 4.3, "{r}");
    let at = format!("{fits}");
    let r = planned(&[&["plan", "--urdf", &f, "--format", "json"][..], &problem, &["--time", &at]].concat());
    assert_eq!(r["certified"], true);
    assert_eq!(
        (&r["clearance"]["holds"], &r["limits"]["inside"]),
        (&serde_json::json!(true), &serde_json::json!(true))
    );
}
