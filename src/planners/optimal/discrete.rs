//! The discretised optimal-control problem: joint paths as clamped B-splines with their end
//! conditions built in, the cost and the holonomy constraint as Gauss–Legendre sums over the knot
//! spans, with exact gradients and Hessians of those sums.
//!
//! The free variables `x` are the interior coefficients of both joints, interleaved
//! `(theta1_i, theta2_i)` so that every Hessian is banded (half-bandwidth `2 p + 1`); the
//! first and last `r` coefficients of each joint (`r = 2`, or 3 with smooth ends) are fixed by
//! `theta(0), theta'(0), [theta''(0)]` and `theta(T), theta'(T) = 0, [theta''(T) = 0]`.

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};

use super::Cost;
use super::band::BandCholesky;
use super::holonomy::{Local, effort_local, energy_local, holonomy_local};
use super::spline::SplineBasis;
use crate::error::Error;
use crate::model::InputError;
use crate::model::Lumped;
use crate::numerics::quadrature::GaussLegendre;

/// Ends of the joint path and the holonomy target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Targets {
    /// `theta(0)` \[rad\].
    pub start: [f64; 2],
    /// `theta'(0)` \[rad/s\].
    pub initial_velocity: [f64; 2],
    /// `theta(T)` \[rad\] (a representative of the goal).
    pub end: [f64; 2],
    /// `phi(0)` \[rad\].
    pub phi_start: f64,
    /// The `phi(T)` to reach \[rad\] (a representative of the goal's `phi`).
    pub phi_end: f64,
}

/// One quadrature node with the non-vanishing basis functions there.
#[derive(Debug, Clone, Copy)]
struct Node {
    /// Index of the first non-vanishing basis function.
    first: usize,
    /// Time \[s\].
    t: f64,
    /// Weight (including the span's half-width).
    weight: f64,
    /// Values of the `p + 1` basis functions.
    value: [f64; 6],
    /// Their first derivatives.
    rate: [f64; 6],
}

/// Largest number `2 (p + 1)` of free variables that one knot span touches.
const LOCAL: usize = 12;

/// Gradient and Hessian of a sum of local terms in the `2 (p + 1)` coefficients of one knot span,
/// interleaved `(theta1_l, theta2_l)`.
struct Block {
    gradient: [f64; LOCAL],
    hessian: [[f64; LOCAL]; LOCAL],
}

impl Block {
    fn new() -> Self {
        Self { gradient: [0.0; LOCAL], hessian: [[0.0; LOCAL]; LOCAL] }
    }

    /// Adds `scale * weight *` (gradient, and Hessian when `hessian`) of a local function at
    /// `node` (chain rule through the linear map coefficients -> `(theta, theta')`). Only the
    /// Hessian's blocks `(l, ll)` with `ll >= l` are summed (see [`Block::symmetrise`]).
    fn add(&mut self, p: usize, node: &Node, local: &Local, scale: f64, hessian: bool) {
        let w = scale * node.weight;
        let lg = &local.gradient;
        for l in 0..=p {
            let (v, r) = (node.value[l] * w, node.rate[l] * w);
            for j in 0..2 {
                self.gradient[2 * l + j] += lg[j] * v + lg[2 + j] * r;
            }
        }
        if !hessian {
            return;
        }
        let lh = &local.hessian;
        for l in 0..=p {
            let (v, r) = (node.value[l], node.rate[l]);
            for j in 0..2 {
                // The local Hessian's row pair of this coefficient, contracted with its factors.
                let row: [f64; 4] = std::array::from_fn(|a| lh[j][a] * v + lh[2 + j][a] * r);
                let out = &mut self.hessian[2 * l + j];
                for ll in l..=p {
                    let (vv, rr) = (node.value[ll] * w, node.rate[ll] * w);
                    out[2 * ll] += row[0] * vv + row[2] * rr;
                    out[2 * ll + 1] += row[1] * vv + row[3] * rr;
                }
            }
        }
    }

    /// Fills the Hessian's blocks `(l, ll)`, `ll < l`, from their transposes.
    fn symmetrise(&mut self, p: usize) {
        for m in 2..2 * (p + 1) {
            for mm in 0..2 * (m / 2) {
                self.hessian[m][mm] = self.hessian[mm][m];
            }
        }
    }
}

/// The tables of one basis and quadrature, shared by every target solved on them: the nodes
/// with their basis values, the free indices, the effort Hessian and the factors of the metric
/// and of the projection's mass matrix.
#[derive(Debug)]
pub struct Table {
    basis: SplineBasis,
    /// Fixed coefficients per joint at each end.
    fixed: usize,
    nodes: Vec<Node>,
    /// Nodes per breakpoint interval (consecutive in `nodes`).
    per_span: usize,
    /// Full index `j n + i` -> free index.
    free_index: Vec<Option<usize>>,
    /// `d^2 (effort) / dx^2`, constant: the metric of the trust region.
    effort_hessian: DMatrix<f64>,
    /// Its band Cholesky factor (`None` when not positive definite).
    metric: Option<BandCholesky>,
    /// The band Cholesky factor of the mass matrix of one joint's free coefficients (`None` when
    /// not positive definite).
    mass: Option<BandCholesky>,
}

impl Table {
    /// The tables of `basis` with `nodes_per_span` Gauss–Legendre nodes on every knot span.
    pub fn new(basis: SplineBasis, smooth_ends: bool, nodes_per_span: usize) -> Result<Self, Error> {
        let p = basis.degree();
        if nodes_per_span < p {
            return Err(Error::from(InputError::InvalidParameter {
                name: "quadrature_nodes".into(),
                value: nodes_per_span as f64,
                expected: "at least the spline degree (exact effort)",
            }));
        }
        let n = basis.len();
        let r = if smooth_ends { 3 } else { 2 };
        if n < 2 * r + 1 {
            return Err(Error::from(InputError::InvalidParameter {
                name: "spans".into(),
                value: n as f64,
                expected: "a basis with a free coefficient",
            }));
        }
        let nf = n - 2 * r;
        let mut free_index = vec![None; 2 * n];
        for j in 0..2 {
            for i in r..n - r {
                free_index[j * n + i] = Some(2 * (i - r) + j);
            }
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
        let mut me = Self {
            basis,
            fixed: r,
            nodes,
            per_span: nodes_per_span,
            free_index,
            effort_hessian: DMatrix::zeros(2 * nf, 2 * nf),
            metric: None,
            mass: None,
        };
        let mut h = DMatrix::zeros(2 * nf, 2 * nf);
        let mut g = DVector::zeros(2 * nf);
        let effort = effort_local([0.0; 2]);
        for chunk in me.nodes.chunks(me.per_span) {
            let mut block = Block::new();
            for node in chunk {
                block.add(p, node, &effort, 1.0, true);
            }
            block.symmetrise(p);
            me.scatter(chunk[0].first, &block, &mut g, Some(&mut h));
        }
        me.metric = BandCholesky::new(&h, me.half_bandwidth());
        me.effort_hessian = h;
        let mut mass = DMatrix::<f64>::zeros(nf, nf);
        for node in &me.nodes {
            for l in 0..=p {
                let Some(i) = me.free_index[node.first + l].map(|f| f / 2) else { continue };
                for ll in 0..=p {
                    if let Some(ii) = me.free_index[node.first + ll].map(|f| f / 2) {
                        mass[(i, ii)] += node.weight * node.value[l] * node.value[ll];
                    }
                }
            }
        }
        me.mass = BandCholesky::new(&mass, p);
        Ok(me)
    }

    /// Half-bandwidth of every Hessian in the free variables: `2 p + 1`.
    pub fn half_bandwidth(&self) -> usize {
        2 * self.basis.degree() + 1
    }

    /// The basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.basis
    }

    /// Adds a span's block (its first basis function `first`) to the sums in the free variables.
    fn scatter(&self, first: usize, block: &Block, g: &mut DVector<f64>, h: Option<&mut DMatrix<f64>>) {
        let p = self.basis.degree();
        let n = self.basis.len();
        let count = 2 * (p + 1);
        let idx: [usize; LOCAL] = std::array::from_fn(|m| {
            if m < count { self.free_index[(m % 2) * n + first + m / 2].unwrap_or(usize::MAX) } else { usize::MAX }
        });
        for m in 0..count {
            if idx[m] != usize::MAX {
                g[idx[m]] += block.gradient[m];
            }
        }
        let Some(h) = h else { return };
        let dim = h.nrows();
        let data = h.as_mut_slice();
        for m in 0..count {
            if idx[m] == usize::MAX {
                continue;
            }
            let col = idx[m] * dim;
            for mm in 0..count {
                if idx[mm] != usize::MAX {
                    data[col + idx[mm]] += block.hessian[m][mm];
                }
            }
        }
    }
}

/// Values (and, by `order`, first and second derivatives) of the cost `f` and the constraint
/// `c = phi(0) - integral g dt - phi_end` at one point `x`.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Cost.
    pub f: f64,
    /// Constraint residual \[rad\].
    pub c: f64,
    /// `df/dx` (empty for order 0).
    pub grad_f: DVector<f64>,
    /// `dc/dx` (empty for order 0).
    pub grad_c: DVector<f64>,
    /// `d^2 f/dx^2` (empty below order 2); `None` where it is the discretisation's effort Hessian
    /// `S` ([`crate::planners::optimal::sqp::Discretised::effort_hessian`], the effort cost's own,
    /// a constant), so that it is not copied at every evaluation: [`Evaluation::hess_f_or`].
    pub hess_f: Option<DMatrix<f64>>,
    /// `d^2 c/dx^2` (empty below order 2).
    pub hess_c: DMatrix<f64>,
}

impl Evaluation {
    /// `d^2 f/dx^2` at order 2: [`Evaluation::hess_f`], or `s`, the effort Hessian, where it is
    /// `None`.
    pub fn hess_f_or<'a>(&'a self, s: &'a DMatrix<f64>) -> &'a DMatrix<f64> {
        self.hess_f.as_ref().unwrap_or(s)
    }

    /// The Lagrangian's Hessian `d^2 f/dx^2 + lambda d^2 c/dx^2` at order 2 (`s`: the effort
    /// Hessian, for a `None` [`Evaluation::hess_f`]).
    pub fn lagrangian_hessian(&self, s: &DMatrix<f64>, lambda: f64) -> DMatrix<f64> {
        let mut w = &self.hess_c * lambda;
        w += self.hess_f_or(s);
        w
    }
}

/// The discretised problem on one basis.
#[derive(Debug, Clone)]
pub struct Discretisation {
    k: Lumped,
    cost: Cost,
    table: Arc<Table>,
    targets: Targets,
    /// Fixed leading and trailing coefficients per joint.
    head: [Vec<f64>; 2],
    tail: [Vec<f64>; 2],
}

impl Discretisation {
    /// The problem on `basis` with `nodes_per_span` Gauss–Legendre nodes on every knot span.
    pub fn new(
        k: Lumped,
        cost: Cost,
        basis: SplineBasis,
        targets: Targets,
        smooth_ends: bool,
        nodes_per_span: usize,
    ) -> Result<Self, Error> {
        let table = Table::new(basis, smooth_ends, nodes_per_span)?;
        Ok(Self::on(k, cost, Arc::new(table), targets))
    }

    /// The problem on shared tables.
    pub fn on(k: Lumped, cost: Cost, table: Arc<Table>, targets: Targets) -> Self {
        let r = table.fixed;
        let mut head = [Vec::new(), Vec::new()];
        let mut tail = [Vec::new(), Vec::new()];
        for j in 0..2 {
            let start = [targets.start[j], targets.initial_velocity[j], 0.0];
            let end = [targets.end[j], 0.0, 0.0];
            let (h, t) = table.basis.end_coefficients(&start[..r], &end[..r]);
            head[j] = h;
            tail[j] = t;
        }
        Self { k, cost, table, targets, head, tail }
    }

    /// Half-bandwidth of every Hessian in the free variables: `2 p + 1`.
    pub fn half_bandwidth(&self) -> usize {
        self.table.half_bandwidth()
    }

    /// Number of free variables.
    pub fn dim(&self) -> usize {
        self.table.effort_hessian.nrows()
    }

    /// The basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.table.basis
    }

    /// The ends and the holonomy target.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The Hessian of the effort `integral |theta'|^2 dt` in `x` (constant, positive definite):
    /// the trust-region metric.
    pub fn effort_hessian(&self) -> &DMatrix<f64> {
        &self.table.effort_hessian
    }

    /// The band Cholesky factor of [`Self::effort_hessian`] (`None` when it is not positive
    /// definite).
    pub fn effort_cholesky(&self) -> Option<&BandCholesky> {
        self.table.metric.as_ref()
    }

    /// All coefficients of both joints, `[theta1 (n) | theta2 (n)]`, from the free ones.
    pub fn coefficients(&self, x: &DVector<f64>) -> [Vec<f64>; 2] {
        let n = self.table.basis.len();
        let r = self.head[0].len();
        let nf = n - 2 * r;
        std::array::from_fn(|j| {
            let mut c = Vec::with_capacity(n);
            c.extend_from_slice(&self.head[j]);
            c.extend((0..nf).map(|m| x[2 * m + j]));
            c.extend_from_slice(&self.tail[j]);
            c
        })
    }

    /// `(theta, theta')` at a node.
    fn point(&self, c: &[Vec<f64>; 2], node: &Node) -> ([f64; 2], [f64; 2]) {
        let p = self.table.basis.degree();
        let mut theta = [0.0; 2];
        let mut rate = [0.0; 2];
        for j in 0..2 {
            let cj = &c[j][node.first..=node.first + p];
            for ((v, r), cl) in node.value.iter().zip(&node.rate).zip(cj) {
                theta[j] += v * cl;
                rate[j] += r * cl;
            }
        }
        (theta, rate)
    }

    /// Cost and constraint at `x`, with first derivatives for `order >= 1` and second
    /// derivatives for `order >= 2`.
    pub fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        let dim = self.dim();
        let table = &*self.table;
        let p = table.basis.degree();
        let c = self.coefficients(x);
        let mut f = 0.0;
        let mut integral = 0.0;
        if order == 0 {
            for node in &table.nodes {
                let (theta, rate) = self.point(&c, node);
                integral += node.weight * holonomy_value(&self.k, theta, rate);
                f += node.weight * self.cost_value(theta, rate);
            }
            let residual = self.targets.phi_start - integral - self.targets.phi_end;
            let empty = || DVector::zeros(0);
            let none = || DMatrix::zeros(0, 0);
            return Evaluation {
                f,
                c: residual,
                grad_f: empty(),
                grad_c: empty(),
                hess_f: Some(none()),
                hess_c: none(),
            };
        }
        let second = order >= 2;
        let (mut grad_f, mut grad_c) = (DVector::zeros(dim), DVector::zeros(dim));
        let mut hess_c = if second { DMatrix::zeros(dim, dim) } else { DMatrix::zeros(0, 0) };
        let mut hess_f = match (second, self.cost) {
            (true, Cost::Effort) => None,
            (true, Cost::Energy) => Some(DMatrix::zeros(dim, dim)),
            (false, _) => Some(DMatrix::zeros(0, 0)),
        };
        let energy = self.cost == Cost::Energy;
        for chunk in table.nodes.chunks(table.per_span) {
            let (mut bc, mut bf) = (Block::new(), Block::new());
            for node in chunk {
                let (theta, rate) = self.point(&c, node);
                let hol = holonomy_local(&self.k, theta, rate);
                integral += node.weight * hol.value;
                // c = phi0 - integral - phi_end: derivatives with the sign -1.
                bc.add(p, node, &hol, -1.0, second);
                let local = match self.cost {
                    Cost::Effort => effort_local(rate),
                    Cost::Energy => energy_local(&self.k, theta, rate),
                };
                f += node.weight * local.value;
                bf.add(p, node, &local, 1.0, second && energy);
            }
            if second {
                bc.symmetrise(p);
                if energy {
                    bf.symmetrise(p);
                }
            }
            let first = chunk[0].first;
            table.scatter(first, &bc, &mut grad_c, second.then_some(&mut hess_c));
            table.scatter(first, &bf, &mut grad_f, if second && energy { hess_f.as_mut() } else { None });
        }
        let residual = self.targets.phi_start - integral - self.targets.phi_end;
        Evaluation { f, c: residual, grad_f, grad_c, hess_f, hess_c }
    }

    /// The quadrature of the holonomy integral `integral_0^T g dt` \[rad\] at `x`, summed as in
    /// [`Self::evaluate`] (so `c = phi(0) - integral - phi_end` to the last bit).
    pub fn holonomy_integral(&self, x: &DVector<f64>) -> f64 {
        let c = self.coefficients(x);
        let mut integral = 0.0;
        for node in &self.table.nodes {
            let (theta, rate) = self.point(&c, node);
            integral += node.weight * holonomy_value(&self.k, theta, rate);
        }
        integral
    }

    fn cost_value(&self, theta: [f64; 2], rate: [f64; 2]) -> f64 {
        match self.cost {
            Cost::Effort => rate[0] * rate[0] + rate[1] * rate[1],
            Cost::Energy => super::holonomy::kinetic_energy(&self.k, theta, rate),
        }
    }

    /// The effort `integral |theta'|^2 dt` \[rad^2/s\] at `x` (exact: polynomial integrand).
    pub fn effort(&self, x: &DVector<f64>) -> f64 {
        let c = self.coefficients(x);
        self.table
            .nodes
            .iter()
            .map(|node| node.weight * self.point(&c, node).1.iter().map(|w| w * w).sum::<f64>())
            .sum()
    }

    /// The free coefficients of the L2 projection (same nodes and weights) of the joint path
    /// `path(t) = [theta1, theta2]` onto the basis, with the end conditions kept exact.
    pub fn project(&self, path: impl Fn(f64) -> [f64; 2]) -> Result<DVector<f64>, Error> {
        let dim = self.dim();
        let nf = dim / 2;
        let table = &*self.table;
        let p = table.basis.degree();
        let zero = DVector::zeros(dim);
        let fixed = self.coefficients(&zero);
        let chol = table.mass.as_ref().ok_or(Error::from(InputError::InvalidParameter {
            name: "spans".into(),
            value: nf as f64,
            expected: "a basis whose mass matrix is positive definite",
        }))?;
        let mut rhs = [DVector::<f64>::zeros(nf), DVector::<f64>::zeros(nf)];
        for node in &table.nodes {
            let target = path(node.t);
            let (theta_fixed, _) = self.point(&fixed, node);
            for l in 0..=p {
                let Some(i) = table.free_index[node.first + l].map(|f| f / 2) else { continue };
                for j in 0..2 {
                    rhs[j][i] += node.weight * node.value[l] * (target[j] - theta_fixed[j]);
                }
            }
        }
        let mut x = DVector::zeros(dim);
        for (j, r) in rhs.iter().enumerate() {
            for (m, v) in chol.solve(r).iter().enumerate() {
                x[2 * m + j] = *v;
            }
        }
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(Error::from(InputError::InvalidParameter {
                name: "seed".into(),
                value: f64::NAN,
                expected: "a finite joint path",
            }))
        }
    }
}

/// `g = a theta1' + b theta2'` alone (values only).
fn holonomy_value(k: &Lumped, theta: [f64; 2], rate: [f64; 2]) -> f64 {
    let (a, b) = super::holonomy::connection(k, theta[0], theta[1]);
    a * rate[0] + b * rate[1]
}
