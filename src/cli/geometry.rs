//! The geometry flags of `plan`, `compare` and `track` (issue 21; docs/spec.md §3): `--obstacle SPEC`
//! (repeatable; circles, capsules, boxes and convex polygons in the inertial frame, m),
//! `--clearance M` (default 0) and `--no-collide A,B` (a pair not to check), added to the shapes
//! the robot file gives its bodies (§1).

use anyhow::Context;
use clap::Args;
use freefloat::model::arm::Arm;
use freefloat::model::arm::collision::{Body, Geometry};
use freefloat::model::geometry::Shape;
use freefloat::plan::clearance::ClearanceReport;
use freefloat::report::numbers::number;

use super::args::RobotArgs;

/// Obstacles, the clearance asked for and the pairs excluded.
#[derive(Debug, Args, Clone)]
pub struct GeometryArgs {
    /// An obstacle in the inertial frame (origin at the system's centre of mass), in metres:
    /// circle:X,Y,R, capsule:X1,Y1,X2,Y2,R, box:X,Y,W,H or polygon:X1,Y1,X2,Y2,X3,Y3[,...]
    /// (convex). Repeatable. Checked against every body with a shape.
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub obstacle: Vec<String>,
    /// The least distance in m between every pair of bodies checked (and each body and every
    /// obstacle) along the verified motion; a plan below it is not certified (exit 3), a track
    /// trial below it fails. 0 to 1000.
    #[arg(long, value_name = "M", default_value_t = 0.0, allow_hyphen_values = true)]
    pub clearance: f64,
    /// A pair of bodies not to check, e.g. base,link2 or link3,obstacle1. Repeatable.
    #[arg(long, value_name = "A,B")]
    pub no_collide: Vec<String>,
}

/// `geometry` (the robot file's shapes) with the flags' obstacles, clearance and exclusions,
/// checked for an arm of `n` links (exit 2 naming the flag).
pub fn with_flags(mut geometry: Geometry, flags: &GeometryArgs, n: usize) -> anyhow::Result<Geometry> {
    for text in &flags.obstacle {
        geometry.obstacles.push(Shape::from_spec("--obstacle", text).map_err(freefloat::Error::from)?);
    }
    for text in &flags.no_collide {
        let pair: Vec<&str> = text.split(',').collect();
        let [a, b] = pair[..] else {
            return Err(freefloat::Error::from(freefloat::model::InputError::InvalidText {
                name: "--no-collide".into(),
                text: text.clone(),
                expected: "two bodies A,B: base, linkK or obstacleK (K from 1)",
            })
            .into());
        };
        let body = |s: &str| s.parse::<Body>().map_err(freefloat::Error::from).context("--no-collide");
        geometry.excluded.push((body(a)?, body(b)?));
    }
    geometry.clearance = flags.clearance;
    geometry.validate(n).map_err(freefloat::Error::from)?;
    Ok(geometry)
}

/// `arm` with the flags' geometry, and the notes on it (see [`notes`]).
pub fn arm_with_flags(arm: &Arm, robot: &RobotArgs, flags: &GeometryArgs) -> anyhow::Result<(Arm, Vec<String>)> {
    let geometry = with_flags(arm.geometry.clone(), flags, arm.joints())?;
    let arm = arm.clone().with_geometry(geometry).map_err(freefloat::Error::from)?;
    let notes = notes(&arm.geometry, robot, flags)?;
    Ok((arm, notes))
}

/// The geometry of the 2-link robot of the flags: its robot file's shapes (the 2-link pipeline's
/// parameters carry none) with the flags', and the notes on it.
pub fn two_link(robot: &RobotArgs, flags: &GeometryArgs) -> anyhow::Result<(Geometry, Vec<String>)> {
    let file = match super::robot_file(robot)? {
        Some(path) => Arm::load(path)?.geometry,
        None => Geometry::default(),
    };
    let geometry = with_flags(file, flags, 2)?;
    let notes = notes(&geometry, robot, flags)?;
    Ok((geometry, notes))
}

/// What the reader must know about the geometry, each also printed on stderr as a note: the
/// URDF reader's (a `<visual>` used for a missing `<collision>`, a mesh skipped), and `--no-collide` where
/// no body has a shape.
fn notes(geometry: &Geometry, robot: &RobotArgs, flags: &GeometryArgs) -> anyhow::Result<Vec<String>> {
    let mut notes = Vec::new();
    if let Some(path) = super::robot_file(robot)?
        && path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
    {
        let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
        notes.extend(Arm::from_urdf_str_noted(&text, path)?.3);
    }
    // Obstacles and a clearance without shapes are refused ([`Geometry::validate`]); an
    // exclusion without them is harmless.
    if !flags.no_collide.is_empty() && geometry.is_empty() {
        notes.push(
            "--no-collide: the robot has no shapes (URDF <collision>, TOML `width`/`shape`), so nothing is checked"
                .into(),
        );
    }
    for note in &notes {
        super::note(&format!("note: {note}\n"));
    }
    Ok(notes)
}

/// The table's line on the clearance (none without shapes).
pub fn table_line(clearance: Option<&ClearanceReport>) -> String {
    let Some(c) = clearance else { return String::new() };
    format!(
        "  min clearance            {} m between {} and {} at t = {} s (required {} m)  {}\n",
        number(c.min),
        c.a,
        c.b,
        number(c.time),
        number(c.required),
        if c.holds() { "CLEAR" } else { "COLLIDES" }
    )
}
