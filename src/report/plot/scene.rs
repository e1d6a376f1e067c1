//! The robot's shapes, the obstacles and the moment of least clearance as the pictures draw them
//! (issue 21 item 7; docs/spec.md §3): what the GIF ([`super::GifView`]) and the report page's
//! animation (`page.js`, through [`crate::report::Animation`]) draw for an arm with shapes or
//! obstacles ([`crate::model::arm::collision::Geometry`]).
//!
//! Every shape is drawn by its outline: the convex hull of its points swept by its disc
//! ([`outline`]; a circle or a capsule's round ends by [`ARC_POINTS`] points per corner). A
//! body's outlines are in its own frame and move with it
//! ([`crate::model::arm::collision::body_poses`]); an obstacle's are in the inertial frame. The
//! least clearance of the verified motion ([`ClearanceReport`]) is marked by the pair's two
//! nearest points ([`nearest_points`]) at the instant drawn nearest its time, in
//! [`CLEAR_COLOUR`] when the clearance holds and in [`COLLISION_COLOUR`] when it does not.

use crate::model::arm::Arm;
use crate::model::arm::collision::{Body, Geometry, body_poses};
use crate::model::geometry::{Pose, Shape, convex_hull, signed_distance};
use crate::plan::clearance::ClearanceReport;

/// Points per corner of a rounded outline (a circle is drawn as a polygon of this many corners).
pub const ARC_POINTS: usize = 48;

/// The colour of the least-clearance marker when the clearance holds (purple, apart from the
/// links' colours).
pub const CLEAR_COLOUR: &str = "#7b3294";

/// The colour of the least-clearance marker when the motion comes closer than the clearance asked
/// for (a collision when that is 0): the red of a joint at its limit.
pub const COLLISION_COLOUR: &str = super::animation::AT_LIMIT_COLOUR;

/// The fill and edge of an obstacle.
pub const OBSTACLE_COLOUR: &str = "#5f5f5f";

/// A polygon's corners `(x, y)` \[m\], in order, the last not repeating the first.
pub type Outline = Vec<[f64; 2]>;

/// The outline of `shape` in its own frame \[m\]: the convex hull of its points swept by its disc
/// (counter-clockwise; a segment or a point when the shape has no radius and no area).
pub fn outline(shape: &Shape) -> Outline {
    if shape.radius <= 0.0 {
        return convex_hull(&shape.points);
    }
    let r = shape.radius;
    let around: Vec<[f64; 2]> = shape
        .points
        .iter()
        .flat_map(|p| {
            (0..ARC_POINTS).map(move |k| {
                let (s, c) = (std::f64::consts::TAU * k as f64 / ARC_POINTS as f64).sin_cos();
                [p[0] + r * c, p[1] + r * s]
            })
        })
        .collect();
    convex_hull(&around)
}

/// The points `points` \[m\] of a body's frame moved to the inertial frame by `pose`.
pub fn placed(points: &[[f64; 2]], pose: &Pose<f64>) -> Outline {
    let (s, c) = pose.angle.sin_cos();
    points.iter().map(|p| [pose.x + c * p[0] - s * p[1], pose.y + s * p[0] + c * p[1]]).collect()
}

/// The nearest points `[on a, on b]` \[m\] of the shapes `hull(a) + disc(ra)` and
/// `hull(b) + disc(rb)` (points already placed in one frame). Apart, they are the two points
/// whose distance is the signed distance; where the discs overlap they cross over by the depth;
/// where the hulls themselves overlap they are only indicative (a corner of one and the nearest
/// point of the other's boundary). `a` and `b` must not be empty (else the origin twice).
pub fn nearest_points(a: &[[f64; 2]], ra: f64, b: &[[f64; 2]], rb: f64) -> [[f64; 2]; 2] {
    let (ha, hb) = (convex_hull(a), convex_hull(b));
    let mut best = (f64::INFINITY, [0.0, 0.0], [0.0, 0.0]);
    // A corner of one hull against every edge of the other (a convex pair apart is nearest there).
    for (corners, edges, swap) in [(&ha, &hb, false), (&hb, &ha, true)] {
        for &p in corners.iter() {
            for (i, &e0) in edges.iter().enumerate() {
                let e1 = edges[(i + 1) % edges.len()];
                let x = nearest_on_segment(p, e0, e1);
                let d = (x[0] - p[0]).hypot(x[1] - p[1]);
                if d < best.0 {
                    best = if swap { (d, x, p) } else { (d, p, x) };
                }
            }
        }
    }
    let (d, pa, pb) = best;
    if !(d.is_finite() && d > 0.0) {
        return [pa, pb];
    }
    let u = [(pb[0] - pa[0]) / d, (pb[1] - pa[1]) / d];
    [[pa[0] + ra * u[0], pa[1] + ra * u[1]], [pb[0] - rb * u[0], pb[1] - rb * u[1]]]
}

/// The point of the segment `e0 e1` nearest to `p`.
fn nearest_on_segment(p: [f64; 2], e0: [f64; 2], e1: [f64; 2]) -> [f64; 2] {
    let d = [e1[0] - e0[0], e1[1] - e0[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 { (((p[0] - e0[0]) * d[0] + (p[1] - e0[1]) * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
    [e0[0] + t * d[0], e0[1] + t * d[1]]
}

/// What the pictures draw of an arm's geometry: each body's outlines in its own frame, the
/// obstacles' in the inertial frame, and the least clearance of the verified motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Per body, the outlines of its shapes in its frame \[m\]: the base first, then links
    /// `1..n` (empty for a body without shapes).
    pub bodies: Vec<Vec<Outline>>,
    /// The obstacles' shapes (inertial frame), in the order given (obstacle 1 first).
    pub obstacles: Vec<Shape>,
    /// The least clearance of the verified motion, when it was checked.
    pub least: Option<ClearanceReport>,
    geometry: Geometry,
}

impl Scene {
    /// The scene of `arm`'s geometry with the verified motion's least clearance `least`; `None`
    /// when no body has a shape and there is no obstacle (the pictures then draw as without
    /// geometry).
    pub fn new(arm: &Arm, least: Option<ClearanceReport>) -> Option<Self> {
        let g = &arm.geometry;
        if g.base.is_empty() && g.links.iter().all(Vec::is_empty) && g.obstacles.is_empty() {
            return None;
        }
        let mut bodies = vec![g.base.iter().map(outline).collect::<Vec<_>>()];
        bodies.extend((1..=arm.joints()).map(|k| g.shapes(Body::Link(k)).iter().map(outline).collect()));
        Some(Self { bodies, obstacles: g.obstacles.clone(), least, geometry: g.clone() })
    }

    /// The obstacles' outlines \[m\] (inertial frame).
    pub fn obstacle_outlines(&self) -> Vec<Outline> {
        self.obstacles.iter().map(outline).collect()
    }

    /// The bodies' outlines \[m\] in the inertial frame at `q = (phi, theta_1..theta_n)` \[rad\]:
    /// the base's first, then each link's.
    pub fn placed_bodies(&self, arm: &Arm, q: &[f64]) -> Vec<Vec<Outline>> {
        let poses = body_poses(arm, q);
        self.bodies.iter().zip(&poses).map(|(shapes, pose)| shapes.iter().map(|o| placed(o, pose)).collect()).collect()
    }

    /// The bounds `[x0, x1, y0, y1]` \[m\] of every outline at every configuration of `qs` and of
    /// the obstacles (`None` when there is nothing).
    pub fn bounds(&self, arm: &Arm, qs: &[Vec<f64>]) -> Option<[f64; 4]> {
        let mut b: Option<[f64; 4]> = None;
        let mut take = |p: &[f64; 2]| {
            let v = b.get_or_insert([p[0], p[0], p[1], p[1]]);
            *v = [v[0].min(p[0]), v[1].max(p[0]), v[2].min(p[1]), v[3].max(p[1])];
        };
        self.obstacle_outlines().iter().flatten().for_each(&mut take);
        for q in qs {
            self.placed_bodies(arm, q).iter().flatten().flatten().for_each(&mut take);
        }
        b
    }

    /// The least clearance's pair `[a, b]` and its nearest points at `q` (the configuration drawn
    /// at the marked instant) \[m\]; `None` without a least clearance or when a member has no shape.
    pub fn least_points(&self, arm: &Arm, q: &[f64]) -> Option<[[f64; 2]; 2]> {
        let least = self.least?;
        let poses = body_poses(arm, q);
        let origin = Pose { x: 0.0, y: 0.0, angle: 0.0 };
        let pose = |body: Body| match body {
            Body::Base => poses.first().copied(),
            Body::Link(k) => poses.get(k).copied(),
            Body::Obstacle(_) => Some(origin),
        };
        let (pa, pb) = (pose(least.a)?, pose(least.b)?);
        let mut best: Option<(f64, [[f64; 2]; 2])> = None;
        for sa in self.geometry.shapes(least.a) {
            let xa = sa.placed(&pa);
            for sb in self.geometry.shapes(least.b) {
                let xb = sb.placed(&pb);
                let d = signed_distance(&xa, sa.radius, &xb, sb.radius);
                if best.is_none_or(|(x, _)| d < x) {
                    best = Some((d, nearest_points(&xa, sa.radius, &xb, sb.radius)));
                }
            }
        }
        best.map(|(_, p)| p)
    }

    /// The colour of the least-clearance marker: [`COLLISION_COLOUR`] when the motion comes closer
    /// than the clearance asked for, else [`CLEAR_COLOUR`] (`None` without a least clearance).
    pub fn marker_colour(&self) -> Option<&'static str> {
        self.least.map(|c| if c.holds() { CLEAR_COLOUR } else { COLLISION_COLOUR })
    }

    /// The caption of the least clearance, e.g. `least clearance 12.3 mm, base / link 4, t =
    /// 6.11 s` (and `(required 20.0 mm)` when it does not hold); `None` without one.
    pub fn caption(&self) -> Option<String> {
        self.least.map(|c| least_caption(&c))
    }
}

/// The words of a least clearance (the GIF's, the figure's and the page's): the clearance in mm,
/// the pair, the time in s, and the clearance asked for when it does not hold.
pub fn least_caption(c: &ClearanceReport) -> String {
    let mut s = format!("least clearance {:.1} mm, {} / {}, t = {:.2} s", c.min * 1e3, c.a, c.b, c.time);
    if !c.holds() {
        s += &format!(" (required {:.1} mm)", c.required * 1e3);
    }
    s
}

/// Which of the instants `ts` \[s\] is nearest to `t` (the first of two as near; `None` when
/// `ts` is empty).
pub fn nearest_instant(ts: &[f64], t: f64) -> Option<usize> {
    (0..ts.len()).min_by(|&i, &j| (ts[i] - t).abs().total_cmp(&(ts[j] - t).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circles_outline_lies_on_the_circle() {
        let c = Shape::circle([0.3, -0.2], 0.1).expect("a circle");
        let o = outline(&c);
        assert_eq!(o.len(), ARC_POINTS);
        for p in &o {
            assert!(((p[0] - 0.3).hypot(p[1] + 0.2) - 0.1).abs() < 1e-12, "{p:?}");
        }
    }

    /// The nearest points of two shapes apart are as far apart as their signed distance says,
    /// each on its shape's boundary; a box's outline is its corners.
    #[test]
    fn nearest_points_are_the_signed_distance_apart() {
        let b = Shape::rectangle([0.0, 0.0], [0.5, 0.4]).expect("a box");
        assert_eq!(outline(&b).len(), 4);
        let c = Shape::capsule([0.6, 0.5], [1.0, 0.9], 0.05).expect("a capsule");
        let [pa, pb] = nearest_points(&b.points, 0.0, &c.points, c.radius);
        let d = signed_distance(&b.points, 0.0, &c.points, c.radius);
        assert!(((pb[0] - pa[0]).hypot(pb[1] - pa[1]) - d).abs() < 1e-12, "{pa:?} {pb:?} {d}");
        // The box's corner (0.25, 0.2) is nearest; the capsule's point 5 cm from its end towards it.
        assert!((pa[0] - 0.25).abs() < 1e-12 && (pa[1] - 0.2).abs() < 1e-12, "{pa:?}");
        let end = (0.6f64 - 0.25).hypot(0.3);
        assert!(((pb[0] - 0.6).hypot(pb[1] - 0.5) - 0.05).abs() < 1e-12 && d > 0.0 && (d - (end - 0.05)).abs() < 1e-12);
    }

    #[test]
    fn the_nearest_instant() {
        assert_eq!(nearest_instant(&[0.0, 1.0, 2.0], 1.4), Some(1));
        assert_eq!(nearest_instant(&[0.0, 1.0, 2.0], 9.0), Some(2));
        assert_eq!(nearest_instant(&[], 1.0), None);
    }
}
