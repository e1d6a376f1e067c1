//! A first phase for the clearance search (issue 21): the augmented Lagrangian of a
//! discretised problem with its inequalities, every constraint soft at first (the holonomy and
//! the rows alike), minimised by L-BFGS. The SQP under the clearance rows starts from a seed
//! that folds the arm into its base and stalls at a stationary point of its infeasibility (the
//! rows push toward the nearest face, off the holonomy); the oracle's solver
//! (`tests_oracle_solver.rs`), with both soft, reaches the clear basin from the same seeds. Its
//! point is the SQP's start, not a plan: the SQP and the certificate judge what it finds.
//!
//! ## Reference
//! J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed., Springer (2006), Secs. 17.4
//! (the bound-constrained augmented Lagrangian) and 7.2 (L-BFGS), doi:10.1007/978-0-387-40065-5.

use nalgebra::DVector;

use crate::planners::optimal::sqp::Discretised;

/// Multiplier updates at most.
const OUTER: usize = 30;

/// L-BFGS iterations per update at most.
const INNER: usize = 200;

/// L-BFGS memory.
const MEMORY: usize = 8;

/// The augmented Lagrangian's value and gradient at `x` with multipliers `lambda` (holonomy) and
/// `z` (rows), penalty `r`; with it the constraint residual and the rows' values.
struct Point {
    value: f64,
    gradient: DVector<f64>,
    c: f64,
    g: Vec<f64>,
}

fn point<P: Discretised>(p: &P, x: &DVector<f64>, lambda: f64, z: &[f64], r: f64) -> Point {
    let e = p.evaluate(x, 1);
    let rows = p.inequalities(x, 1).unwrap_or_default();
    let mut gradient = &e.grad_f + &e.grad_c * (lambda + r * e.c);
    let mut value = e.f + lambda * e.c + 0.5 * r * e.c * e.c;
    for (k, (gi, row)) in rows.values.iter().zip(&rows.rows).enumerate() {
        let zi = z.get(k).copied().unwrap_or(0.0);
        let m = (zi + r * gi).max(0.0);
        value += (m * m - zi * zi) / (2.0 * r);
        if m > 0.0 {
            for &(i, v) in row {
                gradient[i] += m * v;
            }
        }
    }
    Point { value, gradient, c: e.c, g: rows.values }
}

/// The largest violation: `|c|` and every row's positive part.
fn violation(at: &Point) -> f64 {
    at.g.iter().fold(at.c.abs(), |m, v| m.max(*v))
}

/// The augmented-Lagrangian iteration from `x`: at most [`OUTER`] updates of the multipliers
/// after [`INNER`] L-BFGS steps each, the penalty five times larger where the violation did not
/// fall to a quarter; the point and the holonomy's multiplier. Stops once the violation is under
/// `tolerance`.
pub(super) fn augmented_lagrangian<P: Discretised>(p: &P, mut x: DVector<f64>, tolerance: f64) -> (DVector<f64>, f64) {
    let (mut lambda, mut z, mut r) = (0.0, Vec::new(), 10.0);
    let mut last = f64::INFINITY;
    for _ in 0..OUTER {
        x = minimise(p, x, lambda, &z, r);
        let at = point(p, &x, lambda, &z, r);
        lambda += r * at.c;
        z.resize(at.g.len(), 0.0);
        z.iter_mut().zip(&at.g).for_each(|(zi, gi)| *zi = (*zi + r * gi).max(0.0));
        let v = violation(&at);
        if v <= tolerance {
            break;
        }
        if v > 0.25 * last && r < 1e8 {
            r *= 5.0;
        }
        last = v;
    }
    (x, lambda)
}

/// L-BFGS (memory [`MEMORY`]) with a backtracking Armijo line search on the augmented
/// Lagrangian.
fn minimise<P: Discretised>(p: &P, mut x: DVector<f64>, lambda: f64, z: &[f64], r: f64) -> DVector<f64> {
    let mut at = point(p, &x, lambda, z, r);
    let mut memory: Vec<(DVector<f64>, DVector<f64>)> = Vec::new();
    for _ in 0..INNER {
        // Two-loop recursion.
        let mut d = -&at.gradient;
        let mut alphas = Vec::with_capacity(memory.len());
        for (s, y) in memory.iter().rev() {
            let a = s.dot(&d) / y.dot(s);
            d.axpy(-a, y, 1.0);
            alphas.push(a);
        }
        if let Some((s, y)) = memory.last() {
            d *= s.dot(y) / y.dot(y);
        }
        for ((s, y), a) in memory.iter().zip(alphas.iter().rev()) {
            let b = y.dot(&d) / y.dot(s);
            d.axpy(a - b, s, 1.0);
        }
        if d.dot(&at.gradient) >= 0.0 {
            d = -&at.gradient;
            memory.clear();
        }
        let slope = d.dot(&at.gradient);
        let mut step = 1.0;
        let mut accepted = None;
        for _ in 0..40 {
            let trial = &x + &d * step;
            let value = point_value(p, &trial, lambda, z, r);
            if value <= at.value + 1e-4 * step * slope {
                accepted = Some(trial);
                break;
            }
            step *= 0.5;
        }
        let Some(trial) = accepted else { break };
        let next = point(p, &trial, lambda, z, r);
        let s = &trial - &x;
        let y = &next.gradient - &at.gradient;
        if s.dot(&y) > 1e-12 * s.norm() * y.norm() {
            memory.push((s, y));
            if memory.len() > MEMORY {
                memory.remove(0);
            }
        }
        let done = (at.value - next.value).abs() <= 1e-13 * (1.0 + at.value.abs());
        (x, at) = (trial, next);
        if done {
            break;
        }
    }
    x
}

/// The augmented Lagrangian's value alone (the line search's trials).
fn point_value<P: Discretised>(p: &P, x: &DVector<f64>, lambda: f64, z: &[f64], r: f64) -> f64 {
    let e = p.evaluate(x, 0);
    let rows = p.inequalities(x, 0).unwrap_or_default();
    let mut value = e.f + lambda * e.c + 0.5 * r * e.c * e.c;
    for (k, gi) in rows.values.iter().enumerate() {
        let zi = z.get(k).copied().unwrap_or(0.0);
        let m = (zi + r * gi).max(0.0);
        value += (m * m - zi * zi) / (2.0 * r);
    }
    value
}
