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
    let mut y = DVector::zeros(x.len());
    matvec_into(a, hb, x, &mut y);
    y
}

/// [`matvec`] into `y` (of the length of `x`; its values are overwritten).
pub fn matvec_into(a: &DMatrix<f64>, hb: usize, x: &DVector<f64>, y: &mut DVector<f64>) {
    let n = x.len();
    y.fill(0.0);
    let (data, out) = (a.as_slice(), y.as_mut_slice());
    for (j, &xj) in x.as_slice().iter().enumerate() {
        let (lo, hi) = (j.saturating_sub(hb), (j + hb + 1).min(n));
        for (yi, aij) in out[lo..hi].iter_mut().zip(&data[j * n + lo..j * n + hi]) {
            *yi += aij * xj;
        }
    }
}

/// The band Cholesky factor `L` (`A = L L^T`, lower, half-bandwidth `hb`) of a symmetric
/// matrix, or `None` when `A` is not positive definite. `L` is stored by rows in band form:
/// row `i` holds `L[i, i - hb ..= i]` (entries left of column 0 are zero).
#[derive(Debug, Clone)]
pub struct BandCholesky {
    l: Vec<f64>,
    /// The band of `L` again by columns below the diagonal, for the backward substitution:
    /// `columns[i * hb + m] = L[i + 1 + m, i]` (contiguous, where the rows are `hb` apart).
    columns: Vec<f64>,
    n: usize,
    hb: usize,
}

impl BandCholesky {
    /// Factors `a` (only its lower band is read).
    pub fn new(a: &DMatrix<f64>, hb: usize) -> Option<Self> {
        let n = a.nrows();
        let w = hb + 1;
        let mut l = vec![0.0; n * w];
        // Column-major: A[i, j] is data[j * n + i].
        let data = a.as_slice();
        // L[i, k] is l[i * w + k + hb - i]. (The sums run over slices, in the order of k.)
        for j in 0..n {
            let lo = j.saturating_sub(hb);
            let row_j = j * w + hb - j;
            let mut d = data[j * n + j];
            for x in &l[row_j + lo..row_j + j] {
                d -= x * x;
            }
            if !(d > 0.0) || !d.is_finite() {
                return None;
            }
            let d = d.sqrt();
            l[row_j + j] = d;
            for i in j + 1..(j + hb + 1).min(n) {
                let row_i = i * w + hb - i;
                let from = i.saturating_sub(hb).max(lo);
                let mut s = data[j * n + i];
                for (x, y) in l[row_i + from..row_i + j].iter().zip(&l[row_j + from..row_j + j]) {
                    s -= x * y;
                }
                l[row_i + j] = s / d;
            }
        }
        let mut columns = vec![0.0; n * hb];
        for i in 0..n {
            for k in i + 1..(i + hb + 1).min(n) {
                columns[i * hb + k - i - 1] = l[k * w + hb - k + i];
            }
        }
        Some(Self { l, columns, n, hb })
    }

    /// `A^-1 b`.
    pub fn solve(&self, b: &DVector<f64>) -> DVector<f64> {
        let (n, hb, w) = (self.n, self.hb, self.hb + 1);
        let l = &self.l;
        let mut out = b.clone();
        let y = out.as_mut_slice();
        for i in 0..n {
            let (row, lo) = (i * w + hb - i, i.saturating_sub(hb));
            let mut s = y[i];
            for (lik, yk) in l[row + lo..row + i].iter().zip(&y[lo..i]) {
                s -= lik * yk;
            }
            y[i] = s / l[row + i];
        }
        for i in (0..n).rev() {
            // L[k, i] for k = i + 1 .. hi, in that order.
            let hi = (i + hb + 1).min(n);
            let mut s = y[i];
            for (lki, yk) in self.columns[i * hb..i * hb + hi - i - 1].iter().zip(&y[i + 1..hi]) {
                s -= lki * yk;
            }
            y[i] = s / l[i * w + hb];
        }
        out
    }
}
