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
    let _ = writeln!(
        s,
        "  planning             {}",
        if arm.as_src().is_some() {
            "2 links: every method and command"
        } else {
            "plan (optimal, ecsa) with --from/--to of n + 1 angles"
        }
    );
    s
}
