//! Receding-horizon re-planning: from the measured state, with its joint velocity, to the goal
//! in the remaining time, with the minimum-effort planner for `n` joints
//! ([`ChainPlanner`]) on cheap settings, warm-started by the rest of the current reference; and
//! the reference that the joint loop follows between re-plans.

use super::motion::{ArmMotion, JointPoint};
use super::plant::State;
use crate::Method;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::ode::OdeOptions;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainProblem, ClearanceRise, WarmStart};

/// The most spans of a re-plan's basis ([`Replanner`]): a motion of 25 joint turns, the
/// hardest of issue 22's hard set, takes about 160.
pub const MAX_REPLAN_SPANS: usize = 256;

/// Re-plan periods over which a re-plan from a state inside the clearance margin wins the margin
/// back ([`ReplanOptions::margin`]).
const RISE_PERIODS: f64 = 2.0;

/// Options of the re-planning.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplanOptions {
    /// Re-plans per second \[Hz\]; default 5. At most the control rate. With the default
    /// gains ([`super::Gains::for_rate`]) the joint loop holds the plan, and the re-plans only
    /// correct the base's drift: on issue 22's hard set 5 Hz ends every trial as 50 Hz did, at a
    /// tenth of the work.
    pub rate: f64,
    /// No re-plan starts in the last `final_window` seconds \[s\]; the last one, the final
    /// correction, starts exactly `final_window` before the end (besides the re-plan rate's
    /// ticks) and is tracked to the end by the joint loop: the base drifts on the model's error
    /// from it on, and shorter horizons ask for accelerations that amplify the noise; default
    /// 0.25 s (issue 22's hard sets: docs/spec.md §3, `track`).
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
    /// The clearance the plans keep beyond the model's \[m\] (issue 21 item 6): the first plan
    /// and every re-plan keep `clearance + margin` ([`ReplanOptions::planning_model`]), the run
    /// fails only under `clearance` (the true robot is not the model: a plan that grazes a body
    /// at its clearance leaves the perturbed robot no room); default 0.02 m (docs/spec.md §3,
    /// `track`). A re-plan from a state already inside the margin keeps half of what is left at
    /// its start, and the whole margin again from two re-plan periods on
    /// ([`crate::planners::chain::ClearanceRise`]). Nothing changes on a robot without shapes.
    pub margin: f64,
    /// The headroom the plans leave inside the robot's declared limits, a fraction in `[0, 1)`
    /// (issue 20 item 6): the first plan and every re-plan are made inside
    /// [`crate::model::arm::Limits::with_headroom`] of it (velocity, acceleration and torque
    /// limits times `1 - limit_margin`, position ranges shrunk to `1 - limit_margin` of their
    /// width about their centre), the run fails only outside the limits themselves and the plant
    /// saturates at the true torque limits: a plan that rides on a limit leaves the feedback of
    /// a perturbed robot no room. A re-plan from a measured state already beyond the tightened
    /// limits has them widened to admit it ([`ReplanOptions::planning_model`]); a horizon too
    /// short for the whole margin lowers it ([`ReplanOptions::first_plan`]). Default 0.05
    /// (docs/spec.md §3, `track`); nothing changes on a robot without limits.
    pub limit_margin: f64,
    /// The planner's options: a coarse basis, one target, one finalist, the goal taken
    /// literally (the representative of the first plan, `ChainProblem::wrap = false`). Each
    /// re-plan starts from the measured joint velocity (`ChainProblem::initial_velocity`) and
    /// from the rest of the current reference ([`ChainOptions::warm_start`], set per re-plan),
    /// and is that start's solution or none ([`ChainOptions::warm_start_only`]: no search).
    pub planner: ChainOptions,
}

impl Default for ReplanOptions {
    fn default() -> Self {
        Self {
            rate: 5.0,
            final_window: 0.25,
            accept: 1e-6,
            threshold: 1e-7,
            margin: 0.02,
            limit_margin: 0.05,
            planner: ChainOptions {
                coarse_spans: 6,
                max_spans: 6,
                // No thin end layer (see `Replanner::knots_for`).
                grading: 0,
                targets_solved: 1,
                finalists: 1,
                far_finalists: 0,
                // A re-plan starts from the plan it corrects, and is that plan's correction or
                // none: the search after a failed warm start found no plan in 157 of 157 re-plans
                // of the 3-link example at its velocity limit (stop 54). The ladder's last step
                // searches on arms with shapes or without limits (`Replanner::replan`).
                warm_start_only: true,
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
        if !(self.margin.is_finite() && (0.0..=1.0).contains(&self.margin)) {
            return bad("margin", self.margin, "a clearance margin in [0, 1] m");
        }
        if !(self.limit_margin.is_finite() && (0.0..1.0).contains(&self.limit_margin)) {
            return bad("limit-margin", self.limit_margin, "a fraction of every limit in [0, 1)");
        }
        if !(self.accept > 0.0) {
            return bad("replan accept tolerance", self.accept, "a positive number [rad]");
        }
        self.planner.validate()
    }

    /// Refuses a margin the user gave (`given`) for a model without shapes or obstacles, naming
    /// `margin`: there is no clearance for it to extend, and it would be accepted and ignored.
    pub fn check_margin(model: &Arm, given: Option<f64>) -> Result<(), Error> {
        match given {
            Some(value) if value != 0.0 && model.geometry.is_empty() => Err(InputError::InvalidParameter {
                name: "margin".into(),
                value,
                expected: "no margin: the robot has no shapes or obstacles, so no clearance to keep it beyond \
                           (give the robot file shapes, or --obstacle)",
            }
            .into()),
            _ => Ok(()),
        }
    }

    /// Refuses a limit margin the user gave (`given`) for a model without limits, naming
    /// `limit-margin`: there are no limits to keep it inside, and it would be accepted and
    /// ignored. A margin of 0 (none) is accepted for any robot.
    pub fn check_limit_margin(model: &Arm, given: Option<f64>) -> Result<(), Error> {
        match given {
            Some(value) if value != 0.0 && model.limits.is_empty() => Err(InputError::InvalidParameter {
                name: "limit-margin".into(),
                value,
                expected: "no limit margin: the robot has no limits to keep it inside \
                           (give the robot file limits, or --limit)",
            }
            .into()),
            _ => Ok(()),
        }
    }

    /// The model the plans of `problem` are made on: `model` keeping its clearance plus
    /// [`ReplanOptions::margin`] \[m\] and inside its limits less [`ReplanOptions::limit_margin`]
    /// ([`crate::model::arm::Limits::with_headroom`], which admits the problem's start, goal and
    /// initial velocity); `model` itself without shapes, obstacles or limits.
    pub fn planning_model(&self, model: &Arm, problem: &ChainProblem) -> Arm {
        Self::model_for(model, self.margin, self.limit_margin, problem)
    }

    /// The first plan of a run of `problem` on `model`: the minimum-effort plan on the planning
    /// model ([`ReplanOptions::planning_model`]). Where the horizon is too short for the whole
    /// limit margin ([`Error::HorizonTooShort`] at it, with the shortest horizon `T*` that fits
    /// it), the margin is lowered to the one a time-scaling of that plan would leave at the
    /// horizon `T`: `1 - (1 - margin) (T* / T)^k`, `k = 2` where an acceleration or torque limit
    /// binds at `T*` (they scale with the square of the speed), else 1; to 0 (the limits
    /// themselves, the error of a plan without margin) where that is not positive or does not
    /// fit either (the planner's own search decides: the time-scaling is only a guess where
    /// another quantity than the binding one, or a range, limits too). The margin
    /// the plan keeps is left in [`ReplanOptions::limit_margin`], for the re-plans.
    pub fn first_plan(&mut self, model: &Arm, problem: &ChainProblem) -> Result<ArmPlanned, Error> {
        let request = ArmRequest::new(problem.clone());
        let plan = |options: &Self| plan_arm(&options.planning_model(model, problem), Method::Optimal, &request);
        let (shortest, quantity) = match plan(self) {
            Err(Error::HorizonTooShort { shortest, quantity, .. }) if self.limit_margin > 0.0 => (shortest, quantity),
            other => return other,
        };
        let squared = matches!(quantity, "acceleration" | "torque");
        let ratio = (shortest / problem.horizon).max(1.0).powi(if squared { 2 } else { 1 });
        let fits = 1.0 - (1.0 - self.limit_margin) * ratio;
        if fits > 0.0 {
            self.limit_margin = fits;
            match plan(self) {
                Err(Error::HorizonTooShort { .. }) => {}
                other => return other,
            }
        }
        self.limit_margin = 0.0;
        plan(self)
    }

    /// [`ReplanOptions::planning_model`] with the clearance margin `margin` \[m\] and the limit
    /// margin `limit_margin`.
    fn model_for(model: &Arm, margin: f64, limit_margin: f64, problem: &ChainProblem) -> Arm {
        let mut arm = model.clone();
        if !arm.geometry.is_empty() {
            arm.geometry.clearance += margin;
        }
        let ends = [problem.start.as_slice(), problem.goal.as_slice()];
        arm.limits = model.limits.with_headroom(limit_margin, &ends, &problem.initial_velocity);
        arm
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
    /// The clearance reserve of the last accepted re-plan \[m\]
    /// ([`crate::planners::chain::ChainStats::clearance_reserve`]).
    reserve: f64,
}

impl Replanner {
    /// Re-plans toward `goal` (`n + 1` angles), taken literally (the end of the first plan).
    pub fn new(goal: Vec<f64>, options: ReplanOptions) -> Self {
        Self { goal, options, planner: None, reserve: 0.0 }
    }

    /// A plan on `model` from the measured state at time `t` to the goal at `horizon` \[s\],
    /// warm-started by the rest of `current`, the reference being followed (no search where
    /// that start does not converge, but at the ladder's last step on an arm with shapes or
    /// without limits, see below): `None` when the planner fails, its
    /// plan is not accepted (see [`ReplanOptions::accept`]) or its certificate finds it closer
    /// than the model's clearance to a body or an obstacle. The plan keeps the limit margin
    /// ([`ReplanOptions::limit_margin`]) except where the measured state is already beyond it
    /// (widened to it), or where no plan keeps it: then half of it, then none (the limits
    /// themselves). Every re-plan starts with the whole margin: starting where the last one
    /// ended (at none, soon) left the 3-link example at its velocity limit riding the limit, and
    /// 4 of 4 trials broke it (3 of 4 succeeded starting with the whole margin). On a robot
    /// without limits the ladder is one step, and the search follows a warm start that fails:
    /// near a plan whose base angle is costly to move (a large holonomy multiplier, e.g. a joint
    /// spinning whole turns) the measured drift of 0.2 s can be more than the warm start's SQP
    /// corrects in its iterations (hard set problem 10 with the spin goals: 259 failed re-plans
    /// in 10 trials without the search, 2 with it).
    pub fn replan(
        &mut self,
        model: &Arm,
        measured: &State,
        t: f64,
        horizon: f64,
        current: &Reference,
    ) -> Option<ChainPlan> {
        // Without limits the margins of the ladder are one and the same problem: one step.
        let full = if model.limits.is_empty() { 0.0 } else { self.options.limit_margin };
        let ladder = [full, 0.5 * full, 0.0];
        let last = if full > 0.0 { ladder.len() - 1 } else { 0 };
        for (step, margin) in ladder[..=last].iter().enumerate() {
            let search = step == last && (!model.geometry.is_empty() || model.limits.is_empty());
            if let Ok(plan) = self.replan_inside(model, measured, t, horizon, current, (*margin, search)) {
                return plan;
            }
        }
        None
    }

    /// [`Replanner::replan`] keeping `limit_margin` inside the limits: `Err` where the planner
    /// fails (the next step of the ladder follows), `Ok(None)` where its plan is refused. With
    /// `search` the planner's search follows a warm start that fails (the ladder's last step on
    /// an arm with shapes: the SPART-like arm's re-plans from its first plan found their plans
    /// so, in 8 to 47 s; on an arm without limits), else [`ChainOptions::warm_start_only`] holds.
    fn replan_inside(
        &mut self,
        model: &Arm,
        measured: &State,
        t: f64,
        horizon: f64,
        current: &Reference,
        (limit_margin, search): (f64, bool),
    ) -> Result<Option<ChainPlan>, ()> {
        let problem = ChainProblem {
            start: measured.q.clone(),
            goal: self.goal.clone(),
            horizon: horizon - t,
            initial_velocity: measured.dq[1..].to_vec(),
            wrap: false,
        };
        // The margin beyond the clearance, half of what is left where the measured state is
        // already inside it (the rows near `t = 0` could not hold the full margin).
        let geometry = &model.geometry;
        let margin = match geometry.min_clearance(model, &measured.q) {
            Some(d) => self.options.margin.min(0.5 * (d.distance - geometry.clearance)).max(0.0),
            None => 0.0,
        };
        // The limits less their margin, widened where the measured state is already beyond it.
        let widened;
        let model = if geometry.is_empty() && model.limits.is_empty() {
            model
        } else {
            widened = ReplanOptions::model_for(model, margin, limit_margin, &problem);
            &widened
        };
        if self.planner.as_ref().is_none_or(|p| p.arm() != model) {
            self.planner = Some(ChainPlanner::new(model.clone(), self.options.planner.clone()));
        }
        let Some(planner) = self.planner.as_mut() else { return Ok(None) };
        let knots = Self::knots_for(current, t, horizon);
        let times: Vec<f64> = match &knots {
            // Cubic Hermite samples at every breakpoint and midpoint reproduce the rest of a
            // spline of those knots exactly.
            Some(b) => b.windows(2).flat_map(|w| [w[0], 0.5 * (w[0] + w[1])]).chain(b.last().copied()).collect(),
            None => {
                let spans = Self::spans_for(current, t, horizon, self.options.planner.coarse_spans);
                (0..=4 * spans).map(|i| (horizon - t) * i as f64 / (4 * spans) as f64).collect()
            }
        };
        let spans = knots.as_ref().map_or((times.len() - 1) / 4, |b| b.len() - 1);
        (planner.options.coarse_spans, planner.options.max_spans) = (spans, spans);
        planner.options.knots = knots;
        planner.options.warm_start = Self::rest_of(current, t, &times);
        planner.options.warm_start_only = self.options.planner.warm_start_only && !search;
        // The rows keep what the last re-plan's certificate needed beyond them (at most the
        // margin), so that this one does not dip under the clearance between them and solve again.
        planner.options.clearance_reserve = self.reserve.min(margin);
        // The margin not kept at the start won back over the next re-plan periods: a re-plan
        // that kept half of what was left for the whole of its horizon eroded the margin re-plan
        // by re-plan (the SPART-like arm with 5 % perturbation: 3 of 10 trials touched).
        let extra = if geometry.is_empty() { 0.0 } else { self.options.margin - margin };
        planner.options.clearance_rise = ClearanceRise { extra, over: RISE_PERIODS / self.options.rate };
        let Ok(plan) = planner.plan(&problem) else { return Err(()) };
        // A plan whose verified motion comes closer than the model's clearance is refused (issue
        // 21): the last plan stays, as for any refused re-plan.
        if plan.verification.collision().is_err() {
            return Ok(None);
        }
        let e = plan.verification.final_error;
        let accepted = e.is_finite() && e <= self.options.accept;
        if accepted {
            self.reserve = plan.stats.clearance_reserve;
        }
        Ok(accepted.then_some(plan))
    }

    /// The spans of a re-plan's basis from `t` to `horizon`: enough for the rest of `current` to
    /// be a warm start, one per radian of the largest joint travel left (a joint loop takes six,
    /// as the planner's own bases give them), at least `least` and at most [`MAX_REPLAN_SPANS`].
    /// On a coarser basis the projection of a reference of many loops misses the goal's base
    /// angle by up to a radian, and each re-plan falls back to the planner's full search.
    fn spans_for(current: &Reference, t: f64, horizon: f64, least: usize) -> usize {
        const SAMPLES: usize = 400;
        let mut travel: Vec<f64> = Vec::new();
        let mut last: Option<Vec<f64>> = None;
        for i in 0..=SAMPLES {
            let Ok(p) = current.joints_at(t + (horizon - t) * i as f64 / SAMPLES as f64) else { return least };
            if let Some(last) = &last {
                travel.resize(p.theta.len(), 0.0);
                for ((d, a), b) in travel.iter_mut().zip(&p.theta).zip(last) {
                    *d += (a - b).abs();
                }
            }
            last = Some(p.theta);
        }
        let most = travel.iter().fold(0.0_f64, |m, d| m.max(*d));
        (most.ceil() as usize).clamp(least, MAX_REPLAN_SPANS.max(least))
    }

    /// The breakpoints of a re-plan's basis from `t` to `horizon` (its own time from 0), where
    /// `current` is a spline: its breakpoints after `t`, the first dropped when it is nearer to
    /// `t` than half its span (a thin first span conditions the solve badly), those of a thin
    /// last layer dropped; the last span's two halves where only it is left. `None` where
    /// `current` is no spline.
    fn knots_for(current: &Reference, t: f64, horizon: f64) -> Option<Vec<f64>> {
        let (motion, t0) = current.motion();
        let b = motion.breakpoints()?;
        if ((t0 + motion.horizon()) - horizon).abs() > 1e-9 * horizon {
            return None;
        }
        let mut knots = vec![0.0];
        for w in b.windows(2) {
            let (start, end) = (t0 + w[0], t0 + w[1]);
            if end > t && end < horizon && (knots.len() > 1 || end - t >= 0.5 * (end - start)) {
                knots.push(end - t);
            }
        }
        // No thin last span: the minimum-effort plan brakes within its last span (the optimum of
        // the effort has impulsive ends), and the torque of a stop in a thin layer, times the
        // actuators' relative noise, is the final error of the run.
        let mut widths: Vec<f64> = b.windows(2).map(|w| w[1] - w[0]).collect();
        widths.sort_by(f64::total_cmp);
        let typical = widths[widths.len() / 2];
        while knots.len() > 1 && (horizon - t) - knots[knots.len() - 1] < 0.75 * typical {
            knots.pop();
        }
        // The last span alone left (the final correction): its two halves.
        if knots.len() == 1 {
            knots.push(0.5 * (horizon - t));
        }
        knots.push(horizon - t);
        Some(knots)
    }

    /// The joint path of `current` from `t` at the times `times` from 0 (increasing), with its
    /// own time starting at 0; `None` if it cannot be evaluated.
    fn rest_of(current: &Reference, t: f64, times: &[f64]) -> Option<WarmStart> {
        let n = times.len();
        let mut path =
            WarmStart { t: Vec::with_capacity(n), theta: Vec::with_capacity(n), rate: Vec::with_capacity(n) };
        for &s in times {
            let p = current.joints_at(t + s).ok()?;
            path.t.push(s);
            path.theta.push(p.theta);
            path.rate.push(p.rate);
        }
        Some(path)
    }
}
