//! The base-range rows' curvature in the SQP's model (issue 20; [`Discretised::curvature`]):
//! the multiplier-weighted Hessian of `phi(t_k)` at the rows' breakpoints, so that the QP's
//! model of a base-range problem is second order in its active rows (their terms outside the
//! band go to the QP as extra variables, [`Discretised::curved_rows`]). Without it the model
//! had the effort's curvature alone, and the trust region's steps on an active base row were
//! gradient-like: the 3-link tests' arm inside `-30:60` deg stopped after 240 SQP iterations
//! (OptimalFailed, KKT 6.9e-5).
//!
//! The obstacles' clearance rows (issue 21) depend on `phi(t)` too, the base pose carrying the
//! body toward the obstacle: their curvature through it, `z_i (d g_i / d phi) hess phi(t_i)`, is
//! of the holonomy's kind (`lambda hess phi(T)`) and as large, and it is modelled the same way
//! ([`Limited::obstacle_curvature`]; the distance's own second derivatives are left out). Without
//! it the model on the 3-link obstacle bench was indefinite on the active rows' null space at 103
//! of its 109 SQP iterations, each step the shift's `W + tau S` and the iteration linear at a
//! rate of 0.87; with it 60 iterations to the same plan.

use nalgebra::{DMatrix, DVector};

use super::super::connection::{Local, specialised};
use super::clearance::OBSTACLE_PIECES;
use super::phi_path::{Values, path_on};
use super::{Limited, torque_times};
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::sqp::Discretised;
use rayon::prelude::*;

impl Limited<'_> {
    /// The indices of the base-range rows among [`Limited::inequalities`]' (empty without a
    /// base range).
    pub(super) fn base_rows(&self) -> std::ops::Range<usize> {
        if self.base.is_none() {
            return 0..0;
        }
        let basis = self.disc.basis();
        let torque = if self.torque.is_empty() { 0 } else { 2 * self.torque.len() * torque_times(basis).len() };
        let from = self.linear.len() + torque;
        from..from + 2 * (basis.breakpoints().len() - 1)
    }

    /// The base-range rows' curvature `sum_k z_k hess g_k` ([`Discretised::curvature`]), `z`
    /// the multipliers of every row of [`Limited::inequalities`] (the base rows after the linear
    /// and the torque ones, two per breakpoint: `phi - hi`, then `lo - phi`); `None` where no
    /// base row has a positive multiplier.
    ///
    /// `phi(t_k) = phi(0) - integral_0^{t_k} g(theta, theta')`, so its Hessian is a sum over the
    /// quadrature's nodes before `t_k` of `-w B^T hess g B`, `B` the node's basis values and
    /// rates (local: inside the band). Weighted by the rows' multipliers it is one pass over the
    /// nodes with the weight `-w sum_{t_k >= t} (z_hi,k - z_lo,k)`; `g = a(theta) . theta'` is
    /// linear in `theta'`, so `hess g` is its `theta`-block and the mixed one.
    pub(super) fn base_curvature(&self, x: &DVector<f64>, z: &[f64]) -> Option<DMatrix<f64>> {
        self.base?;
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let b = basis.breakpoints();
        let spans = b.len() - 1;
        let rows = z.get(self.base_rows())?;
        if rows.iter().all(|v| !(*v > 0.0)) {
            return None;
        }
        // The weight of span `s`'s nodes: the rows' at every breakpoint after it.
        let mut weight = vec![0.0; spans];
        let mut sum = 0.0;
        for s in (0..spans).rev() {
            sum += rows[2 * s] - rows[2 * s + 1];
            weight[s] = sum;
        }
        let c = self.disc.coefficients(x);
        let dim = self.disc.dim();
        let mut h = DMatrix::zeros(dim, dim);
        let rule = GaussLegendre::new(8);
        let mut local = Local::new(n);
        let (mut th, mut w) = (vec![0.0; n], vec![0.0; n]);
        for (s, win) in b.windows(2).enumerate() {
            if weight[s] == 0.0 {
                continue;
            }
            let span = basis.span_of_interval(s);
            let first = span - p;
            let (mid, half) = ((win[0] + win[1]) / 2.0, (win[1] - win[0]) / 2.0);
            for (xi, wi) in rule.nodes.iter().zip(&rule.weights) {
                let t = mid + half * xi;
                let [value, rate] = self.path_at(&c, span, t, &mut th, &mut w);
                self.connection.local(&th, &w, &mut local);
                let scale = -half * wi * weight[s];
                self.add_to_span(&mut h, first, (p, n), |l, j, ll, jj| {
                    // d^2 g / dc_lj dc_ll,jj: theta-theta, theta-theta' both ways.
                    let v = local.hessian[j * n + jj] * value[l] * value[ll]
                        + local.mixed[j * n + jj] * value[l] * rate[ll]
                        + local.mixed[jj * n + j] * rate[l] * value[ll];
                    scale * v
                });
            }
        }
        Some(h)
    }
}

impl Limited<'_> {
    /// The obstacles' rows' curvature through the base angle, `sum_i z_i (d g_i / d phi)
    /// hess phi(t_i)` over the rows with a positive multiplier ([`Limited::phi_slopes`], as at
    /// the last evaluation with gradients, the iterate's), on the rows' own quadrature nodes
    /// ([`Limited::phi_path_each`]'s at [`OBSTACLE_PIECES`] parts per span: on 8 nodes per span,
    /// each weighted by the rows after its part, the 3-link obstacle bench's repair no longer
    /// cleared); `None` where no such row has a positive multiplier.
    pub(super) fn obstacle_curvature(&self, x: &DVector<f64>, z: &[f64]) -> Option<DMatrix<f64>> {
        let slopes = self.phi_slopes.borrow();
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let b = basis.breakpoints();
        let parts = (b.len() - 1) * OBSTACLE_PIECES;
        let active = |&&(row, _, _): &&(usize, usize, f64)| z.get(row).is_some_and(|v| *v > 0.0);
        if !slopes.iter().any(|r| active(&r)) {
            return None;
        }
        // The weight of each part's nodes: the rows' at every point after it.
        let mut weight = vec![0.0; parts];
        for &(row, point, slope) in slopes.iter().filter(active) {
            weight[point.min(parts - 1)] += z[row] * slope;
        }
        for k in (0..parts - 1).rev() {
            weight[k] += weight[k + 1];
        }
        // A rejected step's next iteration asks again at the same iterate and multipliers: the
        // same weights at the same coefficients give the same matrix (3-link obstacle bench: 4
        // of its 62 calls).
        let key: Vec<u64> = x.iter().chain(&weight).map(|v| v.to_bits()).collect();
        if let Some((_, h)) = self.obstacle_hessian.borrow().as_ref().filter(|(k, _)| *k == key) {
            return Some(h.clone());
        }
        let c = self.disc.coefficients(x);
        let dim = self.disc.dim();
        let mut h = DMatrix::zeros(dim, dim);
        let rule = super::phi_path::rule(OBSTACLE_PIECES);
        let per_part = rule.weights.len();
        let nodes = self.node_values(OBSTACLE_PIECES);
        let nodes: &[Values] = &nodes;
        // The nodes' sines and cosines where the rows' evaluation at this iterate kept them.
        let sines = self.known_sines(&c, OBSTACLE_PIECES, nodes.len());
        let sines = sines.as_deref();
        let connection = self.connection;
        // A span's block in its `p + 1` coefficients of each joint, as `(p + 1)^2` tiles of
        // `n x n` (tile `(l, ll)` at `((l (p + 1) + ll) n + j) n + jj`), the tiles `ll >= l`
        // summed over its nodes (each node's term is symmetric; the others are their
        // transposes); `None` where no node of the span has a weight.
        let (tiles, nn) = (p + 1, n * n);
        let block_of = |s: usize| -> Option<Vec<f64>> {
            let parts = s * OBSTACLE_PIECES..(s + 1) * OBSTACLE_PIECES;
            if weight[parts].iter().all(|v| *v == 0.0) {
                return None;
            }
            let (win, span) = (&b[s..s + 2], basis.span_of_interval(s));
            let mut local = Local::new(n);
            let (mut th, mut w) = (vec![0.0; n], vec![0.0; n]);
            let mut block = vec![0.0; tiles * tiles * nn];
            // A node's `scale (value_ll hess g + rate_ll mixed)` and `scale value_ll mixed^T`
            // of each `ll` ([`node_terms`]).
            let mut terms = vec![0.0; 2 * tiles * nn];
            let width = (win[1] - win[0]) / OBSTACLE_PIECES as f64;
            for k in 0..OBSTACLE_PIECES {
                let part = s * OBSTACLE_PIECES + k;
                if weight[part] == 0.0 {
                    continue;
                }
                let (from, to) = (
                    win[0] + width * k as f64,
                    if k + 1 == OBSTACLE_PIECES { win[1] } else { win[0] + width * (k + 1) as f64 },
                );
                let half = (to - from) / 2.0;
                for (i, wi) in rule.weights.iter().enumerate() {
                    let at = part * per_part + i;
                    let values = &nodes[at];
                    path_on(n, p, &c, span, values, &mut th, &mut w);
                    match sines {
                        Some(v) => connection.local_known(&th, &w, &mut local, &v[at * n..(at + 1) * n]),
                        None => connection.local(&th, &w, &mut local),
                    }
                    let scale = -half * wi * weight[part];
                    add_node(n, p, scale, values, &local, &mut terms, &mut block);
                }
            }
            Some(block)
        };
        // The spans share nothing: their blocks in parallel, added to `h` in their order (the
        // same sums as one pass over them).
        let blocks: Vec<Option<Vec<f64>>> = (0..b.len() - 1).into_par_iter().map(block_of).collect();
        for (s, block) in blocks.iter().enumerate() {
            let Some(block) = block else { continue };
            let entry = |l: usize, j: usize, ll: usize, jj: usize| {
                if ll >= l {
                    block[(l * tiles + ll) * nn + j * n + jj]
                } else {
                    block[(ll * tiles + l) * nn + jj * n + j]
                }
            };
            self.add_to_span(&mut h, basis.span_of_interval(s) - p, (p, n), entry);
        }
        *self.obstacle_hessian.borrow_mut() = Some((key, h.clone()));
        Some(h)
    }

    /// Adds `entry(l, j, ll, jj)` to `h` at the free coefficients of basis function `first + l`
    /// of joint `j` and `first + ll` of joint `jj`: a knot span's `(p + 1) n` coefficients,
    /// `p` the degree and `n` the joints.
    fn add_to_span(
        &self,
        h: &mut DMatrix<f64>,
        first: usize,
        (p, n): (usize, usize),
        mut entry: impl FnMut(usize, usize, usize, usize) -> f64,
    ) {
        // The span's free indices `(l, j, index)`, found once (not per entry).
        let free: Vec<(usize, usize, usize)> = (0..=p)
            .flat_map(|l| (0..n).map(move |j| (l, j)))
            .filter_map(|(l, j)| Some((l, j, self.index(first + l, j)?)))
            .collect();
        for &(l, j, row) in &free {
            for &(ll, jj, col) in &free {
                h[(row, col)] += entry(l, j, ll, jj);
            }
        }
    }
}

/// Adds one node's term to a span's block of [`Limited::obstacle_curvature`]: tile `(l, ll)`,
/// `ll >= l`, gains `value_l (v hess g + r mixed) + rate_l v mixed^T`, `v = scale value_ll` and
/// `r = scale rate_ll` (`terms` the work space of the bracketed factors of each `ll`, `2 (p + 1)
/// n^2`). Specialised on the joint count and the cubic degree (the loops unrolled, the same
/// operations in the same order: the same bits).
fn add_node(n: usize, p: usize, scale: f64, values: &Values, local: &Local, terms: &mut [f64], block: &mut [f64]) {
    specialised!(n, |n| match p {
        3 => node_terms(n, 3, scale, values, local, terms, block),
        p => node_terms(n, p, scale, values, local, terms, block),
    })
}

/// [`add_node`] for `n` joints and degree `p` (inlined where they are constants).
#[inline(always)]
fn node_terms(
    n: usize,
    p: usize,
    scale: f64,
    [value, rate]: &Values,
    local: &Local,
    terms: &mut [f64],
    block: &mut [f64],
) {
    let (tiles, nn) = (p + 1, n * n);
    let (hessian, mixed) = (&local.hessian[..nn], &local.mixed[..nn]);
    let (first, second) = terms[..2 * tiles * nn].split_at_mut(tiles * nn);
    // d^2 g / dc_lj dc_ll,jj: theta-theta, theta-theta' both ways.
    for ll in 0..tiles {
        let (v, r) = (scale * value[ll], scale * rate[ll]);
        let (one, two) = (&mut first[ll * nn..(ll + 1) * nn], &mut second[ll * nn..(ll + 1) * nn]);
        for j in 0..n {
            for jj in 0..n {
                one[j * n + jj] = v * hessian[j * n + jj] + r * mixed[j * n + jj];
                two[j * n + jj] = v * mixed[jj * n + j];
            }
        }
    }
    let block = &mut block[..tiles * tiles * nn];
    for l in 0..tiles {
        let (v, r) = (value[l], rate[l]);
        for ll in l..tiles {
            let tile = &mut block[(l * tiles + ll) * nn..(l * tiles + ll + 1) * nn];
            let (one, two) = (&first[ll * nn..(ll + 1) * nn], &second[ll * nn..(ll + 1) * nn]);
            for i in 0..nn {
                tile[i] += v * one[i] + r * two[i];
            }
        }
    }
}
