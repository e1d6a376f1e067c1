//! The clearance (issue 21 item 4; docs/spec.md §2) as constraints of the minimum-effort
//! planner: for every pair of bodies [`Geometry::pairs`] checks, the row
//! `(c_min + margin - d_ab(q(t))) / L <= 0` at the ends of [`PIECES`] equal parts of every knot
//! span, `q(t) = (phi(t), theta(t))` with the base angle integrated along the path
//! ([`Limited::phi_path`], Eq. 7 at zero momentum), `c_min` the clearance asked for and `L` the
//! arm's mean link length (rows of order one, as the limits' are).
//!
//! The signed distances are exact and so are their derivatives in `q`: one dual-number pass of
//! [`Geometry::clearances`] per coordinate; in the free coefficients by the chain rule through
//! `theta(t)` (the basis' values) and `phi(t)` (its exact gradient). The rows hold at the points
//! only; between them a distance can dip by about `h^2 max |d''| / 8` on a spacing `h`, so each
//! row keeps [`MARGIN`] more than asked, and the certificate judges the continuous motion
//! ([`crate::plan::clearance`]): a plan under the clearance between points is never certified.
//! The rows at `t = 0` and `t = T` are left out: the start and goal are fixed.

use num_dual::Dual64;

use super::Limited;
use crate::model::arm::collision::Geometry;
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
    /// The rows for the arm's geometry; `None` when no pair is checked.
    pub(super) fn new(arm: &crate::model::arm::Arm) -> Option<Self> {
        let geometry: &Geometry = &arm.geometry;
        if geometry.pairs(arm.joints()).is_empty() {
            return None;
        }
        let mean = arm.links.iter().map(|l| l.length).sum::<f64>() / arm.joints() as f64;
        Some(Self { keep: geometry.clearance + MARGIN, scale: 1.0 / mean.max(1e-3) })
    }
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
        let turns = !geometry.obstacles.is_empty();
        let points = if turns { self.phi_path(c, PIECES, order) } else { self.path_points(PIECES) };
        for point in points {
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
                for pair in geometry.clearances(self.arm, &q) {
                    out.values.push((rows.keep - pair.distance) * rows.scale);
                }
                continue;
            }
            // d d_ab / d q_i, one dual pass per coordinate.
            let mut slopes: Vec<Vec<f64>> = Vec::new();
            let mut values = Vec::new();
            for i in usize::from(!turns)..=n {
                let dq: Vec<Dual64> = q
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| if k == i { Dual64::new(v, 1.0) } else { Dual64::from(v) })
                    .collect();
                let pairs = geometry.clearances(self.arm, &dq);
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
                let mut row: Vec<(usize, f64)> = Vec::with_capacity((p + 1) * n + point.grad.len());
                for (l, v) in value.iter().enumerate().take(p + 1) {
                    for j in 0..n {
                        if let Some(idx) = self.index(first + l, j) {
                            row.push((idx, -rows.scale * s[j + 1] * v));
                        }
                    }
                }
                // Through phi(t), with obstacles: every coefficient up to t.
                if turns {
                    for (idx, g) in point.grad.iter().enumerate().filter(|(_, g)| **g != 0.0) {
                        match row.iter_mut().find(|(i, _)| *i == idx) {
                            Some(e) => e.1 -= rows.scale * s[0] * g,
                            None => row.push((idx, -rows.scale * s[0] * g)),
                        }
                    }
                }
                out.rows.push(row);
            }
        }
    }
}
