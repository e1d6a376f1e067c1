//! The discretised optimal-control problem: joint paths as clamped B-splines with their end
//! conditions built in, the cost and the holonomy constraint as Gauss–Legendre sums over the knot
//! spans, with exact gradients and Hessians of those sums.
//!
//! The free variables `x` are the interior coefficients of both joints, interleaved
//! `(theta1_i, theta2_i)` so that every Hessian is banded (half-bandwidth `2 p + 1`); the
//! first and last `r` coefficients of each joint (`r = 2`, or 3 with smooth ends) are fixed by
//! `theta(0), theta'(0), [theta''(0)]` and `theta(T), theta'(T) = 0, [theta''(T) = 0]`.

use nalgebra::{DMatrix, DVector};

use super::Cost;
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
    /// `d^2 f/dx^2` (empty below order 2).
    pub hess_f: DMatrix<f64>,
    /// `d^2 c/dx^2` (empty below order 2).
    pub hess_c: DMatrix<f64>,
}

/// The discretised problem on one basis.
#[derive(Debug, Clone)]
pub struct Discretisation {
    k: Lumped,
    cost: Cost,
    basis: SplineBasis,
    targets: Targets,
    /// Fixed leading and trailing coefficients per joint.
    head: [Vec<f64>; 2],
    tail: [Vec<f64>; 2],
    nodes: Vec<Node>,
    /// Full index `j n + i` -> free index.
    free_index: Vec<Option<usize>>,
    /// `d^2 (effort) / dx^2`, constant: the metric of the trust region.
    effort_hessian: DMatrix<f64>,
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
        let mut head = [Vec::new(), Vec::new()];
        let mut tail = [Vec::new(), Vec::new()];
        for j in 0..2 {
            let start = [targets.start[j], targets.initial_velocity[j], 0.0];
            let end = [targets.end[j], 0.0, 0.0];
            let (h, t) = basis.end_coefficients(&start[..r], &end[..r]);
            head[j] = h;
            tail[j] = t;
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
                let d = basis.ders(span, t);
                nodes.push(Node { first: span - p, t, weight: half * wi, value: d[0], rate: d[1] });
            }
        }
        let mut me = Self {
            k,
            cost,
            basis,
            targets,
            head,
            tail,
            nodes,
            free_index,
            effort_hessian: DMatrix::zeros(2 * nf, 2 * nf),
        };
        let mut h = DMatrix::zeros(2 * nf, 2 * nf);
        let mut g = DVector::zeros(2 * nf);
        let x0 = DVector::zeros(2 * nf);
        let coefficients = me.coefficients(&x0);
        for node in &me.nodes {
            let (_, rate) = me.point(&coefficients, node);
            me.accumulate(node, &effort_local(rate), 1.0, &mut g, Some(&mut h));
        }
        me.effort_hessian = h;
        Ok(me)
    }

    /// Half-bandwidth of every Hessian in the free variables: `2 p + 1`.
    pub fn half_bandwidth(&self) -> usize {
        2 * self.basis.degree() + 1
    }

    /// Number of free variables.
    pub fn dim(&self) -> usize {
        self.effort_hessian.nrows()
    }

    /// The basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.basis
    }

    /// The ends and the holonomy target.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The Hessian of the effort `integral |theta'|^2 dt` in `x` (constant, positive definite):
    /// the trust-region metric.
    pub fn effort_hessian(&self) -> &DMatrix<f64> {
        &self.effort_hessian
    }

    /// All coefficients of both joints, `[theta1 (n) | theta2 (n)]`, from the free ones.
    pub fn coefficients(&self, x: &DVector<f64>) -> [Vec<f64>; 2] {
        let n = self.basis.len();
        let r = self.head[0].len();
        let nf = n - 2 * r;
        std::array::from_fn(|j| {
            let mut c = self.head[j].clone();
            c.extend((0..nf).map(|m| x[2 * m + j]));
            c.extend_from_slice(&self.tail[j]);
            c
        })
    }

    /// `(theta, theta')` at a node.
    fn point(&self, c: &[Vec<f64>; 2], node: &Node) -> ([f64; 2], [f64; 2]) {
        let p = self.basis.degree();
        let mut theta = [0.0; 2];
        let mut rate = [0.0; 2];
        for j in 0..2 {
            for l in 0..=p {
                let cj = c[j][node.first + l];
                theta[j] += node.value[l] * cj;
                rate[j] += node.rate[l] * cj;
            }
        }
        (theta, rate)
    }

    /// Adds `scale * weight *` (gradient, Hessian) of a local function at `node` to the sums in
    /// the free variables (chain rule through the linear map coefficients -> `(theta, theta')`).
    fn accumulate(&self, node: &Node, local: &Local, scale: f64, g: &mut DVector<f64>, h: Option<&mut DMatrix<f64>>) {
        let p = self.basis.degree();
        let n = self.basis.len();
        let w = scale * node.weight;
        // The 2 (p + 1) local coefficients: free index, joint, (value, rate) factors.
        let count = 2 * (p + 1);
        let mut idx = [usize::MAX; 12];
        let mut joint = [0usize; 12];
        let mut fac = [[0.0; 2]; 12];
        let mut raw = [[0.0; 2]; 12];
        for l in 0..=p {
            for j in 0..2 {
                let m = 2 * l + j;
                idx[m] = self.free_index[j * n + node.first + l].unwrap_or(usize::MAX);
                joint[m] = j;
                raw[m] = [node.value[l], node.rate[l]];
                fac[m] = [node.value[l] * w, node.rate[l] * w];
            }
        }
        let lg = &local.gradient;
        for m in 0..count {
            if idx[m] != usize::MAX {
                let j = joint[m];
                g[idx[m]] += lg[j] * fac[m][0] + lg[2 + j] * fac[m][1];
            }
        }
        let Some(h) = h else { return };
        let lh = &local.hessian;
        let dim = h.nrows();
        let data = h.as_mut_slice();
        for m in 0..count {
            if idx[m] == usize::MAX {
                continue;
            }
            let j = joint[m];
            // The local Hessian's row pair of this coefficient, contracted with its factors.
            let [v, r] = raw[m];
            let row: [f64; 4] = std::array::from_fn(|a| lh[j][a] * v + lh[2 + j][a] * r);
            let col = idx[m] * dim;
            for mm in 0..count {
                if idx[mm] == usize::MAX {
                    continue;
                }
                let jj = joint[mm];
                data[col + idx[mm]] += row[jj] * fac[mm][0] + row[2 + jj] * fac[mm][1];
            }
        }
    }

    /// Cost and constraint at `x`, with first derivatives for `order >= 1` and second
    /// derivatives for `order >= 2`.
    pub fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        let dim = self.dim();
        let c = self.coefficients(x);
        let mut f = 0.0;
        let mut integral = 0.0;
        let (mut grad_f, mut grad_c) = if order >= 1 {
            (DVector::zeros(dim), DVector::zeros(dim))
        } else {
            (DVector::zeros(0), DVector::zeros(0))
        };
        let mut hess_c = if order >= 2 { DMatrix::zeros(dim, dim) } else { DMatrix::zeros(0, 0) };
        let mut hess_f = match (order >= 2, self.cost) {
            (true, Cost::Effort) => self.effort_hessian.clone(),
            (true, Cost::Energy) => DMatrix::zeros(dim, dim),
            (false, _) => DMatrix::zeros(0, 0),
        };
        for node in &self.nodes {
            let (theta, rate) = self.point(&c, node);
            if order == 0 {
                integral += node.weight * holonomy_value(&self.k, theta, rate);
                f += node.weight * self.cost_value(theta, rate);
                continue;
            }
            let hol = holonomy_local(&self.k, theta, rate);
            integral += node.weight * hol.value;
            // c = phi0 - integral - phi_end: derivatives with the sign -1.
            let hc = (order >= 2).then_some(&mut hess_c);
            self.accumulate(node, &hol, -1.0, &mut grad_c, hc);
            let local = match self.cost {
                Cost::Effort => effort_local(rate),
                Cost::Energy => energy_local(&self.k, theta, rate),
            };
            f += node.weight * local.value;
            let hf = (order >= 2 && self.cost == Cost::Energy).then_some(&mut hess_f);
            self.accumulate(node, &local, 1.0, &mut grad_f, hf);
        }
        let residual = self.targets.phi_start - integral - self.targets.phi_end;
        Evaluation { f, c: residual, grad_f, grad_c, hess_f, hess_c }
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
        self.nodes.iter().map(|node| node.weight * self.point(&c, node).1.iter().map(|w| w * w).sum::<f64>()).sum()
    }

    /// The free coefficients of the L2 projection (same nodes and weights) of the joint path
    /// `path(t) = [theta1, theta2]` onto the basis, with the end conditions kept exact.
    pub fn project(&self, path: impl Fn(f64) -> [f64; 2]) -> Result<DVector<f64>, Error> {
        let dim = self.dim();
        let nf = dim / 2;
        let p = self.basis.degree();
        let zero = DVector::zeros(dim);
        let fixed = self.coefficients(&zero);
        let mut mass = DMatrix::<f64>::zeros(nf, nf);
        let mut rhs = [DVector::<f64>::zeros(nf), DVector::<f64>::zeros(nf)];
        for node in &self.nodes {
            let target = path(node.t);
            let (theta_fixed, _) = self.point(&fixed, node);
            for l in 0..=p {
                let Some(i) = self.free_index[node.first + l].map(|f| f / 2) else { continue };
                for j in 0..2 {
                    rhs[j][i] += node.weight * node.value[l] * (target[j] - theta_fixed[j]);
                }
                for ll in 0..=p {
                    if let Some(ii) = self.free_index[node.first + ll].map(|f| f / 2) {
                        mass[(i, ii)] += node.weight * node.value[l] * node.value[ll];
                    }
                }
            }
        }
        let chol = mass.cholesky().ok_or(Error::from(InputError::InvalidParameter {
            name: "spans".into(),
            value: nf as f64,
            expected: "a basis whose mass matrix is positive definite",
        }))?;
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
