//! The largest value of a function known on a uniform grid: each local maximum of the grid is
//! refined by golden-section search between its neighbours, so that a peak between two grid
//! points is found too (peak joint velocities, the range of the band steering's `lambda`).
//!
//! ## Reference
//! J. Kiefer, *Sequential minimax search for a maximum*, Proc. Amer. Math. Soc. 4 (1953)
//! 502–506, doi:10.1090/S0002-9939-1953-0055639-3.

/// Golden-section search for a maximum of `f` on `[a, b]` (unimodal there), to a bracket of
/// width at most `tolerance`: `(x, f(x))`, the best point evaluated (never worse than the ends
/// `f(a)`, `f(b)` when those are passed as `ends`).
pub fn golden_max<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    a: f64,
    b: f64,
    ends: [f64; 2],
    tolerance: f64,
) -> Result<(f64, f64), E> {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (a, b);
    let mut best = if ends[0] >= ends[1] { (a, ends[0]) } else { (b, ends[1]) };
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let (mut f1, mut f2) = (f(x1)?, f(x2)?);
    // At most 100 iterations: the bracket shrinks by 0.618 each, far below any useful tolerance.
    for _ in 0..100 {
        if !(hi - lo > tolerance) {
            break;
        }
        if f1 >= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1)?;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2)?;
        }
    }
    for (x, fx) in [(x1, f1), (x2, f2)] {
        if fx > best.1 {
            best = (x, fx);
        }
    }
    Ok(best)
}

/// The maximum of `f` given its `values` at the uniform grid `t0 + i h`: the grid's largest
/// value, raised by golden-section refinement ([`golden_max`], to `tolerance` in `t`) of every
/// interior local maximum of the grid within `slack` of it (all of them for `slack = inf`).
/// Returns `(t, f(t))` of the largest value found.
pub fn refined_max<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    t0: f64,
    h: f64,
    values: &[f64],
    slack: f64,
    tolerance: f64,
) -> Result<(f64, f64), E> {
    let Some((i_max, &v_max)) = values.iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1)) else {
        return Ok((t0, f64::NEG_INFINITY));
    };
    let mut best = (t0 + i_max as f64 * h, v_max);
    for i in 1..values.len().saturating_sub(1) {
        let (l, m, r) = (values[i - 1], values[i], values[i + 1]);
        if m >= l && m >= r && m >= v_max - slack {
            let a = t0 + (i - 1) as f64 * h;
            let found = golden_max(&mut f, a, a + 2.0 * h, [l, r], tolerance)?;
            if found.1 > best.1 {
                best = found;
            }
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A peak between grid points is found to the tolerance; the grid alone misses it.
    #[test]
    fn finds_a_peak_between_grid_points() {
        let f = |t: f64| Ok::<_, ()>(1.0 - (t - 0.537).powi(2));
        let h = 0.1;
        let values: Vec<f64> = (0..=10).map(|i| f(i as f64 * h).unwrap()).collect();
        let grid = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(grid < 1.0 - 1e-3);
        let (t, v) = refined_max(f, 0.0, h, &values, f64::INFINITY, 1e-9).unwrap();
        assert_relative_eq!(t, 0.537, epsilon = 1e-8);
        assert_relative_eq!(v, 1.0, epsilon = 1e-14);
    }

    /// Of two local maxima, the higher one wins even when the grid prefers the other.
    #[test]
    fn the_higher_of_two_peaks() {
        let f = |t: f64| Ok::<_, ()>((-(t - 0.25).powi(2) * 400.0).exp() + 1.02 * (-(t - 0.75).powi(2) * 4e4).exp());
        let h = 0.02;
        let values: Vec<f64> = (0..=50).map(|i| f(i as f64 * h).unwrap()).collect();
        let (t, v) = refined_max(f, 0.0, h, &values, f64::INFINITY, 1e-10).unwrap();
        assert_relative_eq!(t, 0.75, epsilon = 1e-6);
        assert!(v > 1.01);
    }

    /// A maximum at an end of the grid is kept.
    #[test]
    fn a_maximum_at_the_end() {
        let f = |t: f64| Ok::<_, ()>(t);
        let values: Vec<f64> = (0..=4).map(|i| i as f64 * 0.25).collect();
        let (t, v) = refined_max(f, 0.0, 0.25, &values, 0.0, 1e-9).unwrap();
        assert_relative_eq!(t, 1.0);
        assert_relative_eq!(v, 1.0);
    }
}
