//! Chebyshev series on an interval: fit, value, derivative and antiderivative, for the smooth
//! band edges of the global normal form (functions of `theta1` alone).
//!
//! ## Reference
//! L. N. Trefethen, *Approximation Theory and Approximation Practice*, SIAM 2013,
//! doi:10.1137/1.9781611975949, chs. 3 and 21.

use crate::Scalar;

/// `f(x) = sum_k c_k T_k(y)`, `y = (2x - a - b) / (b - a)`, on `[a, b]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Chebyshev {
    /// Lower end of the interval.
    pub a: f64,
    /// Upper end of the interval.
    pub b: f64,
    /// Coefficients `c_k`.
    pub coeffs: Vec<f64>,
}

impl Chebyshev {
    /// Interpolates `values` given at the `n` Chebyshev points of the first kind
    /// `x_j = (a+b)/2 + (b-a)/2 cos(pi (j + 1/2) / n)` (see [`Chebyshev::points`]).
    pub fn from_values(a: f64, b: f64, values: &[f64]) -> Self {
        let n = values.len();
        let coeffs = (0..n)
            .map(|k| {
                let s: f64 = values
                    .iter()
                    .enumerate()
                    .map(|(j, v)| v * (std::f64::consts::PI * k as f64 * (j as f64 + 0.5) / n as f64).cos())
                    .sum();
                s * if k == 0 { 1.0 } else { 2.0 } / n as f64
            })
            .collect::<Vec<f64>>();
        // Chop the tail below rounding: fewer terms, same values.
        let scale = coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let keep = coeffs.iter().rposition(|c| c.abs() > 1e-15 * scale).map_or(1, |i| i + 1);
        let mut coeffs = coeffs;
        coeffs.truncate(keep);
        Self { a, b, coeffs }
    }

    /// The `n` interpolation points of [`Chebyshev::from_values`].
    pub fn points(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|j| (a + b) / 2.0 + (b - a) / 2.0 * (std::f64::consts::PI * (j as f64 + 0.5) / n as f64).cos())
            .collect()
    }

    /// The value at `x` (Clenshaw); dual `x` gives exact derivatives of the series.
    pub fn eval<D: Scalar>(&self, x: D) -> D {
        let y = (x * 2.0 - (self.a + self.b)) / (self.b - self.a);
        let (mut b1, mut b2) = (D::zero(), D::zero());
        for &c in self.coeffs.iter().skip(1).rev() {
            let b0 = y * b1 * 2.0 - b2 + c;
            b2 = b1;
            b1 = b0;
        }
        y * b1 - b2 + self.coeffs.first().copied().unwrap_or(0.0)
    }

    /// The antiderivative, zero at `a`.
    pub fn integral(&self) -> Self {
        let n = self.coeffs.len();
        let scale = (self.b - self.a) / 2.0;
        let c = |k: usize| self.coeffs.get(k).copied().unwrap_or(0.0);
        let mut out = vec![0.0; n + 1];
        for (k, slot) in out.iter_mut().enumerate().skip(1) {
            let prev = if k == 1 { 2.0 * c(0) } else { c(k - 1) };
            *slot = scale * (prev - c(k + 1)) / (2.0 * k as f64);
        }
        let mut s = Self { a: self.a, b: self.b, coeffs: out };
        s.coeffs[0] = -s.eval(self.a);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn interpolates_and_integrates_smooth_functions() {
        let (a, b) = (-1.3, 4.2);
        let f = |x: f64| (0.7 * x).sin() + 0.1 * x * x;
        let pts = Chebyshev::points(a, b, 40);
        let c = Chebyshev::from_values(a, b, &pts.iter().map(|&x| f(x)).collect::<Vec<_>>());
        let big_f = c.integral();
        for x in [-1.3, 0.0, 1.7, 4.2] {
            assert_relative_eq!(c.eval(x), f(x), epsilon = 1e-13);
            let exact =
                -(0.7 * x).cos() / 0.7 + 0.1 * x.powi(3) / 3.0 - (-(0.7 * a).cos() / 0.7 + 0.1 * a.powi(3) / 3.0);
            assert_relative_eq!(big_f.eval(x), exact, epsilon = 1e-12);
        }
    }
}
