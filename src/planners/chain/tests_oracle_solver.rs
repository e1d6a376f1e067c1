//! The oracle's solver ([`super::tests_oracle`]): the augmented Lagrangian of its transcription
//! with L-BFGS inner steps.
//!
//! ## Reference
//! J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed., Springer (2006), Secs. 17.4
//! (the bound-constrained augmented Lagrangian) and 7.2 (L-BFGS), doi:10.1007/978-0-387-40065-5.

use super::tests_oracle::Transcription;

/// The augmented-Lagrangian iteration from `x` (the nodes' free angles): at most 30 updates of
/// the multipliers after [`minimise`], the penalty `r` five times larger where the violation did
/// not fall to a quarter; the solution and the last `r`.
pub(super) fn augmented_lagrangian(t: &Transcription, mut x: Vec<f64>) -> (Vec<f64>, f64) {
    let rows = t.evaluate(&x).2.len();
    let (mut lambda, mut z, mut r) = (0.0, vec![0.0; rows], 10.0);
    let mut last = f64::INFINITY;
    for _ in 0..30 {
        x = minimise(t, x, lambda, &z, r, 300);
        let (_, c, g) = t.evaluate(&x);
        lambda += r * c;
        z.iter_mut().zip(&g).for_each(|(zi, gi)| *zi = (*zi + r * gi).max(0.0));
        let violation = g.iter().fold(c.abs(), |m, v| m.max(*v));
        if violation <= 1e-9 {
            break;
        }
        if violation > 0.25 * last && r < 1e8 {
            r *= 5.0;
        }
        last = violation;
    }
    (x, r)
}

/// The inequalities' part of the augmented Lagrangian, `sum (max(0, z + r g)^2 - z^2) / 2r`.
pub(super) fn penalty(g: &[f64], z: &[f64], r: f64) -> f64 {
    g.iter().zip(z).map(|(gi, zi)| ((zi + r * gi).max(0.0).powi(2) - zi * zi) / (2.0 * r)).sum()
}

/// L-BFGS (memory 8) with a backtracking Armijo line search on the augmented Lagrangian.
pub(super) fn minimise(
    t: &Transcription,
    mut x: Vec<f64>,
    lambda: f64,
    z: &[f64],
    r: f64,
    iterations: usize,
) -> Vec<f64> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    let mut f = t.lagrangian(&x, lambda, z, r);
    let mut g = t.gradient(&x, lambda, z, r);
    let mut memory: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    for _ in 0..iterations {
        // Two-loop recursion.
        let mut d: Vec<f64> = g.iter().map(|v| -v).collect();
        let mut alphas = Vec::new();
        for (s, y) in memory.iter().rev() {
            let a = dot(s, &d) / dot(y, s);
            d.iter_mut().zip(y).for_each(|(di, yi)| *di -= a * yi);
            alphas.push(a);
        }
        if let Some((s, y)) = memory.last() {
            let gamma = dot(s, y) / dot(y, y);
            d.iter_mut().for_each(|di| *di *= gamma);
        }
        for ((s, y), a) in memory.iter().zip(alphas.iter().rev()) {
            let b = dot(y, &d) / dot(y, s);
            d.iter_mut().zip(s).for_each(|(di, si)| *di += (a - b) * si);
        }
        if dot(&d, &g) >= 0.0 {
            d = g.iter().map(|v| -v).collect();
            memory.clear();
        }
        let slope = dot(&d, &g);
        let mut step = 1.0;
        let mut accepted = None;
        for _ in 0..40 {
            let trial: Vec<f64> = x.iter().zip(&d).map(|(a, b)| a + step * b).collect();
            let ft = t.lagrangian(&trial, lambda, z, r);
            if ft <= f + 1e-4 * step * slope {
                accepted = Some((trial, ft));
                break;
            }
            step *= 0.5;
        }
        let Some((trial, ft)) = accepted else { break };
        let gt = t.gradient(&trial, lambda, z, r);
        let s: Vec<f64> = trial.iter().zip(&x).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = gt.iter().zip(&g).map(|(a, b)| a - b).collect();
        if dot(&s, &y) > 1e-12 * dot(&s, &s).sqrt() * dot(&y, &y).sqrt() {
            memory.push((s, y));
            if memory.len() > 8 {
                memory.remove(0);
            }
        }
        let done = (f - ft).abs() <= 1e-13 * (1.0 + f.abs());
        (x, f, g) = (trial, ft, gt);
        if done {
            break;
        }
    }
    x
}
