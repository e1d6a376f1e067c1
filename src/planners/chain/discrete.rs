//! The discretised problem of an `n`-joint arm: each joint path a clamped B-spline on one shared
//! basis ([`SplineBasis`]) with the end conditions in its first and last coefficients, the effort
//! and the holonomy constraint as Gauss–Legendre sums over the knot spans, with exact gradients and
//! Hessians.
//!
//! The free variables are the interior coefficients interleaved by coefficient,
//! `x[(i - r) n + j]` for coefficient `i` of joint `j`, so every Hessian is banded with
//! half-bandwidth `n (p + 1) - 1`.

use std::sync::{Arc, Mutex, PoisonError};

use nalgebra::{DMatrix, DVector};

use super::connection::{Connection, Local, MAX_JOINTS, specialised};
use super::energy::{EnergyLocal, energy, energy_local};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::band::BandCholesky;
use crate::planners::optimal::discrete::Evaluation;
use crate::planners::optimal::spline::{MAX_DEGREE, SplineBasis};
use crate::planners::optimal::sqp::Discretised;

mod hessian;

/// Ends of the joint paths and the holonomy target.
#[derive(Debug, Clone, PartialEq)]
pub struct Targets {
    /// `theta(0)` \[rad\].
    pub start: Vec<f64>,
    /// `theta'(0)` \[rad/s\].
    pub initial_velocity: Vec<f64>,
    /// `theta(T)` \[rad\] (a representative of the goal).
    pub end: Vec<f64>,
    /// `phi(0)` \[rad\].
    pub phi_start: f64,
    /// The `phi(T)` to reach \[rad\].
    pub phi_end: f64,
}

/// One quadrature node with the basis functions that do not vanish there.
#[derive(Debug, Clone, Copy)]
struct Node {
    first: usize,
    t: f64,
    weight: f64,
    value: [f64; MAX_DEGREE + 1],
    rate: [f64; MAX_DEGREE + 1],
}

/// The tables of one basis, quadrature and joint count: nodes, the effort's constant Hessian
/// with its band factor, and the mass matrix's factor of one joint (for projections).
#[derive(Debug)]
pub struct Table {
    basis: SplineBasis,
    joints: usize,
    fixed: usize,
    nodes: Vec<Node>,
    effort_hessian: DMatrix<f64>,
    metric: Option<BandCholesky>,
    mass: Option<BandCholesky>,
}

impl Table {
    /// The tables for `joints` joints on `basis` with `nodes_per_span` nodes per knot span;
    /// `fixed` coefficients per joint at each end (2: value and velocity; 3: and acceleration).
    pub fn new(basis: SplineBasis, joints: usize, fixed: usize, nodes_per_span: usize) -> Result<Self, Error> {
        let p = basis.degree();
        let len = basis.len();
        if len < 2 * fixed + 1 || nodes_per_span < p {
            return Err(Error::from(InputError::InvalidParameter {
                name: "spans".into(),
                value: len as f64,
                expected: "a basis with a free coefficient and at least p quadrature nodes per span",
            }));
        }
        let rule = GaussLegendre::new(nodes_per_span);
        let b = basis.breakpoints();
        let mut nodes = Vec::with_capacity((b.len() - 1) * nodes_per_span);
        for s in 0..b.len() - 1 {
            let span = basis.span_of_interval(s);
            let (mid, half) = ((b[s] + b[s + 1]) / 2.0, (b[s + 1] - b[s]) / 2.0);
            for (xi, wi) in rule.nodes.iter().zip(&rule.weights) {
                let t = mid + half * xi;
                let [value, rate] = basis.values_and_rates(span, t);
                nodes.push(Node { first: span - p, t, weight: half * wi, value, rate });
            }
        }
        let nf = len - 2 * fixed;
        let mut mass = DMatrix::zeros(nf, nf);
        let mut stiffness = DMatrix::zeros(nf, nf);
        for node in &nodes {
            for l in 0..=p {
                let Some(i) = free(node.first + l, fixed, len) else { continue };
                for ll in 0..=p {
                    if let Some(ii) = free(node.first + ll, fixed, len) {
                        mass[(i, ii)] += node.weight * node.value[l] * node.value[ll];
                        stiffness[(i, ii)] += 2.0 * node.weight * node.rate[l] * node.rate[ll];
                    }
                }
            }
        }
        let dim = nf * joints;
        let mut effort_hessian = DMatrix::zeros(dim, dim);
        for i in 0..nf {
            for ii in i.saturating_sub(p)..(i + p + 1).min(nf) {
                for j in 0..joints {
                    effort_hessian[(i * joints + j, ii * joints + j)] = stiffness[(i, ii)];
                }
            }
        }
        let hb = joints * (p + 1) - 1;
        let metric = BandCholesky::new(&effort_hessian, hb);
        let mass = BandCholesky::new(&mass, p);
        Ok(Self { basis, joints, fixed, nodes, effort_hessian, metric, mass })
    }

    /// The basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.basis
    }
}

/// The free index of coefficient `i` (of `len`), `None` for the fixed ones.
fn free(i: usize, fixed: usize, len: usize) -> Option<usize> {
    (fixed..len - fixed).contains(&i).then(|| i - fixed)
}

/// The discretised problem on one basis.
#[derive(Debug, Clone)]
pub struct Discretisation {
    connection: Arc<Connection>,
    table: Arc<Table>,
    targets: Targets,
    /// Fixed leading and trailing coefficients, per joint.
    head: Vec<Vec<f64>>,
    tail: Vec<Vec<f64>>,
    /// The arm whose kinetic energy is the cost ([`Cost::Energy`](crate::planners::optimal::Cost));
    /// `None`: the effort.
    energy: Option<Arc<Arm>>,
    /// The links' sines and cosines at the nodes of the last integrals, and a spare Hessian.
    kept: KeptAngles,
}

/// The sines and cosines of the links' angles at every node (`n` per node) at the last `x`
/// whose integrals were taken: the SQP takes the derivatives of an accepted trial step at the
/// same `x` (bit for bit), whose sines and cosines are then not taken again. Beside them, a
/// constraint Hessian the SQP is done with ([`Discretised::recycle`]), zero outside its band,
/// for the next evaluation with second derivatives. A clone starts empty (a discretisation per
/// solve).
#[derive(Debug, Default)]
struct KeptAngles(Mutex<Option<Kept>>, Mutex<Option<DMatrix<f64>>>);

/// The `x` of the last integrals and the sines and cosines at its nodes.
type Kept = (DVector<f64>, Vec<(f64, f64)>);

impl Clone for KeptAngles {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Discretisation {
    /// The problem of `targets` on shared tables.
    pub fn on(connection: Arc<Connection>, table: Arc<Table>, targets: Targets) -> Self {
        let r = table.fixed;
        let (mut head, mut tail) = (Vec::new(), Vec::new());
        for j in 0..table.joints {
            let start = [targets.start[j], targets.initial_velocity[j], 0.0];
            let end = [targets.end[j], 0.0, 0.0];
            let (h, t) = table.basis.end_coefficients(&start[..r], &end[..r]);
            head.push(h);
            tail.push(t);
        }
        Self { connection, table, targets, head, tail, energy: None, kept: KeptAngles::default() }
    }

    /// The same problem with the kinetic energy of `arm` at zero angular momentum as the cost
    /// (`integral_0^T 1/2 theta'^T R theta' dt` \[J s\], see [`super::energy`]) instead of the
    /// effort.
    pub fn with_energy(mut self, arm: Arc<Arm>) -> Self {
        self.energy = Some(arm);
        self
    }

    /// The cost at `x`: the effort \[rad^2/s\], or the energy integral \[J s\] with
    /// [`Self::with_energy`].
    pub fn cost(&self, x: &DVector<f64>) -> f64 {
        let Some(arm) = &self.energy else { return self.integrals(x).1 };
        let n = self.table.joints;
        let c = self.coefficients(x);
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        let mut f = 0.0;
        for node in &self.table.nodes {
            self.point(&c, node, &mut theta, &mut rate);
            f += node.weight * energy(arm, &theta, &rate);
        }
        f
    }

    /// The ends and the holonomy target.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.table.basis
    }

    /// All coefficients per joint from the free ones.
    pub fn coefficients(&self, x: &DVector<f64>) -> Vec<Vec<f64>> {
        let n = self.table.joints;
        let nf = x.len() / n;
        (0..n)
            .map(|j| {
                let mut c = Vec::with_capacity(nf + 2 * self.table.fixed);
                c.extend_from_slice(&self.head[j]);
                c.extend((0..nf).map(|m| x[m * n + j]));
                c.extend_from_slice(&self.tail[j]);
                c
            })
            .collect()
    }

    /// `(theta, theta')` at a node into the buffers.
    fn point(&self, c: &[Vec<f64>], node: &Node, theta: &mut [f64], rate: &mut [f64]) {
        point_of(self.table.basis.degree(), c, node, theta, rate);
    }

    /// The quadrature of `integral_0^T g dt` \[rad\] and of the effort \[rad^2/s\] at `x`.
    pub fn integrals(&self, x: &DVector<f64>) -> (f64, f64) {
        let (n, p) = (self.table.joints, self.table.basis.degree());
        specialised!(n, |n| match p {
            3 => self.integrals_of(x, n, 3),
            p => self.integrals_of(x, n, p),
        })
    }

    /// [`Self::integrals`] for `n` joints and degree `p` (those of the table; inlined where they
    /// are constants).
    #[inline(always)]
    fn integrals_of(&self, x: &DVector<f64>, n: usize, p: usize) -> (f64, f64) {
        let c = self.coefficients(x);
        let ([mut theta, mut rate], m) = ([[0.0; MAX_JOINTS]; 2], n);
        let (theta, rate) = (&mut theta[..m], &mut rate[..m]);
        let (mut holonomy, mut effort) = (0.0, 0.0);
        let mut memo = self.kept.0.lock().unwrap_or_else(PoisonError::into_inner);
        // The buffers of the last integrals reused, the nodes' sines and cosines written in
        // place.
        let (mut at, mut kept) = memo.take().unwrap_or_else(|| (DVector::zeros(0), Vec::new()));
        kept.resize(self.table.nodes.len() * n, (0.0, 0.0));
        for (node, keep) in self.table.nodes.iter().zip(kept.chunks_exact_mut(n)) {
            point_of(p, &c, node, theta, rate);
            holonomy += node.weight * self.connection.value_of(n, theta, rate, Some(keep));
            effort += node.weight * rate.iter().map(|w| w * w).sum::<f64>();
        }
        if at.len() == x.len() {
            at.copy_from(x);
        } else {
            at = x.clone();
        }
        *memo = Some((at, kept));
        (holonomy, effort)
    }

    /// The free coefficients of the L2 projection (same nodes) of `path` onto the basis, the end
    /// conditions kept exact.
    pub fn project(&self, path: impl Fn(f64, &mut [f64])) -> Result<DVector<f64>, Error> {
        let table = &*self.table;
        let (n, p, len, r) = (table.joints, table.basis.degree(), table.basis.len(), table.fixed);
        let nf = len - 2 * r;
        let bad = || {
            Error::from(InputError::InvalidParameter {
                name: "seed".into(),
                value: f64::NAN,
                expected: "a finite joint path on a basis with a positive definite mass matrix",
            })
        };
        let chol = table.mass.as_ref().ok_or_else(bad)?;
        let fixed = self.coefficients(&DVector::zeros(n * nf));
        let mut rhs = vec![DVector::<f64>::zeros(nf); n];
        let (mut target, mut theta, mut rate) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for node in &table.nodes {
            path(node.t, &mut target);
            // The fixed coefficients' path is zero (exactly) where none of them is local.
            if node.first < r || node.first + p >= len - r {
                self.point(&fixed, node, &mut theta, &mut rate);
            } else {
                theta.fill(0.0);
            }
            for l in 0..=p {
                let Some(i) = free(node.first + l, r, len) else { continue };
                for j in 0..n {
                    rhs[j][i] += node.weight * node.value[l] * (target[j] - theta[j]);
                }
            }
        }
        let mut x = DVector::zeros(n * nf);
        for (j, rj) in rhs.iter().enumerate() {
            for (m, v) in chol.solve(rj).iter().enumerate() {
                x[m * n + j] = *v;
            }
        }
        x.iter().all(|v| v.is_finite()).then_some(x).ok_or_else(bad)
    }
}

impl Discretised for Discretisation {
    fn dim(&self) -> usize {
        self.table.effort_hessian.nrows()
    }

    fn half_bandwidth(&self) -> usize {
        self.table.joints * (self.table.basis.degree() + 1) - 1
    }

    fn effort_hessian(&self) -> &DMatrix<f64> {
        &self.table.effort_hessian
    }

    fn effort_cholesky(&self) -> Option<&BandCholesky> {
        self.table.metric.as_ref()
    }

    /// Effort `f` and `c = phi(0) - integral g dt - phi_end` at `x`, with derivatives by `order`.
    fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        let (n, p) = (self.table.joints, self.table.basis.degree());
        let residual = |integral: f64| self.targets.phi_start - integral - self.targets.phi_end;
        if order == 0 {
            let (integral, effort) = self.integrals(x);
            let f = if self.energy.is_some() { self.cost(x) } else { effort };
            let (empty, none) = (DVector::zeros(0), DMatrix::zeros(0, 0));
            return Evaluation {
                f,
                c: residual(integral),
                grad_f: empty.clone(),
                grad_c: empty,
                hess_f: Some(none.clone()),
                hess_c: none,
            };
        }
        // The same operations in the same order for every (n, p); inlined with them constant
        // for two to seven joints and cubic splines (the seed solves) the loops unroll.
        specialised!(n, |n| match p {
            3 => self.derivatives(x, order >= 2, n, 3),
            p => self.derivatives(x, order >= 2, n, p),
        })
    }

    fn recycle(&self, hess_c: DMatrix<f64>) {
        if hess_c.nrows() == self.dim() && hess_c.ncols() == self.dim() {
            *self.kept.1.lock().unwrap_or_else(PoisonError::into_inner) = Some(hess_c);
        }
    }
}

impl Discretisation {
    /// [`Discretised::evaluate`] at `order >= 1` (`second`: with the Hessians), for `n` joints
    /// and degree `p` (those of the table).
    #[inline(always)]
    fn derivatives(&self, x: &DVector<f64>, second: bool, n: usize, p: usize) -> Evaluation {
        let table = &*self.table;
        let (len, r) = (table.basis.len(), table.fixed);
        let dim = x.len();
        let residual = |integral: f64| self.targets.phi_start - integral - self.targets.phi_end;
        let c = self.coefficients(x);
        // The point and a row of the Hessian on the stack (kept in registers where `n` is a
        // constant).
        let ([mut theta, mut rate, mut row], m) = ([[0.0; MAX_JOINTS]; 3], n);
        let (theta, rate, row) = (&mut theta[..m], &mut rate[..m], &mut row[..m]);
        let mut local = Local::new(n);
        let (mut f, mut integral) = (0.0, 0.0);
        let (mut grad_f, mut grad_c) = (DVector::zeros(dim), DVector::zeros(dim));
        let hb = n * (p + 1) - 1;
        let mut hess_c = if second { self.zero_hessian(dim, hb) } else { DMatrix::zeros(0, 0) };
        // Free index of each local coefficient (usize::MAX when fixed).
        let mut idx = [usize::MAX; MAX_DEGREE + 1];
        let mut mixed = [0.0; MAX_JOINTS];
        let mut hess_f = match (second, &self.energy) {
            // The effort's Hessian is the table's, not copied ([`Evaluation::hess_f_or`]).
            (true, None) => None,
            (true, Some(_)) => Some(DMatrix::zeros(dim, dim)),
            (false, _) => Some(DMatrix::zeros(0, 0)),
        };
        // Buffers of the energy only where it is the cost (empty ones allocate nothing).
        let mut e_local = EnergyLocal::new(if self.energy.is_some() { n } else { 0 });
        // The sines and cosines of the last integrals where they were taken at this very `x`.
        let memo = self.kept.0.lock().unwrap_or_else(PoisonError::into_inner);
        let same = |y: &DVector<f64>| y.len() == dim && y.iter().zip(x.iter()).all(|(a, b)| a.to_bits() == b.to_bits());
        let known = memo.as_ref().filter(|(y, _)| same(y)).map(|(_, kept)| kept.as_slice());
        for (k, node) in table.nodes.iter().enumerate() {
            point_of(p, &c, node, theta, rate);
            self.connection.local_of(n, theta, rate, &mut local, known.map(|v| &v[k * n..(k + 1) * n]));
            let w = node.weight;
            integral += w * local.value;
            if let Some(arm) = &self.energy {
                energy_local(arm, theta, rate, &mut e_local);
                f += w * e_local.value;
            } else {
                f += w * rate.iter().map(|v| v * v).sum::<f64>();
            }
            for (l, slot) in idx.iter_mut().enumerate().take(p + 1) {
                *slot = free(node.first + l, r, len).map_or(usize::MAX, |i| i * n);
            }
            for (l, &il) in idx.iter().enumerate().take(p + 1) {
                if il == usize::MAX {
                    continue;
                }
                let (v, dr) = (node.value[l] * w, node.rate[l] * w);
                // c = phi0 - integral - phi_end: derivatives with the sign -1.
                let gc = &mut grad_c.as_mut_slice()[il..il + n];
                for ((g, lg), la) in gc.iter_mut().zip(&local.gradient).zip(&local.a) {
                    *g -= lg * v + la * dr;
                }
                let gf = &mut grad_f.as_mut_slice()[il..il + n];
                if self.energy.is_some() {
                    for ((g, et), er) in gf.iter_mut().zip(&e_local.d_theta).zip(&e_local.d_rate) {
                        *g += et * v + er * dr;
                    }
                } else {
                    for (g, rj) in gf.iter_mut().zip(rate.iter()) {
                        *g += 2.0 * rj * dr;
                    }
                }
            }
            if !second {
                continue;
            }
            if let (Some(_), Some(h)) = (&self.energy, hess_f.as_mut()) {
                hessian::add_energy(h, &e_local, node, &idx[..=p], n, w);
            }
            // The free local coefficients `(l, free index times n)`, in order: the loops below
            // run over them alone. (Every entry takes one term per node, so the order of the
            // loops does not change the sums.)
            let mut free_locals = [(0, 0); MAX_DEGREE + 1];
            let mut count = 0;
            for (l, &il) in idx.iter().enumerate().take(p + 1) {
                if il != usize::MAX {
                    free_locals[count] = (l, il);
                    count += 1;
                }
            }
            let free_locals = &free_locals[..count];
            let data = hess_c.as_mut_slice();
            // Every local coefficient free (all nodes but the end spans'), cubic splines: the
            // same terms unrolled ([`hessian::interior`]).
            let base = free_locals.first().map_or(0, |f| f.1);
            let unrolled = count == p + 1
                && match (n, p) {
                    (2, 3) => hessian::interior::<2, 4>(data, dim, base, node, &local, w),
                    (3, 3) => hessian::interior::<3, 4>(data, dim, base, node, &local, w),
                    (4, 3) => hessian::interior::<4, 4>(data, dim, base, node, &local, w),
                    _ => false,
                };
            let general = if unrolled { &free_locals[..0] } else { free_locals };
            for (a, &(l, il)) in general.iter().enumerate() {
                let (v, dr) = (node.value[l] * w, node.rate[l] * w);
                for j in 0..n {
                    // d^2 g / d c_{l j} d(theta_jj, theta'_jj) contracted with c_{l j}'s factors.
                    let hessian = &local.hessian[j * n..(j + 1) * n];
                    for ((out, h), m) in row.iter_mut().zip(hessian).zip(local.mixed[j..].iter().step_by(n)) {
                        *out = h * v + m * dr;
                    }
                    // The mixed terms times `v` (as `m * v * rr` multiplies them first).
                    for (mv, m) in mixed.iter_mut().zip(&local.mixed[j * n..(j + 1) * n]) {
                        *mv = m * v;
                    }
                    let col = (il + j) * dim;
                    // The rows on and below the diagonal (`ll >= l`, and `jj >= j` where
                    // `ll = l`); the others are mirrored after the sum. The mixed term of
                    // (l, j) as theta and (ll, jj) as theta'.
                    let (vv, rr) = (node.value[l], node.rate[l]);
                    let out = &mut data[col + il + j..col + il + n];
                    for ((o, rw), mv) in out.iter_mut().zip(&row[j..n]).zip(&mixed[j..n]) {
                        *o -= rw * vv + mv * rr;
                    }
                    for &(ll, index) in &general[a + 1..] {
                        let (vv, rr) = (node.value[ll], node.rate[ll]);
                        let out = &mut data[col + index..col + index + n];
                        for ((o, rw), mv) in out.iter_mut().zip(&row[..n]).zip(&mixed[..n]) {
                            *o -= rw * vv + mv * rr;
                        }
                    }
                }
            }
        }
        if second {
            // The upper band from the lower one (the Hessian is symmetric).
            let data = hess_c.as_mut_slice();
            for col in 0..dim {
                for below in col + 1..(col + hb + 1).min(dim) {
                    data[below * dim + col] = data[col * dim + below];
                }
            }
        }
        Evaluation { f, c: residual(integral), grad_f, grad_c, hess_f, hess_c }
    }

    /// A `dim x dim` zero matrix: the spare one ([`Discretised::recycle`]) with its band of
    /// half-bandwidth `hb` zeroed (every entry written is inside the band, so the others are
    /// zero still), else a new one.
    fn zero_hessian(&self, dim: usize, hb: usize) -> DMatrix<f64> {
        let spare = self.kept.1.lock().unwrap_or_else(PoisonError::into_inner).take();
        let Some(mut h) = spare.filter(|h| h.nrows() == dim && h.ncols() == dim) else {
            return DMatrix::zeros(dim, dim);
        };
        let data = h.as_mut_slice();
        for col in 0..dim {
            data[col * dim + col.saturating_sub(hb)..col * dim + (col + hb + 1).min(dim)].fill(0.0);
        }
        h
    }
}

/// [`Discretisation::point`] on a basis of degree `p` (inlined where `p` is a constant).
#[inline(always)]
fn point_of(p: usize, c: &[Vec<f64>], node: &Node, theta: &mut [f64], rate: &mut [f64]) {
    for (j, cj) in c.iter().enumerate() {
        let cj = &cj[node.first..=node.first + p];
        let (mut v, mut r) = (0.0, 0.0);
        for ((value, rate), c) in node.value.iter().zip(&node.rate).zip(cj) {
            v += value * c;
            r += rate * c;
        }
        theta[j] = v;
        rate[j] = r;
    }
}
