//! The polynomial controls of Sec. 5 (`v1 = b1 t + c1 t^2 + d1 t^3`, `v2 = b2 t + c2 t^2`) and
//! the closed-form path of the chained form (10) under them.

use super::ChainedPoint;
use crate::Scalar;
use crate::error::Error;

/// Highest polynomial degree kept (`z3` has degree 7).
const LEN: usize = 9;

/// A real polynomial `sum_i c[i] t^i` of degree < 9.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polynomial {
    /// Coefficients, lowest degree first.
    pub coeffs: [f64; LEN],
}

impl Polynomial {
    /// From the coefficients, lowest degree first (at most 9).
    pub fn new(coeffs: &[f64]) -> Self {
        let mut c = [0.0; LEN];
        c[..coeffs.len()].copy_from_slice(coeffs);
        Self { coeffs: c }
    }

    /// Value at `t` (Horner); with a dual `t` this also gives exact time derivatives.
    pub fn eval<D: Scalar>(&self, t: D) -> D {
        self.coeffs.iter().rev().fold(D::zero(), |acc, &c| acc * t + c)
    }

    /// The derivative.
    pub fn derivative(&self) -> Self {
        let mut c = [0.0; LEN];
        for i in 1..LEN {
            c[i - 1] = self.coeffs[i] * i as f64;
        }
        Self { coeffs: c }
    }

    /// The antiderivative with value `c0` at `t = 0`. The top coefficient must be zero.
    fn integral(&self, c0: f64) -> Self {
        debug_assert!(self.coeffs[LEN - 1].abs() == 0.0, "invariant: degree < 8");
        let mut c = [0.0; LEN];
        c[0] = c0;
        for i in 0..LEN - 1 {
            c[i + 1] = self.coeffs[i] / (i + 1) as f64;
        }
        Self { coeffs: c }
    }

    /// The product; the degrees must add up to less than 9.
    fn mul(&self, other: &Self) -> Self {
        let mut c = [0.0; LEN];
        for (i, a) in self.coeffs.iter().enumerate() {
            for (j, b) in other.coeffs.iter().enumerate() {
                if i + j < LEN {
                    c[i + j] += a * b;
                } else {
                    debug_assert!(a * b == 0.0, "invariant: degree < 9");
                }
            }
        }
        Self { coeffs: c }
    }
}

/// The closed-form path of the chained form (10) under the polynomial controls of Sec. 5.
#[derive(Debug, Clone, PartialEq)]
pub struct PolynomialSteering {
    /// Horizon `T` \[s\].
    pub horizon: f64,
    /// Start `z0`.
    pub z0: [f64; 3],
    /// Goal `zd`.
    pub zd: [f64; 3],
    /// `v1(t)`, `v2(t)`.
    pub v: [Polynomial; 2],
    /// `z1(t)`, `z2(t)`, `z3(t)`.
    pub z: [Polynomial; 3],
}

impl PolynomialSteering {
    /// The controls of Sec. 5 from `z0` to `zd` in time `T`, with `w = zd - z0`:
    /// `b1 = 4(22 w1 w2 - 35 w3 + 35 w1 z02) / (3 w2 T^2)`,
    /// `c1 = -4(19 w1 w2 - 35 w3 + 35 w1 z02) / (w2 T^3)`,
    /// `d1 = 140(w1 w2 - 2 w3 + 2 w1 z02) / (3 w2 T^4)`, `b2 = 6 w2 / T^2`, `c2 = -6 w2 / T^3`.
    ///
    /// These need `w2 != 0` (docs/spec.md §6, item 5): otherwise [`Error::DegenerateSteering`], except
    /// for `zd = z0`, where the path rests at `z0`.
    pub fn new(z0: [f64; 3], zd: [f64; 3], horizon: f64) -> Result<Self, Error> {
        let t = horizon;
        let [w1, w2, w3] = [zd[0] - z0[0], zd[1] - z0[1], zd[2] - z0[2]];
        if w1 == 0.0 && w2 == 0.0 && w3 == 0.0 {
            // Already there: rest, zero controls.
            let zero = Polynomial::new(&[]);
            let z = [Polynomial::new(&[z0[0]]), Polynomial::new(&[z0[1]]), Polynomial::new(&[z0[2]])];
            return Ok(Self { horizon, z0, zd, v: [zero, zero], z });
        }
        if w2.abs() <= 1e-9 * (1.0 + z0[1].abs().max(zd[1].abs())) {
            return Err(Error::DegenerateSteering { w2 });
        }
        let z02 = z0[1];
        let b1 = 4.0 * (22.0 * w1 * w2 - 35.0 * w3 + 35.0 * w1 * z02) / (3.0 * w2 * t * t);
        let c1 = -4.0 * (19.0 * w1 * w2 - 35.0 * w3 + 35.0 * w1 * z02) / (w2 * t.powi(3));
        let d1 = 140.0 * (w1 * w2 - 2.0 * w3 + 2.0 * w1 * z02) / (3.0 * w2 * t.powi(4));
        let b2 = 6.0 * w2 / (t * t);
        let c2 = -6.0 * w2 / t.powi(3);
        let v1 = Polynomial::new(&[0.0, b1, c1, d1]);
        let v2 = Polynomial::new(&[0.0, b2, c2]);
        let z1 = v1.integral(z0[0]);
        let z2 = v2.integral(z0[1]);
        let z3 = z2.mul(&v1).integral(z0[2]);
        Ok(Self { horizon, z0, zd, v: [v1, v2], z: [z1, z2, z3] })
    }

    /// The path at time `t` \[s\]; with a dual `t`, the dual parts are exact time derivatives.
    pub fn at<D: Scalar>(&self, t: D) -> ChainedPoint<D> {
        ChainedPoint {
            z: [self.z[0].eval(t), self.z[1].eval(t), self.z[2].eval(t)],
            v: [self.v[0].eval(t), self.v[1].eval(t)],
        }
    }
}
