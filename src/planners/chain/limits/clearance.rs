//! The clearance between the robot's own bodies (issue 21 items 3, 4; docs/spec.md §2) as
//! constraints of the minimum-effort planner: for every pair of the robot's bodies that
//! [`Geometry::pairs`] checks, the row `(c_min + margin - d_ab(theta(t))) / L <= 0` at the ends of
//! [`PIECES`] equal parts of every knot span, `c_min` the clearance asked for and `L` the arm's
//! mean link length (rows of order one, as the limits' are). Such a distance does not depend on
//! the base angle `phi`: turning the whole system about its centre of mass (what `phi` does at
//! fixed `theta`) moves no body relative to another, so each row is local in the coefficients.
//! Obstacle pairs are not constrained yet (their rows would depend on `phi(t)`, the whole path up
//! to `t`); the certificate checks them.
//!
//! The signed distances are exact and so are their derivatives: one dual-number pass of
//! [`Geometry::clearances`] per joint angle, then the chain rule through the basis' values. The
//! rows hold at the points only; between them a distance can dip by about `h^2 max |d''| / 8` on
//! a spacing `h` (or more where the nearest features change), so each row keeps [`MARGIN`] more
//! than asked, and the certificate judges the continuous motion ([`crate::plan::clearance`]):
//! the planner solves a plan under the clearance again, keeping more (`certified_clear`). The
//! rows at `t = 0` and `t = T` are left out: the start and goal are fixed.

use num_dual::Dual64;

use super::Limited;
use crate::model::arm::collision::{Body, Geometry, PairClearance};
use crate::planners::optimal::sqp::Inequalities;

/// Points per knot span at which every pair's clearance is bounded.
pub(super) const PIECES: usize = 4;

/// Extra clearance each row keeps \[m\] (a distance's dip between points, module docs).
const MARGIN: f64 = 1e-3;

/// The clearance rows of an arm with shapes.
#[derive(Debug, Clone)]
pub(super) struct Clearance {
    /// The least distance each row keeps \[m\]: the clearance asked for and [`MARGIN`].
    keep: f64,
    /// `1 / L` \[1/m\].
    scale: f64,
}

impl Clearance {
    /// The rows for the arm's geometry; `None` when no pair of its own bodies is checked.
    pub(super) fn new(arm: &crate::model::arm::Arm) -> Option<Self> {
        let geometry: &Geometry = &arm.geometry;
        if !geometry.pairs(arm.joints()).iter().any(|&(_, b)| !matches!(b, Body::Obstacle(_))) {
            return None;
        }
        let mean = arm.links.iter().map(|l| l.length).sum::<f64>() / arm.joints() as f64;
        Some(Self { keep: geometry.clearance + MARGIN, scale: 1.0 / mean.max(1e-3) })
    }
}

/// True for a pair of the robot's own bodies (not an obstacle).
fn own<D>(pair: &PairClearance<D>) -> bool {
    !matches!(pair.b, Body::Obstacle(_))
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
        // about its centre of mass, which is what `phi` does at fixed `theta`: the base angle is
        // not needed, and the rows are local in the coefficients.
        for point in self.path_points(PIECES) {
            if point.t >= horizon {
                continue;
            }
            let first = point.span - p;
            let [value, _] = basis.values_and_rates(point.span, point.t);
            q[0] = point.phi;
            for j in 0..n {
                q[j + 1] = (0..=p).map(|l| value[l] * c[j][first + l]).sum();
            }
            if order == 0 {
                for pair in geometry.clearances(self.arm, &q).into_iter().filter(own) {
                    out.values.push((rows.keep - pair.distance) * rows.scale);
                }
                continue;
            }
            // d d_ab / d q_i, one dual pass per coordinate.
            let mut slopes: Vec<Vec<f64>> = Vec::new();
            let mut values = Vec::new();
            for i in 1..=n {
                let dq: Vec<Dual64> = q
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| if k == i { Dual64::new(v, 1.0) } else { Dual64::from(v) })
                    .collect();
                let pairs: Vec<_> = geometry.clearances(self.arm, &dq).into_iter().filter(own).collect();
                if slopes.is_empty() {
                    values = pairs.iter().map(|x| x.distance.re).collect();
                    slopes = vec![vec![0.0; n + 1]; pairs.len()];
                }
                for (s, x) in slopes.iter_mut().zip(&pairs) {
                    s[i] = x.distance.eps;
                }
            }
            for (d, s) in values.iter().zip(&slopes) {
                out.values.push((rows.keep - d) * rows.scale);
                // Through theta(t): the p + 1 coefficients of the span, per joint.
                let mut row: Vec<(usize, f64)> = Vec::with_capacity((p + 1) * n);
                for (l, v) in value.iter().enumerate().take(p + 1) {
                    for j in 0..n {
                        if let Some(idx) = self.index(first + l, j) {
                            row.push((idx, -rows.scale * s[j + 1] * v));
                        }
                    }
                }
                out.rows.push(row);
            }
        }
    }
}
