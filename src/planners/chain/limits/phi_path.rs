//! The base angle along a path (Eq. 7 at zero momentum, `phi(t) = phi(0) - integral_0^t g`),
//! with its exact gradient in the free coefficients: the base-range rows' quantity, read at the
//! ends of equal parts of every knot span ([`super::Limited::phi_path`]), and the joint path at a
//! time that the rows and their curvature ([`super::curvature`]) share.

use super::super::connection::{Local, specialised};
use super::Limited;
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::spline::MAX_DEGREE;
use crate::planners::optimal::sqp::Discretised;

/// Gauss–Legendre nodes per knot span, split among its parts ([`rule`]).
const NODES: usize = 8;

/// Least Gauss–Legendre nodes per part of a knot span.
const LEAST_NODES: usize = 2;

/// The Gauss–Legendre rule of each of `pieces` equal parts of a knot span: [`NODES`] shared
/// among them, at least [`LEAST_NODES`] each. A part of the obstacles' rows
/// ([`super::clearance::OBSTACLE_PIECES`], a sixteenth of a span, 20 ms on a 10 s plan of 32 spans)
/// is short enough that two nodes (exact to degree 3) integrate `g` there to about `1e-12` rad;
/// at eight nodes a part, the 3-link obstacle bench's `phi(t)` and its curvature took 55 % of
/// the plan's instructions on 4096 nodes an evaluation.
pub(super) fn rule(pieces: usize) -> GaussLegendre {
    GaussLegendre::new((NODES / pieces.max(1)).max(LEAST_NODES))
}

/// [`Limited::path_with`] without the [`Limited`]: `n` joints, degree `p`.
pub(super) fn path_on(n: usize, p: usize, c: &[Vec<f64>], span: usize, values: &Values, th: &mut [f64], w: &mut [f64]) {
    let first = span - p;
    specialised!(n, |n| match p {
        3 => path_of(n, 3, c, first, values, th, w),
        p => path_of(n, p, c, first, values, th, w),
    })
}

/// [`Limited::path_with`] for `n` joints and degree `p`, the span's first coefficient `first`
/// (inlined where `n` and `p` are constants: the loops unrolled, the same sums in the same
/// order as `(0..=p).map(..).sum()`).
#[inline(always)]
fn path_of(n: usize, p: usize, c: &[Vec<f64>], first: usize, [value, rate]: &Values, th: &mut [f64], w: &mut [f64]) {
    let (value, rate) = (&value[..=p], &rate[..=p]);
    for ((th, w), c) in th[..n].iter_mut().zip(&mut w[..n]).zip(&c[..n]) {
        let c = &c[first..=first + p];
        *th = value.iter().zip(c).map(|(v, c)| v * c).sum();
        *w = rate.iter().zip(c).map(|(r, c)| r * c).sum();
    }
}

/// The basis' values and rates at one time (those of the `p + 1` functions of its span).
pub(super) type Values = [[f64; MAX_DEGREE + 1]; 2];

impl Limited<'_> {
    /// The base angle `phi(t) = phi(0) - integral_0^t g` (Eq. 7 at zero momentum) at the ends of
    /// the `pieces` equal parts of every knot span (`t = T` last), by Gauss–Legendre quadrature
    /// per part ([`rule`]), with its exact gradient in the free coefficients for `order >= 1`
    /// (empty otherwise).
    pub(super) fn phi_path(&self, c: &[Vec<f64>], pieces: usize, order: usize) -> Vec<PathPoint> {
        let mut out = Vec::new();
        self.phi_path_each(c, pieces, order, |p| {
            out.push(PathPoint { t: p.t, span: p.span, phi: p.phi, grad: p.grad.to_vec(), values: p.values });
        });
        out
    }

    /// The joint angles (into `th`) and rates (into `w`) of the path with coefficients `c` at
    /// `t` in the basis' knot span `span`, and the basis' values and rates there.
    pub(super) fn path_at(
        &self,
        c: &[Vec<f64>],
        span: usize,
        t: f64,
        th: &mut [f64],
        w: &mut [f64],
    ) -> [[f64; MAX_DEGREE + 1]; 2] {
        let values = self.disc.basis().values_and_rates(span, t);
        self.path_with(c, span, &values, th, w);
        values
    }

    /// [`Limited::path_at`] with the basis' values and rates at the time given.
    pub(super) fn path_with(&self, c: &[Vec<f64>], span: usize, values: &Values, th: &mut [f64], w: &mut [f64]) {
        let p = self.disc.basis().degree();
        let first = span - p;
        specialised!(self.arm.joints(), |n| match p {
            3 => path_of(n, 3, c, first, values, th, w),
            p => path_of(n, p, c, first, values, th, w),
        })
    }

    /// The basis' values and rates at every quadrature node of [`Limited::phi_path_each`] at
    /// `pieces` parts per knot span, in its order: the nodes do not move while the basis is
    /// the same, so they are found once per [`Limited`] (and `pieces`), not at every
    /// evaluation (on the 3-link obstacle bench 4096 nodes at each of its ~215 evaluations).
    pub(super) fn node_values(&self, pieces: usize) -> std::rc::Rc<[Values]> {
        let mut cache = self.nodes.borrow_mut();
        if let Some((_, v)) = cache.iter().find(|(k, _)| *k == pieces) {
            return v.clone();
        }
        let basis = self.disc.basis();
        let rule = rule(pieces);
        let mut out = Vec::new();
        for (s, win) in basis.breakpoints().windows(2).enumerate() {
            let span = basis.span_of_interval(s);
            let width = (win[1] - win[0]) / pieces as f64;
            for k in 0..pieces {
                let (from, to) =
                    (win[0] + width * k as f64, if k + 1 == pieces { win[1] } else { win[0] + width * (k + 1) as f64 });
                let (mid, half) = ((from + to) / 2.0, (to - from) / 2.0);
                out.extend(rule.nodes.iter().map(|xi| basis.values_and_rates(span, mid + half * xi)));
            }
        }
        let values: std::rc::Rc<[Values]> = out.into();
        cache.push((pieces, values.clone()));
        values
    }

    /// The basis' values and rates at the end of every part of [`Limited::phi_path_each`] at
    /// `pieces` parts per knot span (its points' times, each in its own span), found once per
    /// [`Limited`] and `pieces` (the clearance rows read them at every point of every
    /// evaluation: 64 thousand calls on the 3-link obstacle bench).
    pub(super) fn end_values(&self, pieces: usize) -> std::rc::Rc<[Values]> {
        let mut cache = self.ends.borrow_mut();
        if let Some((_, v)) = cache.iter().find(|(k, _)| *k == pieces) {
            return v.clone();
        }
        let basis = self.disc.basis();
        let mut out = Vec::new();
        for (s, win) in basis.breakpoints().windows(2).enumerate() {
            let span = basis.span_of_interval(s);
            let width = (win[1] - win[0]) / pieces as f64;
            for k in 0..pieces {
                let to = if k + 1 == pieces { win[1] } else { win[0] + width * (k + 1) as f64 };
                out.push(basis.values_and_rates(span, to));
            }
        }
        let values: std::rc::Rc<[Values]> = out.into();
        cache.push((pieces, values.clone()));
        values
    }

    /// [`Limited::phi_path`]'s points handed to `each` in order, the gradient borrowed (not
    /// copied for every point: the obstacles' rows read it only near an obstacle).
    pub(super) fn phi_path_each(
        &self,
        c: &[Vec<f64>],
        pieces: usize,
        order: usize,
        mut each: impl FnMut(PathPoint<&[f64]>),
    ) {
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let connection = self.connection;
        let rule = rule(pieces);
        let nodes = self.node_values(pieces);
        let mut node = nodes.iter();
        let ends = self.end_values(pieces);
        let mut end = ends.iter();
        let b = basis.breakpoints();
        let mut phi = self.disc.targets().phi_start;
        let mut grad = vec![0.0; if order >= 1 { self.disc.dim() } else { 0 }];
        let mut local = Local::new(n);
        let (mut th, mut w) = (vec![0.0; n], vec![0.0; n]);
        // Each node's sines and cosines, kept where they are taken (the trial's values) and read
        // where they are known (the accepted iterate's rows, [`Limited::obstacle_curvature`]).
        let (known, mut sines) = self.node_sines(c, pieces, nodes.len());
        let mut sines = sines.chunks_exact_mut(n);
        // The span's free coefficients `(l, j, index)` (found once per span, not per node).
        let mut free = Vec::with_capacity((p + 1) * n);
        for (s, win) in b.windows(2).enumerate() {
            let span = basis.span_of_interval(s);
            let first = span - p;
            let width = (win[1] - win[0]) / pieces as f64;
            free.clear();
            let span_free = (0..=p).flat_map(|l| (0..n).map(move |j| (l, j)));
            free.extend(span_free.filter_map(|(l, j)| self.index(first + l, j).map(|k| (l, j, k))));
            for k in 0..pieces {
                let (from, to) =
                    (win[0] + width * k as f64, if k + 1 == pieces { win[1] } else { win[0] + width * (k + 1) as f64 });
                let half = (to - from) / 2.0;
                for wi in &rule.weights {
                    let values = node.next().expect("one basis' values per node");
                    let keep = sines.next().expect("one node's sines per node");
                    self.path_with(c, span, values, &mut th, &mut w);
                    let [value, rate] = values;
                    let weight = half * wi;
                    if order >= 1 {
                        // First derivatives only: the gradient of `phi(t)` (bit for bit
                        // `Connection::local`'s, without its Hessian's sums), and `phi(t)` the
                        // same bits as at order 0 (`plain`: the clearance rows reuse the order-0
                        // distances at the same coefficients, `super::clearance`).
                        if !known {
                            connection.value_keeping(&th, &w, keep);
                        }
                        connection.first_order_known(&th, &w, &mut local, keep);
                        phi -= weight * local.plain;
                        for &(l, j, idx) in &free {
                            grad[idx] -= weight * (local.gradient[j] * value[l] + local.a[j] * rate[l]);
                        }
                    } else {
                        phi -= weight * connection.value_keeping(&th, &w, keep);
                    }
                }
                let values = *end.next().expect("one basis' values per part");
                each(PathPoint { t: to, span, phi, grad: &grad, values });
            }
        }
    }

    /// The sines and cosines of the links' angles at the `len` quadrature nodes of
    /// [`Limited::phi_path_each`] at `pieces` parts per knot span, `n` per node, and whether
    /// they are those of the coefficients `c` (else they are to be found, and are kept for `c`).
    pub(super) fn node_sines(
        &self,
        c: &[Vec<f64>],
        pieces: usize,
        len: usize,
    ) -> (bool, std::cell::RefMut<'_, Vec<(f64, f64)>>) {
        let key: Vec<u64> = c.iter().flatten().map(|v| v.to_bits()).collect();
        let mut memo = self.sines.borrow_mut();
        let i = match memo.iter().position(|s| s.pieces == pieces) {
            Some(i) => i,
            None => {
                memo.push(Sines { pieces, ..Default::default() });
                memo.len() - 1
            }
        };
        let size = len * self.arm.joints();
        let known = memo[i].key == key && memo[i].values.len() == size;
        if !known {
            // Every node's are written before they are read (no zeros needed where the size is kept).
            memo[i].key = key;
            memo[i].values.resize(size, (0.0, 0.0));
        }
        (known, std::cell::RefMut::map(memo, |m| &mut m[i].values))
    }

    /// [`Limited::node_sines`] where they are those of the coefficients `c` (read only).
    pub(super) fn known_sines(
        &self,
        c: &[Vec<f64>],
        pieces: usize,
        len: usize,
    ) -> Option<std::cell::Ref<'_, [(f64, f64)]>> {
        let memo = self.sines.borrow();
        let size = len * self.arm.joints();
        let i = memo.iter().position(|s| s.pieces == pieces && s.values.len() == size)?;
        let same = memo[i].key.len() == c.iter().map(Vec::len).sum::<usize>()
            && memo[i].key.iter().zip(c.iter().flatten()).all(|(k, v)| *k == v.to_bits());
        same.then(|| std::cell::Ref::map(memo, |m| &m[i].values[..]))
    }

    /// The times of [`Limited::phi_path`] without the base angle (`phi` 0, no gradient).
    pub(super) fn path_points(&self, pieces: usize) -> Vec<PathPoint> {
        let b = self.disc.basis().breakpoints();
        let p = self.disc.basis().degree();
        let mut out = Vec::with_capacity(pieces * (b.len() - 1));
        for (s, win) in b.windows(2).enumerate() {
            let width = (win[1] - win[0]) / pieces as f64;
            for k in 1..=pieces {
                let t = if k == pieces { win[1] } else { win[0] + width * k as f64 };
                let values = self.disc.basis().values_and_rates(s + p, t);
                out.push(PathPoint { t, span: s + p, phi: 0.0, grad: Vec::new(), values });
            }
        }
        out
    }
}

/// The sines and cosines of the links' angles at every quadrature node of
/// [`Limited::phi_path_each`] at `pieces` parts per knot span, at the coefficients whose bits are
/// `key` ([`Limited::node_sines`]).
#[derive(Debug, Clone, Default)]
pub(super) struct Sines {
    pieces: usize,
    key: Vec<u64>,
    values: Vec<(f64, f64)>,
}

/// The base angle at one time of [`Limited::phi_path`] (its gradient owned, or borrowed by
/// [`Limited::phi_path_each`]).
pub(super) struct PathPoint<G = Vec<f64>> {
    /// The time \[s\].
    pub(super) t: f64,
    /// The knot span (of the basis' numbering) the point closes.
    pub(super) span: usize,
    /// `phi(t)` \[rad\].
    pub(super) phi: f64,
    /// `d phi(t) / dx` in the free coefficients (empty for order 0).
    pub(super) grad: G,
    /// The basis' values and rates at `t` (those of the span's `p + 1` functions).
    pub(super) values: Values,
}
