//! The bodies' shapes as the robot files give them (issue 21; docs/spec.md §1): a URDF's
//! `<collision>` (else `<visual>`) geometry projected to the plane of motion, and the TOML robot
//! file's `width` and `shape` keys. The shapes land in [`Geometry`], each in its body's frame
//! ([`super::collision`]: the base's at its centre of mass, link `k`'s at joint `k` with `x` along
//! the link).
//!
//! **Projection of a URDF element** placed at `origin` (`xyz`, `rpy`: `R = Rz(yaw) Ry(pitch)
//! Rx(roll)`) in its link's frame, the link itself at `at` in the body's frame (fixed joints have
//! `rpy = 0`, so the offset is a translation):
//! - `<sphere>`: the circle of its radius about the origin's `(x, y)`;
//! - `<box>`: the convex hull of its eight corners projected to `(x, y)` (for `roll = pitch = 0`
//!   the rectangle of its `x, y` size turned by `yaw`);
//! - `<cylinder>`: by its axis `R z`: along `z` the circle of its radius; in the plane the
//!   rectangle `length x 2 radius` along the axis; tilted, the capsule of the projected axis and
//!   its radius (which contains the true footprint; a note says so);
//! - `<capsule>` (URDF 1.2 / urdf-rs): the projected axis swept by its radius (exact);
//! - `<mesh>`: skipped, with a note (freefloat reads no mesh files).

use super::collision::Geometry;
use crate::model::InputError;
use crate::model::geometry::{MAX_EXTENT, Shape, convex_hull};

/// Off-plane tolerance of a projected axis (unit vector components).
const AXIS_TOLERANCE: f64 = 1e-9;

/// The shapes of one rigid body of a URDF: `parts` are its links with their places `at` in the
/// body's frame \[m\]; `name` names the body. The `<collision>` elements of every part; when the
/// body has none, its `<visual>` elements, and its name joins `visual_bodies` (one note names
/// them all, [`visual_note`]). Errors are the reason and the link that gives it.
pub(super) fn urdf_body_shapes(
    parts: &[(&urdf_rs::Link, [f64; 2])],
    name: &str,
    notes: &mut Vec<String>,
    visual_bodies: &mut Vec<String>,
) -> Result<Vec<Shape>, (String, String)> {
    let collisions = parts.iter().any(|(l, _)| !l.collision.is_empty());
    let visuals = parts.iter().any(|(l, _)| !l.visual.is_empty());
    if !collisions && visuals {
        visual_bodies.push(format!("`{name}`"));
    }
    let mut shapes = Vec::new();
    for (link, at) in parts {
        let elements: Vec<(&urdf_rs::Geometry, &urdf_rs::Pose)> = if collisions {
            link.collision.iter().map(|c| (&c.geometry, &c.origin)).collect()
        } else {
            link.visual.iter().map(|v| (&v.geometry, &v.origin)).collect()
        };
        for (geometry, origin) in elements {
            match project(geometry, origin, *at) {
                Ok((shape, note)) => {
                    if let Some(note) = note {
                        notes.push(format!("link `{}`: {note}", crate::model::excerpt(&link.name)));
                    }
                    shapes.extend(shape);
                }
                Err(reason) => return Err((link.name.clone(), reason)),
            }
        }
    }
    Ok(shapes)
}

/// The one note on the bodies whose `<visual>` geometry stands in for a missing `<collision>`
/// (`None` when there are none).
pub(super) fn visual_note(visual_bodies: &[String]) -> Option<String> {
    match visual_bodies {
        [] => None,
        [one] => Some(format!("body {one} has no <collision>: its <visual> geometry is used for collisions")),
        many => Some(format!(
            "bodies {} have no <collision>: their <visual> geometry is used for collisions",
            many.join(", ")
        )),
    }
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)` applied to `v`.
fn rotate([roll, pitch, yaw]: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    let x = [v[0], cr * v[1] - sr * v[2], sr * v[1] + cr * v[2]];
    let y = [cp * x[0] + sp * x[2], x[1], -sp * x[0] + cp * x[2]];
    [cy * y[0] - sy * y[1], sy * y[0] + cy * y[1], y[2]]
}

fn positive(what: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() && value > 0.0 && value <= MAX_EXTENT {
        Ok(value)
    } else {
        Err(format!("{what} {value}: expected a finite value > 0 and at most 1e3 m"))
    }
}

/// One element's planar shape (module docs) and a note; `None` for a mesh.
fn project(
    geometry: &urdf_rs::Geometry,
    origin: &urdf_rs::Pose,
    at: [f64; 2],
) -> Result<(Option<Shape>, Option<String>), String> {
    let rpy = *origin.rpy;
    let xyz = *origin.xyz;
    if rpy.iter().chain(&xyz).any(|v| !v.is_finite()) {
        return Err("geometry origin not finite".into());
    }
    let c = [at[0] + xyz[0], at[1] + xyz[1]];
    let place = |v: [f64; 3]| {
        let r = rotate(rpy, v);
        [c[0] + r[0], c[1] + r[1]]
    };
    let shape_error = |e: InputError| format!("its planar shape is not valid: {e}");
    let axis = rotate(rpy, [0.0, 0.0, 1.0]);
    let in_plane = (axis[0] * axis[0] + axis[1] * axis[1]).sqrt();
    let (shape, note) = match geometry {
        urdf_rs::Geometry::Sphere { radius } => (Shape::circle(c, positive("sphere radius", *radius)?), None),
        urdf_rs::Geometry::Box { size } => {
            let size = **size;
            if size.iter().any(|s| !(s.is_finite() && *s >= 0.0 && *s <= MAX_EXTENT)) {
                return Err(format!(
                    "box size ({}, {}, {}): expected finite sides from 0 to 1e3 m",
                    size[0], size[1], size[2]
                ));
            }
            let h = size.map(|s| s / 2.0);
            let mut corners = Vec::with_capacity(8);
            for sx in [-1.0, 1.0] {
                for sy in [-1.0, 1.0] {
                    for sz in [-1.0, 1.0] {
                        corners.push(place([sx * h[0], sy * h[1], sz * h[2]]));
                    }
                }
            }
            (Shape::new(convex_hull(&corners), 0.0), None)
        }
        urdf_rs::Geometry::Cylinder { radius, length } => {
            let (r, l) = (positive("cylinder radius", *radius)?, positive("cylinder length", *length)?);
            if in_plane <= AXIS_TOLERANCE {
                (Shape::circle(c, r), None)
            } else if axis[2].abs() <= AXIS_TOLERANCE {
                let u = [axis[0] / in_plane, axis[1] / in_plane];
                let n = [-u[1], u[0]];
                let corner = |a: f64, b: f64| {
                    [c[0] + a * l / 2.0 * u[0] + b * r * n[0], c[1] + a * l / 2.0 * u[1] + b * r * n[1]]
                };
                (
                    Shape::new(vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)], 0.0),
                    None,
                )
            } else {
                let half = [axis[0] * l / 2.0, axis[1] * l / 2.0];
                let shape = Shape::capsule([c[0] - half[0], c[1] - half[1]], [c[0] + half[0], c[1] + half[1]], r);
                (shape, Some("a cylinder tilted out of the plane: its footprint is bounded by a capsule".to_string()))
            }
        }
        urdf_rs::Geometry::Capsule { radius, length } => {
            let (r, l) = (positive("capsule radius", *radius)?, positive("capsule length", *length)?);
            let half = [axis[0] * l / 2.0, axis[1] * l / 2.0];
            if in_plane <= AXIS_TOLERANCE {
                (Shape::circle(c, r), None)
            } else {
                (Shape::capsule([c[0] - half[0], c[1] - half[1]], [c[0] + half[0], c[1] + half[1]], r), None)
            }
        }
        urdf_rs::Geometry::Mesh { filename, .. } => {
            let note = format!("mesh `{}` skipped (freefloat reads no mesh files)", crate::model::excerpt(filename));
            return Ok((None, Some(note)));
        }
    };
    Ok((Some(shape.map_err(shape_error)?), note))
}

/// A `shape` key of the TOML robot file: one shape text or a list of them.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(untagged)]
pub(super) enum ShapeText {
    /// `shape = "circle:0.2,0,0.05"`.
    One(String),
    /// `shape = ["circle:..", "box:.."]`.
    Many(Vec<String>),
}

impl ShapeText {
    /// The shapes, each by [`Shape::from_spec`] under the key `name`.
    fn shapes(&self, name: &str) -> Result<Vec<Shape>, InputError> {
        let texts = match self {
            ShapeText::One(t) => std::slice::from_ref(t),
            ShapeText::Many(v) => v.as_slice(),
        };
        texts.iter().map(|t| Shape::from_spec(name, t)).collect()
    }
}

/// The geometry of a TOML robot file: the base's `shape`, and per link (`width`, `shape`,
/// `length`): a link of `width = W` is the capsule from joint to joint of radius `W / 2`, and its
/// `shape` texts are added (link frame, [`Shape::from_spec`] syntax).
pub(super) fn toml_geometry(
    base: Option<&ShapeText>,
    links: &[(Option<f64>, Option<&ShapeText>, f64)],
) -> Result<Geometry, InputError> {
    let mut geometry = Geometry::default();
    if let Some(text) = base {
        geometry.base = text.shapes("robot.shape")?;
    }
    let mut any = false;
    let mut per_link = Vec::with_capacity(links.len());
    for (k, (width, text, length)) in links.iter().enumerate() {
        let mut shapes = Vec::new();
        if let Some(w) = *width {
            if !(w.is_finite() && w > 0.0 && w <= MAX_EXTENT) {
                return Err(InputError::InvalidParameter {
                    name: format!("link[{}].width", k + 1),
                    value: w,
                    expected: "a link width > 0 and at most 1e3 m (a capsule along the link, radius width / 2)",
                });
            }
            shapes.push(Shape::capsule([0.0, 0.0], [*length, 0.0], w / 2.0)?);
        }
        if let Some(text) = text {
            shapes.extend(text.shapes(&format!("link[{}].shape", k + 1))?);
        }
        any |= !shapes.is_empty();
        per_link.push(shapes);
    }
    if any {
        geometry.links = per_link;
    }
    Ok(geometry)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(xyz: [f64; 3], rpy: [f64; 3]) -> urdf_rs::Pose {
        urdf_rs::Pose { xyz: urdf_rs::Vec3(xyz), rpy: urdf_rs::Vec3(rpy) }
    }

    fn close(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
        a.len() == b.len()
            && a.iter().all(|p| b.iter().any(|q| (p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12))
    }

    #[test]
    fn each_urdf_solid_projects_to_its_footprint() {
        let at = [0.5, 0.0];
        // A sphere at (0.1, 0.2, 0.3) of the link placed 0.5 m along the body: a circle.
        let (s, _) =
            project(&urdf_rs::Geometry::Sphere { radius: 0.03 }, &pose([0.1, 0.2, 0.3], [0.0; 3]), at).unwrap();
        let s = s.unwrap();
        assert!(close(&s.points, &[[0.6, 0.2]]) && (s.radius - 0.03).abs() < 1e-15);
        // A box turned by yaw = 90 deg: its x size runs along y.
        let b = urdf_rs::Geometry::Box { size: urdf_rs::Vec3([0.4, 0.1, 0.2]) };
        let (s, _) = project(&b, &pose([0.0; 3], [0.0, 0.0, std::f64::consts::FRAC_PI_2]), at).unwrap();
        assert!(close(&s.unwrap().points, &[[0.45, -0.2], [0.55, -0.2], [0.55, 0.2], [0.45, 0.2]]));
        // A cylinder along z: a circle; turned by pitch = 90 deg its axis is x: a 0.5 x 0.1 rectangle.
        let c = urdf_rs::Geometry::Cylinder { radius: 0.05, length: 0.5 };
        let (s, _) = project(&c, &pose([0.25, 0.0, 0.0], [0.0; 3]), [0.0, 0.0]).unwrap();
        let s = s.unwrap();
        assert!(close(&s.points, &[[0.25, 0.0]]) && (s.radius - 0.05).abs() < 1e-15);
        let (s, note) =
            project(&c, &pose([0.25, 0.0, 0.0], [0.0, std::f64::consts::FRAC_PI_2, 0.0]), [0.0, 0.0]).unwrap();
        let s = s.unwrap();
        assert!(close(&s.points, &[[0.0, -0.05], [0.5, -0.05], [0.5, 0.05], [0.0, 0.05]]) && s.radius == 0.0, "{s:?}");
        assert!(note.is_none());
        // Tilted by 45 deg: a capsule of the projected axis, with a note.
        let (s, note) = project(&c, &pose([0.0; 3], [0.0, std::f64::consts::FRAC_PI_4, 0.0]), [0.0, 0.0]).unwrap();
        let h = 0.25 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(close(&s.unwrap().points, &[[-h, 0.0], [h, 0.0]]) && note.is_some());
        // A mesh: nothing, with a note.
        let m = urdf_rs::Geometry::Mesh { filename: "base.stl".into(), scale: None };
        let (s, note) = project(&m, &pose([0.0; 3], [0.0; 3]), at).unwrap();
        assert!(s.is_none() && note.unwrap().contains("base.stl"));
        // Bad numbers are refused with the reason.
        assert!(project(&urdf_rs::Geometry::Sphere { radius: -1.0 }, &pose([0.0; 3], [0.0; 3]), at).is_err());
        let nan = urdf_rs::Geometry::Box { size: urdf_rs::Vec3([f64::NAN, 0.1, 0.1]) };
        assert!(project(&nan, &pose([0.0; 3], [0.0; 3]), at).is_err());
    }

    #[test]
    fn toml_width_is_a_capsule_along_the_link_and_shapes_add_to_it() {
        let text = ShapeText::Many(vec!["circle:0.1,0,0.05".into()]);
        let g = toml_geometry(None, &[(Some(0.08), None, 0.5), (None, Some(&text), 0.4)]).unwrap();
        assert_eq!(g.links[0], vec![Shape::capsule([0.0, 0.0], [0.5, 0.0], 0.04).unwrap()]);
        assert_eq!(g.links[1], vec![Shape::circle([0.1, 0.0], 0.05).unwrap()]);
        let e = toml_geometry(None, &[(Some(-1.0), None, 0.5)]).unwrap_err();
        assert!(e.to_string().contains("link[1].width"), "{e}");
        let bad = ShapeText::One("circle:0,0".into());
        let e = toml_geometry(Some(&bad), &[(None, None, 0.5)]).unwrap_err();
        assert!(e.to_string().contains("robot.shape"), "{e}");
        assert!(toml_geometry(None, &[(None, None, 0.5)]).unwrap().is_unset());
    }
}
