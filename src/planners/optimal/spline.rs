//! Clamped B-spline bases of the joint paths, with knots graded geometrically toward both ends,
//! and the end conditions that fix the first and last coefficients.
//!
//! ## Reference
//! L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer (1997), Algorithms A2.1 (span) and
//! A2.3 (basis functions and their derivatives), doi:10.1007/978-3-642-59223-2.

use crate::error::Error;
use crate::model::InputError;

/// Largest supported degree (quintic, for smooth ends).
pub const MAX_DEGREE: usize = 5;

/// Values and derivatives of the `p + 1` basis functions that do not vanish on one knot span:
/// `ders[k][l]` is the `k`-th derivative of basis function `span - p + l`.
pub type Ders = [[f64; MAX_DEGREE + 1]; 3];

/// A clamped B-spline basis of degree `p` on `[0, T]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SplineBasis {
    degree: usize,
    /// Full knot vector: `p + 1` zeros, the interior breakpoints, `p + 1` times `T`.
    knots: Vec<f64>,
    /// Distinct breakpoints `0 = b_0 < ... < b_N = T`.
    breakpoints: Vec<f64>,
}

impl SplineBasis {
    /// The basis of degree `degree` (3 or 5) on `[0, horizon]` with `spans` uniform spans of width
    /// `h = T / spans`, the first and last of which are split further at `h / 4^j`,
    /// `j = 1..=grading`: thin end layers, where the path leaves and reaches rest.
    pub fn graded(degree: usize, horizon: f64, spans: usize, grading: usize) -> Result<Self, Error> {
        if !(1..=MAX_DEGREE).contains(&degree) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "degree".into(),
                value: degree as f64,
                expected: "a B-spline degree from 1 to 5",
            }));
        }
        if spans < 2 || !(horizon.is_finite() && horizon > 0.0) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "spans".into(),
                value: spans as f64,
                expected: "at least 2 knot spans on a positive, finite horizon",
            }));
        }
        let h = horizon / spans as f64;
        let mut b = vec![0.0];
        for j in (1..=grading).rev() {
            b.push(h / 4f64.powi(j as i32));
        }
        for i in 1..spans {
            b.push(i as f64 * h);
        }
        for j in 1..=grading {
            b.push(horizon - h / 4f64.powi(j as i32));
        }
        b.push(horizon);
        let mut knots = vec![0.0; degree];
        knots.extend_from_slice(&b);
        knots.extend(std::iter::repeat_n(horizon, degree));
        Ok(Self { degree, knots, breakpoints: b })
    }

    /// The basis of degree `degree` on the given breakpoints `0 = b_0 < .. < b_N = T` (at least
    /// two spans; a re-plan's basis keeps the breakpoints of the reference it corrects, so that
    /// the reference's rest is a spline of it).
    pub fn on_breakpoints(degree: usize, breakpoints: &[f64]) -> Result<Self, Error> {
        let horizon = breakpoints.last().copied().unwrap_or(0.0);
        let increasing = breakpoints.windows(2).all(|w| w[1] > w[0]) && breakpoints.iter().all(|b| b.is_finite());
        if !(1..=MAX_DEGREE).contains(&degree)
            || breakpoints.len() < 3
            || breakpoints[0] != 0.0
            || !increasing
            || !(horizon > 0.0)
        {
            return Err(Error::from(InputError::InvalidParameter {
                name: "breakpoints".into(),
                value: breakpoints.len() as f64,
                expected: "a degree from 1 to 5 and at least 3 finite, increasing breakpoints from 0",
            }));
        }
        let mut knots = vec![0.0; degree];
        knots.extend_from_slice(breakpoints);
        knots.extend(std::iter::repeat_n(horizon, degree));
        Ok(Self { degree, knots, breakpoints: breakpoints.to_vec() })
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The number `n` of basis functions (coefficients per joint).
    pub fn len(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// Always false: a basis has at least `p + 1` functions.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The distinct breakpoints `0 = b_0 < ... < b_N = T` \[s\].
    pub fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        self.breakpoints[self.breakpoints.len() - 1]
    }

    /// The knot-span index `i` (`knots[i] <= t < knots[i + 1]`, the last span closed) of the
    /// breakpoint interval `s` (`b_s <= t <= b_{s+1}`).
    pub fn span_of_interval(&self, s: usize) -> usize {
        s + self.degree
    }

    /// The breakpoint interval holding `t` (clamped to `[0, T]`).
    pub fn interval(&self, t: f64) -> usize {
        let b = &self.breakpoints;
        let last = b.len() - 2;
        if !(t > b[0]) {
            return 0;
        }
        // partition_point: the number of breakpoints <= t.
        b.partition_point(|&x| x <= t).saturating_sub(1).min(last)
    }

    /// The triangular table `ndu` of Piegl–Tiller A2.3 at `t` in knot span `span`: the basis
    /// functions of every degree up to `p` (upper triangle) and the knot differences (lower).
    fn triangle(&self, span: usize, t: f64) -> [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1] {
        // Cubic (every basis of the minimum-effort planner but the smooth ends') with `p` a
        // constant: the loops unroll, the same operations in the same order (the same bits).
        match self.degree {
            3 => self.triangle_of(3, span, t),
            p => self.triangle_of(p, span, t),
        }
    }

    /// [`Self::triangle`] for degree `p` (the basis'; inlined where it is a constant).
    #[inline(always)]
    fn triangle_of(&self, p: usize, span: usize, t: f64) -> [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1] {
        let u = &self.knots;
        let mut ndu = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        let mut left = [0.0; MAX_DEGREE + 1];
        let mut right = [0.0; MAX_DEGREE + 1];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = t - u[span + 1 - j];
            right[j] = u[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        ndu
    }

    /// Values, first and second derivatives of the basis functions of knot span `span` at `t`
    /// (Piegl–Tiller A2.3, up to the second derivative).
    pub fn ders(&self, span: usize, t: f64) -> Ders {
        match self.degree {
            3 => self.ders_of(3, span, t),
            p => self.ders_of(p, span, t),
        }
    }

    /// [`Self::ders`] for degree `p` (the basis'; inlined where it is a constant: the same bits).
    #[inline(always)]
    fn ders_of(&self, p: usize, span: usize, t: f64) -> Ders {
        let ndu = self.triangle_of(p, span, t);
        let mut ders: Ders = [[0.0; MAX_DEGREE + 1]; 3];
        for (j, d) in ders[0].iter_mut().enumerate().take(p + 1) {
            *d = ndu[j][p];
        }
        let nd = 2.min(p);
        let mut a = [[0.0; MAX_DEGREE + 1]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0] = [0.0; MAX_DEGREE + 1];
            a[0][0] = 1.0;
            for k in 1..=nd {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    a[s2][0] = a[s1][0] / ndu[pk + 1][r - k];
                    d = a[s2][0] * ndu[r - k][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if (r as isize - 1) <= pk as isize { k - 1 } else { p - r };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                    d += a[s2][k] * ndu[r][pk];
                }
                ders[k][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for (k, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
            for d in row.iter_mut().take(p + 1) {
                *d *= factor;
            }
            factor *= (p - k) as f64;
        }
        ders
    }

    /// The Taylor coefficients `c_k = theta^(k)(b) / k!`, `k = 0..=p` (zero above), of the spline
    /// with coefficients `c` on knot span `span` about its left breakpoint `b`: on the span,
    /// `theta(b + x) = sum_k c_k x^k`, a polynomial for Horner's rule. The `k`-th derivative is
    /// the degree `p - k` spline of the differenced coefficients
    /// `c^(k)_i = (p - k + 1) (c^(k-1)_i - c^(k-1)_(i-1)) / (u_(i+p-k+1) - u_i)` (Piegl–Tiller
    /// Eq. 3.8, A3.3), evaluated at `b` from the degree `p - k` functions of A2.3's table: rounding
    /// relative to the differences, not to the coefficients (which the basis functions' `k`-th
    /// derivatives, of size `h^-k` on a span `h` of the graded ends, would multiply).
    pub fn taylor(&self, span: usize, c: &[f64]) -> [f64; MAX_DEGREE + 1] {
        let (p, u) = (self.degree, &self.knots);
        let ndu = self.triangle(span, u[span]);
        let first = span - p;
        // d[l]: the coefficient of function `first + l` of the current derivative, l = k..=p.
        let mut d = [0.0; MAX_DEGREE + 1];
        d[..=p].copy_from_slice(&c[first..=first + p]);
        let mut out = [0.0; MAX_DEGREE + 1];
        let mut factorial = 1.0;
        for k in 0..=p {
            if k > 0 {
                for l in (k..=p).rev() {
                    let i = first + l;
                    d[l] = (p - k + 1) as f64 * (d[l] - d[l - 1]) / (u[i + p - k + 1] - u[i]);
                }
                factorial *= k as f64;
            }
            // The degree r = p - k functions `span - r + j` are ndu[j][r], j = 0..=r.
            let r = p - k;
            out[k] = (0..=r).map(|j| ndu[j][r] * d[k + j]).sum::<f64>() / factorial;
        }
        out
    }

    /// Values and first derivatives of the basis functions of knot span `span` at `t`: the
    /// first two rows of [`Self::ders`] at about half the work (the derivatives from the
    /// degree `p - 1` functions, Piegl–Tiller Eq. 2.9).
    pub fn values_and_rates(&self, span: usize, t: f64) -> [[f64; MAX_DEGREE + 1]; 2] {
        match self.degree {
            3 => self.values_and_rates_of(3, span, t),
            p => self.values_and_rates_of(p, span, t),
        }
    }

    /// [`Self::values_and_rates`] for degree `p` (the basis'; inlined where it is a constant:
    /// the same bits).
    #[inline(always)]
    fn values_and_rates_of(&self, p: usize, span: usize, t: f64) -> [[f64; MAX_DEGREE + 1]; 2] {
        let ndu = self.triangle_of(p, span, t);
        let mut out = [[0.0; MAX_DEGREE + 1]; 2];
        // N'_{r} = p (N_{r-1, p-1} / (u_{r+p} - u_r) - N_{r, p-1} / (u_{r+p+1} - u_{r+1})), the
        // knot differences being ndu[p][.] and the degree p - 1 values ndu[.][p - 1].
        let mut previous = 0.0;
        for r in 0..=p {
            out[0][r] = ndu[r][p];
            let current = if r < p { ndu[r][p - 1] / ndu[p][r] } else { 0.0 };
            out[1][r] = p as f64 * (previous - current);
            previous = current;
        }
        out
    }

    /// `(theta, theta', theta'')` of the spline with coefficients `c` at `t` \[rad, rad/s, rad/s^2\].
    pub fn evaluate(&self, c: &[f64], t: f64) -> [f64; 3] {
        let mut out = [0.0; 3];
        self.evaluate_each(std::slice::from_ref(&c), t, |_, v| out = v);
        out
    }

    /// [`Self::evaluate`] of every spline of `coefficients` at one `t`, the basis functions
    /// computed once: `out(j, [theta, theta', theta''])` of the `j`-th, bit for bit.
    pub fn evaluate_each<C: AsRef<[f64]>>(&self, coefficients: &[C], t: f64, mut out: impl FnMut(usize, [f64; 3])) {
        let s = self.interval(t);
        let span = self.span_of_interval(s);
        let d = self.ders(span, t);
        let first = span - self.degree;
        for (j, c) in coefficients.iter().enumerate() {
            let c = c.as_ref();
            let mut v = [0.0; 3];
            for (k, o) in v.iter_mut().enumerate() {
                *o = (0..=self.degree).map(|l| d[k][l] * c[first + l]).sum();
            }
            out(j, v);
        }
    }

    /// The first derivatives alone of every spline of `coefficients` at `t`: `out(j, theta')`
    /// of the `j`-th, bit for bit the `theta'` of [`Self::evaluate_each`] (the first-derivative
    /// row of Piegl–Tiller A2.3, whose `k = 1` step is two terms per function, without the
    /// second derivatives).
    pub fn rates_each<C: AsRef<[f64]>>(&self, coefficients: &[C], t: f64, mut out: impl FnMut(usize, f64)) {
        let p = self.degree;
        let span = self.span_of_interval(self.interval(t));
        let ndu = self.triangle(span, t);
        let mut rate = [0.0; MAX_DEGREE + 1];
        for (r, d) in rate.iter_mut().enumerate().take(p + 1) {
            // A2.3 at k = 1: `a_0 = 1 / ndu[p][r - 1]` where `r >= 1`, `a_1 = -1 / ndu[p][r]`
            // where `r <= p - 1`, each times its degree `p - 1` function; then times `p`.
            let mut sum = 0.0;
            if r >= 1 {
                sum = 1.0 / ndu[p][r - 1] * ndu[r - 1][p - 1];
            }
            if r < p {
                sum += -1.0 / ndu[p][r] * ndu[r][p - 1];
            }
            *d = sum * p as f64;
        }
        let first = span - p;
        for (j, c) in coefficients.iter().enumerate() {
            let c = c.as_ref();
            out(j, (0..=p).map(|l| rate[l] * c[first + l]).sum());
        }
    }

    /// The values alone of every spline of `coefficients` at `t` into `out` (bit for bit those of
    /// [`Self::evaluate`], without the derivatives: a projection's path).
    pub fn values_each<C: AsRef<[f64]>>(&self, coefficients: &[C], t: f64, out: &mut [f64]) {
        let s = self.interval(t);
        let span = self.span_of_interval(s);
        let value = self.triangle(span, t).map(|row| row[self.degree]);
        let first = span - self.degree;
        for (o, c) in out.iter_mut().zip(coefficients) {
            let c = c.as_ref();
            *o = (0..=self.degree).map(|l| value[l] * c[first + l]).sum();
        }
    }

    /// The coefficients fixed by the end conditions: `theta^(k)(0) = start[k]` and
    /// `theta^(k)(T) = end[k]` for `k < start.len()` (value, velocity, acceleration). On a clamped
    /// basis the `k`-th derivative at an end involves only the first (last) `k + 1` coefficients,
    /// so they follow by forward (backward) substitution. Returns `(head, tail)`.
    pub fn end_coefficients(&self, start: &[f64], end: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let p = self.degree;
        let n = self.len();
        let d0 = self.ders(p, 0.0);
        let mut head = Vec::with_capacity(start.len());
        for (k, &target) in start.iter().enumerate() {
            let known: f64 = (0..k).map(|l| d0[k][l] * head[l]).sum();
            head.push((target - known) / d0[k][k]);
        }
        // On the last span the functions are n-1-p .. n-1, i.e. local index l = p - j for c_{n-1-j}.
        let d1 = self.ders(n - 1, self.horizon());
        let mut tail_rev: Vec<f64> = Vec::with_capacity(end.len());
        for (k, &target) in end.iter().enumerate() {
            let known: f64 = (0..k).map(|j| d1[k][p - j] * tail_rev[j]).sum();
            tail_rev.push((target - known) / d1[k][p - k]);
        }
        tail_rev.reverse();
        (head, tail_rev)
    }
}

#[cfg(test)]
mod tests {
    use super::SplineBasis;

    /// `rates_each` is the `theta'` of `evaluate_each` bit for bit (the peak velocity of a plan
    /// is taken with it), on every degree, graded and uniform, at breakpoints and between them.
    #[test]
    fn rates_each_is_evaluate_each_bit_for_bit() {
        for degree in 1..=5 {
            for grading in [0, 2] {
                let basis = SplineBasis::graded(degree, 7.3, 9, grading).expect("a valid basis");
                let c: Vec<Vec<f64>> =
                    (0..3).map(|j| (0..basis.len()).map(|i| ((i * 7 + j * 3) as f64 * 0.37).sin()).collect()).collect();
                for k in 0..=400 {
                    let t = 7.3 * k as f64 / 400.0;
                    let mut want = [0.0; 3];
                    basis.evaluate_each(&c, t, |j, [_, rate, _]| want[j] = rate);
                    basis
                        .rates_each(&c, t, |j, rate| assert_eq!(rate.to_bits(), want[j].to_bits(), "p {degree} t {t}"));
                }
            }
        }
    }
}
