//! The minimum-norm solution of the ECSA's end-point equation ([`ChainSolver::MinimumNorm`]):
//! $$\min_c \tfrac12 |c|^2 \quad \text{s.t.} \quad K(c) = q_d,$$
//! the coefficients of least norm (in the metric of the pseudo-inverse `J^T (J J^T)^-1`, whose
//! step is the least-norm solution of the linearised equation) that reach the goal.
//!
//! **Why not the pseudo-inverse iteration from the straight line.** The joint rows of `K` are
//! linear; the harmonics change `phi(T)` mostly through the loops they draw, and a loop's
//! rotation (its area times the connection's curvature, by Stokes' theorem) grows with the
//! *square* of its amplitude. The linearisation at the line sees only the first-order bending
//! of the line, so the least-norm Newton step sized by it overshoots: on the README's 3-link
//! example the pseudo-inverse iteration's residual goes 1.87, 2.23, 1.27, .. rad and ends on
//! harmonics of effort 6369 rad^2/s (the optimal planner's: 2.708), whose open-loop torques
//! fail their certificate; this solver reaches effort 18.37 there, certified at both levels.
//!
//! **Lagrange–Newton with continuation.** With the multipliers `mu` (one per row of `K`) the
//! first-order conditions are `F(c, mu) = (c + J^T mu, K(c) - q_s) = 0`, solved by Newton's method
//! on `F`:
//! $$\begin{pmatrix} I + \mu_0 \nabla^2 \varphi(T) & J^\top \\ J & 0 \end{pmatrix}
//! \begin{pmatrix} \delta c \\ \mu^+ \end{pmatrix} = -\begin{pmatrix} c \\ K(c) - q_s \end{pmatrix},$$
//! the Hessian of the Lagrangian carrying the curvature the plain pseudo-inverse step ignores
//! (the joint rows are linear: only `phi`'s row has a Hessian; it is the forward difference of
//! the exact gradient, [`HESSIAN_STEP`]). The target is continued from where the least-norm
//! straight line ends: `q_s = (phi_line + s delta, theta_d)`, `delta = wrap(phi_d - phi_line)`
//! (literal with `wrap = false`), `s` from 0 to 1. At `s = 0` the line itself solves `F = 0`
//! (with `mu_0 = 0`); each step in `s` starts from the tangent of the solution path
//! (`[H J^T; J 0] (c', mu') = (0, delta e_0)`), its change of `c` capped to `|c|`, and is
//! corrected by Newton with a backtracking line search on `|F|`; a step whose corrector fails
//! within [`CORRECTOR_ITERATIONS`] is halved (down to [`MIN_STEP`]), a successful one doubles
//! the next. At the line the tangent is the overshooting pseudo-inverse step, and where `phi(T)`
//! has (almost) no first-order dependence on the harmonics (a pitchfork: the 7-link test arm)
//! no step from it converges; so the path is also followed from a second start, the first step
//! predicted by the [`LoopModel`] (the least-norm loop of the line's quadratic model), and of
//! the two solutions the one of smaller `|c|` is returned (its own iteration account).
//!
//! The solution is a stationary point of `|c|^2` on the solution set (checked by the tests: `c`
//! in the row space of `J`), not proven the global minimum (the problem is not convex). On the
//! README's 3-link example the tangent start reaches `|c|^2`-effort 18.37 for every schedule
//! tried (first step 1 to 1/32, cap 0.3 to 100 `|c|`), the model's start 42.7; on the 7-link test
//! arm only the model's start converges (effort 3.17, the optimal planner's 2.85).
//! The final corrector at `s = 1` runs to the residual tolerance with `|c + J^T mu| <=`
//! [`STATIONARITY`]` (1 + |c|)`, and the quadrature rule is refined as in the
//! [parent module](super).

use nalgebra::{DMatrix, DVector};

use super::{Basis, ChainEcsaPlanner, ChainEndPoint, MAX_PIECES, Solved};
use crate::error::Error;
use crate::model::wrap_angle;
use crate::numerics::iteration::{IterationStats, Termination};
use crate::numerics::ode::OdeStats;
use crate::planners::chain::ChainProblem;

/// Relative step of the forward difference of `phi(T)`'s exact gradient (the Hessian's error is
/// of that order, which only slows Newton's quadratic convergence to a fast linear one).
pub const HESSIAN_STEP: f64 = 1e-7;
/// Newton iterations allowed per continuation step before the step is halved.
pub const CORRECTOR_ITERATIONS: usize = 8;
/// The smallest continuation step in `s`.
pub const MIN_STEP: f64 = 1.0 / 1024.0;
/// `|F|_inf` at which an intermediate continuation step counts as corrected.
pub const INTERMEDIATE: f64 = 1e-6;
/// Relative stationarity `|c + J^T mu|_inf / (1 + |c|_inf)` of the final solution.
pub const STATIONARITY: f64 = 1e-9;

/// The corrector's iterate: `c`, `mu`, its end point and the parts of `F`.
struct Iterate {
    c: DVector<f64>,
    mu: DVector<f64>,
    k: ChainEndPoint,
    /// `K(c) - q_s`.
    error: DVector<f64>,
    /// `c + J^T mu`.
    gradient: DVector<f64>,
}

impl Iterate {
    fn merit(&self) -> f64 {
        (self.error.norm_squared() + self.gradient.norm_squared()).sqrt()
    }

    fn residual(&self) -> f64 {
        self.error.amax()
    }

    fn stationarity(&self) -> f64 {
        self.gradient.amax() / (1.0 + self.c.amax())
    }
}

/// Why a corrector stopped without converging.
enum Stop {
    /// Too many iterations, or no decrease of `|F|`: halve the continuation step.
    Retry,
    /// A terminal failure of the whole solve.
    Fail(Termination),
}

struct Path<'a> {
    planner: &'a ChainEcsaPlanner,
    basis: &'a Basis,
    start: &'a [f64],
    goal: &'a [f64],
    line: f64,
    delta: f64,
    pieces: usize,
    iterations: usize,
    max_iterations: usize,
    history: Vec<f64>,
}

impl Path<'_> {
    fn iterate(&self, s: f64, c: DVector<f64>, mu: DVector<f64>) -> Iterate {
        let k = self.planner.evaluate(self.basis, self.start, c.as_slice(), self.pieces, true);
        let target = |i: usize| if i == 0 { self.line + s * self.delta } else { self.goal[i] };
        let error = DVector::from_fn(k.q.len(), |i, _| k.q[i] - target(i));
        let gradient = &c + k.jacobian.transpose() * &mu;
        Iterate { c, mu, k, error, gradient }
    }

    /// `c` with the least-squares multipliers `mu = -(J J^T)^-1 J c` (least `|c + J^T mu|`).
    fn with_multipliers(&self, s: f64, c: DVector<f64>) -> Iterate {
        let k = self.planner.evaluate(self.basis, self.start, c.as_slice(), self.pieces, true);
        let j = &k.jacobian;
        let mu = (j * j.transpose()).cholesky().map_or_else(|| DVector::zeros(j.nrows()), |g| -g.solve(&(j * &c)));
        self.iterate(s, c, mu)
    }

    /// The Hessian of `phi(T)` in `c` at `x`: forward differences of the exact gradient row,
    /// symmetrised.
    fn hessian(&self, x: &Iterate) -> DMatrix<f64> {
        let size = x.c.len();
        let h = HESSIAN_STEP * (1.0 + x.c.amax());
        let mut hessian = DMatrix::zeros(size, size);
        for col in 0..size {
            let mut c = x.c.clone();
            c[col] += h;
            let k = self.planner.evaluate(self.basis, self.start, c.as_slice(), self.pieces, true);
            for row in 0..size {
                hessian[(row, col)] = (k.jacobian[(0, row)] - x.k.jacobian[(0, row)]) / h;
            }
        }
        (&hessian + hessian.transpose()) * 0.5
    }

    /// The KKT matrix `[I + mu_0 H_phi, J^T; J 0]` at `x`.
    fn kkt(&self, x: &Iterate) -> DMatrix<f64> {
        let (p, size) = (x.k.jacobian.nrows(), x.c.len());
        let mut a = DMatrix::zeros(size + p, size + p);
        if x.mu[0] != 0.0 {
            a.view_mut((0, 0), (size, size)).copy_from(&(self.hessian(x) * x.mu[0]));
        }
        for i in 0..size {
            a[(i, i)] += 1.0;
            for r in 0..p {
                a[(i, size + r)] = x.k.jacobian[(r, i)];
                a[(size + r, i)] = x.k.jacobian[(r, i)];
            }
        }
        a
    }

    /// Newton on `F = 0` at the parameter `s` from `x` to `|F|_inf <= INTERMEDIATE` (or, when
    /// `last`, to the residual tolerance and [`STATIONARITY`]), with a backtracking line search.
    fn correct(&mut self, s: f64, mut x: Iterate, last: bool, tolerance: f64) -> Result<(Iterate, DMatrix<f64>), Stop> {
        let mut kkt = None;
        for round in 0.. {
            let finite = x.merit().is_finite();
            self.history.push(if finite { x.residual() } else { f64::NAN });
            if !finite {
                return Err(Stop::Fail(Termination::NonFinite));
            }
            let done = if last {
                x.residual() <= tolerance && x.stationarity() <= STATIONARITY
            } else {
                x.residual().max(x.gradient.amax()) <= INTERMEDIATE
            };
            if done {
                let a = kkt.unwrap_or_else(|| self.kkt(&x));
                return Ok((x, a));
            }
            if self.iterations >= self.max_iterations {
                return Err(Stop::Fail(Termination::MaxIterations));
            }
            // Far from the solution after the allowed iterations: a smaller step in `s`. (The
            // final corrector, once near, may take more to reach the tight tolerances.)
            let near = x.merit() <= INTERMEDIATE;
            if round >= CORRECTOR_ITERATIONS && !(last && near && round < 3 * CORRECTOR_ITERATIONS) {
                return Err(Stop::Retry);
            }
            let a = self.kkt(&x);
            let size = x.c.len();
            let rhs = -DVector::from_iterator(size + x.mu.len(), x.c.iter().chain(x.error.iter()).copied());
            let Some(solution) = a.clone().lu().solve(&rhs) else {
                return Err(Stop::Retry);
            };
            let dc = solution.rows(0, size).into_owned();
            let dmu = solution.rows(size, x.mu.len()) - &x.mu;
            self.iterations += 1;
            let merit = x.merit();
            let mut alpha = 1.0;
            x = loop {
                let trial = self.iterate(s, &x.c + &dc * alpha, &x.mu + &dmu * alpha);
                if trial.merit() < (1.0 - 1e-4 * alpha) * merit {
                    break trial;
                }
                alpha *= 0.5;
                if alpha < 1.0 / 64.0 {
                    return Err(Stop::Retry);
                }
            };
            kkt = Some(a);
        }
        unreachable!()
    }
}

/// The loop seed: the quadratic model of `phi(T)` at the straight line on the null space `P` of
/// the joint rows (where `theta(T)` stays put), `phi = phi_line + g.z + z^T Q z / 2`, and its
/// least-norm solution `min |z|^2` s.t. `g.z + z^T Q z / 2 = d`: `z = -nu (I + nu Q)^-1 g` with
/// `nu` between 0 and the pole `-1/lambda` of the largest eigenvalue of `Q` of the sign of `d`,
/// by bisection (the trust-region problem's secular equation); when `g` has (almost) no part
/// along that eigenvector the eigenvector is added, scaled so that `lambda r^2 / 2` makes up
/// the rest: the loop whose area times the curvature is the rotation needed.
struct LoopModel {
    vectors: DMatrix<f64>,
    values: DVector<f64>,
    /// `V^T P g`.
    gradient: DVector<f64>,
}

impl LoopModel {
    /// The model at the line `x` with the Hessian `q` of `phi(T)`.
    fn new(x: &Iterate, q: &DMatrix<f64>) -> Self {
        let j = &x.k.jacobian;
        let size = x.c.len();
        let theta = j.rows(1, j.nrows() - 1);
        // The joint rows are orthogonal (disjoint columns) and of equal norm.
        let norm2 = theta.row(0).norm_squared();
        let p = DMatrix::<f64>::identity(size, size) - theta.transpose() * theta / norm2;
        let eigen = (&p * q * &p).symmetric_eigen();
        let gradient = eigen.eigenvectors.transpose() * (&p * j.row(0).transpose());
        Self { vectors: eigen.eigenvectors, values: eigen.eigenvalues, gradient }
    }

    /// The change of `c` of least norm whose model rotation is `d`.
    fn seed(&self, d: f64) -> DVector<f64> {
        let sign = if d < 0.0 { -1.0 } else { 1.0 };
        let (g, lambda) = (&self.gradient * sign, &self.values * sign);
        let z = |nu: f64| DVector::from_fn(g.len(), |k, _| -nu * g[k] / (1.0 + nu * lambda[k]));
        let model = |z: &DVector<f64>| (0..g.len()).map(|k| g[k] * z[k] + 0.5 * lambda[k] * z[k] * z[k]).sum::<f64>();
        let (top, largest) = lambda.argmax();
        let (mut lo, mut hi) = (if largest > 0.0 { -1.0 / largest } else { -1e12 }, 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if model(&z(mid)) > d.abs() { lo = mid } else { hi = mid }
        }
        let mut seed = z(hi);
        let short = d.abs() - model(&seed);
        if largest > 0.0 && short > 0.0 {
            seed[top] += (2.0 * short / largest).sqrt() * if seed[top] < 0.0 { -1.0 } else { 1.0 };
        }
        &self.vectors * seed
    }
}

impl ChainEcsaPlanner {
    /// [`ChainSolver::MinimumNorm`](super::ChainSolver::MinimumNorm): see the
    /// [module docs](self).
    pub(super) fn minimum_norm(&self, basis: &Basis, problem: &ChainProblem) -> Result<Solved, Error> {
        let norm = |r: &Result<Solved, Error>| r.as_ref().map_or(f64::INFINITY, |s| s.c.norm());
        let (tangent, seeded) = (self.follow(basis, problem, false), self.follow(basis, problem, true));
        if norm(&seeded) < norm(&tangent) { seeded } else { tangent }
    }

    /// The continuation from the line, its first step predicted by the tangent or (`seeded`)
    /// by the [`LoopModel`].
    fn follow(&self, basis: &Basis, problem: &ChainProblem, seeded: bool) -> Result<Solved, Error> {
        let o = &self.options;
        let (n, m) = (self.arm.joints(), basis.terms());
        let (start, goal) = (&problem.start, &problem.goal);
        let ends = basis.integrals();
        let norm2: f64 = ends[..m].iter().map(|e| e * e).sum();
        // The least-norm c of the joint rows, c_i = (theta_id - theta_i0) A(T) / |A(T)|^2, and
        // its multipliers (c + J^T mu = 0 with mu_0 = 0).
        let c = DVector::from_fn(n * m, |k, _| (goal[k / m + 1] - start[k / m + 1]) * ends[k % m] / norm2);
        let mu = DVector::from_fn(n + 1, |i, _| if i == 0 { 0.0 } else { -(goal[i] - start[i]) / norm2 });
        let pieces = (64 * basis.harmonics()).min(MAX_PIECES);
        let line = self.evaluate(basis, start, c.as_slice(), pieces, false).q[0];
        let delta = if problem.wrap { wrap_angle(goal[0] - line) } else { goal[0] - line };
        let mut path = Path {
            planner: self,
            basis,
            start,
            goal,
            line,
            delta,
            pieces,
            iterations: 0,
            max_iterations: o.max_iterations,
            history: Vec::new(),
        };
        let fail = |path: Path, termination| {
            let residual = path.history.last().copied().unwrap_or(f64::NAN);
            Err(Error::EcsaFailed {
                stats: IterationStats {
                    iterations: path.iterations,
                    residual,
                    tolerance: o.residual_tolerance,
                    residual_history: path.history,
                    termination,
                    ode: OdeStats::default(),
                },
            })
        };
        let mut x = path.iterate(0.0, c, mu);
        let model = seeded.then(|| LoopModel::new(&x, &path.hessian(&x)));
        let (mut s, mut ds, mut steps) = (0.0, 1.0_f64, 0);
        let mut kkt: Option<DMatrix<f64>> = None;
        let size = n * m;
        while s < 1.0 {
            let next = (s + ds).min(1.0);
            let last = s + ds >= 1.0;
            // The tangent predictor from the last KKT matrix, its step in `c` capped to
            // `|c|` (at the line the tangent is the pseudo-inverse step that overshoots).
            if let Some(model) = model.as_ref().filter(|_| s == 0.0) {
                let guess = path.with_multipliers(next, &x.c + model.seed(next * delta));
                match path.correct(next, guess, last, o.residual_tolerance) {
                    Ok((y, b)) => {
                        (x, s, steps) = (y, next, steps + 1);
                        kkt = Some(b);
                    }
                    Err(Stop::Fail(termination)) => return fail(path, termination),
                    Err(Stop::Retry) if ds < 2.0 * MIN_STEP => return fail(path, Termination::MaxIterations),
                    Err(Stop::Retry) => ds *= 0.5,
                }
                continue;
            }
            let a = kkt.take().unwrap_or_else(|| path.kkt(&x));
            let mut rhs = DVector::zeros(size + n + 1);
            rhs[size] = delta;
            let (mut c, mut mu) = (x.c.clone(), x.mu.clone());
            if let Some(t) = a.clone().lu().solve(&rhs) {
                let (dc, dmu) = (t.rows(0, size) * (next - s), t.rows(size, n + 1) * (next - s));
                let scale = (x.c.norm() / dc.norm()).min(1.0);
                c += dc * scale;
                mu += dmu * scale;
            }
            kkt = Some(a);
            let guess = path.iterate(next, c, mu);
            let r = path.correct(next, guess, last, o.residual_tolerance);
            match r {
                Ok((y, b)) => {
                    (x, s, steps) = (y, next, steps + 1);
                    kkt = Some(b);
                    ds = (2.0 * ds).min(1.0);
                }
                Err(Stop::Fail(termination)) => return fail(path, termination),
                Err(Stop::Retry) => {
                    ds *= 0.5;
                    if ds < MIN_STEP {
                        return fail(path, Termination::MaxIterations);
                    }
                }
            }
        }
        // The quadrature rule: as the pseudo-inverse iteration's, continuing the corrector.
        let change = loop {
            let fine = self.evaluate(basis, start, x.c.as_slice(), 2 * path.pieces, false);
            let change = (fine.q[0] - x.k.q[0]).abs();
            if change <= 0.01 * o.residual_tolerance || 2 * path.pieces > MAX_PIECES {
                break change;
            }
            path.pieces *= 2;
            path.history.pop();
            let y = path.iterate(1.0, x.c.clone(), x.mu.clone());
            match path.correct(1.0, y, true, o.residual_tolerance) {
                Ok((y, _)) => x = y,
                Err(Stop::Fail(termination)) => return fail(path, termination),
                Err(Stop::Retry) => return fail(path, Termination::MaxIterations),
            }
        };
        let residual = x.residual();
        Ok(Solved {
            c: x.c,
            iteration: IterationStats {
                iterations: path.iterations,
                residual,
                tolerance: o.residual_tolerance,
                residual_history: path.history,
                termination: Termination::Converged,
                ode: OdeStats::default(),
            },
            pieces: path.pieces,
            change,
            continuation_steps: steps,
        })
    }
}
