//! The optimal planner's motion: the joint path is a spline, exact at any time, and the base
//! angle is its holonomy integral (Eq. 5 with zero momentum), by Gauss–Legendre quadrature on
//! each knot span (and on the partial span up to `t`).

use std::sync::OnceLock;

use serde::Serialize;

use super::holonomy::{connection, holonomy_local};
use super::spline::SplineBasis;
use super::sqp::Termination;
use crate::error::Error;
use crate::model::system::shape;
use crate::model::{Configuration, Lumped};
use crate::numerics::ode::OdeError;
use crate::numerics::quadrature::GaussLegendre;
use crate::plan::{Motion, MotionPoint, PlanningProblem, Trajectory};

/// Nodes of the Gauss–Legendre rule of the motion's base angle, per knot span (or part of one).
pub const MOTION_NODES: usize = 24;

/// The `n`-node Gauss–Legendre rule, `n` one of 4, 8 and [`MOTION_NODES`] (the rules used
/// here), computed once.
fn rule(n: usize) -> &'static GaussLegendre {
    static RULES: [OnceLock<GaussLegendre>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    debug_assert!(matches!(n, 4 | 8 | MOTION_NODES), "no cached {n}-node rule");
    let slot = match n {
        4 => 0,
        8 => 1,
        _ => 2,
    };
    RULES[slot].get_or_init(|| GaussLegendre::new(if slot == 2 { MOTION_NODES } else { n }))
}

/// Statistics of an optimal plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OptimalStats {
    /// SQP iterations, summed over every seed and refinement level.
    pub iterations: usize,
    /// SQP iterations of the last solve (finest basis) of the returned plan.
    pub final_iterations: usize,
    /// The minimised cost: the effort \[rad^2/s\] or the kinetic-energy integral \[J s\].
    pub cost: f64,
    /// The effort `integral_0^T |theta'|^2 dt` \[rad^2/s\] of the plan.
    pub effort: f64,
    /// `|phi(T) - phi_target|` of the optimiser's quadrature \[rad\].
    pub constraint_residual: f64,
    /// `|phi(T) - phi_target|` with the motion's finer quadrature ([`MOTION_NODES`] per span)
    /// \[rad\].
    pub holonomy_residual: f64,
    /// Relative KKT residual (see [`super::SqpOptions::kkt_tolerance`]).
    pub kkt_residual: f64,
    /// The Lagrange multiplier of the holonomy constraint.
    pub multiplier: f64,
    /// How the last solve stopped.
    pub termination: Termination,
    /// Uniform knot spans of the final basis (before the end grading).
    pub spans: usize,
    /// Spline degree (3, or 5 with smooth ends).
    pub degree: usize,
    /// Gauss–Legendre nodes per knot span of the optimiser.
    pub quadrature_nodes: usize,
    /// Seeds solved on the coarse basis.
    pub seeds: usize,
    /// The joint goal reached, `theta(T)` \[rad\] (a representative of the goal modulo 2 pi).
    pub theta_end: [f64; 2],
    /// The base angle reached, `phi(T)` \[rad\] (a representative of the goal modulo 2 pi).
    pub phi_end: f64,
}

/// The optimal planner's motion: joint splines and their holonomy.
#[derive(Debug, Clone)]
pub struct OptimalMotion {
    k: Lumped,
    basis: SplineBasis,
    coefficients: [Vec<f64>; 2],
    /// `phi` at every breakpoint.
    phi_breaks: Vec<f64>,
    rule: GaussLegendre,
    /// Statistics of the solve.
    pub stats: OptimalStats,
}

impl OptimalMotion {
    /// The motion of the joint splines with `coefficients` on `basis`, from `phi(0) = phi0`.
    pub(crate) fn new(
        k: Lumped,
        basis: SplineBasis,
        coefficients: [Vec<f64>; 2],
        phi0: f64,
        stats: OptimalStats,
    ) -> Self {
        let rule = rule(MOTION_NODES).clone();
        let mut me = Self { k, basis, coefficients, phi_breaks: vec![phi0], rule, stats };
        let b = me.basis.breakpoints().to_vec();
        let mut phi = phi0;
        for s in 0..b.len() - 1 {
            phi -= me.holonomy(s, b[s], b[s + 1]);
            me.phi_breaks.push(phi);
        }
        me
    }

    /// `integral_{t0}^{t1} (a theta1' + b theta2') dt` on knot interval `s` (Gauss–Legendre).
    fn holonomy(&self, s: usize, t0: f64, t1: f64) -> f64 {
        let span = self.basis.span_of_interval(s);
        self.rule.integrate(t0, t1, |t| {
            let [th, w] = self.joints_in(span, t, 1);
            let (a, b) = connection(&self.k, th[0], th[1]);
            a * w[0] + b * w[1]
        })
    }

    /// `[theta, theta', theta'']` (joints) at `t` in knot span `span`, up to derivative `order`.
    fn joints_in<const K: usize>(&self, span: usize, t: f64, order: usize) -> [[f64; 2]; K] {
        let d = if order <= 1 {
            let [v, r] = self.basis.values_and_rates(span, t);
            [v, r, Default::default()]
        } else {
            self.basis.ders(span, t)
        };
        let p = self.basis.degree();
        let first = span - p;
        let mut out = [[0.0; 2]; K];
        for (k, o) in out.iter_mut().enumerate().take(order.min(2) + 1) {
            for (j, oj) in o.iter_mut().enumerate() {
                *oj = (0..=p).map(|l| d[k][l] * self.coefficients[j][first + l]).sum();
            }
        }
        out
    }

    /// The spline basis.
    pub fn basis(&self) -> &SplineBasis {
        &self.basis
    }

    /// The coefficients of `theta1` and `theta2` \[rad\].
    pub fn coefficients(&self) -> &[Vec<f64>; 2] {
        &self.coefficients
    }

    fn check_time(&self, t: f64) -> Result<(), Error> {
        let horizon = self.basis.horizon();
        if t >= 0.0 && t <= horizon * (1.0 + 1e-14) {
            Ok(())
        } else {
            Err(OdeError { t, reason: "time outside [0, T] of the plan" }.into())
        }
    }

    /// The sampled trajectory at `samples` equally spaced times: `q`, `q' = g(q) u` and `q''`
    /// exact; `z` is `None`. `phi` is accumulated from sample to sample (pieces split at the
    /// breakpoints, a 4-node Gauss–Legendre rule on pieces at most an eighth of their knot
    /// interval, as with 1001 samples, else an 8-node rule: the integrand is smooth on a knot
    /// interval and the pieces are short).
    pub fn trajectory(&self, problem: &PlanningProblem, samples: usize) -> Result<Trajectory, Error> {
        let horizon = self.basis.horizon();
        let n = samples.max(2);
        let dt = horizon / (n - 1) as f64;
        let k = problem.robot.lumped();
        let (short, long) = (rule(4), rule(8));
        let b = self.basis.breakpoints();
        let mut tr = Trajectory { ddq: Some(Vec::with_capacity(n)), ..Default::default() };
        let (mut phi, mut previous) = (self.phi_breaks[0], 0.0);
        for i in 0..n {
            let t = if i + 1 == n { horizon } else { i as f64 * dt };
            let s = self.basis.interval(t);
            let span = self.basis.span_of_interval(s);
            if b[s] >= previous {
                // A breakpoint lies in (previous, t]: restart from it.
                phi = self.phi_breaks[s];
                previous = b[s];
            }
            if t > previous {
                let rule = if 8.0 * (t - previous) <= b[s + 1] - b[s] { short } else { long };
                phi -= rule.integrate(previous, t, |x| {
                    let [th, w] = self.joints_in(span, x, 1);
                    let (a, bb) = connection(&self.k, th[0], th[1]);
                    a * w[0] + bb * w[1]
                });
            }
            previous = t;
            let [th, u, du] = self.joints_in(span, t, 2);
            let q = Configuration::new(phi, th[0], th[1]);
            // phi' = -g(theta, theta') (Eq. 7) and phi'' = -dg/dt by the chain rule.
            let g = holonomy_local(&k, th, u);
            let dg = g.gradient[0] * u[0] + g.gradient[1] * u[1] + g.gradient[2] * du[0] + g.gradient[3] * du[1];
            let (v, a) = ([-g.value, u[0], u[1]], [-dg, du[0], du[1]]);
            tr.t.push(t);
            tr.q.push(q.to_array());
            tr.dq.push(v);
            if let Some(ddq) = tr.ddq.as_mut() {
                ddq.push(a);
            }
        }
        Ok(tr)
    }

    /// `(min |sigma|, min |P|)` over a trajectory's samples (Eqs. 9, 13): how close the path
    /// comes to the NFA's singular curves, which this planner crosses freely.
    pub fn margins(&self, trajectory: &Trajectory) -> (f64, f64) {
        trajectory.q.iter().fold((f64::INFINITY, f64::INFINITY), |(s, p), q| {
            let sh = shape(&self.k, q[1], q[2]);
            (s.min(sh.sigma.abs()), p.min(sh.P.abs()))
        })
    }
}

impl Motion for OptimalMotion {
    fn horizon(&self) -> f64 {
        self.basis.horizon()
    }

    fn at(&self, t: f64) -> Result<MotionPoint, Error> {
        self.check_time(t)?;
        let s = self.basis.interval(t);
        let span = self.basis.span_of_interval(s);
        let [th, u, du] = self.joints_in(span, t, 2);
        let b0 = self.basis.breakpoints()[s];
        let phi = if t > b0 { self.phi_breaks[s] - self.holonomy(s, b0, t) } else { self.phi_breaks[s] };
        Ok(MotionPoint { q: Configuration::new(phi, th[0], th[1]), u, du })
    }

    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        self.check_time(t)?;
        let span = self.basis.span_of_interval(self.basis.interval(t));
        let [_, u] = self.joints_in(span, t, 1);
        Ok(u)
    }

    fn breakpoints(&self) -> Vec<f64> {
        let b = self.basis.breakpoints();
        b[1..b.len() - 1].to_vec()
    }
}
