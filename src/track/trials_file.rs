//! The file of a Monte Carlo run (`track --trials N --out FILE.csv`, one shard or the whole):
//! one row per trial and controller under two comment lines that identify the run and check the
//! rows (the format and its checks are [`crate::analysis::shards`]'s), so that `track merge`
//! can refuse whatever does not belong together and summarise exactly as the unsharded run.
//!
//! ```text
//! # freefloat-track-trials v2 run=<hash> shard=K/N rows=<count> checksum=<hash>
//! # run: trials=6 seed=0 controllers=open,ct success_tolerance=0.001 truth=perturbed:0.05,0.0 ...
//! trial,controller,final_error,diverged,replans,replan_failures,min_clearance,clearance_between,clearance_time,clearance_required,check
//! 0,open,0.0123...,false,0,0,,,,,<hash>
//! ```
//!
//! Every cell is deterministic (no wall time), so a shard run again is the same file, and the
//! merge of the shards equals the unsharded run's file byte for byte. A diverged run has
//! `diverged = true` and an empty `final_error`: no cell holds a non-finite number. A run whose
//! motion broke one of the arm's declared limits has the reason there instead
//! (`position_limit`, `base_limit`, `velocity_limit`) and an empty `final_error`, and so does a
//! run whose true motion came closer than the clearance (`collision`). The four `clearance`
//! cells give the trial's least clearance \[m\], its pair of bodies (`link 2/obstacle 1`), its
//! time \[s\] and the clearance asked for \[m\] when the model has shapes, and are empty
//! otherwise (v2; v1 files had no clearance cells).

use std::cell::OnceCell;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::control::Controller;
use super::monte_carlo::{MonteCarloOptions, Trial};
use super::run::TrackOptions;
use crate::analysis::shards::{self, FileKind, Shard, ShardFile, field, file_error, finite};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::collision::Body;
use crate::plan::clearance::ClearanceReport;
use crate::planners::chain::ChainProblem;

/// The first words of a trials file.
pub const MAGIC: &str = "# freefloat-track-trials v2";

/// The CSV columns: [`TrialRow`]'s fields, then the row's `check`.
pub const COLUMNS: [&str; 10] = [
    "trial",
    "controller",
    "final_error",
    "diverged",
    "replans",
    "replan_failures",
    "min_clearance",
    "clearance_between",
    "clearance_time",
    "clearance_required",
];

/// The trials file's kind: [`MAGIC`] and [`COLUMNS`].
pub const KIND: FileKind = FileKind { magic: MAGIC, name: "track trials", columns: &COLUMNS };

/// One controller on one trial, as a row of the file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrialRow {
    /// Trial number, from 0.
    pub trial: usize,
    /// The controller.
    pub controller: Controller,
    /// Final error \[rad\], full precision; `None` (an empty cell) when the motion diverged.
    pub final_error: Option<f64>,
    /// How the run ended: `false` (at its horizon), `true` (the motion diverged) or the declared
    /// limit its motion broke (`position_limit`, ...); its final error then is infinite.
    pub diverged: Ended,
    /// Re-plans used.
    pub replans: usize,
    /// Re-plans failed.
    pub replan_failures: usize,
    /// The least clearance of the true motion \[m\], when the model has shapes.
    pub min_clearance: Option<f64>,
    /// Its pair of bodies.
    pub clearance_between: Option<Pair>,
    /// Its time \[s\].
    pub clearance_time: Option<f64>,
    /// The clearance asked for \[m\].
    pub clearance_required: Option<f64>,
}

/// The pair of bodies of a least clearance, the cell `link 2/obstacle 1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pair(pub Body, pub Body);

impl Serialize for Pair {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{}/{}", self.0, self.1))
    }
}

impl<'de> Deserialize<'de> for Pair {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        let body = |t: &str| -> Option<Body> {
            let number = |rest: &str| rest.parse::<usize>().ok().filter(|&k| k >= 1);
            match t {
                "base" => Some(Body::Base),
                _ => t
                    .strip_prefix("link ")
                    .and_then(number)
                    .map(Body::Link)
                    .or_else(|| t.strip_prefix("obstacle ").and_then(number).map(Body::Obstacle)),
            }
        };
        text.split_once('/').and_then(|(a, b)| Some(Pair(body(a)?, body(b)?))).ok_or_else(|| {
            serde::de::Error::custom(format!("clearance_between = `{text}`: expected e.g. link 2/obstacle 1"))
        })
    }
}

/// How a trial ended, the `diverged` cell of its row: `false`, `true`, or the reason of a
/// failure other than divergence (a broken limit, [`crate::track::Failure::reason`]), so that
/// the rows of runs without limits are those of earlier versions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// The run reached its horizon (`false`).
    Horizon,
    /// The motion diverged (`true`).
    Diverged,
    /// The motion broke a declared limit, or collided: the failure's reason.
    Broke(&'static str),
}

/// The failure reasons a row may name besides `true`/`false`.
const FAILURE_REASONS: [&str; 4] = ["position_limit", "base_limit", "velocity_limit", "collision"];

impl Ended {
    /// The end of a trial that failed for `failure` (`None`: it did not, or it diverged when its
    /// error is infinite).
    fn of(t: &Trial) -> Self {
        match t.failure {
            Some(reason) if FAILURE_REASONS.contains(&reason) => Ended::Broke(reason),
            _ if t.final_error.is_finite() => Ended::Horizon,
            _ => Ended::Diverged,
        }
    }

    /// The cell's text.
    fn cell(self) -> &'static str {
        match self {
            Ended::Horizon => "false",
            Ended::Diverged => "true",
            Ended::Broke(reason) => reason,
        }
    }

    /// The failure reason for [`Trial::failure`].
    fn failure(self) -> Option<&'static str> {
        match self {
            Ended::Horizon => None,
            Ended::Diverged => Some("diverged"),
            Ended::Broke(reason) => Some(reason),
        }
    }
}

impl Serialize for Ended {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.cell())
    }
}

impl<'de> Deserialize<'de> for Ended {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        match text.as_str() {
            "false" => Ok(Ended::Horizon),
            "true" => Ok(Ended::Diverged),
            other => FAILURE_REASONS.iter().find(|r| **r == other).map(|r| Ended::Broke(r)).ok_or_else(|| {
                serde::de::Error::custom(format!(
                    "diverged = `{other}`: expected false, true, position_limit, base_limit, velocity_limit or collision"
                ))
            }),
        }
    }
}

impl From<&Trial> for TrialRow {
    fn from(t: &Trial) -> Self {
        let finite = t.final_error.is_finite();
        Self {
            trial: t.trial,
            controller: t.controller,
            final_error: finite.then_some(t.final_error),
            diverged: Ended::of(t),
            replans: t.replans,
            replan_failures: t.replan_failures,
            min_clearance: t.clearance.map(|c| c.min),
            clearance_between: t.clearance.map(|c| Pair(c.a, c.b)),
            clearance_time: t.clearance.map(|c| c.time),
            clearance_required: t.clearance.map(|c| c.required),
        }
    }
}

impl From<&TrialRow> for Trial {
    fn from(r: &TrialRow) -> Self {
        Self {
            trial: r.trial,
            controller: r.controller,
            final_error: r.final_error.unwrap_or(f64::INFINITY),
            failure: r.diverged.failure(),
            replans: r.replans,
            replan_failures: r.replan_failures,
            clearance: match (r.min_clearance, r.clearance_between, r.clearance_time, r.clearance_required) {
                (Some(min), Some(Pair(a, b)), Some(time), Some(required)) => {
                    Some(ClearanceReport { min, a, b, time, required })
                }
                _ => None,
            },
        }
    }
}

/// The arm in shortest round-trip floats: `M:..,I:..,a:..,b:..` then `/l:..,d:..,m:..,i:..` per
/// link, then `/limits:..` when it declares limits.
fn robot_description(r: &Arm) -> String {
    let mut out = format!("M:{:?},I:{:?},a:{:?},b:{:?}", r.base.mass, r.base.inertia, r.mount.a, r.mount.b);
    for l in &r.links {
        out += &format!("/l:{:?},d:{:?},m:{:?},i:{:?}", l.length, l.com, l.mass, l.inertia);
    }
    // Declared limits change the rows (a trial may break them); none leaves the words as before.
    if !r.limits.is_empty() {
        out += &format!("/limits:{:?}", r.limits).replace(' ', "");
    }
    // So do shapes and obstacles (the clearance cells, collisions).
    if !r.geometry.is_empty() {
        out += &format!("/geometry:{:?}", r.geometry).replace(' ', "");
    }
    out
}

/// Numbers in shortest round-trip form, comma-separated.
fn list(values: &[f64]) -> String {
    values.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(",")
}

/// The canonical description of a Monte Carlo run: `key=value` words of every option that
/// changes a row (the trials, the seed, the controllers, the success tolerance, the true robot
/// or its perturbation, the nominal arm (`links=n` and every parameter), the problem, the planner
/// of the first plan (named by `planner`), the control, re-planning and identification options
/// and the disturbances), floats in shortest round-trip form. The shard is not part of it.
pub fn run_description(
    model: &Arm,
    problem: &ChainProblem,
    options: &TrackOptions,
    mc: &MonteCarloOptions,
    planner: &str,
) -> String {
    let truth = match &mc.truth {
        Some(t) => format!("robot:{}", robot_description(t)),
        None => format!("perturbed:{:?},{:?}", mc.perturbation.relative, mc.perturbation.mount),
    };
    let controllers: Vec<&str> = mc.controllers.iter().map(|c| c.name()).collect();
    let d = &options.disturbances;
    let limit = if d.torque_limit.is_finite() { format!("{:?}", d.torque_limit) } else { "none".into() };
    let bias = if d.torque_bias.is_empty() { "none".into() } else { list(&d.torque_bias) };
    let (replan, identify) = (&options.replan, &options.identify);
    // The plans' margin beyond the clearance changes the plans only where there are shapes.
    let mut margin = if model.geometry.is_empty() { String::new() } else { format!(" margin={:?}", replan.margin) };
    // The headroom inside the limits changes them only where there are limits.
    if !model.limits.is_empty() {
        margin += &format!(" limit_margin={:?}", replan.limit_margin);
    }
    format!(
        "trials={} seed={} controllers={} success_tolerance={:?} truth={truth} links={} robot={} start={} goal={} \
         horizon={:?} start_velocity={} wrap={} planner={planner} rate={:?} substeps={} kp={:?} kd={:?} \
         hold_correction={} replan_rate={:?} final_window={:?} accept={:?} threshold={:?} forgetting={:?} \
         prior_weight={:?} torque_noise={:?} torque_bias={bias} torque_limit={limit} noise_q={:?} noise_dq={:?} \
         replan_planner={}",
        mc.trials,
        mc.seed,
        controllers.join(","),
        mc.success_tolerance,
        model.joints(),
        robot_description(model),
        list(&problem.start),
        list(&problem.goal),
        problem.horizon,
        list(&problem.initial_velocity),
        problem.wrap,
        options.rate,
        options.substeps,
        options.gains().kp,
        options.gains().kd,
        options.hold_correction,
        replan.rate,
        replan.final_window,
        replan.accept,
        replan.threshold,
        identify.forgetting_time,
        identify.prior_weight,
        d.torque_noise,
        d.q_noise,
        d.dq_noise,
        format!("{:?}", replan.planner).replace(' ', ""),
    ) + &margin
}

/// What a merge needs of a run's description: the number of trials, the seed, the controllers
/// (in order) and the success tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Trials of the whole run.
    pub trials: usize,
    /// The run's seed.
    pub seed: u64,
    /// The controllers, in the order of the run.
    pub controllers: Vec<Controller>,
    /// The success tolerance \[rad\].
    pub success_tolerance: f64,
}

impl RunSummary {
    /// Reads the `trials`, `seed`, `controllers` and `success_tolerance` words of a
    /// [`run_description`]; says which is missing or damaged.
    pub fn parse(run: &str) -> Result<Self, String> {
        let word = |key: &str| field(run, key).ok_or_else(|| format!("the `# run:` line has no {key}="));
        let bad = |key: &str| format!("the `# run:` line has a damaged {key}=");
        let trials = word("trials")?.parse().map_err(|_| bad("trials"))?;
        let seed = word("seed")?.parse().map_err(|_| bad("seed"))?;
        let controllers = word("controllers")?
            .split(',')
            .map(Controller::from_name)
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| bad("controllers"))?;
        let success_tolerance: f64 = word("success_tolerance")?.parse().map_err(|_| bad("success_tolerance"))?;
        if controllers.is_empty() || !success_tolerance.is_finite() {
            return Err(bad(if controllers.is_empty() { "controllers" } else { "success_tolerance" }));
        }
        Ok(Self { trials, seed, controllers, success_tolerance })
    }

    fn position(&self, controller: Controller) -> Option<usize> {
        self.controllers.iter().position(|&c| c == controller)
    }
}

/// The file of `shard` of the run `run` ([`run_description`]): one row per trial and
/// controller, in the order of [`super::monte_carlo()`]'s trials.
pub fn write(run: &str, shard: Shard, trials: &[Trial]) -> Result<Vec<u8>, Error> {
    let rows: Vec<TrialRow> = trials.iter().map(TrialRow::from).collect();
    shards::write(&KIND, run, shard, &rows)
}

/// Reads and checks one file: its header, every row's check, the row count and the checksum,
/// and every row: a trial of the run and of the shard, a controller of the run, a finite,
/// non-negative final error unless diverged (and then none). Errors name the file and the line.
pub fn read(bytes: &[u8], path: &Path) -> Result<ShardFile<TrialRow>, Error> {
    let summary: OnceCell<Result<RunSummary, String>> = OnceCell::new();
    shards::read(&KIND, bytes, path, |row: &TrialRow, run, shard| {
        let run = summary.get_or_init(|| RunSummary::parse(run)).as_ref().map_err(Clone::clone)?;
        check_row(row, run, shard)
    })
}

fn check_row(r: &TrialRow, run: &RunSummary, shard: Shard) -> Result<(), String> {
    let at = |what: String| format!("trial {} ({}): {what}", r.trial, r.controller.name());
    if r.trial >= run.trials || !shard.holds(r.trial) {
        return Err(at(format!("not a trial of shard {}/{} of {} trials", shard.k, shard.n, run.trials)));
    }
    if run.position(r.controller).is_none() {
        return Err(at("not a controller of the run".into()));
    }
    match (r.final_error, r.diverged == Ended::Horizon) {
        (Some(e), true) => {
            finite("final_error", e).map_err(at)?;
            if e < 0.0 {
                return Err(at(format!("final_error = {e} is negative")));
            }
        }
        (None, false) => {}
        _ => return Err(at("a final error is given exactly when the run did not fail".into())),
    }
    let cells = [r.min_clearance, r.clearance_time, r.clearance_required];
    match (cells, r.clearance_between) {
        ([Some(min), Some(time), Some(required)], Some(_)) => {
            finite("min_clearance", min).map_err(at)?;
            finite("clearance_time", time).map_err(at)?;
            finite("clearance_required", required).map_err(at)?;
        }
        ([None, None, None], None) => {}
        _ => return Err(at("the four clearance cells are all given or all empty".into())),
    }
    Ok(())
}

/// Merges checked files into the whole run ([`shards::merge_files`]): same run, every shard
/// once, then every trial of the run once with every controller, in the run's order. Returns
/// the merged file (`shard = 1/1`), equal to the unsharded run's, and the run's summary words.
pub fn merge_files(files: Vec<(PathBuf, ShardFile<TrialRow>)>) -> Result<(ShardFile<TrialRow>, RunSummary), Error> {
    let Some((path, first)) = files.first() else {
        return Err(file_error(Path::new("<merge>"), None, "no files to merge"));
    };
    let run = RunSummary::parse(&first.run).map_err(|what| file_error(path, Some(2), what))?;
    let merged = shards::merge_files(
        files,
        |r| (r.trial, run.position(r.controller)),
        |_, rows| {
            let c = run.controllers.len();
            let whole = rows.len() == run.trials * c
                && rows.iter().enumerate().all(|(i, r)| r.trial == i / c && r.controller == run.controllers[i % c]);
            if whole {
                Ok(())
            } else {
                Err(format!(
                    "the shards hold {} rows, not the run's {} trials of {} controllers, each once",
                    rows.len(),
                    run.trials,
                    c
                ))
            }
        },
    )?;
    Ok((merged, run))
}
