//! Tests of the S-l1-QP path ([`super::inequality`]).

use nalgebra::{DMatrix, DVector};

use super::{Discretised, Inequalities, SqpOptions};
use crate::planners::optimal::band::BandCholesky;
use crate::planners::optimal::discrete::Evaluation;
use crate::planners::optimal::sqp;

/// `min 1/2 (x0^2 + (x1 - 0.3)^2 - x2^2) + 0.1 x2` subject to `x0 = 1`, `|x2| <= 1`: the
/// cost is concave in `x2`, so its Hessian is indefinite on the equality's tangent space,
/// and the bound `x2 >= -1` (multiplier 1.1) is what makes `x* = (1, 0.3, -1)` a strict
/// minimum (positive curvature on the null space of both gradients, the `x1` axis).
struct Concave {
    s: DMatrix<f64>,
    chol: BandCholesky,
}

impl Discretised for Concave {
    fn dim(&self) -> usize {
        3
    }
    fn half_bandwidth(&self) -> usize {
        2
    }
    fn effort_hessian(&self) -> &DMatrix<f64> {
        &self.s
    }
    fn effort_cholesky(&self) -> Option<&BandCholesky> {
        Some(&self.chol)
    }
    fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        let f = 0.5 * (x[0] * x[0] + (x[1] - 0.3).powi(2) - x[2] * x[2]) + 0.1 * x[2];
        let (grad_f, grad_c, hess_f, hess_c) = if order >= 1 {
            (
                DVector::from_vec(vec![x[0], x[1] - 0.3, 0.1 - x[2]]),
                DVector::from_vec(vec![1.0, 0.0, 0.0]),
                DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, -1.0])),
                DMatrix::zeros(3, 3),
            )
        } else {
            (DVector::zeros(0), DVector::zeros(0), DMatrix::zeros(0, 0), DMatrix::zeros(0, 0))
        };
        Evaluation { f, c: x[0] - 1.0, grad_f, grad_c, hess_f: Some(hess_f), hess_c }
    }
    fn inequalities(&self, x: &DVector<f64>, order: usize) -> Option<Inequalities> {
        let rows = if order >= 1 { vec![vec![(2, 1.0)], vec![(2, -1.0)]] } else { Vec::new() };
        Some(Inequalities { values: vec![x[2] - 1.0, -x[2] - 1.0], rows, running: None })
    }
}

/// With the active bound's term in the convex model the step is Newton's on the constraints'
/// null space, so the iteration converges in a handful of iterations; a uniform shift `W + tau
/// S` (`tau >= 1` here, the old fallback) contracts the error in `x1` by only `tau / (1 +
/// tau)` an iteration and needs hundreds.
#[test]
fn an_active_bound_convexifies_a_concave_direction() {
    let s = DMatrix::identity(3, 3);
    let chol = BandCholesky::new(&s, 2).expect("the identity is positive definite");
    let problem = Concave { s, chol };
    // The QP meets its linearised equality to about Clarabel's 1e-10, so this path is held to
    // that (below it the steering raises the penalty until the multipliers are noise; the
    // planner's refined solves, at 1e-12, then stop as stalled and the certificate judges).
    let options = SqpOptions { max_iterations: 30, constraint_tolerance: 1e-10, ..SqpOptions::default() };
    let r =
        sqp::solve(&problem, DVector::from_vec(vec![0.5, 2.0, -0.8]), &options, None).expect("a finite problem solves");
    assert!(r.converged(), "{:?} after {} iterations, kkt {:.1e}, x {:?}", r.termination, r.iterations, r.kkt, r.x);
    assert!(r.iterations <= 12, "{} iterations", r.iterations);
    for (got, want) in r.x.iter().zip([1.0, 0.3, -1.0]) {
        assert!((got - want).abs() <= 1e-8, "x = {:?}", r.x);
    }
}
