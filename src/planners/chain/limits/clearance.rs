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
//! the path up to `t`, and `d d_ab / d phi` times that gradient beside the local terms.
//!
//! The signed distances are exact and so are their derivatives: one dual-number pass of
//! [`Geometry::clearances`] per joint angle, then the chain rule through the basis' values. The
//! rows hold at the points only; between them a distance can dip by about `h^2 max |d''| / 8` on
//! a spacing `h` (or more where the nearest features change), so each row keeps [`MARGIN`] more
//! than asked, and the certificate judges the continuous motion ([`crate::plan::clearance`]):
//! the planner solves a plan under the clearance again, keeping more (`certified_clear`). The
//! rows at `t = 0` and `t = T` are left out: the start and goal are fixed.

use nalgebra::{Const, DMatrix, U1};
use num_dual::{Derivative, DualSVec64, HyperDual64};

use super::{Limited, PathPoint};
use crate::model::arm::collision::{Body, Geometry, PairClearance};
use crate::planners::optimal::sqp::{Discretised, Inequalities};

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
}

impl Clearance {
    /// The rows for the arm's geometry, the obstacles' pairs only with `obstacles`, each keeping
    /// `reserve` \[m\] more ([`crate::planners::chain::ChainOptions::clearance_reserve`]);
    /// `None` when no pair has a row.
    pub(super) fn new(arm: &crate::model::arm::Arm, obstacles: bool, reserve: f64) -> Option<Self> {
        let geometry: &Geometry = &arm.geometry;
        let pairs = geometry.pairs(arm.joints());
        let against = |&(_, b): &(Body, Body)| matches!(b, Body::Obstacle(_));
        let obstacles = obstacles && pairs.iter().any(against);
        if !obstacles && pairs.iter().all(against) {
            return None;
        }
        let mean = arm.links.iter().map(|l| l.length).sum::<f64>() / arm.joints() as f64;
        let pairs = pairs.into_iter().filter(|pair| obstacles || !against(pair)).collect();
        Some(Self {
            keep: geometry.clearance + MARGIN + reserve,
            scale: 1.0 / mean.max(1e-3),
            obstacles,
            pairs,
            pieces: PIECES,
        })
    }

    /// The same rows at `pieces` points per knot span (at least one) where no obstacle has rows.
    pub(super) fn at(self, pieces: usize) -> Self {
        Self { pieces: pieces.max(1), ..self }
    }
}

/// True for a pair of a body and an obstacle.
fn obstacle<D>(pair: &PairClearance<D>) -> bool {
    matches!(pair.b, Body::Obstacle(_))
}

impl Limited<'_> {
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
        let mut at = |point: PathPoint<&[f64]>| {
            if point.t >= horizon {
                return;
            }
            let first = point.span - p;
            let [value, _] = basis.values_and_rates(point.span, point.t);
            q[0] = point.phi;
            for j in 0..n {
                q[j + 1] = (0..=p).map(|l| value[l] * c[j][first + l]).sum();
            }
            if order == 0 {
                for pair in geometry.clearances_of(self.arm, &q, &rows.pairs) {
                    out.values.push((rows.keep - pair.distance) * rows.scale);
                }
                return;
            }
            // d d_ab / d q_i, one vector-dual pass per CHUNK coordinates (phi's only with
            // obstacles): the same exact derivatives as one pass per coordinate, with the poses'
            // sines and cosines computed once per pass.
            let mut slopes: Vec<Vec<f64>> = Vec::new();
            let mut values = Vec::new();
            let mut against_obstacle = Vec::new();
            for start in (from..=n).step_by(CHUNK) {
                let dq: Vec<Multi> = q
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| match k.checked_sub(start).filter(|r| *r < CHUNK) {
                        Some(r) => Multi::new(v, Derivative::derivative_generic(Const::<CHUNK>, U1, r)),
                        None => Multi::from(v),
                    })
                    .collect();
                let pairs = geometry.clearances_of(self.arm, &dq, &rows.pairs);
                if slopes.is_empty() {
                    values = pairs.iter().map(|x| x.distance.re).collect();
                    against_obstacle = pairs.iter().map(obstacle).collect();
                    slopes = vec![vec![0.0; n + 1]; pairs.len()];
                }
                for (s, x) in slopes.iter_mut().zip(&pairs) {
                    let eps = x.distance.eps.unwrap_generic(Const::<CHUNK>, U1);
                    for (r, slot) in s.iter_mut().skip(start).take(CHUNK).enumerate() {
                        *slot = eps[r];
                    }
                }
            }
            for ((d, s), far) in values.iter().zip(&slopes).zip(&against_obstacle) {
                out.values.push((rows.keep - d) * rows.scale);
                // Through theta(t): the p + 1 coefficients of the span, per joint; and against
                // an obstacle through phi(t) too, whose gradient reaches every earlier one.
                // A body more than NEAR from the obstacle keeps its row but not its dense
                // gradient: the row cannot become active in one step (the merit function judges
                // every step on the rows' values), and the QP stays sparse.
                if *far && *d > rows.keep + NEAR {
                    out.rows.push(Vec::new());
                    continue;
                }
                let mut dense = vec![0.0; if *far { dim } else { 0 }];
                for (k, g) in dense.iter_mut().zip(point.grad) {
                    *k = -rows.scale * s[0] * g;
                }
                let mut row: Vec<(usize, f64)> = Vec::with_capacity((p + 1) * n);
                for (l, v) in value.iter().enumerate().take(p + 1) {
                    for j in 0..n {
                        if let Some(idx) = self.index(first + l, j) {
                            let term = -rows.scale * s[j + 1] * v;
                            match dense.get_mut(idx) {
                                Some(slot) => *slot += term,
                                None => row.push((idx, term)),
                            }
                        }
                    }
                }
                if *far {
                    row = dense.into_iter().enumerate().filter(|(_, v)| *v != 0.0).collect();
                }
                out.rows.push(row);
            }
        };
        if rows.obstacles {
            self.phi_path_each(c, OBSTACLE_PIECES, order, at);
        } else {
            for p in self.path_points(rows.pieces) {
                at(PathPoint { t: p.t, span: p.span, phi: p.phi, grad: &p.grad[..] });
            }
        }
    }
}

impl Limited<'_> {
    /// The number of rows before the clearance rows in [`Discretised::inequalities`]' order:
    /// the linear rows, the torque rows (two per joint and time) and the base range's (two per
    /// knot span).
    fn rows_before_clearance(&self) -> usize {
        let basis = self.disc.basis();
        let torque = if self.torque.is_empty() { 0 } else { 2 * self.torque.len() * super::torque_times(basis).len() };
        let base = if self.base.is_some() { 2 * (basis.breakpoints().len() - 1) } else { 0 };
        self.linear.len() + torque + base
    }

    /// Adds to `w` the positive semi-definite part of `z_i hess g_i` of every clearance row
    /// with a positive multiplier `z_i`, in the joint angles at its point: `-z_i / L` times
    /// the distance's Hessian in `theta(t)` (one hyper-dual pass of the pair per entry), its
    /// negative eigenvalues dropped, through the span's basis values (inside the band). A
    /// row against an obstacle keeps the Gauss–Newton model: its curvature through `phi(t)` is
    /// dense, and its part in `theta` alone made the 3-link arm's repair around its obstacle
    /// (`benches/clearance.rs`) stall at 26 iterations, its plan 0.069 m inside the obstacle.
    /// Without it the iteration converges linearly where a row of the robot's own bodies binds
    /// (its curvature is the part of the Lagrangian's Hessian the model misses): on the
    /// SPART-like bench 430 SQP iterations to effort 5.4668262247, with it 254 to 5.4302188385.
    pub(super) fn clearance_curvature(&self, c: &[Vec<f64>], z: &[f64], w: &mut DMatrix<f64>) {
        let Some(rows) = &self.clearance else { return };
        let z = &z[self.rows_before_clearance().min(z.len())..];
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let (geometry, horizon, count) = (&self.arm.geometry, basis.horizon(), rows.pairs.len());
        let mut q = vec![0.0; n + 1];
        let mut point_index = 0;
        let mut at = |t: f64, span: usize, phi: f64| {
            if t >= horizon {
                return;
            }
            let zs = z.get(point_index * count..(point_index + 1) * count).unwrap_or(&[]);
            point_index += 1;
            if zs.iter().all(|v| !(*v > 0.0)) {
                return;
            }
            let first = span - p;
            let [value, _] = basis.values_and_rates(span, t);
            q[0] = phi;
            for j in 0..n {
                q[j + 1] = (0..=p).map(|l| value[l] * c[j][first + l]).sum();
            }
            for (pair, &zi) in rows.pairs.iter().zip(zs) {
                if !(zi > 0.0) || matches!(pair.1, Body::Obstacle(_)) {
                    continue;
                }
                let mut h = DMatrix::zeros(n, n);
                let mut qd: Vec<HyperDual64> = q.iter().map(|&v| HyperDual64::from_re(v)).collect();
                for j in 0..n {
                    for k in j..n {
                        qd[j + 1] = qd[j + 1].derivative1();
                        qd[k + 1] = qd[k + 1].derivative2();
                        let d = geometry.clearances_of(self.arm, &qd, std::slice::from_ref(pair))[0].distance;
                        qd[j + 1] = HyperDual64::from_re(q[j + 1]);
                        qd[k + 1] = HyperDual64::from_re(q[k + 1]);
                        let v = -rows.scale * zi * d.eps1eps2;
                        (h[(j, k)], h[(k, j)]) = (v, v);
                    }
                }
                let eigen = h.symmetric_eigen();
                if eigen.eigenvalues.iter().all(|l| !(*l > 0.0)) {
                    continue;
                }
                let kept = eigen.eigenvalues.map(|l| l.max(0.0));
                let plus = &eigen.eigenvectors * DMatrix::from_diagonal(&kept) * eigen.eigenvectors.transpose();
                for l in 0..=p {
                    for m in 0..=p {
                        for j in 0..n {
                            for k in 0..n {
                                if let (Some(a), Some(b)) = (self.index(first + l, j), self.index(first + m, k)) {
                                    w[(a, b)] += value[l] * value[m] * plus[(j, k)];
                                }
                            }
                        }
                    }
                }
            }
        };
        if rows.obstacles {
            self.phi_path_each(c, OBSTACLE_PIECES, 0, |point| at(point.t, point.span, point.phi));
        } else {
            for point in self.path_points(rows.pieces) {
                at(point.t, point.span, point.phi);
            }
        }
    }
}
