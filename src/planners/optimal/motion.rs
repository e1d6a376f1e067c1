//! The optimal planner's motion: the joint path is a spline, exact at any time (each knot
//! span's polynomial by Horner's rule on its Taylor coefficients, computed once), and the base
//! angle is its holonomy integral (Eq. 5 with zero momentum), by Gauss–Legendre quadrature on
//! each knot span (and on the partial span up to `t`).

use std::sync::OnceLock;

use serde::Serialize;

use super::holonomy::{holonomy_integrand, holonomy_local};
use super::spline::{MAX_DEGREE, SplineBasis};
use super::sqp::Termination;
use crate::error::Error;
use crate::model::system::shape;
use crate::model::{Configuration, Lumped};
use crate::numerics::ode::OdeError;
use crate::numerics::quadrature::GaussLegendre;
use crate::plan::{Motion, MotionPoint, PlanningProblem, Trajectory};

/// Nodes of the Gauss–Legendre rule of the motion's base angle, per knot span (or part of one).
pub const MOTION_NODES: usize = 24;

/// The `n`-node Gauss–Legendre rule, `n` 8 or [`MOTION_NODES`] (the rules used here), computed
/// once.
fn rule(n: usize) -> &'static GaussLegendre {
    static RULES: [OnceLock<GaussLegendre>; 2] = [OnceLock::new(), OnceLock::new()];
    debug_assert!(matches!(n, 8 | MOTION_NODES), "no cached {n}-node rule");
    let slot = usize::from(n != 8);
    RULES[slot].get_or_init(|| GaussLegendre::new(if slot == 1 { MOTION_NODES } else { 8 }))
}

/// `integral_a^b f` by the 4-node Gauss–Lobatto rule (exact for degree 5) given the end
/// values `fa = f(a)`, `fb = f(b)`: weights `1/6, 5/6, 5/6, 1/6` on nodes `-1, -1/sqrt 5,
/// 1/sqrt 5, 1` of `[-1, 1]` (Abramowitz–Stegun 25.4.32).
fn lobatto4(a: f64, b: f64, fa: f64, fb: f64, f: impl Fn(f64) -> f64) -> f64 {
    let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
    let x = half / 5f64.sqrt();
    half * ((fa + fb) / 6.0 + 5.0 / 6.0 * (f(mid - x) + f(mid + x)))
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
    /// The Taylor coefficients of `theta1` and `theta2` on every breakpoint interval about its
    /// left end ([`SplineBasis::taylor`]; zero above the degree).
    pieces: Vec<[[f64; MAX_DEGREE + 1]; 2]>,
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
        let pieces = (0..basis.breakpoints().len() - 1)
            .map(|s| {
                let span = basis.span_of_interval(s);
                [basis.taylor(span, &coefficients[0]), basis.taylor(span, &coefficients[1])]
            })
            .collect();
        let mut me = Self { k, basis, coefficients, pieces, phi_breaks: vec![phi0], rule, stats };
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
        self.rule.integrate(t0, t1, |t| self.integrand(s, t))
    }

    /// The holonomy integrand `a theta1' + b theta2'` (Eq. 8) at `t` on breakpoint interval `s`.
    fn integrand(&self, s: usize, t: f64) -> f64 {
        let [th, w] = self.joints_in(s, t);
        holonomy_integrand(&self.k, th, w)
    }

    /// The first `K` of `[theta, theta', theta'']` (joints) at `t` on breakpoint interval `s`:
    /// Horner's rule on the interval's Taylor coefficients.
    #[inline]
    fn joints_in<const K: usize>(&self, s: usize, t: f64) -> [[f64; 2]; K] {
        let x = t - self.basis.breakpoints()[s];
        let mut out = [[0.0; 2]; K];
        for (j, c) in self.pieces[s].iter().enumerate() {
            // The value, the first and half the second derivative, highest power first.
            let (mut v, mut d, mut h) = (c[MAX_DEGREE], 0.0, 0.0);
            for &ck in c[..MAX_DEGREE].iter().rev() {
                if K > 2 {
                    h = h * x + d;
                }
                d = d * x + v;
                v = v * x + ck;
            }
            let all = [v, d, 2.0 * h];
            for (o, a) in out.iter_mut().zip(all) {
                o[j] = a;
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
    /// exact; `z` is `None`. `phi` is accumulated from sample to sample, pieces split at the
    /// breakpoints (the integrand is smooth on a knot interval): on a piece at most a 24th of
    /// its knot interval, as with 1001 samples on 32 spans, the 4-node Gauss–Lobatto rule, whose
    /// end nodes are the samples' own `phi'` (two evaluations of the connection a sample instead
    /// of four),
    /// else the 8-node Gauss–Legendre rule (the Lobatto rule's error goes as the piece's 7th
    /// power: on the paper's plans 1e-14 rad at a 24th, 1.6e-12 rad at an eighth of a span;
    /// the test `sampled_trajectory_matches_de_boor_and_the_fine_rule`). `problem` is the
    /// motion's (its robot's constants are the motion's, which give `phi'`).
    pub fn trajectory(&self, problem: &PlanningProblem, samples: usize) -> Result<Trajectory, Error> {
        debug_assert!(problem.robot.lumped() == self.k, "the trajectory of another robot's motion");
        let horizon = self.basis.horizon();
        let n = samples.max(2);
        let dt = horizon / (n - 1) as f64;
        let long = rule(8);
        let b = self.basis.breakpoints();
        let mut tr = Trajectory { ddq: Some(Vec::with_capacity(n)), ..Default::default() };
        // `g_previous`: the integrand at `previous` when that is the last sample.
        let (mut phi, mut previous, mut g_previous) = (self.phi_breaks[0], 0.0, None);
        for i in 0..n {
            let t = if i + 1 == n { horizon } else { i as f64 * dt };
            let s = self.basis.interval(t);
            if b[s] >= previous {
                // A breakpoint lies in (previous, t]: restart from it.
                (phi, previous, g_previous) = (self.phi_breaks[s], b[s], None);
            }
            let [th, u, du] = self.joints_in(s, t);
            // phi' = -g(theta, theta') (Eq. 7) and phi'' = -dg/dt by the chain rule.
            let g = holonomy_local(&self.k, th, u);
            if t > previous {
                phi -= if 24.0 * (t - previous) <= b[s + 1] - b[s] {
                    let g0 = g_previous.unwrap_or_else(|| self.integrand(s, previous));
                    lobatto4(previous, t, g0, g.value, |x| self.integrand(s, x))
                } else {
                    long.integrate(previous, t, |x| self.integrand(s, x))
                };
            }
            (previous, g_previous) = (t, Some(g.value));
            let q = Configuration::new(phi, th[0], th[1]);
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
        let [th, u, du] = self.joints_in(s, t);
        let b0 = self.basis.breakpoints()[s];
        let phi = if t > b0 { self.phi_breaks[s] - self.holonomy(s, b0, t) } else { self.phi_breaks[s] };
        Ok(MotionPoint { q: Configuration::new(phi, th[0], th[1]), u, du })
    }

    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        self.check_time(t)?;
        let [_, u] = self.joints_in(self.basis.interval(t), t);
        Ok(u)
    }

    fn breakpoints(&self) -> Vec<f64> {
        let b = self.basis.breakpoints();
        b[1..b.len() - 1].to_vec()
    }
}
