//! Monte Carlo runs: many seeded true robots and noise sequences, each tracked by every
//! controller asked for, in parallel; success rates by controller.
//!
//! Trial `i` depends only on the options and `i` ([`trial_seed`]), so a run can be cut into
//! shards ([`Shard`]: the trials `i` with `i mod n = k - 1`) run anywhere, written to checked
//! files ([`super::trials_file`]) and merged into exactly the unsharded run's trials; the summary
//! of either is [`summarise`]'s.

use rayon::prelude::*;
use serde::Serialize;

use super::control::Controller;
use super::motion::ArmMotion;
use super::noise::Noise;
use super::perturb::Perturbation;
use super::run::{TrackOptions, check_run, hold_correction, track_with};
use crate::analysis::shards::Shard;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::plan::clearance::ClearanceReport;
use crate::planners::chain::ChainProblem;

/// Most trials of one run: each keeps its result (about 50 bytes per controller), and at about
/// a second each a million trials take days on a workstation.
pub const MAX_TRIALS: usize = 1_000_000;

/// Most control ticks of one Monte Carlo run or shard (trials x controllers x ticks per run):
/// the default run at [`MAX_TRIALS`] has 1e10 (days on a workstation); docs/spec.md §3.
pub const MAX_MONTE_CARLO_TICKS: f64 = 1e11;

/// Options of a Monte Carlo run.
#[derive(Debug, Clone, PartialEq)]
pub struct MonteCarloOptions {
    /// Number of trials; 1 to [`MAX_TRIALS`].
    pub trials: usize,
    /// Seed of the trials: trial `i` draws its robot and noise from [`trial_seed`]`(seed, i)`.
    pub seed: u64,
    /// The true arm of every trial (of the model's joint count): `None` draws one per trial by
    /// [`MonteCarloOptions::perturbation`].
    pub truth: Option<Arm>,
    /// The model error drawn per trial when `truth` is `None`.
    pub perturbation: Perturbation,
    /// The controllers run on each trial (on the same robot and noise).
    pub controllers: Vec<Controller>,
    /// A trial succeeds when its final error is at most this \[rad\]; default 1e-3.
    pub success_tolerance: f64,
    /// The part of the trials to run; default [`Shard::ALL`].
    pub shard: Shard,
}

impl Default for MonteCarloOptions {
    fn default() -> Self {
        Self {
            trials: 100,
            seed: 0,
            truth: None,
            perturbation: Perturbation::default(),
            controllers: vec![Controller::Adaptive],
            success_tolerance: 1e-3,
            shard: Shard::ALL,
        }
    }
}

/// The seed of trial `trial` of a run seeded `seed`.
pub fn trial_seed(seed: u64, trial: u64) -> u64 {
    let mut n = Noise::new(seed, u64::MAX - trial);
    (n.uniform() * (1u64 << 53) as f64) as u64
}

/// One controller on one trial.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Trial {
    /// Trial number, from 0.
    pub trial: usize,
    /// The controller.
    pub controller: Controller,
    /// Final error \[rad\] (infinite if the run failed).
    pub final_error: f64,
    /// Why the run failed ([`crate::track::Failure::reason`]: `diverged`, a declared limit its
    /// motion broke, `position_limit`, `base_limit`, `velocity_limit`, or `collision`); `None`
    /// if it did not.
    pub failure: Option<&'static str>,
    /// Re-plans used.
    pub replans: usize,
    /// Re-plans failed.
    pub replan_failures: usize,
    /// The least clearance of the true motion, when the model has shapes
    /// ([`crate::track::Tracked::clearance`]).
    pub clearance: Option<ClearanceReport>,
}

/// Success rate and error quantiles of one controller.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Summary {
    /// The controller.
    pub controller: Controller,
    /// Trials run.
    pub trials: usize,
    /// Trials with final error within the tolerance.
    pub successes: usize,
    /// `successes / trials`.
    pub success_rate: f64,
    /// Trials whose run failed (diverged, or broke a declared limit): their final error
    /// counts as infinite in the quantiles.
    pub failed: usize,
    /// Of the failed trials, those whose motion broke a declared limit of the arm (a position,
    /// base or velocity limit, [`crate::model::arm::Limits`]).
    pub limit_failures: usize,
    /// Of the failed trials, those whose true motion came closer than the clearance asked for
    /// (`collision`, [`crate::track::Tracked::clearance`]).
    pub collision_failures: usize,
    /// The least clearance over the trials \[m\], when the model has shapes.
    pub min_clearance: Option<f64>,
    /// Median final error \[rad\]; `None` without trials, or when it falls on a failed trial
    /// (never a non-finite number).
    pub median_error: Option<f64>,
    /// 95th percentile of the final error \[rad\]; `None` as for the median.
    pub p95_error: Option<f64>,
    /// Largest final error \[rad\]; `None` as for the median.
    pub max_error: Option<f64>,
    /// Re-plans that failed, over all trials.
    pub replan_failures: usize,
}

/// Runs the trials of `mc.shard` in parallel (rayon), calling `progress` after each; returns
/// their results (trial-major, controllers in `mc.controllers`' order) and their summary by
/// controller ([`summarise`]). Results are deterministic: no wall time is kept.
pub fn monte_carlo(
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    options: &TrackOptions,
    mc: &MonteCarloOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<(Vec<Trial>, Vec<Summary>), Error> {
    if mc.trials == 0 || mc.controllers.is_empty() {
        return Err(InputError::InvalidParameter {
            name: "trials".into(),
            value: mc.trials as f64,
            expected: "at least one trial of at least one controller",
        }
        .into());
    }
    if mc.trials > MAX_TRIALS {
        return Err(InputError::InvalidParameter {
            name: "trials".into(),
            value: mc.trials as f64,
            expected: "at most 1e6 trials per run (each one keeps its result)",
        }
        .into());
    }
    mc.perturbation.validate()?;
    options.validate()?;
    check_run(model, problem, plan, options)?;
    for &controller in &mc.controllers {
        TrackOptions { controller, record: false, ..options.clone() }.check_budget(problem.horizon)?;
    }
    let runs = mc.shard.indices(mc.trials).count() as f64 * mc.controllers.len() as f64;
    let ticks = runs * options.ticks(problem.horizon);
    if ticks > MAX_MONTE_CARLO_TICKS {
        return Err(InputError::TooMuchWork {
            what: format!("{runs} runs of {} s at {} Hz", problem.horizon, options.rate),
            work: ticks,
            limit: MAX_MONTE_CARLO_TICKS,
            unit: "control ticks",
            hint: "fewer trials or controllers, shards, a shorter --time or a lower --rate".into(),
        }
        .into());
    }
    let correction = if mc.controllers.iter().all(|&c| c == Controller::Open) {
        None
    } else {
        hold_correction(model, problem, plan, options)?
    };
    let indices: Vec<usize> = mc.shard.indices(mc.trials).collect();
    let per_trial: Vec<Vec<Trial>> = indices
        .into_par_iter()
        .map(|i| {
            let seed = trial_seed(mc.seed, i as u64);
            let truth = match &mc.truth {
                Some(r) => r.clone(),
                None => mc.perturbation.apply(model, seed)?,
            };
            let trials = mc
                .controllers
                .iter()
                .map(|&controller| {
                    let o = TrackOptions { controller, record: false, ..options.clone() };
                    let r = track_with(model, problem, plan, correction.as_ref(), &truth, &o, seed)?;
                    Ok(Trial {
                        trial: i,
                        controller,
                        final_error: r.final_error,
                        failure: r.failure.map(|f| f.reason),
                        replans: r.replans,
                        replan_failures: r.replan_failures,
                        clearance: r.clearance,
                    })
                })
                .collect::<Result<Vec<_>, Error>>();
            progress();
            trials
        })
        .collect::<Result<_, Error>>()?;
    let trials: Vec<Trial> = per_trial.into_iter().flatten().collect();
    let summaries = summarise(&mc.controllers, &trials, mc.success_tolerance);
    Ok((trials, summaries))
}

/// The summary of each of `controllers` over its `trials`: success (final error at most
/// `tolerance` \[rad\]), the median, 95th percentile (nearest rank) and largest final error
/// (a diverged run counts as infinite), and the failed re-plans.
pub fn summarise(controllers: &[Controller], trials: &[Trial], tolerance: f64) -> Vec<Summary> {
    controllers.iter().map(|&c| summary(c, trials, tolerance)).collect()
}

fn summary(controller: Controller, trials: &[Trial], tolerance: f64) -> Summary {
    let mine: Vec<&Trial> = trials.iter().filter(|t| t.controller == controller).collect();
    let mut errors: Vec<f64> =
        mine.iter().map(|t| if t.final_error.is_nan() { f64::INFINITY } else { t.final_error }).collect();
    errors.sort_by(f64::total_cmp);
    let n = errors.len();
    let finite = |e: Option<&f64>| e.copied().filter(|e| e.is_finite());
    let quantile = |p: f64| finite(errors.get(((n as f64 - 1.0).max(0.0) * p).round() as usize));
    let successes = errors.iter().filter(|&&e| e <= tolerance).count();
    Summary {
        controller,
        trials: n,
        successes,
        success_rate: successes as f64 / n.max(1) as f64,
        failed: errors.iter().filter(|e| !e.is_finite()).count(),
        limit_failures: mine.iter().filter(|t| t.failure.is_some_and(|f| f.ends_with("_limit"))).count(),
        collision_failures: mine.iter().filter(|t| t.failure == Some("collision")).count(),
        min_clearance: mine.iter().filter_map(|t| t.clearance.map(|c| c.min)).reduce(f64::min),
        median_error: quantile(0.5),
        p95_error: quantile(0.95),
        max_error: finite(errors.last()),
        replan_failures: mine.iter().map(|t| t.replan_failures).sum(),
    }
}
