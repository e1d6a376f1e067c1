//! The largest value of a function known at sample times: each local maximum of the grid is
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

/// The maximum of `f` given its `values` at the ascending `times`: the samples' largest value,
/// raised by golden-section refinement ([`golden_max`], to `tolerance` in `t`) of every interior
/// local maximum of the samples within `slack` of it (all of them for `slack = inf`), between
/// its two neighbours. Returns `(t, f(t))` of the largest value found.
pub fn refined_max<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    times: &[f64],
    values: &[f64],
    slack: f64,
    tolerance: f64,
) -> Result<(f64, f64), E> {
    let Some((i_max, &v_max)) = values.iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1)) else {
        return Ok((f64::NAN, f64::NEG_INFINITY));
    };
    let mut best = (times[i_max], v_max);
    for i in 1..values.len().min(times.len()).saturating_sub(1) {
        let (l, m, r) = (values[i - 1], values[i], values[i + 1]);
        if m >= l && m >= r && m >= v_max - slack {
            let found = bracketed_max(&mut f, [times[i - 1], times[i + 1]], [l, r], tolerance)?;
            if found.1 > best.1 {
                best = found;
            }
        }
    }
    Ok(best)
}

/// Points scanned between two samples before the golden-section search.
const SCAN: usize = 16;

/// The maximum of `f` on `[a, b]` (values `ends` there): `f` on [`SCAN`] equal steps first (the
/// samples may hold more than one peak between them), then [`golden_max`] around the best step.
fn bracketed_max<E>(
    f: &mut impl FnMut(f64) -> Result<f64, E>,
    [a, b]: [f64; 2],
    ends: [f64; 2],
    tolerance: f64,
) -> Result<(f64, f64), E> {
    let h = (b - a) / SCAN as f64;
    let mut scan = Vec::with_capacity(SCAN + 1);
    scan.push(ends[0]);
    for j in 1..SCAN {
        scan.push(f(a + j as f64 * h)?);
    }
    scan.push(ends[1]);
    let j = scan.iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1)).map_or(0, |m| m.0);
    let (lo, hi) = (j.saturating_sub(1), (j + 1).min(SCAN));
    let at = |k: usize| if k == SCAN { b } else { a + k as f64 * h };
    golden_max(f, at(lo), at(hi), [scan[lo], scan[hi]], tolerance)
}

/// The largest value of `f` over the span of `times`, given its `values` there: [`refined_max`]
/// of the sampled local maxima within twice the largest change between two samples of the top,
/// to `1e-9` of the span in time (the peak joint velocities of a plan, not only its samples').
pub fn refined_peak<E>(f: impl FnMut(f64) -> Result<f64, E>, times: &[f64], values: &[f64]) -> Result<f64, E> {
    let slack = values.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
    let span = match (times.first(), times.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    Ok(refined_max(f, times, values, 2.0 * slack, 1e-9 * span)?.1)
}

/// `n + 1` equally spaced times from 0 to `horizon`, the last exactly `horizon`.
pub fn uniform_times(horizon: f64, n: usize) -> Vec<f64> {
    let h = horizon / n as f64;
    (0..=n).map(|i| if i == n { horizon } else { i as f64 * h }).collect()
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
        let (t, v) = refined_max(f, &uniform_times(1.0, 10), &values, f64::INFINITY, 1e-9).unwrap();
        assert_relative_eq!(t, 0.537, epsilon = 1e-8);
        assert_relative_eq!(v, 1.0, epsilon = 1e-14);
    }

    /// Of two local maxima, the higher one wins even when the grid prefers the other.
    #[test]
    fn the_higher_of_two_peaks() {
        let f = |t: f64| Ok::<_, ()>((-(t - 0.25).powi(2) * 400.0).exp() + 1.02 * (-(t - 0.75).powi(2) * 4e4).exp());
        let h = 0.02;
        let values: Vec<f64> = (0..=50).map(|i| f(i as f64 * h).unwrap()).collect();
        let (t, v) = refined_max(f, &uniform_times(1.0, 50), &values, f64::INFINITY, 1e-10).unwrap();
        assert_relative_eq!(t, 0.75, epsilon = 1e-6);
        assert!(v > 1.01);
    }

    /// A maximum at an end of the grid is kept.
    #[test]
    fn a_maximum_at_the_end() {
        let f = |t: f64| Ok::<_, ()>(t);
        let values: Vec<f64> = (0..=4).map(|i| i as f64 * 0.25).collect();
        let (t, v) = refined_max(f, &uniform_times(1.0, 4), &values, 0.0, 1e-9).unwrap();
        assert_relative_eq!(t, 1.0);
        assert_relative_eq!(v, 1.0);
    }
}
