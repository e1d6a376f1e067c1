//! The shapes of an arm's bodies, the obstacles around it, and the clearance between them
//! (issue 21; docs/spec.md §1).
//!
//! Each body carries convex [`Shape`]s in its own frame: the base's frame has its origin at the
//! base's centre of mass and its x axis at the angle `phi`; link `k`'s frame has its origin at
//! joint `k` and its x axis along the link (at `psi_k = phi + theta_1 + .. + theta_k`), so a link
//! of length `l` and width `w` is the capsule from `(0, 0)` to `(l, 0)` of radius `w / 2`.
//! Obstacles are shapes in the inertial frame, whose origin is the system's centre of mass (it
//! does not move at zero momentum, so a wall or a client satellite stays put there).
//!
//! The pairs checked ([`Geometry::pairs`]): every two bodies that are not joined (the base and
//! links `2..n`, link `k` and links `k + 2..n`), and every body against every obstacle, less the
//! pairs a user excludes.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::Arm;
use crate::Scalar;
use crate::model::InputError;
use crate::model::geometry::{Pose, Shape, signed_distance};

mod placement;
pub use placement::Placement;

/// One body of the robot, or an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Body {
    /// The base.
    Base,
    /// Link `k`, counted from 1 (it turns with joint `k`).
    Link(usize),
    /// Obstacle `k`, counted from 1 in the order given.
    Obstacle(usize),
}

impl fmt::Display for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Body::Base => write!(f, "base"),
            Body::Link(k) => write!(f, "link {k}"),
            Body::Obstacle(k) => write!(f, "obstacle {k}"),
        }
    }
}

/// The shapes of the robot's bodies (each in its own frame, module docs) and the obstacles (in
/// the inertial frame). Empty by default: a robot without shapes is never checked.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    /// The base's shapes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub base: Vec<Shape>,
    /// Each link's shapes, link 1 first (empty or one entry per link).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub links: Vec<Vec<Shape>>,
    /// Obstacles in the inertial frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<Shape>,
    /// Pairs not to check, e.g. a link that may brush the base by design.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub excluded: Vec<(Body, Body)>,
    /// The least signed distance a certified plan keeps between every pair checked \[m\]
    /// (`--clearance`; default 0: touching is the limit). It lives beside the shapes so that every
    /// certificate that sees the arm sees what it must hold.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub clearance: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl std::str::FromStr for Body {
    type Err = InputError;

    /// `base`, `linkK` or `obstacleK` (`K` from 1; a space before `K` is accepted, as [`Body`]
    /// prints it).
    fn from_str(text: &str) -> Result<Self, InputError> {
        let t = text.trim().to_ascii_lowercase();
        let number = |rest: &str| rest.trim().parse::<usize>().ok().filter(|&k| k >= 1);
        let body = match t.as_str() {
            "base" => Some(Body::Base),
            _ => match (t.strip_prefix("link"), t.strip_prefix("obstacle")) {
                (Some(k), _) => number(k).map(Body::Link),
                (_, Some(k)) => number(k).map(Body::Obstacle),
                _ => None,
            },
        };
        body.ok_or_else(|| InputError::InvalidText {
            name: "body".into(),
            text: text.into(),
            expected: "a body: base, linkK or obstacleK (K counted from 1)",
        })
    }
}

/// The clearance of one pair at one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairClearance<D> {
    /// The first body.
    pub a: Body,
    /// The second body (or obstacle).
    pub b: Body,
    /// Their signed distance \[m\] (negative: the penetration depth).
    pub distance: D,
}

impl Geometry {
    /// True when nothing is to be checked.
    pub fn is_empty(&self) -> bool {
        self.base.is_empty() && self.links.iter().all(Vec::is_empty)
    }

    /// Checks the geometry for an arm of `n` links: no link shapes or one list per link; every
    /// shape as [`Shape::new`] checks it (finite points within 1e3 m, a radius in `[0, 1e3]` m);
    /// every excluded body of the arm or an obstacle given; the clearance finite in `[0, 1e3]` m;
    /// no obstacles and no clearance above 0 without a shape on a body
    /// ([`InputError::NothingToCheck`]: they would check nothing).
    /// Errors name the key: `geometry.link[k].shape[j]`, `geometry.base.shape[j]`,
    /// `geometry.obstacle[k]`, `--no-collide`, `--clearance`.
    pub fn validate(&self, n: usize) -> Result<(), InputError> {
        let bad =
            |name: String, value: f64, expected: &'static str| InputError::InvalidParameter { name, value, expected };
        if !self.links.is_empty() && self.links.len() != n {
            return Err(bad("geometry.link".into(), self.links.len() as f64, "one list of shapes per link of the arm"));
        }
        let check = |key: String, shape: &Shape| {
            Shape::new(shape.points.clone(), shape.radius).map(|_| ()).map_err(|e| match e {
                InputError::InvalidParameter { name, value, expected } => {
                    bad(format!("{key} {}", name.trim_start_matches("shape.")), value, expected)
                }
                other => other,
            })
        };
        for (j, s) in self.base.iter().enumerate() {
            check(format!("geometry.base.shape[{}]", j + 1), s)?;
        }
        for (k, shapes) in self.links.iter().enumerate() {
            for (j, s) in shapes.iter().enumerate() {
                check(format!("geometry.link[{}].shape[{}]", k + 1, j + 1), s)?;
            }
        }
        for (k, s) in self.obstacles.iter().enumerate() {
            check(format!("geometry.obstacle[{}]", k + 1), s)?;
        }
        for &(a, b) in &self.excluded {
            if a == b {
                return Err(InputError::InvalidText {
                    name: "--no-collide".into(),
                    text: format!("{a},{b}"),
                    expected: "two different bodies (a body is never checked against itself)",
                });
            }
            for body in [a, b] {
                let known = match body {
                    Body::Base => true,
                    Body::Link(k) => (1..=n).contains(&k),
                    Body::Obstacle(k) => (1..=self.obstacles.len()).contains(&k),
                };
                if !known {
                    return Err(InputError::InvalidText {
                        name: "--no-collide".into(),
                        text: format!("{body}: the arm has {n} links, {} obstacle(s) given", self.obstacles.len()),
                        expected: "a body of the arm (base, link1..linkN) or an obstacle given (obstacle1..obstacleM)",
                    });
                }
            }
        }
        if !(self.clearance.is_finite() && (0.0..=crate::model::geometry::MAX_EXTENT).contains(&self.clearance)) {
            return Err(bad("--clearance".into(), self.clearance, "a clearance from 0 to 1e3 m"));
        }
        if self.is_empty() && (!self.obstacles.is_empty() || self.clearance > 0.0) {
            return Err(InputError::NothingToCheck { obstacles: self.obstacles.len(), clearance: self.clearance });
        }
        Ok(())
    }

    /// True when nothing at all is set: no shapes, obstacles, exclusions or clearance (the arm
    /// then serialises without a `geometry` key).
    pub fn is_unset(&self) -> bool {
        *self == Self::default()
    }

    /// The shapes of `body` (none for a body without shapes; an obstacle's one shape).
    pub fn shapes(&self, body: Body) -> &[Shape] {
        match body {
            Body::Base => &self.base,
            Body::Link(k) => self.links.get(k.wrapping_sub(1)).map_or(&[], Vec::as_slice),
            Body::Obstacle(k) => self.obstacles.get(k.wrapping_sub(1)).map(std::slice::from_ref).unwrap_or(&[]),
        }
    }

    /// The pairs checked for an arm of `n` links (module docs), both members with shapes, the
    /// excluded pairs (either order) left out.
    pub fn pairs(&self, n: usize) -> Vec<(Body, Body)> {
        let mut bodies = vec![Body::Base];
        bodies.extend((1..=n).map(Body::Link));
        let joined = |a: Body, b: Body| match (a, b) {
            (Body::Base, Body::Link(1)) => true,
            (Body::Link(i), Body::Link(j)) => i.abs_diff(j) == 1,
            _ => false,
        };
        let mut out = Vec::new();
        for (i, &a) in bodies.iter().enumerate() {
            for &b in &bodies[i + 1..] {
                if !joined(a, b) {
                    out.push((a, b));
                }
            }
            out.extend((1..=self.obstacles.len()).map(|k| (a, Body::Obstacle(k))));
        }
        out.retain(|&(a, b)| {
            !self.shapes(a).is_empty()
                && !self.shapes(b).is_empty()
                && !self.excluded.iter().any(|&(x, y)| (x, y) == (a, b) || (y, x) == (a, b))
        });
        out
    }

    /// A bound on the distance from the system's centre of mass (the inertial origin) of every
    /// point of `body`'s shapes, over every configuration \[m\] (infinite for an obstacle). The
    /// centre of mass stays at the origin, `M r_0 + sum_k m_k c_k = 0` with `M` the total mass,
    /// so the base's centre `r_0` is within `sum_k m_k |c_k - r_0| / M` of it, where
    /// `|c_k - r_0| <= |mount| + l_1 + .. + l_(k-1) + |com_k|`; joint `k` (link `k`'s frame) is
    /// within `|mount| + l_1 + .. + l_(k-1)` of `r_0`; a shape's points are within their largest
    /// distance from their frame's origin plus the shape's radius.
    pub fn reach(&self, arm: &Arm, body: Body) -> f64 {
        let mount = arm.mount.a.hypot(arm.mount.b);
        let joint = |k: usize| mount + arm.links[..k - 1].iter().map(|l| l.length).sum::<f64>();
        let moments = arm.links.iter().enumerate().map(|(i, l)| l.mass * (joint(i + 1) + l.com.abs()));
        let base = moments.sum::<f64>() / arm.total_mass();
        let origin = match body {
            Body::Base => base,
            Body::Link(k) => base + joint(k),
            Body::Obstacle(_) => return f64::INFINITY,
        };
        let extent = |s: &Shape| s.points.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max) + s.radius;
        origin + self.shapes(body).iter().map(extent).fold(0.0, f64::max)
    }

    /// The pairs of [`Geometry::pairs`] that can come within `keep` \[m\] of each other: a body
    /// and an obstacle farther from the system's centre of mass than the body's [`Self::reach`]
    /// plus `keep` never do, in any configuration (the distance from a point within `R` of the
    /// origin to a set at distance `d` from it is at least `d - R`), and are left out.
    pub fn pairs_within(&self, arm: &Arm, keep: f64) -> Vec<(Body, Body)> {
        let origin = [[0.0, 0.0]];
        let mut pairs = self.pairs(arm.joints());
        pairs.retain(|&(a, b)| match b {
            Body::Obstacle(_) => {
                let away = self.shapes(b).iter().map(|s| signed_distance(&origin, 0.0, &s.points, s.radius));
                away.fold(f64::INFINITY, f64::min) - self.reach(arm, a) <= keep
            }
            _ => true,
        });
        pairs
    }

    /// The signed distance of every pair of [`Geometry::pairs`] at `q = (phi, theta_1..theta_n)`,
    /// generic over [`Scalar`] so that dual numbers give the exact derivatives in `q`. A body
    /// of several shapes is their union: its distance to another is the least over its shapes.
    pub fn clearances<D: Scalar>(&self, arm: &Arm, q: &[D]) -> Vec<PairClearance<D>> {
        self.clearances_of(arm, q, &self.pairs(arm.joints()))
    }

    /// [`Geometry::clearances`] of the pairs `pairs` only (some of [`Geometry::pairs`], in their
    /// order), for a caller that evaluates them at many `q`: the pairs found once.
    pub fn clearances_of<D: Scalar>(&self, arm: &Arm, q: &[D], pairs: &[(Body, Body)]) -> Vec<PairClearance<D>> {
        let mut out = Vec::with_capacity(pairs.len());
        self.clearances_into(arm, q, pairs, &mut Placement::default(), &mut out);
        out
    }

    /// The least clearance at `q` and its pair; `None` when no pair is checked.
    pub fn min_clearance(&self, arm: &Arm, q: &[f64]) -> Option<PairClearance<f64>> {
        self.clearances(arm, q).into_iter().min_by(|x, y| x.distance.total_cmp(&y.distance))
    }
}

/// The frames of the bodies at `q`, in the inertial frame (origin at the system's centre of
/// mass): the base's (at its centre of mass, angle `phi`), then link `k`'s (at joint `k`, angle
/// `psi_k`), `n + 1` poses. The joints are placed as in [`Arm::joint_positions`].
pub fn body_poses<D: Scalar>(arm: &Arm, q: &[D]) -> Vec<Pose<D>> {
    let base = arm.base_position(q);
    let (sp, cp) = q[0].sin_cos();
    let (a, b) = (arm.mount.a, arm.mount.b);
    let mut joint = [base[0] + cp * a - sp * b, base[1] + sp * a + cp * b];
    let mut poses = Vec::with_capacity(arm.joints() + 1);
    poses.push(Pose { x: base[0], y: base[1], angle: q[0] });
    let mut psi = q[0];
    for (link, &theta) in arm.links.iter().zip(&q[1..]) {
        psi += theta;
        poses.push(Pose { x: joint[0], y: joint[1], angle: psi });
        let (s, c) = psi.sin_cos();
        joint = [joint[0] + c * link.length, joint[1] + s * link.length];
    }
    poses
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mount;
    use crate::model::arm::{Base, Link};

    fn arm(n: usize) -> Arm {
        let link = Link { length: 0.5, com: 0.25, mass: 2.0, inertia: 2.0 * 0.25 / 12.0 };
        Arm::new(Base { mass: 20.0, inertia: 1.0 }, Mount::new(0.25, 0.0).unwrap(), vec![link; n]).unwrap()
    }

    fn capsules(n: usize) -> Geometry {
        Geometry {
            base: vec![Shape::rectangle([0.0, 0.0], [0.5, 0.5]).unwrap()],
            links: (0..n).map(|_| vec![Shape::capsule([0.0, 0.0], [0.5, 0.0], 0.04).unwrap()]).collect(),
            ..Default::default()
        }
    }

    /// [`Geometry::reach`] bounds every placed point of every body over random arms (masses,
    /// lengths, centres of mass, mounts) and configurations; an obstacle that
    /// [`Geometry::pairs_within`] leaves out is farther than `keep` from its body in every one.
    #[test]
    fn the_reach_bounds_every_body_and_the_pairs_left_out_never_come_near() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = |lo: f64, hi: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut left_out = 0;
        for _ in 0..40 {
            let n = 1 + (uniform(0.0, 4.0) as usize).min(3);
            let links: Vec<Link> = (0..n)
                .map(|_| {
                    let length = uniform(0.1, 1.0);
                    Link { length, com: uniform(0.0, 1.0) * length, mass: uniform(0.1, 10.0), inertia: 0.1 }
                })
                .collect();
            let mount = Mount::new(uniform(-0.5, 0.5), uniform(-0.5, 0.5)).unwrap();
            let arm = Arm::new(Base { mass: uniform(1.0, 50.0), inertia: 1.0 }, mount, links).unwrap();
            let mut geometry = capsules(n);
            geometry.base.push(Shape::circle([uniform(-0.3, 0.3), uniform(-0.3, 0.3)], 0.05).unwrap());
            let obstacles = (0..6).map(|_| [uniform(-4.0, 4.0), uniform(-4.0, 4.0), uniform(0.05, 0.5)]);
            geometry.obstacles = obstacles.map(|[x, y, r]| Shape::circle([x, y], r).unwrap()).collect();
            let keep = 0.05;
            let kept = geometry.pairs_within(&arm, keep);
            let all = geometry.pairs(n);
            left_out += all.len() - kept.len();
            for _ in 0..200 {
                let q: Vec<f64> = (0..=n).map(|_| uniform(-7.0, 7.0)).collect();
                let poses = body_poses(&arm, &q);
                for (k, pose) in poses.iter().enumerate() {
                    let body = if k == 0 { Body::Base } else { Body::Link(k) };
                    for shape in geometry.shapes(body) {
                        for p in shape.placed(pose) {
                            let far = p[0].hypot(p[1]) + shape.radius;
                            assert!(far <= geometry.reach(&arm, body) + 1e-12, "{body}: {far}");
                        }
                    }
                }
                for (pair, c) in all.iter().zip(geometry.clearances_of(&arm, &q, &all)) {
                    assert!(kept.contains(pair) || c.distance > keep, "{pair:?} at {}", c.distance);
                }
            }
        }
        assert!(left_out > 20, "some obstacles are out of reach: {left_out}");
    }

    #[test]
    fn the_pairs_are_the_bodies_not_joined_and_the_obstacles() {
        let mut g = capsules(4);
        g.obstacles.push(Shape::circle([2.0, 0.0], 0.3).unwrap());
        let pairs = g.pairs(4);
        use Body::*;
        for p in [(Base, Link(2)), (Base, Link(4)), (Link(1), Link(3)), (Link(2), Link(4)), (Link(3), Obstacle(1))] {
            assert!(pairs.contains(&p), "{p:?} checked");
        }
        for p in [(Base, Link(1)), (Link(1), Link(2)), (Link(3), Link(4))] {
            assert!(!pairs.contains(&p), "{p:?} joined");
        }
        // 3 + 2 + 1 unjoined pairs of bodies (base-2, base-3, base-4, 1-3, 1-4, 2-4) and 5 bodies
        // against one obstacle.
        assert_eq!(pairs.len(), 6 + 5);
        g.excluded.push((Link(4), Base));
        assert!(!g.pairs(4).contains(&(Base, Link(4))), "an exclusion in either order");
    }

    #[test]
    fn obstacles_or_a_clearance_without_shapes_are_refused() {
        let obstacle = || vec![Shape::circle([2.0, 0.0], 0.3).unwrap()];
        let bare = [
            Geometry { obstacles: obstacle(), ..Default::default() },
            Geometry { clearance: 0.01, ..Default::default() },
            Geometry { links: vec![vec![]; 3], obstacles: obstacle(), clearance: 0.01, ..Default::default() },
        ];
        for g in bare {
            assert!(matches!(g.validate(3), Err(InputError::NothingToCheck { .. })), "{g:?}");
        }
        // A shape on any body, or only exclusions: accepted.
        let base_only =
            Geometry { base: capsules(3).base, obstacles: obstacle(), clearance: 0.01, ..Default::default() };
        base_only.validate(3).unwrap();
        Geometry { excluded: vec![(Body::Base, Body::Link(2))], ..Default::default() }.validate(3).unwrap();
    }

    #[test]
    fn link_frames_follow_the_joints() {
        let arm = arm(3);
        let q = [0.3, 0.4, -1.1, 0.7];
        let poses = body_poses(&arm, &q);
        let joints = arm.joint_positions(&q);
        for k in 1..=3 {
            assert!((poses[k].x - joints[k][0]).abs() < 1e-15 && (poses[k].y - joints[k][1]).abs() < 1e-15);
        }
        // A link's capsule axis ends at the next joint.
        let tip = Shape::circle([0.5, 0.0], 1e-3).unwrap().placed(&poses[3]);
        assert!((tip[0][0] - joints[4][0]).abs() < 1e-15 && (tip[0][1] - joints[4][1]).abs() < 1e-15);
    }

    #[test]
    fn a_link_folded_onto_the_base_collides_and_a_stretched_arm_does_not() {
        let (arm, g) = (arm(2), capsules(2));
        // Stretched out along +x: link 2 is 0.5 m beyond the base's edge at 0.25.
        let apart = g.min_clearance(&arm, &[0.0, 0.0, 0.0]).unwrap();
        assert!(apart.distance > 0.4, "{apart:?}");
        // Link 2 folded straight back over link 1 and into the base.
        let folded = g.min_clearance(&arm, &[0.0, 0.0, std::f64::consts::PI]).unwrap();
        assert_eq!((folded.a, folded.b), (Body::Base, Body::Link(2)));
        assert!(folded.distance < 0.0, "{folded:?}");
    }

    #[test]
    fn clearance_derivatives_in_q_by_dual_numbers_match_central_differences() {
        use num_dual::Dual64;
        let (arm, mut g) = (arm(3), capsules(3));
        g.obstacles.push(Shape::polygon(vec![[0.9, 0.6], [1.4, 0.7], [1.1, 1.2]]).unwrap());
        let mut checked = 0;
        for i in 0..40 {
            let t = i as f64;
            let q = [0.1 * t.sin(), 0.9 * (1.3 * t).cos(), 1.7 * (0.7 * t).sin(), 2.1 * (0.4 * t).cos()];
            let dir = [0.3, -0.5, 0.8, 0.2];
            let at = |h: f64| -> Vec<f64> {
                let q: Vec<f64> = q.iter().zip(&dir).map(|(x, d)| x + h * d).collect();
                g.clearances(&arm, &q).iter().map(|c| c.distance).collect()
            };
            let qd: Vec<Dual64> = q.iter().zip(&dir).map(|(x, d)| Dual64::new(*x, *d)).collect();
            let dual = g.clearances(&arm, &qd);
            let (h, zero, plus, minus) = (1e-6, at(0.0), at(1e-6), at(-1e-6));
            for (k, c) in dual.iter().enumerate() {
                assert!((c.distance.re - zero[k]).abs() < 1e-15);
                // Skip a kink (the nearest feature changes within +-h).
                if ((plus[k] - zero[k]) / h - (zero[k] - minus[k]) / h).abs() > 1e-4 {
                    continue;
                }
                let central = (plus[k] - minus[k]) / (2.0 * h);
                assert!(
                    (c.distance.eps - central).abs() < 1e-6,
                    "{:?}: {} against {central}",
                    (c.a, c.b),
                    c.distance.eps
                );
                checked += 1;
            }
        }
        assert!(checked > 200, "{checked}");
    }
}
