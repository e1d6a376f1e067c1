//! `freefloat robot FILE`: what freefloat read from a robot file (TOML or URDF), to check a model
//! before planning with it (docs/your-robot.md): the base, the mount, every link's length, centre
//! of mass, mass and inertia, the tool point and the joint names; SI units.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use freefloat::model::arm::Arm;
use freefloat::report::numbers::number;
use freefloat::{Mount, RobotParams};
use serde_json::json;

use super::args::{DomainFormat, RobotInfoArgs};

/// Runs `freefloat robot`.
pub fn run(args: &RobotInfoArgs) -> anyhow::Result<ExitCode> {
    let mut flags = args.robot.clone();
    if args.file.is_some() {
        flags.robot.clone_from(&args.file);
    }
    let path = super::robot_file(&flags)?.cloned();
    let arm = match &path {
        Some(p) => Arm::load(p)?,
        None => Arm::from_params(&RobotParams::src()),
    };
    let arm = match &flags.mount {
        Some(text) => {
            let [a, b] = super::parse_list::<2>("--mount", text)?;
            Arm::new(arm.base, Mount::new(a, b)?, arm.links)?
        }
        None => arm,
    };
    let urdf = path.as_deref().is_some_and(is_urdf);
    let names = match &path {
        Some(p) if urdf => urdf_joint_names(p)?,
        _ => (1..=arm.joints()).map(|k| format!("theta{k}")).collect(),
    };
    let source = path.as_ref().map(|p| p.display().to_string()).unwrap_or_else(|| "the preset src".into());
    let value = describe(&arm, &source, if urdf { "urdf" } else { "toml" }, &names);
    let text = match args.format {
        DomainFormat::Json => format!("{}\n", serde_json::to_string_pretty(&value)?),
        DomainFormat::Table => table(&arm, &source, &names),
    };
    super::emit(&text)?;
    Ok(ExitCode::SUCCESS)
}

fn is_urdf(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
}

/// The names of the moving joints (revolute or continuous), from the base outwards. The file
/// was read and checked by [`Arm::load`] before: they form one chain.
fn urdf_joint_names(path: &Path) -> anyhow::Result<Vec<String>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let robot = urdf_rs::read_from_string(&text).with_context(|| format!("parsing {}", path.display()))?;
    let parent_of: std::collections::HashMap<&str, &str> =
        robot.joints.iter().map(|j| (j.child.link.as_str(), j.parent.link.as_str())).collect();
    let mut moving: Vec<(usize, String)> = robot
        .joints
        .iter()
        .filter(|j| matches!(j.joint_type, urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous))
        .map(|j| (depth(&parent_of, &j.child.link, robot.joints.len()), j.name.clone()))
        .collect();
    moving.sort();
    Ok(moving.into_iter().map(|(_, name)| name).collect())
}

/// The number of joints from the root link down to `link` (at most `limit`: a cycle, which
/// `Arm::load` refuses, never loops here).
fn depth<'a>(parent_of: &std::collections::HashMap<&'a str, &'a str>, mut link: &'a str, limit: usize) -> usize {
    let mut d = 0;
    while let Some(parent) = parent_of.get(link) {
        if d > limit {
            break;
        }
        link = parent;
        d += 1;
    }
    d
}

/// Joint `k` (from 0) at zero angles in the base frame: the mount plus the lengths before it.
fn along(arm: &Arm, k: usize) -> f64 {
    arm.mount.a + arm.links[..k].iter().map(|l| l.length).sum::<f64>()
}

/// The tool point's `x` on the last link: its length [m].
fn tip(arm: &Arm) -> f64 {
    arm.links.last().map(|l| l.length).unwrap_or(0.0)
}

/// The JSON object of `--format json` (SI units).
fn describe(arm: &Arm, source: &str, format: &str, names: &[String]) -> serde_json::Value {
    let n = arm.joints();
    let links: Vec<_> = arm
        .links
        .iter()
        .enumerate()
        .map(|(k, l)| {
            json!({
                "joint": names.get(k), "length": l.length, "com": l.com, "mass": l.mass, "inertia": l.inertia,
                "com_at_zero": [along(arm, k) + l.com, arm.mount.b],
            })
        })
        .collect();
    json!({
        "file": source,
        "format": format,
        "joints": n,
        "joint_names": names,
        "total_mass": arm.total_mass(),
        "base": {"mass": arm.base.mass, "inertia": arm.base.inertia},
        "mount": [arm.mount.a, arm.mount.b],
        "links": links,
        "tool": {"link": n, "x": tip(arm), "at_zero": [along(arm, n), arm.mount.b]},
        "two_link": arm.as_src().is_some(),
        "limits": arm.limits,
        "geometry": arm.geometry,
    })
}

/// The human-readable table.
fn table(arm: &Arm, source: &str, names: &[String]) -> String {
    use std::fmt::Write;
    let n = arm.joints();
    let mut s = String::new();
    let _ = writeln!(s, "freefloat robot: {source}, {n} link(s), total mass {} kg", number(arm.total_mass()));
    let _ = writeln!(
        s,
        "  base                 mass {} kg, inertia {} kg m^2 about its centre of mass (the base frame's origin)",
        number(arm.base.mass),
        number(arm.base.inertia)
    );
    let _ = writeln!(
        s,
        "  mount (a, b)         ({}, {}) m: joint 1 in the base frame",
        number(arm.mount.a),
        number(arm.mount.b)
    );
    let _ = writeln!(
        s,
        "  {:<5}{:<16}{:>12}{:>12}{:>12}{:>18}",
        "link", "joint", "length [m]", "com [m]", "mass [kg]", "inertia [kg m^2]"
    );
    for (k, l) in arm.links.iter().enumerate() {
        let name = names.get(k).map(String::as_str).unwrap_or("-");
        let _ = writeln!(
            s,
            "  {:<5}{:<16}{:>12}{:>12}{:>12}{:>18}",
            k + 1,
            freefloat::model::excerpt(name),
            number(l.length),
            number(l.com),
            number(l.mass),
            number(l.inertia)
        );
    }
    let _ = writeln!(
        s,
        "  tool point           {} m along link {n} (its tip); at zero angles ({}, {}) m in the base frame",
        number(tip(arm)),
        number(along(arm, n)),
        number(arm.mount.b)
    );
    limit_lines(&mut s, arm, names);
    shape_lines(&mut s, arm);
    let _ = writeln!(
        s,
        "  planning             {}",
        if arm.as_src().is_some() {
            "2 links: every method and command"
        } else {
            "every command with --from/--to of n + 1 angles (the NFA and domain need 2 links)"
        }
    );
    s
}

/// The table's lines of the declared limits (docs/spec.md §1): one per limited joint and one for
/// the base's range; `limits  none` without any.
fn limit_lines(s: &mut String, arm: &Arm, names: &[String]) {
    use std::fmt::Write;
    let deg = |v: f64| number(v.to_degrees());
    if arm.limits.is_empty() {
        let _ = writeln!(s, "  limits               none (continuous joints, no velocity or torque limit)");
        return;
    }
    if let Some([lo, hi]) = arm.limits.base {
        let _ = writeln!(s, "  limits base          phi in [{}, {}] deg", deg(lo), deg(hi));
    }
    for k in 0..arm.joints() {
        let l = arm.limits.joint(k);
        let mut parts = Vec::new();
        if let Some([lo, hi]) = l.position {
            parts.push(format!("position [{}, {}] deg", deg(lo), deg(hi)));
        }
        if let Some(v) = l.velocity {
            parts.push(format!("velocity {} rad/s", number(v)));
        }
        if let Some(v) = l.torque {
            parts.push(format!("torque {} N m", number(v)));
        }
        if let Some(v) = l.acceleration {
            parts.push(format!("acceleration {} rad/s^2", number(v)));
        }
        if !parts.is_empty() {
            let name = freefloat::model::excerpt(names.get(k).map(String::as_str).unwrap_or("-"));
            let _ = writeln!(s, "  limits {:<14}{}", format!("{} {name}", k + 1), parts.join(", "));
        }
    }
}

/// The table's lines of the bodies' shapes (docs/spec.md §1, issue 21), each in its body's
/// frame: `shapes  none` without any.
fn shape_lines(s: &mut String, arm: &Arm) {
    use std::fmt::Write;
    let g = &arm.geometry;
    if g.base.is_empty() && g.links.iter().all(Vec::is_empty) {
        let _ = writeln!(s, "  shapes               none (no collision checks)");
        return;
    }
    let describe = |shapes: &[freefloat::model::geometry::Shape]| -> String {
        let one = |sh: &freefloat::model::geometry::Shape| {
            let p = |q: [f64; 2]| format!("({}, {})", number(q[0]), number(q[1]));
            match sh.points.as_slice() {
                [c] => format!("circle r {} at {}", number(sh.radius), p(*c)),
                [a, b] => format!("capsule r {} {}-{}", number(sh.radius), p(*a), p(*b)),
                corners => {
                    let range = |i: usize| {
                        let (lo, hi) = corners
                            .iter()
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| (lo.min(c[i]), hi.max(c[i])));
                        format!("[{}, {}]", number(lo), number(hi))
                    };
                    let r = if sh.radius > 0.0 { format!(" r {}", number(sh.radius)) } else { String::new() };
                    format!("polygon of {} corners{r}, x in {}, y in {}", corners.len(), range(0), range(1))
                }
            }
        };
        if shapes.is_empty() { "none".into() } else { shapes.iter().map(one).collect::<Vec<_>>().join("; ") }
    };
    let _ = writeln!(s, "  shapes base          {} [m]", describe(&g.base));
    for k in 0..arm.joints() {
        let _ = writeln!(
            s,
            "  shapes link {k:<9}{} [m]",
            describe(g.links.get(k).map_or(&[][..], Vec::as_slice)),
            k = k + 1
        );
    }
}
