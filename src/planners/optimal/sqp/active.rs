//! The S-l1-QP step (sibling `inequality` module) from a guess of its active set, without the
//! interior point: the equality-constrained QP of the model with the equality and the guessed
//! rows held as equalities (or, where the guess makes them elastic, as the linear terms of
//! their penalty), solved by the range-space (Schur complement) method on the band Cholesky
//! factor of `W` (Sherman–Morrison for the augmented term `rho a a^T`), and kept only where it
//! satisfies every optimality condition of the whole S-l1-QP; otherwise `None`, and the caller
//! solves the QP by Clarabel.
//!
//! The check makes the step the QP's minimiser, not an approximation of it: the equality's
//! multiplier inside `[-mu, mu]` where it is held, or its elastic residual on the side of its
//! multiplier `+-mu`; each held row's multiplier nonnegative (and at most `mu` where the row
//! has an elastic variable, being broken at `d = 0`); each elastic row still broken by the step;
//! every other row satisfied by the step; and the step inside the trust region's whole box.
//! Those are the KKT conditions of the convex QP written with elastic variables
//! (`subproblem`'s), which are sufficient. A guess that fails them is corrected (a row whose
//! multiplier is negative dropped, one the step breaks added, a multiplier above the penalty
//! made elastic) and solved again, [`ROUNDS`] times at most: a few band solves each, where the
//! interior point takes 10 to 16 iterations of a factorisation of the whole KKT system. Near a
//! solution the active set settles, and the last accepted step's active rows are the QP's
//! (Nocedal, Wright Sec. 16.2 for the range-space formula; Sec. 16.5 for the active-set
//! conditions).
//!
//! The factor of `W`, `H^-1 grad f`, `H^-1 a` and the columns `H^-1 b_i` of the rows met are
//! kept for the iterate ([`Columns`], in the [`Model`]): its QPs (the steering penalties, the
//! second-order correction) differ only in the penalty and the constraints' values. On issue
//! 20's `--time auto` bench the step's instructions 478 -> 319 M (its band solves 9428 ->
//! 5225), the same QPs, steps and plan.
//!
//! ## Reference
//! J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed., Springer (2006), Secs. 16.2 and
//! 16.5, doi:10.1007/978-0-387-40065-5.

use nalgebra::{DMatrix, DVector};

use super::subproblem::{Model, Step};
use crate::planners::optimal::band::BandCholesky;

/// How far a row left out of the guess may be broken by the step, or a guessed row's
/// multiplier be negative (relative to the penalty), and the step still be the QP's minimiser
/// to the interior point's own tolerance (its `QP_TOLERANCE`).
const SLACK: f64 = 1e-12;

/// The QP step of [`Model::solve`] with the constraints' values `c` and `values`, penalty `mu`
/// and trust-region radius `radius`, from the guess that the rows `guess` are the QP's active
/// rows and no elastic variable is positive, corrected up to [`ROUNDS`] times; `None` where no
/// corrected guess gives the QP's minimiser (see the module docs), where the trust region
/// binds, where the model has terms outside the band, or where `W` alone is not positive
/// definite.
pub(super) fn step(model: &Model, c: f64, values: &[f64], mu: f64, radius: f64, guess: &[usize]) -> Option<Step> {
    if !model.dense.is_empty() || model.full.get() {
        return None;
    }
    let e = model.e;
    let a = &e.grad_c;
    let mut cache = model.columns.borrow_mut();
    let Columns { factor, columns: u } = &mut *cache;
    let f = factor.get_or_insert_with(|| Factored::new(model)).as_ref()?;
    let rows = model.rows;
    let dot = |i: usize, v: &DVector<f64>| rows[i].iter().map(|&(k, b)| b * v[k]).sum::<f64>();
    // `H^-1 b_i` of each row met, computed once an iterate.
    u.resize(values.len(), None);
    let mut column = |i: usize| -> DVector<f64> { u[i].get_or_insert_with(|| f.column(&rows[i])).clone() };
    let (u_a, h_f) = (&f.u_a, &f.h_f);
    // The equality held (`sigma` none) or elastic on the side `sigma` (multiplier `sigma mu`);
    // the rows held, and the rows elastic (multiplier `mu`), which must be broken at `d = 0`.
    let mut sigma: Option<f64> = None;
    let mut held: Vec<usize> = guess.to_vec();
    let mut elastic: Vec<usize> = Vec::new();
    for _ in 0..ROUNDS {
        let mut h = h_f.clone();
        if let Some(s) = sigma {
            h.axpy(s * mu, u_a, 1.0);
        }
        for &i in &elastic {
            h.axpy(mu, &column(i), 1.0);
        }
        let columns: Vec<DVector<f64>> =
            sigma.is_none().then(|| u_a.clone()).into_iter().chain(held.iter().map(|&i| column(i))).collect();
        let offset = usize::from(sigma.is_none());
        let row_dot = |r: usize, v: &DVector<f64>| if r < offset { a.dot(v) } else { dot(held[r - offset], v) };
        let m = columns.len();
        // The lower triangle only: the Cholesky factorisation reads no other.
        let schur = DMatrix::from_fn(m, m, |r, s| if s <= r { row_dot(r, &columns[s]) } else { 0.0 });
        let rhs = DVector::from_fn(m, |r, _| -row_dot(r, &h) + if r < offset { c } else { values[held[r - offset]] });
        let y = if m > 0 { schur.cholesky()?.solve(&rhs) } else { DVector::zeros(0) };
        let mut d = -h;
        for (col, yk) in columns.iter().zip(y.iter()) {
            d.axpy(-yk, col, 1.0);
        }
        if !d.iter().all(|v| v.is_finite()) || d.amax() > radius {
            return None;
        }
        // The active set's corrections, all at once.
        let mut changed = false;
        let mut lambda = sigma.map_or(0.0, |s| s * mu);
        if offset == 1 {
            if y[0].abs() > mu {
                sigma = Some(y[0].signum());
                changed = true;
            }
            lambda = y[0];
        } else if sigma.is_some_and(|s| s * (c + a.dot(&d)) < -SLACK) {
            sigma = None;
            changed = true;
        }
        let mut z = vec![0.0; values.len()];
        let mut kept = Vec::with_capacity(held.len());
        for (r, &i) in held.iter().enumerate() {
            let zi = y[r + offset];
            if zi < -SLACK * mu.max(1.0) {
                changed = true;
            } else if values[i] > 0.0 && zi > mu {
                elastic.push(i);
                changed = true;
            } else {
                z[i] = zi.max(0.0);
                kept.push(i);
            }
        }
        let mut slack = Vec::with_capacity(elastic.len());
        for &i in &elastic {
            if values[i] + dot(i, &d) < -SLACK {
                kept.push(i);
                changed = true;
            } else {
                z[i] = mu;
                slack.push(i);
            }
        }
        for i in 0..values.len() {
            if z[i] == 0.0 && !kept.contains(&i) && !slack.contains(&i) && values[i] + dot(i, &d) > SLACK {
                kept.push(i);
                changed = true;
            }
        }
        if changed {
            (held, elastic) = (kept, slack);
            continue;
        }
        // The equality's multiplier in the model without the augmented term (as Clarabel's
        // `mu (z_0 + z_1)` in `Model::solve_rows`).
        let lambda = lambda + model.rho * a.dot(&d);
        return Some(Step { d, lambda, z });
    }
    None
}

/// The band factor of an iterate's `H = W + rho a a^T` (see [`step`]) and the columns
/// `H^-1 b_i` of the rows met so far: the QPs of one iterate (its steering penalties and its
/// second-order correction) share `W` and the rows, and differ only in the penalty and the
/// constraints' values. `factor` is `Some(None)` where `W` is not positive definite.
#[derive(Default)]
pub(super) struct Columns {
    factor: Option<Option<Factored>>,
    columns: Vec<Option<DVector<f64>>>,
}

/// `W`'s band Cholesky factor with what [`step`] reads of `H^-1` beside the rows' columns.
struct Factored {
    chol: BandCholesky,
    rho: f64,
    /// The equality's gradient `a`.
    a: DVector<f64>,
    /// `W^-1 a` and Sherman–Morrison's denominator `1 + rho a^T W^-1 a`.
    wa: DVector<f64>,
    den: f64,
    /// `H^-1 a` and `H^-1 grad f`.
    u_a: DVector<f64>,
    h_f: DVector<f64>,
}

impl Factored {
    /// `None` where `W` is not positive definite or `H`'s denominator is not positive.
    fn new(model: &Model) -> Option<Self> {
        let a = &model.e.grad_c;
        let chol = BandCholesky::new(&model.w, model.hb)?;
        // `H = W + rho a a^T` by Sherman–Morrison on `W`'s factor.
        let wa = chol.solve(a);
        let den = 1.0 + model.rho * a.dot(&wa);
        if !(den > 0.0) {
            return None;
        }
        let u_a = &wa / den;
        let mut f = Factored { chol, rho: model.rho, a: a.clone(), wa, den, u_a, h_f: DVector::zeros(0) };
        f.h_f = f.inverse(&model.e.grad_f);
        Some(f)
    }

    /// `H^-1 v`.
    fn inverse(&self, v: &DVector<f64>) -> DVector<f64> {
        let mut y = self.chol.solve(v);
        let k = self.rho * self.a.dot(&y) / self.den;
        y.axpy(-k, &self.wa, 1.0);
        y
    }

    /// `H^-1 b` of the sparse row `b`.
    fn column(&self, row: &[(usize, f64)]) -> DVector<f64> {
        let mut b = DVector::zeros(self.wa.len());
        for &(k, v) in row {
            b[k] += v;
        }
        self.inverse(&b)
    }
}

/// Most corrections of the guessed active set before the interior point is left the QP.
const ROUNDS: usize = 6;
