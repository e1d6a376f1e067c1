//! The bodies' shapes placed at one configuration and the pairs' signed distances from them
//! (issue 21; docs/spec.md §1): [`Geometry::clearances_of`]'s work, with its buffers kept
//! between calls ([`Placement`]) for a caller that evaluates many configurations (the
//! planner's clearance rows, thousands of points per evaluation), each angle's sine and cosine
//! computed once, and a body's union of shapes searched for its nearest pair with a cheap lower
//! bound that skips the shape pairs that cannot be nearer than one already found.

use super::{Body, Geometry, PairClearance};
use crate::Scalar;
use crate::model::arm::Arm;
use crate::model::geometry::{Pose, Shape, signed_distance};

/// The buffers of [`Geometry::clearances_into`], reused between calls: no allocation once they
/// have grown to the arm's size.
#[derive(Debug, Clone)]
pub struct Placement<D> {
    /// Each body's frame with its angle's sine and cosine: the base's, then links `1..n`'s.
    frames: Vec<(Pose<D>, (D, D))>,
    /// Every placed shape's points (base, links, obstacles).
    points: Vec<[D; 2]>,
    /// Shape `k`'s points are `points[ranges[k].0..ranges[k].1]`.
    ranges: Vec<(usize, usize)>,
    /// Body `i`'s first shape among `ranges` (base 0, link `k` at `k`, obstacle `k` at `n + k`).
    first: Vec<usize>,
    /// The points' real parts, once a body of several shapes asks (empty before).
    real: Vec<[f64; 2]>,
    /// Whether each pair's distance of the last call is a bound ([`Geometry::clearances_beyond`]).
    bounded: Vec<bool>,
    /// Each body's [`capsule_of`] placed by its frame's real parts (as `first`; with a `far`).
    capsules: Vec<([[f64; 2]; 2], f64)>,
    /// Each pair's capsules' bound (with a `far`).
    bounds: Vec<f64>,
    /// Whether each body's shapes are placed (those of a pair not [`Placement::bounded`]).
    needed: Vec<bool>,
    /// Each placed shape's bounding disc ([`disc`]; as `ranges`, once a body of several shapes
    /// asks).
    discs: Vec<([f64; 2], f64)>,
    /// The shape pairs' [`discs_gap`] of one pair of bodies.
    gaps: Vec<f64>,
}

impl<D> Placement<D> {
    /// Whether each pair's distance of the last [`Geometry::clearances_beyond`] is a bound above
    /// its `far` (not the exact distance).
    pub fn bounded(&self) -> &[bool] {
        &self.bounded
    }
}

impl<D> Default for Placement<D> {
    fn default() -> Self {
        Self {
            frames: Vec::new(),
            points: Vec::new(),
            ranges: Vec::new(),
            first: Vec::new(),
            real: Vec::new(),
            bounded: Vec::new(),
            capsules: Vec::new(),
            bounds: Vec::new(),
            needed: Vec::new(),
            discs: Vec::new(),
            gaps: Vec::new(),
        }
    }
}

/// The frames of [`super::body_poses`] with each one's sine and cosine, into `out`: the same
/// arithmetic, bit for bit, as [`Arm::base_position`] and [`super::body_poses`] (which take every
/// angle's sine and cosine twice, and the shapes' placing a third time), each once.
pub(super) fn frames_into<D: Scalar>(arm: &Arm, q: &[D], out: &mut Vec<(Pose<D>, (D, D))>) {
    out.clear();
    let zero = D::from(0.0);
    let base = arm.base_position_each(q, |angle, sc| out.push((Pose { x: zero, y: zero, angle }, sc)));
    let ((sp, cp), (a, b)) = (out[0].1, (arm.mount.a, arm.mount.b));
    // The joints from the base's centre, as `body_poses` places them.
    out[0].0 = Pose { x: base[0], y: base[1], angle: q[0] };
    let mut joint = [base[0] + cp * a - sp * b, base[1] + sp * a + cp * b];
    for (frame, link) in out[1..].iter_mut().zip(&arm.links) {
        let (s, c) = frame.1;
        (frame.0.x, frame.0.y) = (joint[0], joint[1]);
        joint = [joint[0] + c * link.length, joint[1] + s * link.length];
    }
}

/// A lower bound on the signed distance of `hull(a) + disc(ra)` and `hull(b) + disc(rb)` \[m\]:
/// that of their bounding discs (each centred at its points' mean), `|c_a - c_b| - R_a - R_b`.
/// It holds penetrating too: moving the discs apart by their depth separates the shapes inside
/// them, so the shapes' depth is at most the discs'. ([`Geometry::clearances_beyond`] takes it
/// as [`discs_gap`] of discs found once per shape.)
#[cfg(test)]
fn disc_bound(a: &[[f64; 2]], ra: f64, b: &[[f64; 2]], rb: f64) -> f64 {
    discs_gap(disc(a, ra), disc(b, rb))
}

/// The bounding disc of `hull(p) + disc(r)` of [`disc_bound`]: its centre (the points' mean) and
/// radius.
fn disc(p: &[[f64; 2]], r: f64) -> ([f64; 2], f64) {
    match p {
        [x] => (*x, r),
        _ => {
            let k = p.len() as f64;
            let c = p.iter().fold([0.0, 0.0], |s, x| [s[0] + x[0], s[1] + x[1]]);
            let c = [c[0] / k, c[1] / k];
            let far = p.iter().map(|x| (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2)).fold(0.0, f64::max);
            // A hair more than the rounded radius, so that the bound never exceeds the distance.
            (c, far.sqrt() * (1.0 + 1e-12) + r)
        }
    }
}

/// [`disc_bound`] of two discs.
fn discs_gap((ca, ra): ([f64; 2], f64), (cb, rb): ([f64; 2], f64)) -> f64 {
    let (dx, dy) = (ca[0] - cb[0], ca[1] - cb[1]);
    let gap = (dx * dx + dy * dy).sqrt() - ra - rb;
    gap - 1e-12 * (1.0 + gap.abs())
}

/// A capsule in a body's frame that holds all of its shapes: the segment along the frame's `x`
/// axis across their points' `x` range at the middle of their `y` range, and the radius that
/// reaches every point's disc (a point `(x, y)` of that `x` range is `|y - y_0|` from it).
fn capsule_of(shapes: &[Shape]) -> ([[f64; 2]; 2], f64) {
    let points = || shapes.iter().flat_map(|s| s.points.iter());
    let (lo, hi) = points().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    });
    let mid = (lo[1] + hi[1]) / 2.0;
    let radius =
        shapes.iter().flat_map(|s| s.points.iter().map(move |p| (p[1] - mid).abs() + s.radius)).fold(0.0, f64::max);
    ([[lo[0], mid], [hi[0], mid]], radius)
}

/// The distance between the segments `p` and `q` \[m\] (0 where they cross or touch).
fn segments_gap(p: [[f64; 2]; 2], q: [[f64; 2]; 2]) -> f64 {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let (d1, d2) = (cross(q[0], q[1], p[0]), cross(q[0], q[1], p[1]));
    let (d3, d4) = (cross(p[0], p[1], q[0]), cross(p[0], p[1], q[1]));
    if d1 * d2 <= 0.0 && d3 * d4 <= 0.0 {
        return 0.0;
    }
    // The squared distances, one square root of their least (the same value: the square root
    // is monotonic and correctly rounded).
    let to = |x: [f64; 2], [a, b]: [[f64; 2]; 2]| {
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let t = if len2 > 0.0 { (((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let (ex, ey) = (x[0] - a[0] - t * d[0], x[1] - a[1] - t * d[1]);
        ex * ex + ey * ey
    };
    to(p[0], q).min(to(p[1], q)).min(to(q[0], p)).min(to(q[1], p)).sqrt()
}

/// A body's [`capsule_of`] placed by its frame's real parts `(x, y, sin, cos)`.
fn placed_capsule(shapes: &[Shape], [x, y, s, c]: [f64; 4]) -> ([[f64; 2]; 2], f64) {
    let (spine, radius) = capsule_of(shapes);
    (spine.map(|p| [x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]]), radius)
}

/// A lower bound on the signed distance of two bodies \[m\]: that of their placed capsules
/// ([`placed_capsule`]; a hair less, for the rounding).
fn capsule_bound((pa, ra): ([[f64; 2]; 2], f64), (pb, rb): ([[f64; 2]; 2], f64)) -> f64 {
    let gap = segments_gap(pa, pb) - ra - rb;
    gap - 1e-12 * (1.0 + gap.abs() + ra + rb)
}

impl Geometry {
    /// For each body (the base, links `1..n`, then the obstacles), bounds `L_i` \[m/rad\] on the
    /// speed of every point of its bounding capsule (the one [`Geometry::clearances_beyond`]'s
    /// bounds take) in each coordinate of `q = (phi, theta_1..theta_n)`: such a point moves by
    /// at most `sum_i L_i |q'_i - q_i|` from `q` to `q'` (along the segment between them), so a
    /// pair's capsule bound falls by at most both bodies' sums. Turning `phi` turns everything
    /// about the system's centre of mass (a point's speed is its distance from it, bounded as
    /// [`Geometry::reach`] bounds it); `theta_i` turns the links from `i` on about joint `i` and
    /// moves the base's centre by the links' mass-weighted turn.
    pub fn capsule_speeds(&self, arm: &Arm) -> Vec<Vec<f64>> {
        let n = arm.joints();
        let total = arm.total_mass();
        let mount = arm.mount.a.hypot(arm.mount.b);
        // 1-based: `l[s]`, `com[k]`, `w[k] = m_k / M` of link `k`.
        let l: Vec<f64> = std::iter::once(0.0).chain(arm.links.iter().map(|x| x.length.abs())).collect();
        let com: Vec<f64> = std::iter::once(0.0).chain(arm.links.iter().map(|x| x.com.abs())).collect();
        let w: Vec<f64> = std::iter::once(0.0).chain(arm.links.iter().map(|x| x.mass.abs() / total)).collect();
        let reach_in = |from: usize, to: usize| (from..to).map(|s| l[s]).sum::<f64>();
        // The base's centre's speed in `phi` (its distance from the origin) and in `theta_i`.
        let base0: f64 = (1..=n).map(|k| w[k] * (mount + reach_in(1, k) + com[k])).sum();
        let base: Vec<f64> = (0..=n)
            .map(|i| if i == 0 { base0 } else { (i..=n).map(|k| w[k] * (reach_in(i, k) + com[k])).sum() })
            .collect();
        let body_count = n + 1 + self.obstacles.len();
        (0..body_count)
            .map(|j| {
                let shapes = match j {
                    0 => self.shapes(Body::Base),
                    j if j <= n => self.shapes(Body::Link(j)),
                    _ => return vec![0.0; n + 1],
                };
                if shapes.is_empty() {
                    return vec![0.0; n + 1];
                }
                let (spine, _) = capsule_of(shapes);
                let u = spine.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
                let phi = base0 + u + if j >= 1 { mount + reach_in(1, j) } else { 0.0 };
                let joints = (1..=n).map(|i| base[i] + if j >= i { reach_in(i, j) + u } else { 0.0 });
                std::iter::once(phi).chain(joints).collect()
            })
            .collect()
    }

    /// [`Geometry::clearances_of`] into `out` (cleared first), with `placement`'s buffers: the
    /// same values bit for bit, without allocating once the buffers have grown.
    pub fn clearances_into<D: Scalar>(
        &self,
        arm: &Arm,
        q: &[D],
        pairs: &[(Body, Body)],
        placement: &mut Placement<D>,
        out: &mut Vec<PairClearance<D>>,
    ) {
        self.clearances_beyond(arm, q, pairs, f64::INFINITY, placement, out);
    }

    /// [`Geometry::clearances_into`], but a pair whose bodies' `capsule_bound` exceeds `far`
    /// \[m\] has that bound as its distance, a constant (no derivatives; marked in
    /// [`Placement::bounded`]): a lower bound of the distance, above `far`, where the exact
    /// distance is not needed (the planner's rows of bodies far apart carry no gradient). Every
    /// distance at or below `far` is exact.
    pub fn clearances_beyond<D: Scalar>(
        &self,
        arm: &Arm,
        q: &[D],
        pairs: &[(Body, Body)],
        far: f64,
        placement: &mut Placement<D>,
        out: &mut Vec<PairClearance<D>>,
    ) {
        let Placement { frames, points, ranges, first, real, bounded, capsules, bounds, needed, discs, gaps } =
            placement;
        frames_into(arm, q, frames);
        let zero = D::from(0.0);
        let inertial = (Pose { x: zero, y: zero, angle: zero }, zero.sin_cos());
        let n = arm.joints();
        // Body `i`: the base (0), links `1..n`, then the obstacles.
        let count = n + 1 + self.obstacles.len();
        let body = |i: usize| match i {
            0 => Body::Base,
            i if i <= n => Body::Link(i),
            i => Body::Obstacle(i - n),
        };
        let index = |body: Body| match body {
            Body::Base => 0,
            Body::Link(k) => k,
            Body::Obstacle(k) => n + k,
        };
        let frame = |i: usize| if i <= n { frames[i] } else { inertial };
        // The bodies' capsules and the pairs' bounds first: only the bodies of a pair within
        // `far` have their shapes placed (the same points, bit for bit, as every body placed).
        capsules.clear();
        bounds.clear();
        bounded.clear();
        needed.clear();
        needed.resize(count, !(far < f64::INFINITY));
        if far < f64::INFINITY {
            for i in 0..count {
                let (shapes, (pose, (s, c))) = (self.shapes(body(i)), frame(i));
                capsules.push(if shapes.is_empty() {
                    ([[0.0; 2]; 2], f64::INFINITY)
                } else {
                    placed_capsule(shapes, [pose.x.re(), pose.y.re(), s.re(), c.re()])
                });
            }
            for &(a, b) in pairs {
                let (ia, ib) = (index(a), index(b));
                let bound = capsule_bound(capsules[ia], capsules[ib]);
                bounds.push(bound);
                bounded.push(bound > far);
                if !(bound > far) {
                    (needed[ia], needed[ib]) = (true, true);
                }
            }
        } else {
            bounded.resize(pairs.len(), false);
        }
        // The needed bodies' shapes placed once, with their frame's sine and cosine (the same
        // points, bit for bit, as [`crate::model::geometry::Shape::placed`]).
        points.clear();
        ranges.clear();
        first.clear();
        real.clear();
        discs.clear();
        for (i, &need) in needed.iter().enumerate() {
            first.push(ranges.len());
            if !need {
                continue;
            }
            let (pose, sin_cos) = frame(i);
            for shape in self.shapes(body(i)) {
                let from = points.len();
                shape.placed_into(&pose, sin_cos, points);
                ranges.push((from, points.len()));
            }
        }
        out.clear();
        for (k, &(a, b)) in pairs.iter().enumerate() {
            if bounded[k] {
                out.push(PairClearance { a, b, distance: D::from(bounds[k]) });
                continue;
            }
            let (ia, ib) = (index(a), index(b));
            let (sa, sb) = (self.shapes(a), self.shapes(b));
            // The pair of shapes of least distance by the real parts (a union's distance is its
            // least; of equal ones the first in the shapes' order), then that pair alone in `D`:
            // the same value and derivatives as every pair in `D`. One shape each: that pair,
            // without its distance in the real parts first (the same pair, half the work).
            // Otherwise the pair of least [`disc_bound`] first, then every other pair whose
            // bound is not above the least distance found (a pair above it is not nearer: a box
            // against a link's spheres, most of them far).
            let best = if sa.len() == 1 && sb.len() == 1 {
                Some((0, 0))
            } else if sa.is_empty() || sb.is_empty() {
                None
            } else {
                if real.is_empty() {
                    real.extend(points.iter().map(|p| [p[0].re(), p[1].re()]));
                    for i in (0..count).filter(|&i| needed[i]) {
                        for (j, shape) in self.shapes(body(i)).iter().enumerate() {
                            let (from, to) = ranges[first[i] + j];
                            discs.push(disc(&real[from..to], shape.radius));
                        }
                    }
                }
                let re = |body: usize, shape: usize| {
                    let (from, to) = ranges[first[body] + shape];
                    &real[from..to]
                };
                let nb = sb.len();
                gaps.clear();
                for i in 0..sa.len() {
                    gaps.extend((0..nb).map(|j| discs_gap(discs[first[ia] + i], discs[first[ib] + j])));
                }
                let distance = |k: usize| {
                    let (i, j) = (k / nb, k % nb);
                    signed_distance(re(ia, i), sa[i].radius, re(ib, j), sb[j].radius)
                };
                let start = (0..gaps.len()).fold(0, |m, k| if gaps[k] < gaps[m] { k } else { m });
                let (mut at, mut least) = (start, distance(start));
                for (k, &gap) in gaps.iter().enumerate() {
                    if k == start || gap > least {
                        continue;
                    }
                    let d = distance(k);
                    if d < least || (d <= least && k < at) {
                        (at, least) = (k, d);
                    }
                }
                Some((at / nb, at % nb))
            };
            let placed = |body: usize, shape: usize| {
                let (from, to) = ranges[first[body] + shape];
                &points[from..to]
            };
            let distance = match best {
                Some((i, j)) => signed_distance(placed(ia, i), sa[i].radius, placed(ib, j), sb[j].radius),
                None => D::from(f64::INFINITY),
            };
            out.push(PairClearance { a, b, distance });
        }
    }
}

#[cfg(test)]
mod tests;
