//! Receding-horizon re-planning: from the measured state, with its joint velocity, to the goal
//! in the remaining time, with the minimum-effort planner for `n` joints
//! ([`ChainPlanner`]) on cheap settings, warm-started by the rest of the current reference; and
//! the reference that the joint loop follows between re-plans.

use super::motion::{ArmMotion, JointPoint};
use super::plant::State;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::ode::OdeOptions;
use crate::planners::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainProblem, WarmStart};

/// Options of the re-planning.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplanOptions {
    /// Re-plans per second \[Hz\]; default 50. At most the control rate.
    pub rate: f64,
    /// No re-plan starts in the last `final_window` seconds \[s\]: the last one, this long before
    /// the end, is the final correction, tracked to the end by the joint loop (shorter horizons
    /// ask for accelerations that amplify the noise); default 0.3 s.
    pub final_window: f64,
    /// A re-plan is used only when its velocity-level certificate (on the model, from the
    /// measured state) ends within this of the goal \[rad\]; otherwise it counts as a failure and
    /// the last plan stays; default 1e-6.
    pub accept: f64,
    /// A re-plan is due only when the measured configuration is farther than this from the
    /// current plan (`max_i |q_i - q_plan_i|`) \[rad\]: on a robot that follows its plan there
    /// is nothing to correct, and each re-plan costs the hold's discretisation error of a
    /// fresh, shorter plan; default 1e-7.
    pub threshold: f64,
    /// The planner's options: a coarse basis, one target, one finalist, the goal taken
    /// literally (the representative of the first plan, `ChainProblem::wrap = false`). Each
    /// re-plan starts from the measured joint velocity (`ChainProblem::initial_velocity`) and
    /// from the rest of the current reference ([`ChainOptions::warm_start`], set per re-plan).
    pub planner: ChainOptions,
}

impl Default for ReplanOptions {
    fn default() -> Self {
        Self {
            rate: 50.0,
            final_window: 0.3,
            accept: 1e-6,
            threshold: 1e-7,
            planner: ChainOptions {
                coarse_spans: 6,
                max_spans: 6,
                targets_solved: 1,
                finalists: 1,
                loop_planes: 1,
                tolerance: 1e-6,
                ode: OdeOptions { rtol: 1e-9, atol: 1e-9, max_steps: 100_000 },
                ..ChainOptions::default()
            },
        }
    }
}

impl ReplanOptions {
    /// Checks the options against the control rate \[Hz\].
    pub fn validate(&self, control_rate: f64) -> Result<(), Error> {
        let bad = |name: &str, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value, expected }))
        };
        if !(self.rate > 0.0 && self.rate <= control_rate) {
            return bad("replan-rate", self.rate, "a positive rate [Hz] no faster than the control rate");
        }
        if !(self.final_window.is_finite() && self.final_window >= 0.0) {
            return bad("final-window", self.final_window, "a duration >= 0 [s]");
        }
        if !(self.threshold.is_finite() && self.threshold >= 0.0) {
            return bad("replan threshold", self.threshold, "a deviation >= 0 [rad]");
        }
        if !(self.accept > 0.0) {
            return bad("replan accept tolerance", self.accept, "a positive number [rad]");
        }
        self.planner.validate()
    }
}

/// The motion the joint loop follows: a plan and the time it started \[s\].
pub enum Reference<'a> {
    /// The initial plan, starting at `t = 0`.
    Initial(&'a dyn ArmMotion),
    /// A re-plan started at `t0`.
    Replanned {
        /// The re-planned motion (its own time starts at 0).
        motion: Box<ChainPlan>,
        /// When it started \[s\].
        t0: f64,
    },
}

impl Reference<'_> {
    fn motion(&self) -> (&dyn ArmMotion, f64) {
        match self {
            Reference::Initial(m) => (*m, 0.0),
            Reference::Replanned { motion, t0 } => (motion.as_ref(), *t0),
        }
    }

    /// The joints of the reference at time `t` of the run \[s\], held at the plan's end after
    /// it (at rest at the goal).
    pub fn joints_at(&self, t: f64) -> Result<JointPoint, Error> {
        let (motion, t0) = self.motion();
        let mut p = motion.joints_at((t - t0).clamp(0.0, motion.horizon()))?;
        if t - t0 > motion.horizon() {
            p.rate.iter_mut().chain(p.acceleration.iter_mut()).for_each(|x| *x = 0.0);
        }
        Ok(p)
    }

    /// `q = (phi, theta)` of the reference at time `t` of the run \[s\] (held after its end).
    pub fn q(&self, t: f64) -> Result<Vec<f64>, Error> {
        let (motion, t0) = self.motion();
        motion.q((t - t0).clamp(0.0, motion.horizon()))
    }
}

/// The re-planner of a run: the goal's representative and the planner.
pub struct Replanner {
    goal: Vec<f64>,
    options: ReplanOptions,
    /// The planner of the last model (its constants are computed once per model).
    planner: Option<ChainPlanner>,
}

impl Replanner {
    /// Re-plans toward `goal` (`n + 1` angles), taken literally (the end of the first plan).
    pub fn new(goal: Vec<f64>, options: ReplanOptions) -> Self {
        Self { goal, options, planner: None }
    }

    /// A plan on `model` from the measured state at time `t` to the goal at `horizon` \[s\],
    /// warm-started by the rest of `current`, the reference being followed (the planner's full
    /// search follows where that start does not converge): `None` when the planner fails, its
    /// plan is not accepted (see [`ReplanOptions::accept`]) or its certificate finds it closer
    /// than the model's clearance to a body or an obstacle.
    pub fn replan(
        &mut self,
        model: &Arm,
        measured: &State,
        t: f64,
        horizon: f64,
        current: &Reference,
    ) -> Option<ChainPlan> {
        let problem = ChainProblem {
            start: measured.q.clone(),
            goal: self.goal.clone(),
            horizon: horizon - t,
            initial_velocity: measured.dq[1..].to_vec(),
            wrap: false,
        };
        if self.planner.as_ref().is_none_or(|p| p.arm() != model) {
            self.planner = Some(ChainPlanner::new(model.clone(), self.options.planner.clone()));
        }
        let planner = self.planner.as_mut()?;
        planner.options.warm_start = Self::rest_of(current, t, horizon, 4 * self.options.planner.max_spans + 1);
        let plan = planner.plan(&problem).ok()?;
        // A plan whose verified motion comes closer than the model's clearance is refused (issue
        // 21): the last plan stays, as for any refused re-plan.
        plan.verification.collision().ok()?;
        let e = plan.verification.final_error;
        (e.is_finite() && e <= self.options.accept).then_some(plan)
    }

    /// The joint path of `current` from `t` to `horizon` at `n` equally spaced times, with its
    /// own time starting at 0; `None` if it cannot be evaluated.
    fn rest_of(current: &Reference, t: f64, horizon: f64, n: usize) -> Option<WarmStart> {
        let mut path =
            WarmStart { t: Vec::with_capacity(n), theta: Vec::with_capacity(n), rate: Vec::with_capacity(n) };
        for i in 0..n {
            let s = (horizon - t) * i as f64 / (n - 1) as f64;
            let p = current.joints_at(t + s).ok()?;
            path.t.push(s);
            path.theta.push(p.theta);
            path.rate.push(p.rate);
        }
        Some(path)
    }
}
