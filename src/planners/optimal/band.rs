//! Banded symmetric linear algebra on dense storage: the Hessians of the discretised problem
//! couple only coefficients whose B-splines overlap, so with the joints' coefficients interleaved
//! they are banded with half-bandwidth `2 p + 1` (`p` the degree).
//!
//! ## Reference
//! G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins (2013),
//! Algorithm 4.3.5 (band Cholesky).

use nalgebra::{DMatrix, DVector};

/// `y = A x` for a symmetric matrix `A` with half-bandwidth `hb` (full storage).
pub fn matvec(a: &DMatrix<f64>, hb: usize, x: &DVector<f64>) -> DVector<f64> {
    let n = x.len();
    let mut y = DVector::zeros(n);
    for j in 0..n {
        let (lo, hi) = (j.saturating_sub(hb), (j + hb + 1).min(n));
        let column = a.column(j);
        let xj = x[j];
        for i in lo..hi {
            y[i] += column[i] * xj;
        }
    }
    y
}

/// The band Cholesky factor `L` (`A = L L^T`, lower, half-bandwidth `hb`) of a symmetric
/// matrix, or `None` when `A` is not positive definite.
#[derive(Debug, Clone)]
pub struct BandCholesky {
    l: DMatrix<f64>,
    hb: usize,
}

impl BandCholesky {
    /// Factors `a` (only its lower band is read).
    pub fn new(a: &DMatrix<f64>, hb: usize) -> Option<Self> {
        let n = a.nrows();
        let mut l = DMatrix::zeros(n, n);
        for j in 0..n {
            let lo = j.saturating_sub(hb);
            let mut d = a[(j, j)];
            for k in lo..j {
                d -= l[(j, k)] * l[(j, k)];
            }
            if !(d > 0.0) || !d.is_finite() {
                return None;
            }
            let d = d.sqrt();
            l[(j, j)] = d;
            for i in j + 1..(j + hb + 1).min(n) {
                let mut s = a[(i, j)];
                for k in i.saturating_sub(hb).max(lo)..j {
                    s -= l[(i, k)] * l[(j, k)];
                }
                l[(i, j)] = s / d;
            }
        }
        Some(Self { l, hb })
    }

    /// `A^-1 b`.
    pub fn solve(&self, b: &DVector<f64>) -> DVector<f64> {
        let n = b.len();
        let l = &self.l;
        let mut y = b.clone();
        for i in 0..n {
            let mut s = y[i];
            for k in i.saturating_sub(self.hb)..i {
                s -= l[(i, k)] * y[k];
            }
            y[i] = s / l[(i, i)];
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for k in i + 1..(i + self.hb + 1).min(n) {
                s -= l[(k, i)] * y[k];
            }
            y[i] = s / l[(i, i)];
        }
        y
    }
}
