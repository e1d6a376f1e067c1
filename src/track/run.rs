//! One closed-loop run: the plant driven by a controller at a fixed rate with zero-order hold,
//! from the start of a plan to its horizon, for an arm of any number of joints.

use std::time::Instant;

use serde::Serialize;

use super::control::{Controller, Gains, computed_torque, feedforward};
use super::energy::EnergyBalance;
use super::hold::HoldCorrection;
use super::identify::{
    Constants, Identifier, IdentifyOptions, fit_arm, momentum_map_error, parameter_names, parameters,
};
use super::motion::ArmMotion;
use super::plant::{Disturbances, Plant};
use super::replan::{Reference, ReplanOptions, Replanner};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::{InputError, wrap_angle};
use crate::plan::clearance::{ClearanceMonitor, ClearanceReport};
use crate::planners::chain::ChainProblem;

/// Options of a closed-loop run.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackOptions {
    /// The controller; default [`Controller::Adaptive`].
    pub controller: Controller,
    /// Control rate \[Hz\]: the measurement is read and the torque set this often, and held
    /// in between (zero-order hold); default 1000. From 1 to 1e6.
    pub rate: f64,
    /// Runge–Kutta steps of the plant per control tick; default 1.
    pub substeps: usize,
    /// Joint-loop gains; default `None`, [`Gains::for_rate`] at [`TrackOptions::rate`]
    /// ([`TrackOptions::gains`]).
    pub gains: Option<Gains>,
    /// Re-planning (for `replan` and `adaptive`).
    pub replan: ReplanOptions,
    /// Identification (for `adaptive`).
    pub identify: IdentifyOptions,
    /// Actuator and sensor imperfections.
    pub disturbances: Disturbances,
    /// Keep the reference and the actual motion at every tick ([`Tracked::history`]); default
    /// false.
    pub record: bool,
    /// Correct the joint loop's feedforward for the zero-order hold on the nominal model
    /// ([`HoldCorrection`]); default true. Not used by `open`.
    pub hold_correction: bool,
}

impl Default for TrackOptions {
    fn default() -> Self {
        Self {
            controller: Controller::default(),
            rate: 1000.0,
            substeps: 1,
            gains: None,
            replan: ReplanOptions::default(),
            identify: IdentifyOptions::default(),
            disturbances: Disturbances::default(),
            record: false,
            hold_correction: true,
        }
    }
}

impl TrackOptions {
    /// Checks every option.
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.rate >= 1.0 && self.rate <= 1e6) {
            return Err(InputError::InvalidParameter {
                name: "rate".into(),
                value: self.rate,
                expected: "a control rate from 1 to 1e6 Hz",
            }
            .into());
        }
        if !(1..=1000).contains(&self.substeps) {
            return Err(InputError::InvalidParameter {
                name: "substeps".into(),
                value: self.substeps as f64,
                expected: "1 to 1000 integration steps per tick",
            }
            .into());
        }
        let gains = self.gains();
        gains.validate()?;
        if self.controller != Controller::Open {
            gains.validate_sampled(self.rate)?;
        }
        self.replan.validate(self.rate)?;
        self.identify.validate()?;
        self.disturbances.validate()
    }
}

/// Most control ticks of one run (`T * rate`): about a quarter of an hour of one thread at
/// about 10 µs a tick (docs/spec.md §3, "Budgets").
pub const MAX_TICKS: f64 = 1e8;

/// Most re-plans of one run (`T * replan rate`, checked before the run): each is bounded by
/// the re-planner's iteration and integration limits ([`ReplanOptions::planner`]), so a run's
/// re-planning is too. The default run has 500.
pub const MAX_REPLANS: f64 = 10_000.0;

/// Memory of one recorded tick ([`TrackOptions::record`]) with its CSV row and plot points
/// \[bytes\] (generous): a recorded run keeps at most `MEMORY_LIMIT / BYTES_PER_TICK` ticks.
pub const BYTES_PER_TICK: u128 = 512;

impl TrackOptions {
    /// The joint loop's gains: the given ones, or the default at the control rate
    /// ([`Gains::for_rate`]).
    pub fn gains(&self) -> Gains {
        self.gains.unwrap_or_else(|| Gains::for_rate(self.rate))
    }

    /// The number of control ticks of a run of `horizon` \[s\]: `T * rate` rounded, at least 1.
    pub fn ticks(&self, horizon: f64) -> f64 {
        (horizon * self.rate).round().max(1.0)
    }

    /// Checks a run of `horizon` \[s\] against the budgets before it starts: at most
    /// [`MAX_TICKS`] ticks, at most [`MAX_REPLANS`] re-plans (re-planning controllers), and when recorded, their memory ([`BYTES_PER_TICK`] each) within
    /// [`crate::plan::limits::MEMORY_LIMIT`]. Errors carry the estimate.
    pub fn check_budget(&self, horizon: f64) -> Result<(), Error> {
        let ticks = self.ticks(horizon);
        if !(ticks <= MAX_TICKS) {
            return Err(InputError::TooMuchWork {
                what: format!("a run of {horizon} s at a control rate of {} Hz", self.rate),
                work: ticks,
                limit: MAX_TICKS,
                unit: "control ticks",
                hint: "a shorter --time or a lower --rate".into(),
            }
            .into());
        }
        let replans = (horizon * self.replan.rate).floor();
        if self.controller.replans() && replans > MAX_REPLANS {
            return Err(InputError::TooMuchWork {
                what: format!("a run of {horizon} s re-planning at {} Hz", self.replan.rate),
                work: replans,
                limit: MAX_REPLANS,
                unit: "re-plans",
                hint: "a lower --replan-rate or a shorter --time".into(),
            }
            .into());
        }
        if self.record {
            let limit = crate::plan::limits::MEMORY_LIMIT;
            crate::plan::limits::check_memory(
                &format!("recording {ticks} control ticks (--out/--plot of one run)"),
                ticks as u128 * BYTES_PER_TICK,
                &format!("at most {} recorded ticks: a lower --rate or a shorter --time", limit / BYTES_PER_TICK),
            )?;
        }
        Ok(())
    }
}

/// Why a closed-loop run stopped before its horizon: a verdict with a reason, not a number.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Failure {
    /// `diverged`: the simulated motion left the finite numbers; `position_limit`,
    /// `base_limit`, `velocity_limit`: the true motion broke the arm's declared limit
    /// ([`crate::model::arm::Limits`], checked after every integrator step); `collision`: the
    /// true motion came closer than the clearance asked for ([`Tracked::clearance`]).
    pub reason: &'static str,
    /// When it happened \[s\] (for a collision, the time of the least clearance so far).
    pub t: f64,
}

/// The motion of a run, tick by tick (when [`TrackOptions::record`] is set).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct History {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// The reference `q = (phi, theta)` followed at each time (the current plan) \[rad\].
    pub reference: Vec<Vec<f64>>,
    /// The true `q` \[rad\].
    pub actual: Vec<Vec<f64>>,
    /// The torque applied over the tick that starts there, one per joint [N m].
    pub tau: Vec<Vec<f64>>,
}

/// The identified model against the true robot, at the end of an `adaptive` run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    /// The names of the parameters ([`parameter_names`]).
    pub names: Vec<String>,
    /// The inertial parameters of the true arm ([`parameters`]) [kg m^2].
    pub truth: Constants,
    /// The same parameters of the identified model.
    pub identified: Constants,
    /// The same parameters of the nominal model.
    pub nominal: Constants,
    /// [`momentum_map_error`] of the nominal model against the truth.
    pub nominal_map_error: f64,
    /// [`momentum_map_error`] of the identified model against the truth.
    pub identified_map_error: f64,
}

/// What the hold correction did ([`HoldCorrection`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HoldSummary {
    /// Final error of the nominal loop without the correction \[rad\].
    pub error_before: f64,
    /// Final error of the nominal loop with it \[rad\].
    pub error_after: f64,
    /// Largest added joint acceleration [rad/s^2].
    pub peak_acceleration: f64,
}

impl From<&HoldCorrection> for HoldSummary {
    fn from(c: &HoldCorrection) -> Self {
        Self { error_before: c.error_before, error_after: c.error_after, peak_acceleration: c.peak_acceleration }
    }
}

/// The hold correction that runs of `plan` with `options` use (any controller but `open`):
/// `None` when switched off or when it does not reduce the nominal loop's error.
pub fn hold_correction(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    options: &TrackOptions,
) -> Result<Option<HoldCorrection>, Error> {
    options.validate()?;
    check_run(model, problem, plan, options)?;
    if !options.hold_correction {
        return Ok(None);
    }
    HoldCorrection::new(model, problem, plan, options.rate, options.substeps, options.gains())
}

/// Checks a run's pieces against each other: the problem against the model
/// ([`ChainProblem::validate`]), the plan's joint count and horizon, the torque bias's length.
pub fn check_run(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    options: &TrackOptions,
) -> Result<(), Error> {
    model.validate()?;
    problem.validate(model)?;
    let n = model.joints();
    if plan.joints() != n || (plan.horizon() - problem.horizon).abs() > 1e-9 * problem.horizon {
        return Err(InputError::InvalidParameter {
            name: "plan".into(),
            value: plan.joints() as f64,
            expected: "a plan of the model's joint count and the problem's horizon",
        }
        .into());
    }
    options.disturbances.check_joints(n)
}

/// The result of a closed-loop run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tracked {
    /// The controller.
    pub controller: Controller,
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\]; infinite when the run failed ([`Tracked::failure`]):
    /// JSON writes it as `null`, the table and the plot the failure.
    pub final_error: f64,
    /// `wrap(q_i(T) - qd_i)` per coordinate `(phi, theta_1, .., theta_n)` \[rad\].
    pub final_errors: Vec<f64>,
    /// `q'(T)` [rad/s].
    pub final_velocity: Vec<f64>,
    /// `max |tau_k|` applied per joint [N m].
    pub peak_torque: Vec<f64>,
    /// Fraction of the ticks whose command exceeded the torque limit.
    pub saturated_fraction: f64,
    /// Re-plans used.
    pub replans: usize,
    /// Re-plans that failed or were not accepted (the last plan stayed).
    pub replan_failures: usize,
    /// Wall time of all re-plans, identification fits included \[s\].
    pub replan_seconds: f64,
    /// Wall time of the slowest re-plan \[s\].
    pub replan_max_seconds: f64,
    /// Wall time of the run \[s\].
    pub seconds: f64,
    /// Time at which the simulated motion diverged \[s\], if it did.
    pub diverged_at: Option<f64>,
    /// Why the run stopped before its horizon, if it did (a diverged motion).
    pub failure: Option<Failure>,
    /// The identified model (`adaptive` only).
    pub identification: Option<Identification>,
    /// The hold correction of the first plan's feedforward, where the run used one.
    pub hold_correction: Option<HoldSummary>,
    /// The least clearance of the true motion (issue 21 item 6), when the model has shapes: the
    /// model's shapes, obstacles and clearance ([`Arm::geometry`]) on the true arm's motion, at
    /// every integrator step of the plant and between steps by the Hermite minimum of
    /// [`ClearanceMonitor`]. A run that comes closer than the clearance stops with the
    /// [`Failure`] `collision`; the report then is the least clearance up to there.
    pub clearance: Option<ClearanceReport>,
    /// The motion tick by tick, when recorded.
    #[serde(skip)]
    pub history: Option<History>,
}

/// Runs `plan` (planned for `problem` on the nominal arm `model`) on the true arm `truth` (of the
/// model's joint count) under the controller of `options`, from `problem.start` (moving at
/// `problem.initial_velocity`) to the horizon. `seed` keys the plant's noise. The run is checked
/// against the budgets first ([`TrackOptions::check_budget`]: its re-plans are bounded before it
/// starts). Re-planning failures are counted, never fatal; a diverging motion ends the run with a
/// [`Failure`] (and an infinite error).
pub fn track(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    truth: &Arm,
    options: &TrackOptions,
    seed: u64,
) -> Result<Tracked, Error> {
    let clock = Instant::now();
    let correction = match options.controller {
        Controller::Open => None,
        _ => hold_correction(model, problem, plan, options)?,
    };
    let mut run = track_with(model, problem, plan, correction.as_ref(), truth, options, seed)?;
    run.seconds = clock.elapsed().as_secs_f64();
    Ok(run)
}

/// [`track()`] with the hold correction computed beforehand ([`hold_correction`]; Monte Carlo
/// runs share one). `open` ignores it; its wall time is not part of [`Tracked::seconds`].
pub fn track_with(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    correction: Option<&HoldCorrection>,
    truth: &Arm,
    options: &TrackOptions,
    seed: u64,
) -> Result<Tracked, Error> {
    options.validate()?;
    check_run(model, problem, plan, options)?;
    truth.validate()?;
    let n = model.joints();
    if truth.joints() != n {
        return Err(InputError::InvalidParameter {
            name: "true robot".into(),
            value: truth.joints() as f64,
            expected: "a true robot of the model's number of links",
        }
        .into());
    }
    let clock = Instant::now();
    let correction = correction.filter(|_| options.controller != Controller::Open);
    let horizon = problem.horizon;
    options.check_budget(horizon)?;
    let ticks = options.ticks(horizon) as usize;
    let dt = horizon / ticks as f64;
    let gains = options.gains();
    let every = (options.rate / options.replan.rate).round().max(1.0) as usize;
    let last_correction = ((horizon - options.replan.final_window) / dt).round().max(0.0) as usize;
    let controller = options.controller;
    let mut replanner = Replanner::new(plan.q(horizon)?, options.replan.clone());
    let mut identifier = Identifier::new(model, options.identify);
    let mut energy = EnergyBalance::new(n, options.identify.forgetting_time);
    let mut fitted = model.clone();
    let mut reference = Reference::Initial(plan);
    let mut plant =
        Plant::new(truth, &problem.start, options.disturbances.clone(), seed).moving(&problem.initial_velocity);
    let mut history = options.record.then(History::default);
    let (mut peak, mut saturated, mut replans, mut failures) = (vec![0.0_f64; n], 0usize, 0usize, 0usize);
    let (mut replan_seconds, mut replan_max) = (0.0_f64, 0.0_f64);
    let mut diverged_at = None;
    let mut failure = None;
    let geometry = &model.geometry;
    let mut clearance = (!geometry.is_empty()).then(|| ClearanceMonitor::new(truth, geometry, geometry.clearance));
    if let Some(c) = clearance.as_mut() {
        let s = plant.state();
        c.observe(0.0, &s.q, &s.dq);
    }
    let distance = |a: &[f64], b: &[f64]| a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max(wrap_angle(x - y).abs()));
    for i in 0..ticks {
        let t = i as f64 * dt;
        let measured = plant.measure();
        if controller == Controller::Adaptive {
            identifier.update(&measured, dt);
        }
        // On the first plan, the nominal loop's own state is the one to be at.
        let initial = matches!(reference, Reference::Initial(_));
        // The re-plan rate's ticks until the final window, and the window's first tick: the
        // last correction starts `final_window` before the end, not up to a re-plan period
        // earlier (the base drifts on the model's error from the last correction on).
        let due = controller.replans()
            && i > 0
            && ((i % every == 0 && horizon - t >= options.replan.final_window - 0.5 * dt) || i == last_correction);
        let off = match correction.and_then(|c| c.nominal(i)).filter(|_| initial) {
            Some(s) if due => distance(&measured.q, &s.q),
            None if due => distance(&measured.q, &reference.q(t)?),
            _ => 0.0,
        };
        if due && off > options.replan.threshold {
            let started = Instant::now();
            // The momentum fixes the parameters up to a common factor, the joint torques' work
            // fixes the factor ([`super::energy`]): the computed torque needs both.
            if controller == Controller::Adaptive {
                let estimate = identifier.estimate();
                let factor = energy.factor(&estimate);
                let target: Vec<f64> = estimate.iter().map(|x| x * factor).collect();
                if let Ok((arm, _)) = fit_arm(&target, &fitted) {
                    fitted = arm;
                }
            }
            match replanner.replan(&fitted, &measured, t, horizon, &reference) {
                Some(motion) => {
                    reference = Reference::Replanned { motion: Box::new(motion), t0: t };
                    replans += 1;
                }
                None => failures += 1,
            }
            let s = started.elapsed().as_secs_f64();
            (replan_seconds, replan_max) = (replan_seconds + s, replan_max.max(s));
        }
        // The law is evaluated at the centre of the tick (see `computed_torque`).
        let mut centre = reference.joints_at(t + 0.5 * dt)?;
        if let Some(c) = correction.filter(|_| matches!(reference, Reference::Initial(_))) {
            centre = c.corrected(centre, t + 0.5 * dt);
        }
        let command = match controller {
            Controller::Open => feedforward(&fitted, &centre),
            _ => computed_torque(&fitted, &measured, &centre, 0.5 * dt, &gains),
        };
        if controller == Controller::Adaptive {
            // The torque as the actuators take it: clamped at the limits the controller knows.
            let limit =
                |j: usize| model.limits.joint(j).torque.unwrap_or(f64::INFINITY).min(options.disturbances.torque_limit);
            let held: Vec<f64> = command.iter().enumerate().map(|(j, t)| t.clamp(-limit(j), limit(j))).collect();
            energy.update(&measured, &held, dt);
        }
        let before = history.is_some().then(|| plant.state().q);
        let applied = plant.step_observed(&command, dt, options.substeps, t, &mut |s, q, dq| {
            if let Some(c) = clearance.as_mut() {
                c.observe(s, q, dq);
            }
        });
        let applied_broken = applied.broken;
        // A command that left the finite numbers is the divergence below, not a torque.
        let finite = applied.tau.iter().all(|x| x.is_finite());
        if finite {
            for (p, t) in peak.iter_mut().zip(&applied.tau) {
                *p = p.max(t.abs());
            }
        }
        saturated += usize::from(applied.saturated);
        if let (Some(h), Some(before)) = (history.as_mut().filter(|_| finite), before) {
            h.t.push(t);
            h.reference.push(reference.q(t)?);
            h.actual.push(before);
            h.tau.push(applied.tau);
        }
        if !finite || !plant.is_finite() {
            diverged_at = Some(t + dt);
            failure = Some(Failure { reason: "diverged", t: t + dt });
            break;
        }
        if let Some(reason) = applied_broken {
            failure = Some(Failure { reason, t: t + dt });
            break;
        }
        if let Some(c) = clearance.as_ref().and_then(ClearanceMonitor::least).filter(|c| !c.holds()) {
            failure = Some(Failure { reason: "collision", t: c.time });
            break;
        }
    }
    let end = plant.state();
    let final_errors: Vec<f64> = if failure.is_some() {
        vec![f64::INFINITY; n + 1]
    } else {
        end.q.iter().zip(&problem.goal).map(|(q, g)| wrap_angle(q - g)).collect()
    };
    // The last recorded row is the end state: only a finite one (a diverged run's is not).
    if let Some(h) = history.as_mut().filter(|_| failure.is_none()) {
        h.t.push(horizon);
        h.reference.push(reference.q(horizon)?);
        h.actual.push(end.q.clone());
        let last = h.tau.last().cloned().unwrap_or_else(|| vec![0.0; n]);
        h.tau.push(last);
    }
    let identification = (controller == Controller::Adaptive).then(|| Identification {
        names: parameter_names(n),
        truth: parameters(truth),
        identified: parameters(&fitted),
        nominal: parameters(model),
        nominal_map_error: momentum_map_error(model, truth),
        identified_map_error: momentum_map_error(&fitted, truth),
    });
    let final_velocity = end.dq;
    Ok(Tracked {
        controller,
        final_error: final_errors.iter().fold(0.0_f64, |m, e| m.max(e.abs())),
        final_errors,
        final_velocity,
        peak_torque: peak,
        saturated_fraction: saturated as f64 / ticks as f64,
        replans,
        replan_failures: failures,
        replan_seconds,
        replan_max_seconds: replan_max,
        seconds: clock.elapsed().as_secs_f64(),
        diverged_at,
        failure,
        identification,
        hold_correction: correction.map(HoldSummary::from),
        clearance: clearance.and_then(ClearanceMonitor::finish),
        history,
    })
}
