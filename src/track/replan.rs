//! Receding-horizon re-planning: from the measured state, with its joint velocity, to the goal
//! in the remaining time, with the minimum-effort planner on cheap settings; and the reference
//! that the joint loop follows between re-plans.

use super::plant::State;
use crate::error::Error;
use crate::model::{Configuration, InputError, RobotParams};
use crate::numerics::ode::OdeOptions;
use crate::plan::{Method, Motion, MotionPoint, PlanningProblem};
use crate::planners::optimal::{OptimalOptions, Sampled};
use crate::planners::{PlannerOptions, planner};

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
    /// The planner's options: few samples, a coarse basis, one target, no NFA seed, the goal
    /// taken literally (the representative of the first plan). Each re-plan starts from the
    /// measured joint velocity (the problem's `start_velocity`).
    pub planner: OptimalOptions,
}

impl Default for ReplanOptions {
    fn default() -> Self {
        Self {
            rate: 50.0,
            final_window: 0.3,
            accept: 1e-6,
            threshold: 1e-7,
            planner: OptimalOptions {
                samples: 2,
                coarse_spans: 6,
                max_spans: 6,
                nfa_seed: false,
                targets_solved: 1,
                finalists: 1,
                wrap: false,
                tolerance: 1e-6,
                ode: OdeOptions { rtol: 1e-9, atol: 1e-9, max_steps: 100_000 },
                ..OptimalOptions::default()
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
    Initial(&'a (dyn Motion + Sync)),
    /// A re-plan started at `t0`.
    Replanned {
        /// The re-planned motion (its own time starts at 0).
        motion: Box<dyn Motion + Send + Sync>,
        /// When it started \[s\].
        t0: f64,
    },
}

impl Reference<'_> {
    /// The reference at time `t` of the run \[s\], held at the plan's end after it.
    pub fn at(&self, t: f64) -> Result<MotionPoint, Error> {
        let (motion, t0): (&dyn Motion, f64) = match self {
            Reference::Initial(m) => (*m, 0.0),
            Reference::Replanned { motion, t0 } => (motion.as_ref(), *t0),
        };
        let s = (t - t0).clamp(0.0, motion.horizon());
        let mut p = motion.at(s)?;
        if t - t0 > motion.horizon() {
            // Past the end: at rest at the goal.
            (p.u, p.du) = ([0.0; 2], [0.0; 2]);
        }
        Ok(p)
    }
}

/// The re-planner of a run: the goal's representative and the planner.
pub struct Replanner {
    goal: Configuration,
    options: ReplanOptions,
}

impl Replanner {
    /// Re-plans toward `goal`, taken literally (the end of the first plan).
    pub fn new(goal: Configuration, options: ReplanOptions) -> Self {
        Self { goal, options }
    }

    /// A plan on `model` from the measured state at time `t` to the goal at `horizon` \[s\],
    /// warm-started by the rest of `current`, the reference being followed (the planner's full
    /// search follows where that start does not converge): `None` when the planner fails or its
    /// plan is not accepted (see [`ReplanOptions::accept`]).
    pub fn replan(
        &self,
        model: &RobotParams,
        measured: &State,
        t: f64,
        horizon: f64,
        current: &Reference,
    ) -> Option<Box<dyn Motion + Send + Sync>> {
        let problem = PlanningProblem::new(*model, measured.q, self.goal, horizon - t)
            .and_then(|p| p.with_start_velocity([measured.dq[1], measured.dq[2]]))
            .ok()?;
        let mut optimal = self.options.planner.clone();
        optimal.warm_start = Self::rest_of(current, t, horizon, 4 * optimal.max_spans + 1);
        let planner = planner(Method::Optimal, &PlannerOptions { optimal, ..Default::default() });
        let planned = planner.plan(&problem).ok()?;
        let e = planned.plan.verification.final_error;
        (e.is_finite() && e <= self.options.accept).then_some(planned.motion)
    }

    /// The joint path of `current` from `t` to `horizon` at `n` equally spaced times, with its
    /// own time starting at 0; `None` if it cannot be evaluated.
    fn rest_of(current: &Reference, t: f64, horizon: f64, n: usize) -> Option<Sampled> {
        let mut path = Sampled { t: Vec::with_capacity(n), theta: Vec::with_capacity(n), rate: Vec::with_capacity(n) };
        for i in 0..n {
            let s = (horizon - t) * i as f64 / (n - 1) as f64;
            let p = current.at(t + s).ok()?;
            path.t.push(s);
            path.theta.push([p.q.theta1, p.q.theta2]);
            path.rate.push(p.u);
        }
        Some(path)
    }
}
