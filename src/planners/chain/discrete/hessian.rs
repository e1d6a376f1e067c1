//! The Hessian blocks one quadrature node adds to the discretised problem's Hessians
//! ([`Discretisation`](super::Discretisation)'s `derivatives`): the constraint's, for a node
//! whose `p + 1` local coefficients are all free, with the joint count and the degree constant
//! (the loops unrolled, one bounds check per column), and the energy's.

use nalgebra::DMatrix;

use super::{EnergyLocal, Local, MAX_DEGREE, Node};

/// Subtracts `w` times the holonomy integrand's Hessian at `node` from the lower band of
/// `data` (column-major, `dim x dim`) for a node whose `Q = p + 1` local coefficients of `N`
/// joints are all free, the first at free index `base` (times `N`), the others after it.
///
/// The same terms, each entry's in the same order, as the general loop of `derivatives`
/// (every entry takes one term per node): for coefficients `(l, j)` and `(ll, jj)`, `ll > l`
/// or `ll = l, jj >= j`, `(h[j, jj] v_l w + m[jj, j] r_l w) v_ll + m[j, jj] v_l w r_ll`, with
/// `h` the Hessian in `theta`, `m` the mixed derivatives, `v` and `r` the basis functions'
/// values and rates. Returns `true` (done).
#[inline(always)]
pub(super) fn interior<const N: usize, const Q: usize>(
    data: &mut [f64],
    dim: usize,
    base: usize,
    node: &Node,
    local: &Local,
    w: f64,
) -> bool {
    // One call per local coefficient `L`, a constant: every index of its columns is then known
    // at compile time (the loop over `L` as written was not unrolled, and its index arithmetic
    // and bounds checks were half of the block's instructions).
    macro_rules! columns {
        ($($l:literal)*) => {$(
            if $l < Q {
                columns_of::<N, Q, $l>(data, dim, base, node, local, w);
            }
        )*};
    }
    const _: () = assert!(MAX_DEGREE < 6, "one `columns!` entry per local coefficient");
    columns!(0 1 2 3 4 5);
    true
}

/// The `N` columns of local coefficient `L` of [`interior`]'s block.
#[inline(always)]
fn columns_of<const N: usize, const Q: usize, const L: usize>(
    data: &mut [f64],
    dim: usize,
    base: usize,
    node: &Node,
    local: &Local,
    w: f64,
) {
    let (hessian, mixed) = (&local.hessian[..N * N], &local.mixed[..N * N]);
    let (v, dr) = (node.value[L] * w, node.rate[L] * w);
    for j in 0..N {
        let (mut row, mut mv) = ([0.0; N], [0.0; N]);
        for jj in 0..N {
            row[jj] = hessian[j * N + jj] * v + mixed[jj * N + j] * dr;
            mv[jj] = mixed[j * N + jj] * v;
        }
        // Column `col` from its diagonal down to the block's last row.
        let col = base + L * N + j;
        let column = &mut data[col * dim + col..col * dim + base + Q * N];
        let (vv, rr) = (node.value[L], node.rate[L]);
        for jj in j..N {
            column[jj - j] -= row[jj] * vv + mv[jj] * rr;
        }
        for ll in L + 1..Q {
            let (vv, rr) = (node.value[ll], node.rate[ll]);
            for jj in 0..N {
                column[ll * N + jj - L * N - j] -= row[jj] * vv + mv[jj] * rr;
            }
        }
    }
}

/// Adds `weight *` the energy density's Hessian at `node` in the coefficients `idx` (free index
/// times `n` per local basis function, `usize::MAX` where fixed) to `h`: for coefficients
/// `(l, j)` and `(ll, jj)`, `v_l v_ll e_tt[j, jj] + v_l r_ll e_tw[j, jj] + r_l v_ll e_tw[jj, j]
/// + r_l r_ll e_ww[j, jj]`.
pub(super) fn add_energy(h: &mut DMatrix<f64>, e: &EnergyLocal, node: &Node, idx: &[usize], n: usize, weight: f64) {
    let dim = h.nrows();
    let data = h.as_mut_slice();
    for (l, &il) in idx.iter().enumerate() {
        if il == usize::MAX {
            continue;
        }
        let (v, r) = (node.value[l] * weight, node.rate[l] * weight);
        for (ll, &ill) in idx.iter().enumerate() {
            if ill == usize::MAX {
                continue;
            }
            let (vv, rr) = (node.value[ll], node.rate[ll]);
            for j in 0..n {
                let col = (il + j) * dim + ill;
                for jj in 0..n {
                    data[col + jj] += v * vv * e.theta_theta[j * n + jj]
                        + v * rr * e.theta_rate[j * n + jj]
                        + r * vv * e.theta_rate[jj * n + j]
                        + r * rr * e.rate_rate[j * n + jj];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`interior`] writes, bit for bit, the documented term of every pair of coefficients on and
    /// below the diagonal of its block, and nothing else (2 to 4 joints, arbitrary values).
    #[test]
    fn interior_block_is_the_documented_sum_bit_for_bit() {
        fn check<const N: usize>() {
            let mut rng = 0x5EED_u64 + N as u64;
            let mut next = move || {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                (rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            };
            let mut node = Node { first: 0, t: 0.0, weight: 0.0, value: [0.0; 6], rate: [0.0; 6] };
            for l in 0..4 {
                (node.value[l], node.rate[l]) = (next(), next());
            }
            let mut local = Local::new(N);
            local.hessian.iter_mut().chain(local.mixed.iter_mut()).for_each(|x| *x = next());
            let (dim, base, w) = (5 * N + 1, N, 0.37);
            let mut data = vec![0.0; dim * dim];
            interior::<N, 4>(&mut data, dim, base, &node, &local, w);
            let (h, m) = (&local.hessian, &local.mixed);
            for (a, b) in (0..dim).flat_map(|a| (0..dim).map(move |b| (a, b))) {
                // Column `a`, row `b`: coefficient (l, j) and (ll, jj) of the block.
                let inside = a >= base && b >= a && b < base + 4 * N;
                let expected = if inside {
                    let ((l, j), (ll, jj)) = (((a - base) / N, (a - base) % N), ((b - base) / N, (b - base) % N));
                    let (v, dr) = (node.value[l] * w, node.rate[l] * w);
                    let row = h[j * N + jj] * v + m[jj * N + j] * dr;
                    0.0 - (row * node.value[ll] + m[j * N + jj] * v * node.rate[ll])
                } else {
                    0.0
                };
                assert_eq!(data[a * dim + b].to_bits(), expected.to_bits(), "N = {N}, column {a}, row {b}");
            }
        }
        check::<2>();
        check::<3>();
        check::<4>();
    }
}
