//! The tests of the placed shapes' distances, bounds and speed bounds (brute force, bit for bit).
use super::*;
use crate::model::Mount;
use crate::model::arm::{Base, Link};
use crate::model::geometry::tests::rng;

/// The frames are `body_poses`' bit for bit, each with its angle's sine and cosine, on an
/// arm mounted off the base's centre (so that every term of the base's centre counts).
#[test]
fn frames_are_the_body_poses_with_their_sines_and_cosines() {
    let link = |l: f64, m: f64| Link { length: l, com: 0.4 * l, mass: m, inertia: m * l * l / 12.0 };
    let arm = Arm::new(
        Base { mass: 15.0, inertia: 1.0 },
        Mount::new(0.2, -0.1).unwrap(),
        vec![link(0.5, 2.0), link(0.4, 1.5), link(0.3, 1.0)],
    )
    .unwrap();
    let mut next = rng(7);
    let mut frames = Vec::new();
    for _ in 0..50 {
        let q: Vec<f64> = (0..4).map(|_| 6.0 * next() - 3.0).collect();
        frames_into(&arm, &q, &mut frames);
        let poses = super::super::body_poses(&arm, &q);
        assert_eq!(frames.len(), poses.len());
        for ((pose, (s, c)), expected) in frames.iter().zip(&poses) {
            assert_eq!(pose.x.to_bits(), expected.x.to_bits());
            assert_eq!(pose.y.to_bits(), expected.y.to_bits());
            assert_eq!(pose.angle.to_bits(), expected.angle.to_bits());
            let (es, ec) = expected.angle.sin_cos();
            assert_eq!((s.to_bits(), c.to_bits()), (es.to_bits(), ec.to_bits()));
        }
    }
}

/// The disc bound never exceeds the exact signed distance (brute force over random shapes
/// apart and overlapping: circles, capsules and boxes, as the robots carry).
#[test]
fn the_disc_bound_is_below_the_signed_distance() {
    let mut next = rng(11);
    let shape = |next: &mut dyn FnMut() -> f64| {
        let c = [2.0 * next() - 1.0, 2.0 * next() - 1.0];
        match (next() * 3.0) as usize {
            0 => Shape::circle(c, 0.3 * next()).unwrap(),
            1 => Shape::capsule(c, [c[0] + next() - 0.5, c[1] + next() - 0.5], 0.1 * next()).unwrap(),
            _ => Shape::rectangle(c, [0.05 + next(), 0.05 + next()]).unwrap(),
        }
    };
    let (mut apart, mut overlapping) = (0, 0);
    for _ in 0..2000 {
        let (a, b) = (shape(&mut next), shape(&mut next));
        let exact = signed_distance(&a.points, a.radius, &b.points, b.radius);
        let bound = disc_bound(&a.points, a.radius, &b.points, b.radius);
        assert!(bound <= exact, "{a:?} {b:?}: bound {bound} above {exact}");
        if exact > 0.0 { apart += 1 } else { overlapping += 1 }
    }
    assert!(apart > 100 && overlapping > 100, "{apart} apart, {overlapping} overlapping");
}

/// A union's distance is the least signed distance over every pair of its shapes, bit for
/// bit (the exhaustive search, each shape placed by [`Shape::placed`]): the search of least
/// disc bound first skips only shape pairs farther than one found. On the fixture of
/// `distances_beyond_far_are_bounds_above_it_and_the_rest_exact` (a box, links of spheres or
/// a circle and a capsule, two obstacles).
#[test]
fn a_union_is_at_its_least_shape_pair() {
    let (arm, geometry) = fixture();
    let pairs = geometry.pairs(4);
    let mut next = rng(5);
    for _ in 0..300 {
        let q: Vec<f64> = (0..5).map(|_| 6.0 * next() - 3.0).collect();
        let poses = super::super::body_poses(&arm, &q);
        let inertial = Pose { x: 0.0, y: 0.0, angle: 0.0 };
        let pose = |b: Body| match b {
            Body::Base => poses[0],
            Body::Link(k) => poses[k],
            Body::Obstacle(_) => inertial,
        };
        for (pair, got) in pairs.iter().zip(geometry.clearances_of(&arm, &q, &pairs)) {
            let (sa, sb) = (geometry.shapes(pair.0), geometry.shapes(pair.1));
            let mut least = f64::INFINITY;
            for a in sa {
                for b in sb {
                    let d = signed_distance(&a.placed(&pose(pair.0)), a.radius, &b.placed(&pose(pair.1)), b.radius);
                    least = least.min(d);
                }
            }
            assert_eq!(got.distance.to_bits(), least.to_bits(), "{pair:?} at {q:?}");
        }
    }
}

/// The capsules' speed bounds hold: between random configurations near and far apart,
/// every body's placed capsule's ends move by at most the bound (on an arm mounted off the
/// base's centre, links of different masses and centres).
#[test]
fn capsules_move_within_their_speed_bounds() {
    let (arm, geometry) = fixture();
    let link = |l: f64, c: f64, m: f64| Link { length: l, com: c, mass: m, inertia: m * l * l / 12.0 };
    let uneven = Arm::new(
        Base { mass: 8.0, inertia: 1.0 },
        Mount::new(0.2, -0.15).unwrap(),
        vec![link(0.5, 0.1, 4.0), link(0.4, 0.3, 1.0), link(0.45, 0.2, 2.5), link(0.3, 0.25, 0.5)],
    )
    .unwrap();
    let mut next = rng(9);
    let (mut frames, mut tight) = (Vec::new(), 0.0_f64);
    for arm in [arm, uneven] {
        let speeds = geometry.capsule_speeds(&arm);
        let ends = |q: &[f64], frames: &mut Vec<_>| {
            frames_into(&arm, q, frames);
            (0..=4)
                .map(|k| {
                    let (pose, (s, c)): (Pose<f64>, (f64, f64)) = frames[k];
                    let shapes = geometry.shapes(if k == 0 { Body::Base } else { Body::Link(k) });
                    placed_capsule(shapes, [pose.x, pose.y, s, c]).0
                })
                .collect::<Vec<_>>()
        };
        for trial in 0..2000 {
            let q: Vec<f64> = (0..5).map(|_| 6.0 * next() - 3.0).collect();
            let step = if trial % 2 == 0 { 0.01 } else { 3.0 };
            let r: Vec<f64> = q.iter().map(|v| v + step * (2.0 * next() - 1.0)).collect();
            let (a, b) = (ends(&q, &mut frames), ends(&r, &mut frames));
            for k in 0..=4 {
                let bound: f64 = speeds[k].iter().zip(q.iter().zip(&r)).map(|(l, (x, y))| l * (x - y).abs()).sum();
                for e in 0..2 {
                    let moved = (a[k][e][0] - b[k][e][0]).hypot(a[k][e][1] - b[k][e][1]);
                    assert!(moved <= bound + 1e-12, "body {k}: moved {moved} > {bound}");
                    tight = tight.max(moved / bound);
                }
            }
        }
    }
    // Not loose by orders of magnitude either.
    assert!(tight > 0.3, "largest ratio {tight}");
}

/// An arm of four links with a base box, links of spheres or of a circle and a capsule, and
/// two obstacles.
fn fixture() -> (Arm, Geometry) {
    let link = Link { length: 0.5, com: 0.25, mass: 2.0, inertia: 2.0 * 0.25 / 12.0 };
    let arm = Arm::new(Base { mass: 20.0, inertia: 1.0 }, Mount::new(0.25, 0.0).unwrap(), vec![link; 4]).unwrap();
    let spheres = |k: usize| (0..k).map(|i| Shape::circle([0.1 * i as f64, 0.01], 0.04).unwrap());
    let geometry = Geometry {
        base: vec![Shape::rectangle([0.0, 0.0], [0.5, 0.5]).unwrap()],
        links: (0..4)
            .map(|k| match k % 2 {
                0 => spheres(6).collect(),
                _ => vec![
                    Shape::circle([0.1, 0.0], 0.05).unwrap(),
                    Shape::capsule([0.2, 0.0], [0.5, 0.0], 0.04).unwrap(),
                ],
            })
            .collect(),
        obstacles: vec![
            Shape::circle([0.9, 0.3], 0.1).unwrap(),
            Shape::polygon(vec![[-0.9, 0.6], [-0.4, 0.7], [-0.7, 1.2]]).unwrap(),
        ],
        ..Default::default()
    };
    (arm, geometry)
}

/// `clearances_beyond`: every distance at or below `far` is `clearances_of`'s bit for bit,
/// and every one above it either that or a bound between `far` and it (the capsules' bound
/// below the brute-force-checked distance), marked as such. `clearances_of` itself is checked against the brute force and central
/// differences (`collision.rs`, `geometry.rs`).
#[test]
fn distances_beyond_far_are_bounds_above_it_and_the_rest_exact() {
    let (arm, geometry) = fixture();
    let pairs = geometry.pairs(4);
    let mut next = rng(3);
    let (mut placement, mut out) = (Placement::default(), Vec::new());
    let (mut bounded, mut exact_near) = (0, 0);
    for _ in 0..300 {
        let q: Vec<f64> = (0..5).map(|_| 6.0 * next() - 3.0).collect();
        let far = 0.4 * next();
        let exact = geometry.clearances_of(&arm, &q, &pairs);
        geometry.clearances_beyond(&arm, &q, &pairs, far, &mut placement, &mut out);
        for (k, (e, x)) in exact.iter().zip(&out).enumerate() {
            assert_eq!((e.a, e.b), (x.a, x.b));
            if placement.bounded()[k] {
                assert!(far < x.distance && x.distance <= e.distance, "{e:?} {x:?} far {far}");
                bounded += 1;
            } else {
                assert_eq!(e.distance.to_bits(), x.distance.to_bits(), "{e:?} {x:?} far {far}");
                exact_near += usize::from(e.distance <= far);
            }
        }
    }
    assert!(bounded > 100 && exact_near > 100, "{bounded} bounded, {exact_near} exact near");
}
