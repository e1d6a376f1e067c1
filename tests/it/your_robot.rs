//! `freefloat robot`: what freefloat reads from a robot file (docs/your-robot.md), checked on
//! the guide's SPART-like 4-link URDF against numbers computed here by hand from the file.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs")
}

fn json(args: &[&str]) -> serde_json::Value {
    let o = run(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

const SPART: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/spart_like_4dof.urdf");

#[track_caller]
fn close(x: &serde_json::Value, expected: f64) {
    let x = x.as_f64().unwrap_or_else(|| panic!("not a number: {x}"));
    assert!((x - expected).abs() <= 1e-12 * expected.abs().max(1.0), "{x} != {expected}");
}

/// The file's numbers: the camera (2 kg at y = 0.2 m) merged into the 60 kg base by the
/// parallel-axis theorem, the mount measured from the merged centre of mass, four 0.5 m links
/// of 3 kg with the centre of mass at 0.25 m, the tool at the end-effector frame's x = 0.5 m.
#[test]
fn robot_prints_the_spart_like_arm_as_read() {
    let v = json(&["robot", SPART, "--format", "json"]);
    assert_eq!(v["format"], "urdf");
    assert_eq!(v["joints"], 4);
    assert_eq!(v["joint_names"], serde_json::json!(["J1", "J2", "J3", "J4"]));
    let (m_base, m_cam, y_cam): (f64, f64, f64) = (60.0, 2.0, 0.2);
    let mass = m_base + m_cam;
    let y_com = m_cam * y_cam / mass;
    let inertia = 2.5 + m_base * y_com * y_com + 0.01 + m_cam * (y_cam - y_com).powi(2);
    close(&v["base"]["mass"], mass);
    close(&v["base"]["inertia"], inertia);
    close(&v["mount"][0], 0.25);
    close(&v["mount"][1], -y_com);
    for (k, link) in v["links"].as_array().expect("links").iter().enumerate() {
        close(&link["length"], 0.5);
        close(&link["com"], 0.25);
        close(&link["mass"], 3.0);
        close(&link["inertia"], 0.0625);
        close(&link["com_at_zero"][0], 0.25 + 0.5 * k as f64 + 0.25);
    }
    close(&v["total_mass"], mass + 4.0 * 3.0);
    close(&v["tool"]["x"], 0.5);
    close(&v["tool"]["at_zero"][0], 0.25 + 4.0 * 0.5);
    assert_eq!(v["two_link"], false);
    // Each joint's <limit lower="-3.1416" upper="3.1416" effort="20" velocity="1"/> (the file's
    // text, not pi).
    let upper: f64 = "3.1416".parse().unwrap();
    for k in 0..4 {
        let l = &v["limits"]["joints"][k];
        close(&l["position"][0], -upper);
        close(&l["position"][1], upper);
        close(&l["velocity"], 1.0);
        close(&l["torque"], 20.0);
    }
    // The visual boxes as shapes: the base's 0.5 m cube about the root link's origin, moved to the
    // merged centre of mass (y_com higher); each link's 0.5 x 0.05 box from its joint.
    let corners = |shape: &serde_json::Value| -> Vec<[f64; 2]> {
        shape["points"]
            .as_array()
            .expect("points")
            .iter()
            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
            .collect()
    };
    let extent = |c: &[[f64; 2]], i: usize| {
        c.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[i]), hi.max(p[i])))
    };
    let base = corners(&v["geometry"]["base"][0]);
    assert_eq!(base.len(), 4);
    let ((x0, x1), (y0, y1)) = (extent(&base, 0), extent(&base, 1));
    for (x, expected) in [(x0, -0.25), (x1, 0.25), (y0, -0.25 - y_com), (y1, 0.25 - y_com)] {
        assert!((x - expected).abs() < 1e-12, "{x} != {expected}");
    }
    for k in 0..4 {
        let link = corners(&v["geometry"]["links"][k][0]);
        let ((x0, x1), (y0, y1)) = (extent(&link, 0), extent(&link, 1));
        for (x, expected) in [(x0, 0.0), (x1, 0.5), (y0, -0.025), (y1, 0.025)] {
            assert!((x - expected).abs() < 1e-12, "link {}: {x} != {expected}", k + 1);
        }
    }
    let table = String::from_utf8_lossy(&run(&["robot", "--urdf", SPART]).stdout).into_owned();
    for name in
        ["J1", "J4", "tool point", "mount (a, b)", "limits 4 J4", "velocity 1 rad/s, torque 20 N m", "shapes link 4"]
    {
        assert!(table.contains(name), "{name}: {table}");
    }
    let table = String::from_utf8_lossy(&run(&["robot"]).stdout).into_owned();
    assert!(table.contains("limits               none") && table.contains("shapes               none"), "{table}");
}

/// The same arm as TOML and as URDF (examples/robots/three_link.*) reads the same, and the
/// preset is the paper's SRC robot.
#[test]
fn robot_reads_toml_urdf_and_the_preset_alike() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let toml = json(&["robot", &format!("{dir}/examples/robots/three_link.toml"), "--format", "json"]);
    let urdf = json(&["robot", "--urdf", &format!("{dir}/examples/robots/three_link.urdf"), "--format", "json"]);
    assert_eq!(toml["format"], "toml");
    for key in ["length", "com", "mass", "inertia"] {
        for k in 0..3 {
            let x = urdf["links"][k][key].as_f64().expect("a number");
            close(&toml["links"][k][key], x);
        }
    }
    let src = json(&["robot", "--format", "json"]);
    close(&src["links"][0]["length"], 0.619); // the paper's l1 (README, "The robot file")
    close(&src["base"]["mass"], 12.9);
    assert_eq!(src["two_link"], true);
    assert_eq!(run(&["robot", SPART, "--urdf", SPART]).status.code(), Some(2));
}

/// The guide's worked example plans and certifies on the SPART-like arm.
/// The guide's worked example with the file's own limits (20 N m, 1 rad/s, +-3.1416 rad): without
/// them the plan needs more than 20 N m (so the torque limit must bind); with them it is
/// certified at both levels, inside every limit, at 100 % of a torque limit.
#[test]
fn the_guide_plans_the_spart_like_arm() {
    let args = ["plan", "--urdf", SPART, "--from", "0,30,30,30,30", "--to", "10,60,0,40,20", "--torques"];
    let json = |extra: &[&str]| {
        let o = run(&[&args[..], extra, &["--format", "json"]].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).expect("JSON")
    };
    let free = json(&["--limit", "all=none"]);
    let peak = free["max_abs_torque"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).fold(0.0, f64::max);
    assert!(peak > 20.0, "the torque limit binds: {peak} N m without it");
    let r = json(&[]);
    assert_eq!(r["certified"], true);
    assert_eq!(r["limits"]["inside"], true);
    let uses = r["limits"]["uses"].as_array().unwrap();
    let torque =
        uses.iter().filter(|u| u["quantity"] == "torque").map(|u| u["use"].as_f64().unwrap()).fold(0.0, f64::max);
    assert!(torque > 0.99 && torque <= 1.0 + 1e-9, "at the torque limit: {torque}");
    let o = run(&args);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("4-link arm") && out.contains("CERTIFIED") && out.contains("INSIDE"), "{out}");
}
