//! The chain planner's motion: the joint paths are splines on one basis, exact at any time, and
//! the base angle is their holonomy integral (Eq. 7 with zero momentum), by Gauss–Legendre
//! quadrature on each knot span (and on the partial span up to `t`).

use std::sync::Arc;

use serde::Serialize;

use super::connection::Connection;
use crate::numerics::quadrature::GaussLegendre;
use crate::plan::certificate::{ChainVerification, JointMotion};
use crate::planners::optimal::spline::SplineBasis;
use crate::planners::optimal::sqp::Termination;

/// The 4-node Gauss–Legendre rule of [`ChainPlan::sample`]'s short pieces, computed once.
fn short_rule() -> &'static GaussLegendre {
    static RULE: std::sync::OnceLock<GaussLegendre> = std::sync::OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(4))
}

/// Nodes of the Gauss–Legendre rule of the base angle, per knot span (or part of one).
pub const PHI_NODES: usize = 24;

/// The [`PHI_NODES`]-node Gauss–Legendre rule, computed once.
fn phi_rule() -> &'static GaussLegendre {
    static RULE: std::sync::OnceLock<GaussLegendre> = std::sync::OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(PHI_NODES))
}

/// Statistics of a chain plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ChainStats {
    /// SQP iterations, summed over every seed and refinement level.
    pub iterations: usize,
    /// SQP iterations of the last solve (finest basis) of the plan.
    pub final_iterations: usize,
    /// Seeds solved.
    pub seeds: usize,
    /// The effort `integral_0^T |theta'|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// The cost minimised: the effort \[rad^2/s\], or with [`Cost::Energy`](crate::planners::optimal::Cost)
    /// the kinetic energy's integral \[J s\] (quadrature of the final solve).
    pub cost: f64,
    /// Largest `|theta_j'(t)|` over joints and time (sampled finely) \[rad/s\].
    pub peak_velocity: f64,
    /// `|phi(T) - phi_target|` of the last solve's quadrature \[rad\].
    pub constraint_residual: f64,
    /// `|phi(T) - phi_target|` with [`PHI_NODES`] nodes per span \[rad\].
    pub holonomy_residual: f64,
    /// Relative KKT residual of the last solve.
    pub kkt_residual: f64,
    /// Lagrange multiplier of the holonomy constraint.
    pub multiplier: f64,
    /// How the last solve stopped.
    pub termination: Termination,
    /// The last solve converged (or stalled within 100 times its KKT tolerance, its rounding
    /// floor). False for a plan the SQP did not bring to a stationary point: returned only when
    /// no solve converged and this one is certified inside every limit and clearance, so a
    /// feasible motion but not proven the least cost.
    pub converged: bool,
    /// Uniform knot spans of the final basis (before the end grading).
    pub spans: usize,
    /// Graded knots per end of the final basis ([`super::ChainOptions::grading`], or more where a
    /// velocity limit binds where the path leaves or reaches rest).
    #[serde(skip)]
    pub grading: usize,
    /// Gauss–Legendre nodes per span of the final solve.
    pub quadrature_nodes: usize,
    /// Wall time of the planning (without the certificate) \[s\].
    pub plan_seconds: f64,
    /// Clearance the clearance rows kept beyond the clearance asked for and their own margin
    /// \[m\]: [`super::ChainOptions::clearance_reserve`] and what the certificate's retries
    /// added (the distance dips between the rows' points); 0 without shapes.
    #[serde(skip)]
    pub clearance_reserve: f64,
}

/// One point of a chain motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainPoint {
    /// Time \[s\].
    pub t: f64,
    /// Base angle \[rad\].
    pub phi: f64,
    /// Joint angles \[rad\].
    pub theta: Vec<f64>,
    /// Joint velocities (the controls `u`) \[rad/s\].
    pub rate: Vec<f64>,
    /// Joint accelerations \[rad/s^2\].
    pub acceleration: Vec<f64>,
}

/// A certified minimum-effort plan of an `n`-joint arm.
#[derive(Debug, Clone)]
pub struct ChainPlan {
    pub(super) connection: Arc<Connection>,
    pub(super) basis: SplineBasis,
    /// Spline coefficients per joint.
    pub(super) coefficients: Vec<Vec<f64>>,
    /// `phi` at each breakpoint \[rad\].
    pub(super) phi_at_breakpoints: Vec<f64>,
    /// Statistics.
    pub stats: ChainStats,
    /// The velocity-level certificate.
    pub verification: ChainVerification,
}

impl ChainPlan {
    /// Largest `|theta_j'|` over joints at 16 points per knot span \[rad/s\].
    pub(super) fn peak_velocity(&self) -> f64 {
        let b = self.basis().breakpoints();
        let mut peak: f64 = 0.0;
        for w in b.windows(2) {
            for k in 0..=16 {
                let t = w[0] + (w[1] - w[0]) * k as f64 / 16.0;
                self.basis().rates_each(self.coefficients(), t, |_, rate| peak = peak.max(rate.abs()));
            }
        }
        peak
    }

    /// The plan of the joint splines `coefficients` on `basis`, `phi(0) = phi0`; statistics and
    /// certificate to be filled in.
    pub(super) fn new(
        connection: Arc<Connection>,
        basis: SplineBasis,
        coefficients: Vec<Vec<f64>>,
        phi0: f64,
        stats: ChainStats,
    ) -> Self {
        let mut me = Self {
            connection,
            basis,
            coefficients,
            phi_at_breakpoints: Vec::new(),
            stats,
            verification: ChainVerification::pending(),
        };
        let b = me.basis.breakpoints().to_vec();
        let mut phi = vec![phi0];
        for w in b.windows(2) {
            let last = phi[phi.len() - 1];
            phi.push(last - me.holonomy(phi_rule(), w[0], w[1]));
        }
        me.phi_at_breakpoints = phi;
        me
    }

    /// [`Self::new`] with the base angle at the breakpoints known already (`phi_at_breakpoints`,
    /// [`Self::breakpoint_phi`] of the same plan).
    pub(super) fn with_phi(
        connection: Arc<Connection>,
        basis: SplineBasis,
        coefficients: Vec<Vec<f64>>,
        phi_at_breakpoints: Vec<f64>,
        stats: ChainStats,
    ) -> Self {
        Self { connection, basis, coefficients, phi_at_breakpoints, stats, verification: ChainVerification::pending() }
    }

    /// The base angle at the breakpoints \[rad\].
    pub(super) fn breakpoint_phi(&self) -> &[f64] {
        &self.phi_at_breakpoints
    }

    /// `integral_a^b g dt` by `rule`.
    fn holonomy(&self, rule: &GaussLegendre, a: f64, b: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        rule.integrate(a, b, |t| {
            self.state_into(t, &mut theta, &mut rate);
            self.connection.value(&theta, &rate)
        })
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.coefficients.len()
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        self.basis.horizon()
    }

    /// The effort `integral_0^T |theta'|^2 dt` \[rad^2/s\].
    pub fn effort(&self) -> f64 {
        self.stats.effort
    }

    /// The joint angles and velocities at `t` into the buffers.
    fn state_into(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        let s = self.basis.interval(t);
        let span = self.basis.span_of_interval(s);
        let p = self.basis.degree();
        let [value, d] = self.basis.values_and_rates(span, t.clamp(0.0, self.horizon()));
        let first = span - p;
        for (j, c) in self.coefficients.iter().enumerate() {
            theta[j] = (0..=p).map(|l| value[l] * c[first + l]).sum();
            rate[j] = (0..=p).map(|l| d[l] * c[first + l]).sum();
        }
    }

    /// The base angle at `t` \[rad\]: the holonomy integral from the breakpoint before `t`.
    pub fn phi(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.horizon());
        let s = self.basis.interval(t);
        let b = self.basis.breakpoints()[s];
        if t <= b {
            return self.phi_at_breakpoints[s];
        }
        self.phi_at_breakpoints[s] - self.holonomy(phi_rule(), b, t)
    }

    /// `(phi, theta, theta', theta'')` at `t` \[s\] (clamped to `[0, T]`).
    pub fn at(&self, t: f64) -> ChainPoint {
        let t = t.clamp(0.0, self.horizon());
        self.point(t, self.phi(t))
    }

    /// The point at `t` in `[0, T]` with the base angle `phi` there: the joints' angles, rates
    /// and accelerations from the splines.
    fn point(&self, t: f64, phi: f64) -> ChainPoint {
        let mut point = ChainPoint { t, phi, theta: Vec::new(), rate: Vec::new(), acceleration: Vec::new() };
        self.basis.evaluate_each(&self.coefficients, t, |_, [v, d, a]| {
            point.theta.push(v);
            point.rate.push(d);
            point.acceleration.push(a);
        });
        point
    }

    /// `samples >= 2` equally spaced points from 0 to T, the last exactly at T: [`Self::at`] at
    /// each, the base angle carried from one sample to the next (from the breakpoint before it
    /// where one lies between them) by a Gauss–Legendre rule on the piece between them, 4 nodes
    /// on a piece within an eighth of its knot span, else [`PHI_NODES`] (as [`Self::phi`] does
    /// from the breakpoint; the test `sampled_base_angles_agree_with_phi` holds them to 1e-12
    /// rad). At 1001 samples of a 32-span plan that is 4 evaluations of the connection a sample
    /// instead of [`PHI_NODES`] (the 2-link robot's `OptimalMotion::trajectory` does the same).
    pub fn sample(&self, samples: usize) -> Vec<ChainPoint> {
        let samples = samples.max(2);
        let horizon = self.horizon();
        let b = self.basis.breakpoints();
        let (mut phi, mut previous) = (self.phi_at_breakpoints[0], 0.0);
        let mut out = Vec::with_capacity(samples);
        for i in 0..samples {
            let t = if i + 1 == samples { horizon } else { horizon * i as f64 / (samples - 1) as f64 };
            let s = self.basis.interval(t);
            if b[s] >= previous {
                // A breakpoint lies in (previous, t]: restart from it.
                (phi, previous) = (self.phi_at_breakpoints[s], b[s]);
            }
            if t > previous {
                let rule = if 8.0 * (t - previous) <= b[s + 1] - b[s] { short_rule() } else { phi_rule() };
                phi -= self.holonomy(rule, previous, t);
                previous = t;
            }
            out.push(self.point(t, phi));
        }
        out
    }

    /// The spline basis of the joint paths.
    pub fn basis(&self) -> &SplineBasis {
        &self.basis
    }

    /// The spline coefficients of each joint's path on [`Self::basis`].
    pub fn coefficients(&self) -> &[Vec<f64>] {
        &self.coefficients
    }
}

impl JointMotion for ChainPlan {
    fn joints(&self) -> usize {
        self.coefficients.len()
    }

    fn breakpoints(&self) -> &[f64] {
        self.basis.breakpoints()
    }

    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        self.state_into(t, theta, rate);
    }

    fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
        self.basis.evaluate_each(&self.coefficients, t.clamp(0.0, self.horizon()), |j, [_, _, a]| out[j] = a);
    }

    fn phi_rate(&self, t: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        self.state_into(t, &mut theta, &mut rate);
        -self.connection.value(&theta, &rate)
    }
}
