//! Gauss–Legendre quadrature, for integrals the closed forms do not give (the `z3` of the
//! band-steered chained-form path) and for the tests that check the closed forms.
//!
//! ## Reference
//! G. H. Golub, J. H. Welsch, *Calculation of Gauss quadrature rules*, Math. Comp. 23 (1969)
//! 221–230, doi:10.1090/S0025-5718-69-99647-1 (here: Newton's method on the Legendre polynomial
//! from Chebyshev-like initial guesses, as in Numerical Recipes' `gauleg`).

/// An `n`-point Gauss–Legendre rule on [-1, 1]: nodes and weights.
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    /// Nodes in (-1, 1), ascending.
    pub nodes: Vec<f64>,
    /// Weights, summing to 2.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule (exact for polynomials of degree `2n - 1`), `n >= 1`.
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d.is_finite() { d } else { dp };
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// `integral_a^b f(x) dx` with this rule on one interval.
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
        half * self.nodes.iter().zip(&self.weights).map(|(x, w)| w * f(mid + half * x)).sum::<f64>()
    }

    /// `integral_a^b f(x) dx` with this rule on `pieces` equal sub-intervals.
    pub fn integrate_composite(&self, a: f64, b: f64, pieces: usize, mut f: impl FnMut(f64) -> f64) -> f64 {
        let h = (b - a) / pieces.max(1) as f64;
        (0..pieces.max(1)).map(|i| self.integrate(a + i as f64 * h, a + (i + 1) as f64 * h, &mut f)).sum()
    }
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn exact_for_polynomials_and_smooth_functions() {
        for n in [1, 2, 5, 8, 16] {
            let rule = GaussLegendre::new(n);
            assert_relative_eq!(rule.weights.iter().sum::<f64>(), 2.0, epsilon = 1e-14);
            // x^(2n-2) on [0, 1]: 1 / (2n - 1).
            let k = 2 * n as i32 - 2;
            assert_relative_eq!(rule.integrate(0.0, 1.0, |x| x.powi(k)), 1.0 / (k as f64 + 1.0), max_relative = 1e-13);
        }
        let rule = GaussLegendre::new(10);
        assert_relative_eq!(rule.integrate_composite(0.0, 3.0, 8, f64::exp), 3f64.exp() - 1.0, max_relative = 1e-14);
    }
}
