//! Tests of the QP step from a guessed active set ([`super::active`]) against Clarabel's
//! solution of the same QP ([`super::subproblem::Model::solve`]), and of the QP's running form
//! of dense rows ([`super::running`]) against their dense gradients.

use std::cell::{Cell, RefCell};

use nalgebra::{DMatrix, DVector};

use super::active;
use super::subproblem::{Model, Step};
use crate::planners::optimal::discrete::Evaluation;

/// The step from the guess, Clarabel's, and the QP's row values and rows.
type Solved = (Option<Step>, Option<Step>, Vec<f64>, Vec<Vec<(usize, f64)>>);

/// `W` tridiagonal and positive definite in `dim` variables (6 for the gradient given), and the
/// evaluation: the equality `sum d_k = -c` (`c = 0.3`), the cost's gradient.
fn model_terms(dim: usize) -> (DMatrix<f64>, Evaluation) {
    let w = DMatrix::from_fn(dim, dim, |i, j| match i.abs_diff(j) {
        0 => 2.0,
        1 => -0.5,
        _ => 0.0,
    });
    let e = Evaluation {
        f: 0.0,
        c: 0.3,
        grad_f: DVector::from_vec(vec![-1.0, -0.5, 0.2, -0.8, 0.1, -0.3]),
        grad_c: DVector::from_element(dim, 1.0),
        hess_f: None,
        hess_c: DMatrix::zeros(dim, dim),
    };
    (w, e)
}

/// A QP in 6 variables: `W` tridiagonal and positive definite, the equality `sum d_k = -c`,
/// upper bounds `x_k + d_k <= 0.1` as rows of value `x_k - 0.1` (the first broken at `d = 0`
/// by `broken`, so it has an elastic variable), the cost's gradient pushing against them.
fn qp(broken: f64, radius: f64, mu: f64, guess: &[usize]) -> Solved {
    let dim = 6;
    let (w, e) = model_terms(dim);
    let rows: Vec<Vec<(usize, f64)>> = (0..dim).map(|k| vec![(k, 1.0)]).collect();
    let values: Vec<f64> = (0..dim).map(|k| if k == 0 { broken } else { -0.05 * k as f64 }).collect();
    let (working, boxed, solver) = (RefCell::new(vec![true; dim]), RefCell::new(vec![true; dim]), RefCell::new(None));
    let model = Model {
        w,
        rho: 0.5,
        dense: Vec::new(),
        full: Cell::new(false),
        hb: 1,
        e: &e,
        rows: &rows,
        running: None,
        working: &working,
        boxed: &boxed,
        solver: &solver,
        columns: Default::default(),
    };
    let guessed = active::step(&model, e.c, &values, mu, radius, guess);
    let reference = model.solve(e.c, &values, mu, radius);
    (guessed, reference, values, rows)
}

/// Clarabel's step and multipliers, to its tolerance (1e-12 on a scaled problem).
fn assert_same(guessed: &Step, reference: &Step) {
    assert!((&guessed.d - &reference.d).amax() < 1e-8, "steps {} and {}", guessed.d, reference.d);
    assert!((guessed.lambda - reference.lambda).abs() < 1e-6 * (1.0 + reference.lambda.abs()));
    for (a, b) in guessed.z.iter().zip(&reference.z) {
        assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "multipliers {:?} and {:?}", guessed.z, reference.z);
    }
}

#[test]
fn corrected_guesses_give_the_qps_minimiser() {
    // From no guess, from the right one and from a wrong one (rows 4 and 5 do not bind).
    for guess in [vec![], vec![0, 1, 3], vec![4, 5]] {
        let (guessed, reference, values, rows) = qp(-0.02, 10.0, 10.0, &guess);
        let (guessed, reference) = (guessed.expect("a step from the guess"), reference.expect("Clarabel's step"));
        assert_same(&guessed, &reference);
        // Some row binds, and every row holds at the step.
        assert!(guessed.z.iter().any(|z| *z > 1e-3));
        for (v, row) in values.iter().zip(&rows) {
            assert!(v + row.iter().map(|&(k, b)| b * guessed.d[k]).sum::<f64>() <= 1e-12);
        }
    }
}

#[test]
fn elastic_rows_and_equality_where_the_penalty_is_small() {
    // A row broken at d = 0 and a penalty below the multipliers: the l1 terms stay positive.
    for mu in [0.05, 0.3, 10.0] {
        let (guessed, reference, ..) = qp(0.4, 10.0, mu, &[]);
        assert_same(&guessed.expect("a step from the guess"), &reference.expect("Clarabel's step"));
    }
}

#[test]
fn a_binding_trust_region_is_left_to_clarabel() {
    let (guessed, reference, ..) = qp(-0.02, 0.01, 10.0, &[]);
    assert!(guessed.is_none());
    assert!(reference.expect("Clarabel's step").d.amax() <= 0.01 * (1.0 + 1e-9));
}

/// The QP with rows in their running form ([`super::Running`], a variable `e_k` per point) is
/// the QP with their dense gradients: the same step and multipliers. Rows of the form
/// `l_i + a_i grad y_k`, `y_k` a running sum whose gradient fills in point by point (the base
/// angle at the rows' points), one of them broken at `d = 0`.
#[test]
fn the_running_form_is_the_same_qp() {
    use super::{Running, RunningRow};
    let dim = 6;
    let (w, e) = model_terms(dim);
    let steps: Vec<Vec<(usize, f64)>> = (0..3).map(|k| vec![(2 * k, 0.3), (2 * k + 1, -0.2)]).collect();
    let local = |i: usize| vec![(2 * i, 0.5), (2 * i + 1, 0.25)];
    let slope = |i: usize| 1.0 + 0.5 * i as f64;
    let rows: Vec<Vec<(usize, f64)>> = (0..3)
        .map(|i| {
            let mut g = vec![0.0; dim];
            steps[..=i].iter().flatten().for_each(|&(k, v)| g[k] += slope(i) * v);
            local(i).iter().for_each(|&(k, v)| g[k] += v);
            g.into_iter().enumerate().filter(|(_, v)| *v != 0.0).collect()
        })
        .collect();
    let running = Running {
        steps,
        rows: (0..3).map(|i| RunningRow { row: i, point: i, slope: slope(i), local: local(i) }).collect(),
    };
    let values = vec![-0.01, 0.02, -0.05];
    let solve = |running: Option<&Running>| {
        let (working, boxed, solver) = (RefCell::new(vec![true; 3]), RefCell::new(vec![true; dim]), RefCell::new(None));
        let model = Model {
            w: w.clone(),
            rho: 0.5,
            dense: Vec::new(),
            full: Cell::new(false),
            hb: 1,
            e: &e,
            rows: &rows,
            running,
            working: &working,
            boxed: &boxed,
            solver: &solver,
            columns: Default::default(),
        };
        model.solve(e.c, &values, 10.0, 10.0).expect("Clarabel's step")
    };
    let (banded, dense) = (solve(Some(&running)), solve(None));
    assert_same(&banded, &dense);
    assert!(dense.z.iter().filter(|z| **z > 1e-3).count() >= 1, "a row binds: {:?}", dense.z);
}
