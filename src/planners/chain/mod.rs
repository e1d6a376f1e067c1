//! Minimum-effort motion planning for any planar serial arm (issues 11 and 14): the joint path
//! `theta: [0, T] -> R^n` that minimises `J = integral_0^T |theta'|^2 dt` with
//! `theta(0) = theta0`, `theta'(0) = u0`, `theta(T) = thetad`, `theta'(T) = 0`, subject to the one
//! scalar holonomy constraint `phi(T) = phid`, where `phi' = -(G(theta) . theta') / F(theta)`
//! (Eq. 7 with zero momentum, for any `n`).
//!
//! The method is that of the two-joint [`optimal`](crate::planners::optimal) planner, for `n`
//! joints: clamped B-splines on one basis for all joints ([`discrete`]), the holonomy integrand
//! in closed form with exact derivatives ([`connection`]), its trust-region SQP
//! ([`crate::planners::optimal::sqp`]) from the straight line and loop seeds in the joint planes
//! of largest curvature ([`seeds`]), for the nearby goal representatives modulo 2 pi; the best
//! coarse solution is refined until the effort settles, and the plan is returned only when the
//! original system integrated with its controls reaches the goal
//! ([`verify_chain`](crate::plan::certificate::verify_chain)).
//!
//! With one joint `a(theta) dtheta` is exact, so `phi(T)` is fixed by `theta(T)`: the planner
//! checks the goal for consistency ([`Error::HolonomyFixed`]) and then minimises the effort alone.

mod augmented;
pub mod coil;
pub mod connection;
pub mod discrete;
pub mod energy;
mod gauge;
mod hopeless;
pub mod horizon;
mod keep_clear;
mod limits;
pub mod motion;
mod queue;
pub(crate) mod search;
pub mod seeds;
mod single;
mod spin;
mod starts;
#[cfg(test)]
pub(crate) use starts::LINE_SPANS_PER_TURN;
mod tables;
mod too_short;
mod warm;

use std::sync::Arc;

use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::ode::OdeOptions;
use crate::plan::check_horizon;
use crate::planners::optimal::{Cost, SqpOptions};

pub use connection::MAX_JOINTS;
pub use motion::{ChainPlan, ChainPoint, ChainStats};

/// Drive an `n`-joint arm from `start` to `goal` in time `horizon` at zero angular momentum.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainProblem {
    /// `(phi, theta_1, .., theta_n)` at `t = 0` \[rad\].
    pub start: Vec<f64>,
    /// `(phi, theta_1, .., theta_n)` at `t = T` \[rad\].
    pub goal: Vec<f64>,
    /// `T` \[s\].
    pub horizon: f64,
    /// `theta'(0)` \[rad/s\] (`n` values; zeros for rest to rest).
    pub initial_velocity: Vec<f64>,
    /// Count the goal's angles modulo 2 pi: try nearby representatives, keep the best certified
    /// plan. False: the goal's angles literally.
    pub wrap: bool,
}

impl ChainProblem {
    /// Rest to rest, angles modulo 2 pi.
    pub fn rest_to_rest(start: Vec<f64>, goal: Vec<f64>, horizon: f64) -> Self {
        let n = start.len().saturating_sub(1);
        Self { start, goal, horizon, initial_velocity: vec![0.0; n], wrap: true }
    }

    /// Checks the problem against `arm`: `n + 1` start and goal values, `n` initial velocities,
    /// all finite (angles within [`crate::plan::MAX_ANGLE`]), a limited joint's (and `phi`'s with
    /// a base range) start and goal inside the declared range, both ends at least the clearance
    /// from every pair checked, the horizon in
    /// [`crate::plan::HORIZON_RANGE`], `1 <= n <=` [`MAX_JOINTS`].
    pub fn validate(&self, arm: &Arm) -> Result<(), Error> {
        let n = arm.joints();
        let bad = |name: String, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name, value, expected }))
        };
        if !(1..=MAX_JOINTS).contains(&n) {
            return bad("joints".into(), n as f64, "an arm of 1 to 15 joints");
        }
        for (name, v) in [("start", &self.start), ("goal", &self.goal)] {
            if v.len() != n + 1 {
                return bad(format!("{name}.len"), v.len() as f64, "n + 1 values (phi, theta_1..theta_n)");
            }
            for (i, x) in v.iter().enumerate() {
                if !(x.is_finite() && x.abs() <= crate::plan::MAX_ANGLE) {
                    return bad(format!("{name}[{i}]"), *x, "a finite angle with |angle| <= 1e4 rad");
                }
            }
        }
        if self.initial_velocity.len() != n {
            return bad("initial_velocity.len".into(), self.initial_velocity.len() as f64, "n joint velocities");
        }
        for (i, u) in self.initial_velocity.iter().enumerate() {
            if !u.is_finite() {
                return bad(format!("initial_velocity[{i}]"), *u, "a finite joint velocity [rad/s]");
            }
        }
        self.validate_ranges(arm)?;
        self.validate_clearance(arm)?;
        check_horizon("horizon", self.horizon)
    }

    /// The start and the goal against the clearance (issue 21): every motion passes through
    /// both, so an end closer than `arm.geometry.clearance` to a pair that is checked can never
    /// be certified. It is refused at once, naming the pair and its distance, instead of after a
    /// search of every seed (90 to 140 s on the SPART-like arm). A goal's representatives differ
    /// by whole turns of the joints: the same bodies in the same places.
    fn validate_clearance(&self, arm: &Arm) -> Result<(), Error> {
        let geometry = &arm.geometry;
        for (name, q) in [("start (--from)", &self.start), ("goal (--to)", &self.goal)] {
            if let Some(d) = geometry.min_clearance(arm, q).filter(|d| d.distance < geometry.clearance) {
                return Err(Error::from(InputError::InvalidParameter {
                    name: format!(
                        "{name}: the distance between {} and {} [m], under the clearance {} m",
                        d.a, d.b, geometry.clearance
                    ),
                    value: d.distance,
                    expected: "ends at least the clearance apart in every pair checked (move the end, \
                               lower --clearance, or exclude the pair with --no-collide)",
                }));
            }
        }
        Ok(())
    }
}

/// Options of the [`ChainPlanner`] (defaults those of the two-joint planner).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainOptions {
    /// The cost: [`Cost::Effort`] (default) or [`Cost::Energy`], the kinetic energy of the arm
    /// at zero angular momentum (the base's `phi'` from the momentum constraint), see [`energy`].
    pub cost: Cost,
    /// Also `theta''(0) = theta''(T) = 0` (quintic splines), so that the torques start and end at
    /// zero; default false (cubic splines).
    pub smooth_ends: bool,
    /// Tolerance of the certificate's final error \[rad\]; default 1e-9.
    pub tolerance: f64,
    /// Integrator options of the certificate (default rtol = atol = 1e-12).
    pub ode: OdeOptions,
    /// Uniform knot spans of the coarse basis on which every seed is solved; default 8.
    pub coarse_spans: usize,
    /// Largest number of uniform knot spans of the refinement (doubling); default 32.
    pub max_spans: usize,
    /// Graded knots at `h / 4^j`, `j = 1..=grading`, in the first and last spans; default 1
    /// (see [`crate::planners::optimal::OptimalOptions::grading`]).
    pub grading: usize,
    /// The refinement stops when the effort changes by less than this, relative; default 1e-6.
    pub refinement_tolerance: f64,
    /// Gauss–Legendre nodes per knot span; default 8 (raised up to 32 until the motion's finer
    /// quadrature agrees to 1% of the tolerance).
    pub quadrature_nodes: usize,
    /// How many goal representatives (best first by their seeds' estimated effort) are solved
    /// per batch; default 2.
    pub targets_solved: usize,
    /// How many of the best coarse solutions are refined; default 2.
    pub finalists: usize,
    /// How many coarse solutions far from the constraint (`|c| > 1e-3` rad), least cost first,
    /// are refined per batch besides the finalists; default 2. On the coarse basis a line or a
    /// loop often cannot meet the constraint while its refinement on finer bases reaches a plan
    /// below every coarse-feasible one: on the 300 recorded two-link problems
    /// (tests/fixtures/two_link_300.csv) 28 plans were above the better recorded planner with 0,
    /// 7 with 1, 5 with 2.
    pub far_finalists: usize,
    /// Loop seeds per representative, in the joint planes of largest curvature; default 2.
    pub loop_planes: usize,
    /// Largest radius of a loop seed \[rad\]; default 2.
    pub max_loop_radius: f64,
    /// SQP options of the refined solves.
    pub sqp: SqpOptions,
    /// A path to start from (a re-plan's rest of the current reference): projected on the coarse
    /// basis, solved and refined on the goal representative it ends at; when that converges and
    /// certifies it is the plan, else the full search runs (unless
    /// [`ChainOptions::warm_start_only`]). Default none.
    pub warm_start: Option<WarmStart>,
    /// The breakpoints `0 = b_0 < .. < b_N = T` of every basis of the search instead of
    /// `coarse_spans` to `max_spans` uniform ones (set both to `N` then): a re-plan keeps the
    /// knots of the reference it corrects, whose rest is then a spline of the basis and its
    /// warm start exact. Default none.
    pub knots: Option<Vec<f64>>,
    /// Clearance the clearance rows keep beyond the clearance asked for and their own margin
    /// \[m\] (issue 21): a re-plan takes what its reference's certificate needed
    /// ([`ChainStats::clearance_reserve`]), so that it does not dip under the clearance between
    /// the rows' points and solve again. At most 1 m; default 0.
    pub clearance_reserve: f64,
    /// Clearance the rows keep beyond the clearance asked for, rising with time from the plan's
    /// start (issue 21 item 6): a re-plan of `track` from a state already inside its margin
    /// keeps part of it at the start and all of it from the rise's end on, so that the margin
    /// is won back instead of eroding re-plan by re-plan. Default none.
    pub clearance_rise: ClearanceRise,
    /// Where a [`ChainOptions::warm_start`] is given and does not give a plan, fail
    /// ([`Error::OptimalFailed`], termination `warm_start`) instead of the full search: a
    /// re-plan of `track` is a small correction of the plan it starts from, and the search after
    /// a failed warm start found no plan in 157 of 157 re-plans of the 3-link example at its
    /// velocity limit, and took 8 to 47 s a re-plan on the SPART-like arm with shapes. Default
    /// false.
    pub warm_start_only: bool,
}

/// A clearance kept beyond the one asked for that rises linearly from none at `t = 0` to
/// `extra` at `t = over` and stays ([`ChainOptions::clearance_rise`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ClearanceRise {
    /// The clearance kept from `over` on \[m\], in `[0, 1]`.
    pub extra: f64,
    /// The time of the rise \[s\], `>= 0` (none: all of `extra` from the start).
    pub over: f64,
}

impl ClearanceRise {
    /// The clearance kept at time `t` \[m\].
    pub fn at(&self, t: f64) -> f64 {
        if t >= self.over { self.extra } else { self.extra * (t / self.over).max(0.0) }
    }
}

/// Sampled `(t, theta, theta')` of `n` joints, interpolated by cubic Hermite polynomials.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// Increasing times from 0 \[s\].
    pub t: Vec<f64>,
    /// Joint angles at the times \[rad\], `n` per sample.
    pub theta: Vec<Vec<f64>>,
    /// Joint velocities at the times \[rad/s\], `n` per sample.
    pub rate: Vec<Vec<f64>>,
}

impl WarmStart {
    /// Checks the shape against `n` joints: at least 2 samples from `t = 0`, increasing times,
    /// `n` finite angles and velocities per sample.
    pub fn validate(&self, n: usize) -> Result<(), Error> {
        let rows = |v: &Vec<Vec<f64>>| {
            v.len() == self.t.len() && v.iter().all(|r| r.len() == n && r.iter().all(|x| x.is_finite()))
        };
        let times = self.t.first() == Some(&0.0)
            && self.t.windows(2).all(|w| w[1] > w[0])
            && self.t.iter().all(|x| x.is_finite());
        if self.t.len() >= 2 && times && rows(&self.theta) && rows(&self.rate) {
            Ok(())
        } else {
            Err(Error::from(InputError::InvalidParameter {
                name: "warm_start".into(),
                value: self.t.len() as f64,
                expected: "at least 2 samples from t = 0 at increasing times, n finite angles and velocities each",
            }))
        }
    }

    /// The interpolated joint angles at `t` \[s\] (clamped to the samples' span) into `out`.
    pub fn at(&self, t: f64, out: &mut [f64]) {
        let m = self.t.len();
        let i = self.t.partition_point(|&s| s <= t).clamp(1, m - 1) - 1;
        let h = self.t[i + 1] - self.t[i];
        let s = ((t - self.t[i]) / h).clamp(0.0, 1.0);
        let (h00, h10, h01, h11) = (
            2.0 * s * s * s - 3.0 * s * s + 1.0,
            s * s * s - 2.0 * s * s + s,
            -2.0 * s * s * s + 3.0 * s * s,
            s * s * s - s * s,
        );
        for (j, o) in out.iter_mut().enumerate() {
            *o = h00 * self.theta[i][j]
                + h10 * h * self.rate[i][j]
                + h01 * self.theta[i + 1][j]
                + h11 * h * self.rate[i + 1][j];
        }
    }
}

impl Default for ChainOptions {
    fn default() -> Self {
        Self {
            cost: Cost::Effort,
            smooth_ends: false,
            tolerance: 1e-9,
            ode: OdeOptions::default(),
            coarse_spans: 8,
            max_spans: 32,
            grading: 1,
            refinement_tolerance: 1e-6,
            quadrature_nodes: 8,
            targets_solved: 2,
            finalists: 2,
            far_finalists: 2,
            loop_planes: 2,
            max_loop_radius: 2.0,
            sqp: SqpOptions::default(),
            warm_start: None,
            knots: None,
            clearance_reserve: 0.0,
            clearance_rise: ClearanceRise::default(),
            warm_start_only: false,
        }
    }
}

impl ChainOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name: &str, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value, expected }))
        };
        crate::plan::limits::check_tolerance("tolerance", self.tolerance)?;
        if self.coarse_spans < 2 || self.max_spans < self.coarse_spans || self.max_spans > 4096 {
            return bad("max_spans", self.max_spans as f64, "2 <= coarse_spans <= max_spans <= 4096");
        }
        if self.grading > 12 {
            return bad("grading", self.grading as f64, "at most 12 graded knots per end");
        }
        if !(6..=32).contains(&self.quadrature_nodes) {
            return bad("quadrature_nodes", self.quadrature_nodes as f64, "6 to 32 nodes per knot span");
        }
        if self.targets_solved == 0 {
            return bad("targets_solved", 0.0, "at least 1");
        }
        if self.finalists == 0 {
            return bad("finalists", 0.0, "at least 1");
        }
        if !(self.max_loop_radius > 0.0 && self.max_loop_radius < 10.0) {
            return bad("max_loop_radius", self.max_loop_radius, "a radius in (0, 10) rad");
        }
        if !(0.0..=1.0).contains(&self.clearance_reserve) {
            return bad("clearance_reserve", self.clearance_reserve, "a clearance in [0, 1] m");
        }
        let rise = self.clearance_rise;
        if !((0.0..=1.0).contains(&rise.extra) && rise.over.is_finite() && rise.over >= 0.0) {
            return bad("clearance_rise", rise.extra, "a clearance in [0, 1] m rising over a time >= 0 s");
        }
        if !(self.refinement_tolerance > 0.0) {
            return bad("refinement_tolerance", self.refinement_tolerance, "a positive relative change");
        }
        Ok(())
    }
}

/// The minimum-effort planner for an `n`-joint arm (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainPlanner {
    /// The arm (private: its momentum coefficients' constants are computed from it once).
    arm: Arc<Arm>,
    /// Options.
    pub options: ChainOptions,
    connection: Arc<connection::Connection>,
    /// The clearance between the robot's own bodies as constraints (issue 21; off for the first,
    /// unconstrained search, whose plan is the constrained minimum when it clears).
    clearance_rows: bool,
    /// The clearance to the obstacles as constraints too (dense rows through `phi(t)`; off for
    /// the search with rows, on for the repair of its plan, see [`Self::plan`]).
    obstacle_rows: bool,
    /// Points per knot span at which the rows of the robot's own bodies hold (more in the
    /// clearance search's last resort, `keep_clear.rs`).
    clearance_pieces: usize,
    /// The times where the rows of the robot's own bodies hold at `clearance_pieces` points per
    /// span, [`limits::CLEARANCE_PIECES`] elsewhere: the spans near a dip of a plan solved again
    /// with denser rows (`keep_clear.rs`); none: everywhere.
    clearance_dense: Option<Arc<[[f64; 2]]>>,
    /// Whether the clearance search ends with its last resort where no plan cleared
    /// (`keep_clear.rs`; off for the shortest horizon's final search, which has a plan that
    /// clears already: `horizon.rs`).
    last_resort: bool,
    /// Whether the search only decides whether its horizon fits (the shortest horizon's full
    /// search at the probes' failing horizon, `horizon.rs`): its solves give up an infeasible
    /// crawl and are not restarted off the constraint (`limits::solve`).
    deciding: bool,
    /// The goal representative whose line a deciding search does not solve: the shortest
    /// horizon's probe at that horizon decided its family (`horizon.rs`, `decides_line`).
    decided_line: Option<Arc<discrete::Targets>>,
    /// The margins of the torque and base-range rows of a plan solved again because it left those
    /// limits between the rows' points (`limits/hold.rs`; none otherwise).
    held: Option<Arc<limits::Margins>>,
    /// The coil sites found by its calls ([`coil::Sites`]: they depend on the connection, the
    /// ranges and the loops' largest radius, and at three joints or more on the line).
    sites: coil::Sites,
    /// The tables built by its calls ([`tables::KeptTables`]).
    tables: tables::KeptTables,
    /// A two-joint arm's gauge, made by its first call that needs it ([`gauge::KeptGauge`]).
    gauge: gauge::KeptGauge,
}

impl ChainPlanner {
    /// A planner for `arm` with `options`.
    pub fn new(arm: Arm, options: ChainOptions) -> Self {
        let connection = Arc::new(connection::Connection::new(&arm));
        Self {
            arm: Arc::new(arm),
            options,
            connection,
            clearance_rows: true,
            obstacle_rows: true,
            clearance_pieces: limits::CLEARANCE_PIECES,
            clearance_dense: None,
            last_resort: true,
            deciding: false,
            decided_line: None,
            held: None,
            sites: coil::Sites::default(),
            tables: tables::KeptTables::default(),
            gauge: gauge::KeptGauge::default(),
        }
    }

    /// The arm.
    pub fn arm(&self) -> &Arm {
        &self.arm
    }

    /// The spline degree: 5 with smooth ends, else 3.
    fn degree(&self) -> usize {
        if self.options.smooth_ends { 5 } else { 3 }
    }

    /// Coefficients fixed per joint at each end: 3 with smooth ends (`theta, theta', theta''`),
    /// else 2.
    fn fixed(&self) -> usize {
        if self.options.smooth_ends { 3 } else { 2 }
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod tests_clearance;

#[cfg(test)]
mod tests_cost;

#[cfg(test)]
mod tests_limits;

#[cfg(test)]
mod tests_clearance_oracle;
#[cfg(test)]
mod tests_oracle;
#[cfg(test)]
mod tests_oracle_base;
#[cfg(test)]
mod tests_oracle_solver;

#[cfg(test)]
mod tests_recorded;

#[cfg(test)]
mod tests_spin;
#[cfg(test)]
mod tests_too_short;
