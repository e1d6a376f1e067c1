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

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric, diagonally dominant (so positive definite) matrix of half-bandwidth `hb`,
    /// its band's entries irregular.
    fn banded(n: usize, hb: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 4.0 * hb as f64 + (i as f64 * 0.37).sin(),
            d if d <= hb => ((i + j) as f64 * 0.71).cos() / d as f64,
            _ => 0.0,
        })
    }

    /// The routines with the half-bandwidth a constant ([`matvec_with`],
    /// [`BandCholesky::substitute`] with `HB > 0`) give, bit for bit, the generic loops' results
    /// (`HB = 0`), and the pair product each single one's; the solve inverts the product to
    /// rounding.
    #[test]
    fn constant_half_bandwidths_are_the_generic_loops_bit_for_bit() {
        for (n, hb) in [(9, 7), (20, 7), (16, 11), (40, 11), (31, 15), (12, 15)] {
            let (a, b) = (banded(n, hb), banded(n, hb).map(|v| v * 0.5 - 0.1));
            let x = DVector::from_fn(n, |i, _| (i as f64 * 1.3).sin() + 0.2);
            let (mut y, mut generic) = (DVector::zeros(n), DVector::zeros(n));
            matvec_into(&a, hb, &x, &mut y);
            matvec_with::<0>(&a, hb, &x, &mut generic);
            assert!(y.iter().zip(&generic).all(|(p, q)| p.to_bits() == q.to_bits()), "matvec n {n} hb {hb}");
            let (mut ya, mut yb, mut yb_alone) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
            matvec_pair_into((&a, &b), hb, &x, (&mut ya, &mut yb));
            matvec_with::<0>(&b, hb, &x, &mut yb_alone);
            assert!(ya.iter().zip(&generic).all(|(p, q)| p.to_bits() == q.to_bits()), "pair A n {n} hb {hb}");
            assert!(yb.iter().zip(&yb_alone).all(|(p, q)| p.to_bits() == q.to_bits()), "pair B n {n} hb {hb}");
            let chol = BandCholesky::new(&a, hb).expect("diagonally dominant");
            let solved = chol.solve(&y);
            let mut plain = y.clone();
            chol.substitute::<0>(plain.as_mut_slice());
            assert!(solved.iter().zip(&plain).all(|(p, q)| p.to_bits() == q.to_bits()), "solve n {n} hb {hb}");
            assert!((solved - &x).amax() <= 1e-12, "n {n} hb {hb}");
        }
    }
}
