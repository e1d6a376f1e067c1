//! The rows beside the evaluation: the SQP asks for the inequalities at every point where it
//! evaluates the cost and the holonomy, and at the same order (values at a trial point, first
//! derivatives with the Hessians at an accepted iterate; `sqp::inequality`, the augmented
//! Lagrangian of `chain::augmented`). The two do not depend on each other, so the evaluation of
//! the discretisation runs on another thread while the rows are found on this one, and the rows
//! are kept for the request that follows: the same values, in the wall time of the rows alone
//! (the 3-link obstacle bench's evaluations are about a twentieth of its instructions, its rows a
//! third).

use nalgebra::DVector;

use super::Limited;
use crate::planners::optimal::discrete::Evaluation;
use crate::planners::optimal::sqp::{Discretised, Inequalities};

/// Rows found beside an evaluation: the bits of its point, the order, the rows.
#[derive(Debug, Clone)]
pub(super) struct Beside {
    key: Vec<u64>,
    order: usize,
    rows: Inequalities,
}

impl Limited<'_> {
    /// The discretisation's evaluation at `x` ([`Discretised::evaluate`]), with the rows at `x`
    /// at order `min(order, 1)` found beside it and kept ([`Limited::taken_beside`]).
    pub(super) fn evaluate_beside(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        let disc = self.disc;
        let mut evaluation = None;
        let rows = rayon::in_place_scope(|scope| {
            scope.spawn(|_| evaluation = Some(disc.evaluate(x, order)));
            self.rows(x, order.min(1))
        });
        let key = x.iter().map(|v| v.to_bits()).collect();
        *self.beside.borrow_mut() = Some(Beside { key, order: order.min(1), rows });
        evaluation.expect("invariant: the scope ends after its spawned evaluation")
    }

    /// The rows kept beside the last evaluation where it was at `x` and `order` (taken: asked
    /// once), else `None`.
    pub(super) fn taken_beside(&self, x: &DVector<f64>, order: usize) -> Option<Inequalities> {
        let mut kept = self.beside.borrow_mut();
        let same = kept.as_ref().is_some_and(|b| {
            b.order == order && b.key.len() == x.len() && b.key.iter().zip(x.iter()).all(|(k, v)| *k == v.to_bits())
        });
        if same { kept.take().map(|b| b.rows) } else { None }
    }
}
