//! The clearance between the robot's own bodies (issue 21 items 3, 4; docs/spec.md §2) as
//! constraints of the minimum-effort planner: for every pair of the robot's bodies that
//! [`Geometry::pairs`] checks, the row `(c_min + margin - d_ab(theta(t))) / L <= 0` at the ends of
//! [`PIECES`] equal parts of every knot span, `c_min` the clearance asked for and `L` the arm's
//! mean link length (rows of order one, as the limits' are). Such a distance does not depend on
//! the base angle `phi`: turning the whole system about its centre of mass (what `phi` does at
//! fixed `theta`) moves no body relative to another, so each row is local in the coefficients.
//! A body against an obstacle (fixed in the inertial frame, as the system's centre of mass is)
//! does depend on `phi(t) = phi(0) - integral_0^t g` (Eq. 7 at zero momentum), so its row takes
//! `phi(t)`'s exact gradient in every coefficient before `t` ([`Limited::phi_path`]): dense in
//! the path up to `t`, and `d d_ab / d phi` times that gradient beside the local terms. The QP
//! takes such a row in its local form, the local terms and `phi(t_k)`'s change
//! ([`crate::planners::optimal::sqp::Running`]): a few dozen dense rows had filled its KKT
//! factor whole (3-link obstacle bench: factor 5630 -> 2524 nonzeros, the plan's instructions
//! 2.92 -> 2.12 G, the same plan).
//!
//! The signed distances are exact and so are their derivatives: one dual-number pass of
//! [`Geometry::clearances`] per joint angle, then the chain rule through the basis' values. The
//! rows hold at the points only; between them a distance can dip by about `h^2 max |d''| / 8` on
//! a spacing `h` (or more where the nearest features change), so each row keeps [`MARGIN`] more
//! than asked, and the certificate judges the continuous motion ([`crate::plan::clearance`]):
//! the planner solves a plan under the clearance again, keeping more (`certified_clear`). The
//! rows at `t = 0` and `t = T` are left out: the start and goal are fixed.

use nalgebra::{Const, U1};
use num_dual::{Derivative, DualSVec64};

use super::{Limited, PathPoint};
use crate::model::arm::collision::{Body, Geometry, Placement};
use crate::planners::chain::ClearanceRise;
use crate::planners::optimal::sqp::{Discretised, Inequalities, Running, RunningRow};

/// Points per knot span at which every pair's clearance is bounded.
pub(crate) const PIECES: usize = 4;

/// Points per knot span with an obstacle: a link sweeps past a small obstacle between rows
/// that are further apart (its tip moves about 6 cm in a quarter span of a 10 s plan at 1 m/s).
pub(super) const OBSTACLE_PIECES: usize = 16;

/// Coordinates differentiated together in one vector-dual pass of the distances.
const CHUNK: usize = 4;

/// The vector dual number of one pass.
type Multi = DualSVec64<CHUNK>;

/// Extra clearance each row keeps \[m\] (a distance's dip between points, module docs).
const MARGIN: f64 = 1e-3;

/// What a carried lower bound loses at each point beyond its bodies' motion \[m\]: the rounding
/// of the bounds and of the motion's sum (about `1e-15` m on an arm of a metre).
const MOVED_SLACK: f64 = 1e-9;

/// A body's row against an obstacle carries its gradient only within this distance of the
/// clearance kept \[m\]: the dense rows of far bodies would fill the QP's factor for nothing.
const NEAR: f64 = 0.1;

/// The clearance rows of an arm with shapes.
#[derive(Debug, Clone)]
pub(super) struct Clearance {
    /// The least distance each row keeps \[m\]: the clearance asked for, [`MARGIN`] and the
    /// reserve.
    keep: f64,
    /// `1 / L` \[1/m\].
    scale: f64,
    /// Some body against an obstacle is checked: those pairs get rows too (through `phi(t)`).
    obstacles: bool,
    /// The pairs with a row, in [`Geometry::pairs`]' order (found once, not at every point).
    pairs: Vec<(Body, Body)>,
    /// Points per knot span of the rows of the robot's own bodies ([`PIECES`] unless set).
    pieces: usize,
    /// The times where they hold at `pieces` points per span, at [`PIECES`] in the other spans
    /// (none: `pieces` everywhere).
    dense: Option<std::sync::Arc<[[f64; 2]]>>,
    /// The clearance kept beyond `keep` rising from none at `t = 0` to all of it at the rise's
    /// end ([`crate::planners::chain::ClearanceRise`]).
    rise: ClearanceRise,
    /// The distances of the last evaluation of the values alone, with obstacles.
    last: std::cell::RefCell<Distances>,
    /// Each pair's bodies' capsules' speed bounds ([`Geometry::capsule_speeds`]), summed.
    speeds: Vec<Vec<f64>>,
}

/// The distances of an evaluation of the values alone with obstacles, at coefficients `key`: the
/// SQP takes the rows' gradients at the point of its last trial when it accepts the step
/// (`crate::planners::optimal::sqp::inequality`), where the same coefficients give the same
/// `theta(t)` and `phi(t)` (the same bits at either order, [`Limited::phi_path_each`]) and so
/// the same distances: each point's are taken again where its `phi(t)` is the one recorded
/// (3-link obstacle bench: half of the `f64` distance passes).
#[derive(Debug, Clone, Default)]
struct Distances {
    /// The coefficients' bits.
    key: Vec<u64>,
    /// Each point's `phi(t)` bits (the points before the horizon's end, in order).
    phi: Vec<u64>,
    /// Each point's distances of every pair ([`Geometry::clearances_beyond`]'s, bounds where
    /// bounded), `pairs` per point.
    values: Vec<f64>,
    /// Whether each is a bound ([`crate::model::arm::collision::Placement::bounded`]).
    bounded: Vec<bool>,
}

impl Clearance {
    /// The rows for the arm's geometry, the obstacles' pairs only with `obstacles`, each keeping
    /// `reserve` \[m\] more ([`crate::planners::chain::ChainOptions::clearance_reserve`]);
    /// and `rise` more from its end on; `None` when no pair has a row.
    /// An obstacle out of a body's reach ([`Geometry::pairs_within`]) gets no rows with it: a far
    /// one would turn on the dense rows through `phi(t)` for nothing (the certificate still
    /// checks every pair).
    pub(super) fn new(
        arm: &crate::model::arm::Arm,
        obstacles: bool,
        reserve: f64,
        rise: ClearanceRise,
    ) -> Option<Self> {
        let geometry: &Geometry = &arm.geometry;
        let pairs = geometry.pairs_within(arm, geometry.clearance + MARGIN + reserve + rise.extra);
        let against = |&(_, b): &(Body, Body)| matches!(b, Body::Obstacle(_));
        let obstacles = obstacles && pairs.iter().any(against);
        if !obstacles && pairs.iter().all(against) {
            return None;
        }
        let mean = arm.links.iter().map(|l| l.length).sum::<f64>() / arm.joints() as f64;
        let pairs: Vec<(Body, Body)> = pairs.into_iter().filter(|pair| obstacles || !against(pair)).collect();
        let (n, bodies) = (arm.joints(), geometry.capsule_speeds(arm));
        let index = |b: Body| match b {
            Body::Base => 0,
            Body::Link(k) => k,
            Body::Obstacle(k) => n + k,
        };
        let speeds =
            pairs.iter().map(|&(a, b)| bodies[index(a)].iter().zip(&bodies[index(b)]).map(|(x, y)| x + y).collect());
        let speeds = speeds.collect();
        Some(Self {
            keep: geometry.clearance + MARGIN + reserve,
            scale: 1.0 / mean.max(1e-3),
            obstacles,
            pairs,
            pieces: PIECES,
            dense: None,
            rise,
            last: Default::default(),
            speeds,
        })
    }

    /// The same rows at `pieces` points per knot span (at least one) where no obstacle has rows:
    /// in the spans that meet a window of `dense` only, where given, at [`PIECES`] elsewhere.
    pub(super) fn at(self, pieces: usize, dense: Option<std::sync::Arc<[[f64; 2]]>>) -> Self {
        Self { pieces: pieces.max(1), dense, ..self }
    }

    /// The least distance the rows at time `t` keep \[m\].
    fn keep_at(&self, t: f64) -> f64 {
        self.keep + self.rise.at(t)
    }
}

/// True when some body can come within the clearance (and the rows' margin and `reserve`) of
/// an obstacle: [`Geometry::pairs_within`].
pub(crate) fn obstacles_within_reach(arm: &crate::model::arm::Arm, reserve: f64) -> bool {
    let keep = arm.geometry.clearance + MARGIN + reserve;
    arm.geometry.pairs_within(arm, keep).iter().any(|(_, b)| matches!(b, Body::Obstacle(_)))
}

impl Limited<'_> {
    /// The points of the rows of the robot's own bodies: `rows.pieces` per knot span, or in the
    /// spans outside `rows.dense`'s windows [`PIECES`].
    fn own_points(&self, rows: &Clearance) -> Vec<PathPoint> {
        let Some(dense) = &rows.dense else { return self.path_points(rows.pieces) };
        let (b, p) = (self.disc.basis().breakpoints(), self.disc.basis().degree());
        let near = |span: usize| dense.iter().any(|w| w[0] < b[span - p + 1] && b[span - p] < w[1]);
        let mut points: Vec<PathPoint> = self.path_points(rows.pieces).into_iter().filter(|x| near(x.span)).collect();
        points.extend(self.path_points(PIECES.min(rows.pieces)).into_iter().filter(|x| !near(x.span)));
        points.sort_by(|x, y| x.t.total_cmp(&y.t));
        points
    }

    /// The clearance rows (one per pair and point) into `out`.
    pub(super) fn clearance(&self, c: &[Vec<f64>], order: usize, out: &mut Inequalities) {
        let Some(rows) = &self.clearance else { return };
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let geometry = &self.arm.geometry;
        let horizon = basis.horizon();
        let mut q = vec![0.0; n + 1];
        // Distances between the robot's own bodies do not change when the whole system turns
        // about its centre of mass, which is what `phi` does at fixed `theta`: without obstacles
        // the base angle is not needed, and the rows are local in the coefficients.
        let from = if rows.obstacles { 0 } else { 1 };
        let dim = self.disc.dim();
        let mut slopes_of_phi = self.phi_slopes.borrow_mut();
        if order >= 1 {
            slopes_of_phi.clear();
        }
        let mut index = 0;
        // The rows against an obstacle in their local form through `phi(t_k)` (the QP's banded
        // form, [`crate::planners::optimal::sqp::Running`]), and `phi`'s gradient at the last point.
        let mut running = Running::default();
        let mut before = vec![0.0; if rows.obstacles && order >= 1 { dim } else { 0 }];
        // The distances' buffers, kept from point to point (no allocation at each).
        let (mut placement, mut real) = (Placement::<f64>::default(), Vec::with_capacity(rows.pairs.len()));
        let (mut dual_placement, mut dual) = (Placement::<Multi>::default(), Vec::with_capacity(rows.pairs.len()));
        // `d d_ab / d q_i` of pair `k` at `slopes[k (n + 1) + i]`.
        let mut slopes: Vec<f64> = Vec::new();
        // Each pair's work space, kept from point to point.
        let against_obstacle: Vec<bool> = rows.pairs.iter().map(|(_, b)| matches!(b, Body::Obstacle(_))).collect();
        let (mut values, mut bounded) = (vec![0.0; rows.pairs.len()], vec![false; rows.pairs.len()]);
        let (mut wanted, mut subset): (Vec<usize>, Vec<(Body, Body)>) = (Vec::new(), Vec::new());
        let mut dq: Vec<Multi> = Vec::with_capacity(n + 1);
        let mut dense: Vec<f64> = Vec::new();
        // The last distances of the values alone, taken again at the same coefficients (order
        // 1), or recorded anew (order 0), with obstacles only: the order-1 pass without them
        // takes no distances in `f64`.
        let key: Vec<u64> = if rows.obstacles { c.iter().flatten().map(|v| v.to_bits()).collect() } else { Vec::new() };
        let mut last = rows.last.borrow_mut();
        let same = order >= 1 && rows.obstacles && last.key == key;
        let mut fresh = Distances::default();
        let (m, mut evaluated) = (rows.pairs.len(), 0);
        // The values alone: a lower bound on each pair's distance carried from the last point
        // where it was found, less what its bodies can have moved since
        // ([`Geometry::capsule_speeds`]: at most the speed bounds times the coordinates'
        // changes); where every pair's is beyond `far`, the point keeps those bounds and takes
        // no distances (a bound beyond `far` is what `clearances_beyond` gives such a pair, and
        // its row's value is read only as negative: no gradient, never sent to the QP, none in
        // the merit function). On the 3-link obstacle bench most points are far from the obstacle.
        let (mut lower, mut last_q, mut moved) = (vec![f64::NEG_INFINITY; m], vec![f64::NAN; n + 1], vec![0.0; n + 1]);
        let mut at = |point: PathPoint<&[f64]>| {
            let this = index;
            index += 1;
            if !before.is_empty() {
                // Only the coefficients of the point's span change `phi` since the last point.
                let mut step = Vec::with_capacity((p + 1) * n);
                for l in 0..=p {
                    for j in 0..n {
                        let Some(k) = self.index(point.span - p + l, j) else { continue };
                        let change = point.grad[k] - before[k];
                        if change != 0.0 {
                            step.push((k, change));
                            before[k] = point.grad[k];
                        }
                    }
                }
                running.steps.push(step);
            }
            if point.t >= horizon {
                return;
            }
            let first = point.span - p;
            let keep = rows.keep_at(point.t);
            let [value, _] = point.values;
            q[0] = point.phi;
            for j in 0..n {
                q[j + 1] = (0..=p).map(|l| value[l] * c[j][first + l]).sum();
            }
            // A pair whose bodies' bounding capsules are farther apart than `keep + NEAR` has that
            // bound as its distance where no gradient is wanted (`Geometry::clearances_beyond`):
            // in the values alone (order 0), which the merit function reads as `max(0, g)`, zero
            // either way, and a body's row against an obstacle at order 1 (below: no gradient
            // there, a value under `-NEAR / L`, which the QP never sends). The robot's own pairs
            // keep their exact values and gradients at order 1: without them the QP's steps went
            // through a far pair of bodies (the SPART-like bench's plan 5.3854 -> 7.4516, a
            // different minimum), a step of more than NEAR.
            let far = keep + NEAR;
            let k = evaluated;
            evaluated += 1;
            if order == 0 {
                // (The first point's bounds are -inf: `last_q` NaN keeps them so.)
                moved.iter_mut().zip(q.iter().zip(&last_q)).for_each(|(d, (a, b))| *d = (a - b).abs());
                for (bound, speeds) in lower.iter_mut().zip(&rows.speeds) {
                    *bound -= speeds.iter().zip(&moved).map(|(l, d)| l * d).sum::<f64>() + MOVED_SLACK;
                }
                last_q.copy_from_slice(&q);
                let far_apart = lower.iter().all(|b| *b > far);
                if !far_apart {
                    geometry.clearances_beyond(self.arm, &q, &rows.pairs, far, &mut placement, &mut real);
                    lower.iter_mut().zip(&real).for_each(|(b, x)| *b = x.distance);
                }
                out.values.extend(lower.iter().map(|d| (keep - d) * rows.scale));
                if rows.obstacles {
                    fresh.phi.push(point.phi.to_bits());
                    fresh.values.extend_from_slice(&lower);
                    match far_apart {
                        true => fresh.bounded.extend(std::iter::repeat_n(true, m)),
                        false => fresh.bounded.extend_from_slice(placement.bounded()),
                    }
                }
                return;
            }
            // The distances in `f64` first where obstacles have rows: a body's row against an
            // obstacle carries its gradient only within NEAR (below), and most are farther, so
            // the dual pass takes only the pairs whose gradient a row carries (3-link obstacle
            // bench: 7.35 -> 7.15 G instructions, the same plan); the robot's own pairs all carry
            // theirs, and their values come with the dual pass.
            values.iter_mut().for_each(|v| *v = 0.0);
            bounded.iter_mut().for_each(|b| *b = false);
            if rows.obstacles && same && last.phi.get(k) == Some(&point.phi.to_bits()) {
                values.copy_from_slice(&last.values[k * m..(k + 1) * m]);
                bounded.copy_from_slice(&last.bounded[k * m..(k + 1) * m]);
            } else if rows.obstacles {
                geometry.clearances_beyond(self.arm, &q, &rows.pairs, far, &mut placement, &mut real);
                values.iter_mut().zip(&real).for_each(|(v, x)| *v = x.distance);
                bounded.copy_from_slice(placement.bounded());
            }
            wanted.clear();
            wanted.extend((0..rows.pairs.len()).filter(|&k| !against_obstacle[k] || (!bounded[k] && values[k] <= far)));
            subset.clear();
            subset.extend(wanted.iter().map(|&k| rows.pairs[k]));
            // d d_ab / d q_i, one vector-dual pass per CHUNK coordinates (phi's only with
            // obstacles): the same exact derivatives as one pass per coordinate, with the poses'
            // sines and cosines computed once per pass.
            slopes.clear();
            slopes.resize(rows.pairs.len() * (n + 1), 0.0);
            for start in (from..=n).step_by(CHUNK) {
                if subset.is_empty() {
                    break;
                }
                dq.clear();
                dq.extend(q.iter().enumerate().map(|(k, &v)| match k.checked_sub(start).filter(|r| *r < CHUNK) {
                    Some(r) => Multi::new(v, Derivative::derivative_generic(Const::<CHUNK>, U1, r)),
                    None => Multi::from(v),
                }));
                geometry.clearances_into(self.arm, &dq, &subset, &mut dual_placement, &mut dual);
                for (&k, x) in wanted.iter().zip(&dual) {
                    if !against_obstacle[k] {
                        values[k] = x.distance.re;
                    }
                    let eps = x.distance.eps.unwrap_generic(Const::<CHUNK>, U1);
                    for (r, slot) in slopes[k * (n + 1)..][..n + 1].iter_mut().skip(start).take(CHUNK).enumerate() {
                        *slot = eps[r];
                    }
                }
            }
            for (k, ((d, s), against)) in values.iter().zip(slopes.chunks(n + 1)).zip(&against_obstacle).enumerate() {
                out.values.push((keep - d) * rows.scale);
                // Through theta(t): the p + 1 coefficients of the span, per joint; and against
                // an obstacle through phi(t) too, whose gradient reaches every earlier one.
                // A body more than NEAR from the obstacle keeps its row but not its dense
                // gradient: the row cannot become active in one step (the merit function judges
                // every step on the rows' values), and the QP stays sparse.
                if *against && (bounded[k] || *d > keep + NEAR) {
                    out.rows.push(Vec::new());
                    continue;
                }
                if *against {
                    slopes_of_phi.push((out.values.len() - 1, this, -rows.scale * s[0]));
                }
                dense.clear();
                dense.resize(if *against { dim } else { 0 }, 0.0);
                for (k, g) in dense.iter_mut().zip(point.grad) {
                    *k = -rows.scale * s[0] * g;
                }
                let mut row: Vec<(usize, f64)> = Vec::with_capacity((p + 1) * n);
                for (l, v) in value.iter().enumerate().take(p + 1) {
                    for j in 0..n {
                        if let Some(idx) = self.index(first + l, j) {
                            let term = -rows.scale * s[j + 1] * v;
                            if let Some(slot) = dense.get_mut(idx) {
                                *slot += term;
                            }
                            row.push((idx, term));
                        }
                    }
                }
                if *against {
                    let local = std::mem::replace(
                        &mut row,
                        dense.iter().copied().enumerate().filter(|(_, v)| *v != 0.0).collect(),
                    );
                    let (at, slope) = (out.values.len() - 1, -rows.scale * s[0]);
                    running.rows.push(RunningRow { row: at, point: this, slope, local });
                }
                out.rows.push(row);
            }
        };
        if rows.obstacles {
            self.phi_path_each(c, OBSTACLE_PIECES, order, at);
            if order >= 1 {
                out.running = Some(running);
            } else {
                *last = Distances { key, ..fresh };
            }
        } else {
            for p in self.own_points(rows) {
                at(PathPoint { t: p.t, span: p.span, phi: p.phi, grad: &p.grad[..], values: p.values });
            }
        }
    }
}
