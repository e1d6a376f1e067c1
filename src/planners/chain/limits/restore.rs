//! A solve that stalled near the holonomy moved onto it: the final error of a plan is certified
//! to 1e-9 rad, and the SQP of a plan that keeps clearance and rides its limits can stall a little
//! above that (the SPART-like tight fixture with its shapes, T = 24 s, clearance 0.015 m, limits
//! less 5 %: the re-solve with denser rows stopped at `c = 1.3e-6` rad, KKT residual 0.06).

use nalgebra::{DMatrix, DVector};

use super::{Limited, constrained};
use crate::planners::chain::ChainPlanner;
use crate::planners::chain::discrete::Discretisation;
use crate::planners::optimal::sqp::{Discretised, SqpResult};

/// The largest holonomy residual \[rad\] a stalled solve is moved from.
const RESIDUAL: f64 = 1e-5;

/// Rows within this of their limit (each row is scaled to its limit: 0 on it, -1 at zero use)
/// are held where they are by the step.
const ACTIVE: f64 = 1e-4;

/// Moves `result`'s point onto `c = 0` by least-norm steps (at most three) that keep every row
/// within [`ACTIVE`] of its limit where it is to first order: `A d = (-c, 0, ..)` with `A` the
/// holonomy's gradient over the active rows' gradients (the least-squares solution of least norm,
/// by SVD). A step is kept only where `|c|` falls and no row is violated more than before it;
/// the cost and residual follow. A converged solve, one further than [`RESIDUAL`] from the
/// holonomy, or a planner without rows is left as it is. The certificate judges the result as it
/// judges every plan.
pub(crate) fn onto_holonomy(planner: &ChainPlanner, disc: &Discretisation, result: &mut SqpResult) {
    if result.converged() || !(result.c.abs() <= RESIDUAL) || !constrained(planner) {
        return;
    }
    let Some(limited) = Limited::new(planner, disc) else { return };
    // The largest violation `max(0, g_i)` of the rows.
    let largest = |values: &[f64]| values.iter().fold(0.0_f64, |m, v| m.max(*v));
    let worst = |x: &DVector<f64>| limited.inequalities(x, 0).map_or(0.0, |g| largest(&g.values));
    for _ in 0..3 {
        let x = &result.x;
        let e = disc.evaluate(x, 1);
        if e.c == 0.0 || !e.c.is_finite() {
            break;
        }
        let g = limited.inequalities(x, 1);
        let before = g.as_ref().map_or(0.0, |g| largest(&g.values));
        let active: Vec<&Vec<(usize, f64)>> = g
            .as_ref()
            .map(|g| g.values.iter().zip(&g.rows).filter(|(v, _)| **v > -ACTIVE).map(|(_, r)| r).collect())
            .unwrap_or_default();
        let mut a = DMatrix::zeros(1 + active.len(), x.len());
        a.row_mut(0).copy_from(&e.grad_c.transpose());
        for (r, row) in active.iter().enumerate() {
            for &(i, v) in row.iter() {
                a[(r + 1, i)] += v;
            }
        }
        let mut rhs = DVector::zeros(1 + active.len());
        rhs[0] = -e.c;
        let Ok(d) = a.svd(true, true).solve(&rhs, 1e-14) else { break };
        let next_x = x + d;
        let next = disc.evaluate(&next_x, 0);
        if !(next.c.abs() < e.c.abs() && next.f.is_finite() && worst(&next_x) <= before + 1e-12) {
            break;
        }
        result.x = next_x;
        (result.f, result.c) = (next.f, next.c);
    }
}
