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
    match hb {
        7 => matvec_with::<7>(a, hb, x, y),
        11 => matvec_with::<11>(a, hb, x, y),
        15 => matvec_with::<15>(a, hb, x, y),
        _ => matvec_with::<0>(a, hb, x, y),
    }
}

/// Half-bandwidths the band routines take as constants (cubic splines of 2, 3 and 4 joints,
/// `4 n - 1`): a full column or row of the band then has a length known at compile time and its
/// loop unrolls. `HB = 0`: none. The same operations in the same order either way.
#[inline(always)]
fn matvec_with<const HB: usize>(a: &DMatrix<f64>, hb: usize, x: &DVector<f64>, y: &mut DVector<f64>) {
    let n = x.len();
    let hb = if HB > 0 { HB } else { hb };
    y.fill(0.0);
    let (data, out) = (a.as_slice(), y.as_mut_slice());
    for (j, &xj) in x.as_slice().iter().enumerate() {
        let (lo, hi) = if HB > 0 && j >= HB && j + HB < n {
            (j - HB, j - HB + 2 * HB + 1)
        } else {
            (j.saturating_sub(hb), (j + hb + 1).min(n))
        };
        for (yi, aij) in out[lo..hi].iter_mut().zip(&data[j * n + lo..j * n + hi]) {
            *yi += aij * xj;
        }
    }
}

/// [`matvec_into`] of two matrices of half-bandwidth `hb` at once, `ya = A x` and `yb = B x`
/// (one pass over `x`: every entry of `ya` and `yb` the same sum in the same order as
/// [`matvec_into`]'s, so the same bits).
pub fn matvec_pair_into(
    ab: (&DMatrix<f64>, &DMatrix<f64>),
    hb: usize,
    x: &DVector<f64>,
    y: (&mut DVector<f64>, &mut DVector<f64>),
) {
    match hb {
        7 => matvec_pair_with::<7>(ab, hb, x, y),
        11 => matvec_pair_with::<11>(ab, hb, x, y),
        15 => matvec_pair_with::<15>(ab, hb, x, y),
        _ => matvec_pair_with::<0>(ab, hb, x, y),
    }
}

/// [`matvec_pair_into`] with `HB` as in [`matvec_with`].
#[inline(always)]
fn matvec_pair_with<const HB: usize>(
    (a, b): (&DMatrix<f64>, &DMatrix<f64>),
    hb: usize,
    x: &DVector<f64>,
    (ya, yb): (&mut DVector<f64>, &mut DVector<f64>),
) {
    let n = x.len();
    let hb = if HB > 0 { HB } else { hb };
    ya.fill(0.0);
    yb.fill(0.0);
    let (da, db, oa, ob) = (a.as_slice(), b.as_slice(), ya.as_mut_slice(), yb.as_mut_slice());
    for (j, &xj) in x.as_slice().iter().enumerate() {
        let (lo, hi) = if HB > 0 && j >= HB && j + HB < n {
            (j - HB, j - HB + 2 * HB + 1)
        } else {
            (j.saturating_sub(hb), (j + hb + 1).min(n))
        };
        let (ca, cb) = (&da[j * n + lo..j * n + hi], &db[j * n + lo..j * n + hi]);
        for (((ya, yb), aij), bij) in oa[lo..hi].iter_mut().zip(&mut ob[lo..hi]).zip(ca).zip(cb) {
            *ya += aij * xj;
            *yb += bij * xj;
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
        let mut out = b.clone();
        match self.hb {
            7 => self.substitute::<7>(out.as_mut_slice()),
            11 => self.substitute::<11>(out.as_mut_slice()),
            15 => self.substitute::<15>(out.as_mut_slice()),
            _ => self.substitute::<0>(out.as_mut_slice()),
        }
        out
    }

    /// The forward and backward substitutions of [`Self::solve`] in place, with `HB` as in
    /// [`matvec_with`] (the rows with a full band: the sums of `HB` terms unrolled).
    #[inline(always)]
    fn substitute<const HB: usize>(&self, y: &mut [f64]) {
        let (n, hb) = (self.n, if HB > 0 { HB } else { self.hb });
        let w = hb + 1;
        let l = &self.l;
        for i in 0..n {
            let (row, lo) = (i * w + hb - i, if HB > 0 && i >= HB { i - HB } else { i.saturating_sub(hb) });
            let mut s = y[i];
            for (lik, yk) in l[row + lo..row + i].iter().zip(&y[lo..i]) {
                s -= lik * yk;
            }
            y[i] = s / l[row + i];
        }
        for i in (0..n).rev() {
            // L[k, i] for k = i + 1 .. hi, in that order.
            let hi = if HB > 0 && i + HB < n { i + HB + 1 } else { (i + hb + 1).min(n) };
            let mut s = y[i];
            for (lki, yk) in self.columns[i * hb..i * hb + hi - i - 1].iter().zip(&y[i + 1..hi]) {
                s -= lki * yk;
            }
            y[i] = s / l[i * w + hb];
        }
    }
}
