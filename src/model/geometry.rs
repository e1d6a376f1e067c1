//! Planar shapes of the robot's bodies and of obstacles, and their signed distances (issue 21;
//! docs/spec.md §1).
//!
//! Every shape is convex: the convex hull of a few points swept by a disc of radius `r`
//! (`Shape::points`, `Shape::radius`). A circle is one point, a capsule (a link of width `2 r`) two,
//! a box or a convex polygon its corners with `r = 0`. For two such shapes `A = hull(P) + disc(r_A)`
//! and `B = hull(Q) + disc(r_B)` the Minkowski difference is `A - B = hull(P - Q) + disc(r_A + r_B)`,
//! and their signed distance (the gap when apart, minus the penetration depth when they overlap) is
//! the signed distance from the origin to it:
//! `sd(A, B) = sd(0, hull(P - Q)) - r_A - r_B`, where `sd(0, K)` is the distance from the origin to
//! the convex polygon `K` outside it and minus the distance to its boundary inside. That is exact for
//! every pair of shapes, penetration included, and generic over [`Scalar`]: placed with dual numbers,
//! the distance carries its exact derivatives (one-sided where the nearest feature changes, as any
//! distance does).

mod small;

use serde::{Deserialize, Serialize};

use super::InputError;
use crate::Scalar;

/// Most corners of one polygon: a planar body of a space robot is a handful of them, and the
/// Minkowski difference of two polygons has `k_A k_B` candidate points.
pub const MAX_CORNERS: usize = 64;

/// Largest coordinate or radius of a shape \[m\]: a planar testbed is metres across.
pub const MAX_EXTENT: f64 = 1e3;

/// A convex planar shape: the convex hull of `points` swept by a disc of `radius`, in the frame of
/// the body that carries it (or the inertial frame, for an obstacle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Shape {
    /// The hull's points `(x, y)` \[m\] (1 to [`MAX_CORNERS`]).
    pub points: Vec<[f64; 2]>,
    /// The radius of the disc swept along the hull \[m\], `>= 0`.
    pub radius: f64,
}

impl Shape {
    /// A circle of radius `radius` about `centre`.
    pub fn circle(centre: [f64; 2], radius: f64) -> Result<Self, InputError> {
        Self::new(vec![centre], radius)
    }

    /// A capsule: the segment from `a` to `b` swept by a disc of `radius` (a link of width
    /// `2 radius`).
    pub fn capsule(a: [f64; 2], b: [f64; 2], radius: f64) -> Result<Self, InputError> {
        Self::new(vec![a, b], radius)
    }

    /// A rectangle of `size = (width, height)` centred at `centre`, sides along the axes.
    pub fn rectangle(centre: [f64; 2], size: [f64; 2]) -> Result<Self, InputError> {
        let [hx, hy] = [size[0] / 2.0, size[1] / 2.0];
        for (i, s) in size.iter().enumerate() {
            if !(s.is_finite() && *s > 0.0) {
                return Err(bad(&format!("size[{i}]"), *s, "a positive, finite side [m]"));
            }
        }
        let [x, y] = centre;
        Self::new(vec![[x - hx, y - hy], [x + hx, y - hy], [x + hx, y + hy], [x - hx, y + hy]], 0.0)
    }

    /// A convex polygon with the corners `corners` (either orientation); a corner inside the hull
    /// of the others is refused, so that what the user wrote is what is checked.
    pub fn polygon(corners: Vec<[f64; 2]>) -> Result<Self, InputError> {
        let shape = Self::new(corners, 0.0)?;
        if shape.points.len() < 3 {
            return Err(bad("polygon", shape.points.len() as f64, "at least 3 corners"));
        }
        let hull = hull(&shape.points, |p| *p);
        if hull.len() != shape.points.len() {
            return Err(bad(
                "polygon",
                shape.points.len() as f64,
                "a convex polygon: every corner on the hull, no three in a line, no repeats",
            ));
        }
        Ok(shape)
    }

    /// A shape from its points and radius, checked: 1 to [`MAX_CORNERS`] finite points within
    /// [`MAX_EXTENT`], a finite radius in `[0, MAX_EXTENT]`, and a single point needs `radius > 0`.
    pub fn new(points: Vec<[f64; 2]>, radius: f64) -> Result<Self, InputError> {
        if points.is_empty() || points.len() > MAX_CORNERS {
            return Err(bad("points", points.len() as f64, "1 to 64 points"));
        }
        for (i, p) in points.iter().enumerate() {
            for (axis, v) in ["x", "y"].iter().zip(p) {
                if !(v.is_finite() && v.abs() <= MAX_EXTENT) {
                    return Err(bad(&format!("points[{i}].{axis}"), *v, "a finite coordinate within 1e3 m"));
                }
            }
        }
        if !(radius.is_finite() && (0.0..=MAX_EXTENT).contains(&radius)) {
            return Err(bad("radius", radius, "a finite radius from 0 to 1e3 m"));
        }
        if points.len() == 1 && radius == 0.0 {
            return Err(bad("radius", radius, "a circle of radius > 0"));
        }
        Ok(Self { points, radius })
    }

    /// The shape's points moved by the rigid motion `(x, y, angle)` (rotation first), in any
    /// [`Scalar`] so that a placement by dual numbers carries its derivatives.
    pub fn placed<D: Scalar>(&self, pose: &Pose<D>) -> Vec<[D; 2]> {
        let mut out = Vec::with_capacity(self.points.len());
        self.placed_into(pose, pose.angle.sin_cos(), &mut out);
        out
    }

    /// [`Shape::placed`] appended to `out`, with the pose's angle's sine and cosine `(s, c)`
    /// given (one body's shapes share them): the same points, bit for bit.
    pub fn placed_into<D: Scalar>(&self, pose: &Pose<D>, (s, c): (D, D), out: &mut Vec<[D; 2]>) {
        out.extend(self.points.iter().map(|p| [pose.x + c * p[0] - s * p[1], pose.y + s * p[0] + c * p[1]]));
    }
}

/// What [`Shape::from_spec`] accepts.
pub const SHAPE_SPEC: &str = "circle:X,Y,R, capsule:X1,Y1,X2,Y2,R, box:X,Y,W,H or polygon:X1,Y1,X2,Y2,X3,Y3[,...] \
     (metres; a polygon convex, at most 64 corners)";

impl Shape {
    /// A shape from its text form (the command line's `--obstacle`): `circle:X,Y,R`,
    /// `capsule:X1,Y1,X2,Y2,R`, `box:X,Y,W,H` (centre, width, height) or
    /// `polygon:X1,Y1,X2,Y2,X3,Y3,...` \[m\]. `name` names it in errors (e.g. `--obstacle`).
    ///
    /// ```
    /// use freefloat::model::geometry::Shape;
    /// let s = Shape::from_spec("--obstacle", "circle:1.5,0,0.3").unwrap();
    /// assert_eq!((s.points, s.radius), (vec![[1.5, 0.0]], 0.3));
    /// assert!(Shape::from_spec("--obstacle", "circle:1.5,0").is_err());
    /// ```
    pub fn from_spec(name: &str, text: &str) -> Result<Self, InputError> {
        let invalid = || InputError::InvalidText { name: name.into(), text: text.into(), expected: SHAPE_SPEC };
        let (kind, numbers) = text.split_once(':').ok_or_else(invalid)?;
        let x = numbers
            .split(',')
            .map(|v| v.trim().parse::<f64>().map_err(|_| invalid()))
            .collect::<Result<Vec<f64>, _>>()?;
        let named = |e: InputError| match e {
            InputError::InvalidParameter { name: key, value, expected } => {
                InputError::InvalidParameter { name: format!("{name} {key}"), value, expected }
            }
            other => other,
        };
        let shape = match (kind.trim(), x.as_slice()) {
            ("circle", &[cx, cy, r]) => Self::circle([cx, cy], r),
            ("capsule", &[x1, y1, x2, y2, r]) => Self::capsule([x1, y1], [x2, y2], r),
            ("box", &[cx, cy, w, h]) => Self::rectangle([cx, cy], [w, h]),
            ("polygon", v) if v.len() >= 6 && v.len() % 2 == 0 && v.len() <= 2 * MAX_CORNERS => {
                Self::polygon(v.chunks(2).map(|c| [c[0], c[1]]).collect())
            }
            _ => return Err(invalid()),
        };
        shape.map_err(named)
    }
}

/// A rigid placement of a body's frame in the inertial frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose<D> {
    /// Origin `x` \[m\].
    pub x: D,
    /// Origin `y` \[m\].
    pub y: D,
    /// Angle of the frame's x axis \[rad\].
    pub angle: D,
}

fn bad(name: &str, value: f64, expected: &'static str) -> InputError {
    InputError::InvalidParameter { name: format!("shape.{name}"), value, expected }
}

/// The signed distance between the shapes `hull(a) + disc(ra)` and `hull(b) + disc(rb)` whose
/// points are already placed in one frame \[m\]: the gap when they are apart, minus the
/// penetration depth when they overlap (module docs). `a` and `b` must not be empty.
pub fn signed_distance<D: Scalar>(a: &[[D; 2]], ra: f64, b: &[[D; 2]], rb: f64) -> D {
    // Two discs (a point each): the hull of their difference is that one point.
    if let ([p], [q]) = (a, b) {
        return origin_signed_distance(&[[p[0] - q[0], p[1] - q[1]]]) - D::from(ra + rb);
    }
    if a.len() * b.len() <= small::SMALL {
        return small::signed_distance(a, b) - D::from(ra + rb);
    }
    let mut diff = Vec::with_capacity(a.len() * b.len());
    for p in a {
        for q in b {
            diff.push([p[0] - q[0], p[1] - q[1]]);
        }
    }
    let k = hull(&diff, |p| [p[0].re(), p[1].re()]);
    origin_signed_distance(&k) - D::from(ra + rb)
}

/// The convex hull of `points` \[m\], counter-clockwise, without repeated or collinear points (1
/// point or the 2 extremes for a degenerate hull): the footprint of a projected solid.
pub fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    hull(points, |p| *p)
}

/// The convex hull of `points` (Andrew's monotone chain on the real parts `re`), counter-clockwise,
/// without collinear points; 1 point or 2 for a degenerate hull.
fn hull<T: Copy>(points: &[T], re: impl Fn(&T) -> [f64; 2]) -> Vec<T> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&i, &j| {
        let (p, q) = (re(&points[i]), re(&points[j]));
        p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1]))
    });
    // Exact repeats only (a point a rounding away from another is kept; the chain drops it).
    order.dedup_by(|i, j| {
        let (p, q) = (re(&points[*i]), re(&points[*j]));
        p[0].total_cmp(&q[0]).is_eq() && p[1].total_cmp(&q[1]).is_eq()
    });
    if order.len() < 3 {
        return order.iter().map(|&i| points[i]).collect();
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let chain = |indices: &mut dyn Iterator<Item = usize>| -> Vec<usize> {
        let mut half: Vec<usize> = Vec::with_capacity(order.len());
        for i in indices {
            while let [.., o, a] = half[..]
                && cross(re(&points[o]), re(&points[a]), re(&points[i])) <= 0.0
            {
                half.pop();
            }
            half.push(i);
        }
        half.pop();
        half
    };
    let mut out = chain(&mut order.iter().copied());
    out.extend(chain(&mut order.iter().rev().copied()));
    if out.len() < 3 {
        // All points in a line: the two extremes.
        return vec![points[order[0]], points[order[order.len() - 1]]];
    }
    out.iter().map(|&i| points[i]).collect()
}

/// Distance from the origin to the segment `p q`.
fn segment_distance<D: Scalar>(p: [D; 2], q: [D; 2]) -> D {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2.re() > 0.0 { -(p[0] * d[0] + p[1] * d[1]) / len2 } else { D::from(0.0) };
    let t = if t.re() < 0.0 {
        D::from(0.0)
    } else if t.re() > 1.0 {
        D::from(1.0)
    } else {
        t
    };
    let x = [p[0] + d[0] * t, p[1] + d[1] * t];
    (x[0] * x[0] + x[1] * x[1]).sqrt()
}

/// Signed distance from the origin to the convex hull `k` (counter-clockwise; 1, 2 or more points).
fn origin_signed_distance<D: Scalar>(k: &[[D; 2]]) -> D {
    match k {
        [] => D::from(f64::INFINITY),
        [p] => (p[0] * p[0] + p[1] * p[1]).sqrt(),
        [p, q] => segment_distance(*p, *q),
        _ => {
            let m = k.len();
            // Inside when the origin is left of (or on) every edge.
            let mut inside = true;
            let mut depth = D::from(f64::INFINITY);
            let mut outside = D::from(f64::INFINITY);
            for i in 0..m {
                let (p, q) = (k[i], k[(i + 1) % m]);
                let e = [q[0] - p[0], q[1] - p[1]];
                let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
                // Distance of the origin to the edge's line, positive on the inner (left) side.
                let left = (e[0] * (-p[1]) - e[1] * (-p[0])) / len;
                if left.re() < 0.0 {
                    inside = false;
                }
                if left.re() < depth.re() {
                    depth = left;
                }
                let d = segment_distance(p, q);
                if d.re() < outside.re() {
                    outside = d;
                }
            }
            if inside { -depth } else { outside }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use num_dual::Dual64;

    /// A small deterministic generator (xorshift), uniform in [0, 1).
    pub(crate) fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A random shape near the origin: a circle, a capsule or a convex polygon (random points on
    /// an ellipse, so every corner is on the hull).
    fn random_shape(next: &mut impl FnMut() -> f64) -> Shape {
        let c = [next() - 0.5, next() - 0.5];
        match (next() * 3.0) as usize {
            0 => Shape::circle(c, 0.05 + 0.3 * next()).unwrap(),
            1 => {
                let b = [c[0] + next() - 0.5, c[1] + next() - 0.5];
                Shape::capsule(c, b, 0.02 + 0.2 * next()).unwrap()
            }
            _ => {
                let k = 3 + (next() * 5.0) as usize;
                let (rx, ry, rot) = (0.1 + 0.4 * next(), 0.1 + 0.4 * next(), next() * 6.0);
                let mut angles: Vec<f64> = (0..k).map(|_| next() * std::f64::consts::TAU).collect();
                angles.sort_by(f64::total_cmp);
                angles.dedup_by(|a, b| (*a - *b).abs() < 0.3);
                if angles.len() < 3 {
                    angles = vec![0.0, 2.1, 4.2];
                }
                let corners = angles
                    .iter()
                    .map(|t| {
                        let (x, y) = (rx * t.cos(), ry * t.sin());
                        [c[0] + x * rot.cos() - y * rot.sin(), c[1] + x * rot.sin() + y * rot.cos()]
                    })
                    .collect();
                Shape::polygon(corners).unwrap()
            }
        }
    }

    /// The support function `h(u) = max_{x in shape} u . x` of a shape, by brute force over its
    /// points (exact for a hull swept by a disc).
    fn support(points: &[[f64; 2]], r: f64, u: [f64; 2]) -> f64 {
        points.iter().map(|p| p[0] * u[0] + p[1] * u[1]).fold(f64::NEG_INFINITY, f64::max) + r
    }

    /// The signed distance by the separating-axis characterisation, sampled: for convex sets,
    /// `sd(A, B) = max_u (-h_A(u) - h_B(-u))` over unit directions `u` (the widest gap along any
    /// axis; minus the least overlap when they overlap). It shares nothing with the hull-based
    /// routine but the shapes.
    fn sampled_signed_distance(a: &[[f64; 2]], ra: f64, b: &[[f64; 2]], rb: f64) -> f64 {
        let gap = |t: f64| {
            let u = [t.cos(), t.sin()];
            -support(a, ra, u) - support(b, rb, [-u[0], -u[1]])
        };
        // A coarse pass over the circle, then a fine one about its best direction.
        let n = 20_000;
        let step = std::f64::consts::TAU / n as f64;
        let best = (0..n).map(|i| i as f64 * step).max_by(|x, y| gap(*x).total_cmp(&gap(*y))).unwrap_or(0.0);
        (0..=20_000).map(|i| gap(best - step + 2.0 * step * i as f64 / 20_000.0)).fold(f64::NEG_INFINITY, f64::max)
    }

    /// The gap of two apart shapes by dense sampling of their boundaries (for the distance when
    /// apart; an upper bound that the exact distance must not exceed and must come close to).
    fn sampled_gap(a: &Shape, b: &Shape) -> f64 {
        let boundary = |s: &Shape| -> Vec<[f64; 2]> {
            let hull = hull(&s.points, |p| *p);
            let mut out = Vec::new();
            let m = hull.len();
            let steps = if m == 1 { 1 } else { 150 };
            for i in 0..m {
                let (p, q) = (hull[i], hull[(i + 1) % m]);
                for j in 0..steps {
                    let t = j as f64 / steps as f64;
                    let x = [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t];
                    for k in 0..64 {
                        let a = std::f64::consts::TAU * k as f64 / 64.0;
                        out.push([x[0] + s.radius * a.cos(), x[1] + s.radius * a.sin()]);
                    }
                    if s.radius == 0.0 {
                        out.truncate(out.len() - 63);
                    }
                }
            }
            out
        };
        let (pa, pb) = (boundary(a), boundary(b));
        let mut best = f64::INFINITY;
        for p in &pa {
            for q in &pb {
                best = best.min(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
            }
        }
        best
    }

    #[test]
    fn signed_distance_is_the_separating_axis_distance_on_random_pairs() {
        let mut next = rng(0x21_5EED);
        let (mut apart, mut overlapping) = (0, 0);
        for _ in 0..300 {
            let (a, b) = (random_shape(&mut next), random_shape(&mut next));
            let d = signed_distance(&a.points, a.radius, &b.points, b.radius);
            let reference = sampled_signed_distance(&a.points, a.radius, &b.points, b.radius);
            // The sampled maximum is below the true one by at most |A - B| times the fine
            // pass's step (3e-4 / 2e4 rad), ~1e-8 m for shapes a metre across.
            assert!((d - reference).abs() < 1e-7, "{a:?} {b:?}: {d} against {reference}");
            if d > 0.0 { apart += 1 } else { overlapping += 1 }
        }
        assert!(apart > 50 && overlapping > 50, "both cases covered: {apart} apart, {overlapping} overlapping");
    }

    #[test]
    fn the_gap_of_apart_shapes_is_the_closest_pair_of_boundary_points() {
        let mut next = rng(7);
        let mut checked = 0;
        while checked < 25 {
            let (a, mut b) = (random_shape(&mut next), random_shape(&mut next));
            for p in &mut b.points {
                p[0] += 1.2;
            }
            let d = signed_distance(&a.points, a.radius, &b.points, b.radius);
            if d <= 0.0 {
                continue;
            }
            let sampled = sampled_gap(&a, &b);
            // The sampler errs up: discs at 64 angles by up to r (1 - cos(pi / 64)) < 4e-4 for
            // r <= 0.3 m on each shape, sides at 150 points by less.
            assert!(d <= sampled + 1e-12 && sampled - d < 1e-3, "{d} against sampled {sampled}");
            checked += 1;
        }
    }

    #[test]
    fn known_pairs() {
        let c = |x, y, r| Shape::circle([x, y], r).unwrap();
        let sd = |a: &Shape, b: &Shape| signed_distance(&a.points, a.radius, &b.points, b.radius);
        // Two unit circles 3 apart: gap 1; 1.5 apart: overlap 0.5.
        assert!((sd(&c(0.0, 0.0, 1.0), &c(3.0, 0.0, 1.0)) - 1.0).abs() < 1e-15);
        assert!((sd(&c(0.0, 0.0, 1.0), &c(1.5, 0.0, 1.0)) + 0.5).abs() < 1e-15);
        // A unit square and a point circle above its corner region and deep inside it.
        let square = Shape::rectangle([0.0, 0.0], [2.0, 2.0]).unwrap();
        assert!((sd(&square, &c(4.0, 5.0, 1.0)) - 4.0).abs() < 1e-15, "corner (1, 1) to (4, 5) is 5, minus r");
        assert!((sd(&square, &c(0.2, 0.0, 0.1)) + 0.9).abs() < 1e-15, "0.8 to the right side, plus r");
        // Crossing capsules: the penetration depth is the smaller way out.
        let h = Shape::capsule([-1.0, 0.0], [1.0, 0.0], 0.1).unwrap();
        let v = Shape::capsule([0.0, -1.0], [0.0, 1.0], 0.1).unwrap();
        // hull(P - Q) is the square of corners (+-1, +-1): 1 to its side, plus both radii.
        assert!((sd(&h, &v) + 1.2).abs() < 1e-15);
        // Parallel capsules 0.5 apart.
        let h2 = Shape::capsule([-1.0, 0.5], [1.0, 0.5], 0.1).unwrap();
        assert!((sd(&h, &h2) - 0.3).abs() < 1e-15);
    }

    #[test]
    fn derivatives_by_dual_numbers_match_central_differences() {
        let mut next = rng(11);
        let mut checked = 0;
        for _ in 0..200 {
            let (a, b) = (random_shape(&mut next), random_shape(&mut next));
            let (x, y, angle) = (next() - 0.5, next() - 0.5, next() * 6.0);
            let dir = [next() - 0.5, next() - 0.5, next() - 0.5];
            let at = |h: f64| -> f64 {
                let pose = Pose { x: x + h * dir[0], y: y + h * dir[1], angle: angle + h * dir[2] };
                signed_distance(&a.placed(&pose), a.radius, &b.points, b.radius)
            };
            let pose = Pose { x: Dual64::new(x, dir[0]), y: Dual64::new(y, dir[1]), angle: Dual64::new(angle, dir[2]) };
            let bd: Vec<[Dual64; 2]> = b.points.iter().map(|p| [Dual64::from(p[0]), Dual64::from(p[1])]).collect();
            let d = signed_distance(&a.placed(&pose), a.radius, &bd, b.radius);
            assert!((d.re - at(0.0)).abs() < 1e-15);
            let h = 1e-6;
            let (plus, minus) = (at(h), at(-h));
            let central = (plus - minus) / (2.0 * h);
            // Skip the placements where the nearest feature changes within +-h (a kink).
            let one_sided = ((plus - at(0.0)) / h - (at(0.0) - minus) / h).abs();
            if one_sided > 1e-4 {
                continue;
            }
            assert!((d.eps - central).abs() < 1e-6, "{} against {central}", d.eps);
            checked += 1;
        }
        assert!(checked > 150, "most placements are smooth: {checked}");
    }

    #[test]
    fn shapes_from_their_text_form() {
        let sq = Shape::from_spec("--obstacle", "box:1,2,0.5,0.25").unwrap();
        // 1 - 0.25 and 2 - 0.125.
        assert!((sq.points[0][0] - 0.75).abs() < 1e-15 && (sq.points[0][1] - 1.875).abs() < 1e-15);
        let tri = Shape::from_spec("--obstacle", "polygon: 0,0, 1,0, 0,1").unwrap();
        assert_eq!(tri.points.len(), 3);
        assert!(Shape::from_spec("o", "capsule:0,0,1,0,0.1").unwrap().radius.to_bits() == 0.1f64.to_bits());
        for bad in ["", "circle", "circle:1,2", "circle:1,2,x", "star:1,2,3", "polygon:0,0,1,0", "polygon:0,0,1,0,0"] {
            let Err(InputError::InvalidText { name, .. }) = Shape::from_spec("--obstacle", bad) else {
                panic!("{bad:?} refused as text")
            };
            assert_eq!(name, "--obstacle");
        }
        let Err(InputError::InvalidParameter { name, .. }) = Shape::from_spec("--obstacle", "circle:0,0,-1") else {
            panic!("a negative radius refused")
        };
        assert_eq!(name, "--obstacle shape.radius");
        assert!(Shape::from_spec("--obstacle", "circle:nan,0,1").is_err());
        assert!(Shape::from_spec("--obstacle", "polygon:0,0,1,0,0.5,0.1,0.5,1").is_err(), "not convex");
    }

    #[test]
    fn bad_shapes_are_refused_by_name() {
        assert!(Shape::circle([0.0, 0.0], 0.0).is_err());
        assert!(Shape::circle([f64::NAN, 0.0], 1.0).is_err());
        assert!(Shape::capsule([0.0, 0.0], [1.0, 0.0], -0.1).is_err());
        assert!(Shape::rectangle([0.0, 0.0], [0.0, 1.0]).is_err());
        assert!(Shape::new(vec![[0.0, 0.0]; 65], 0.1).is_err());
        // A dent: (0.5, 0.2) is inside the triangle of the others.
        let dent = Shape::polygon(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 0.2], [0.5, 1.0]]);
        let Err(InputError::InvalidParameter { name, .. }) = dent else { panic!("refused") };
        assert_eq!(name, "shape.polygon");
        assert!(Shape::polygon(vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).is_err(), "collinear");
        assert!(Shape::polygon(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).is_ok());
    }
}
