//! Mounting-point design (Sec. 6, item 3: "mount the on-board manipulator appropriately"): a grid
//! of mounting points `(a, b)`, and at each two metrics:
//! - for the paper's 2-link robot, the domain of Eq. (14) seen from `q0` and the success rate of
//!   the Normal Form Approach on random start/goal pairs ([`SweepOptions::nfa`]; the normal form
//!   is the 2-joint robot's, so an arm of another number of links is refused with the reason);
//! - for any arm, the effort `integral |theta'|^2 dt` of the certified minimum-effort plan of
//!   the reference problem `start -> goal` ([`SweepOptions::effort`]): what the mount costs the
//!   motion that matters to the user.
//!
//! A sweep is split into points numbered row-major (`index = ib * steps_a + ia`); every point is
//! computed independently and deterministically from the options and its index, so a sweep can be
//! cut into shards ([`Shard`]) run anywhere and [`merge`]d into exactly the unsharded result.
//!
//! The random pairs are **common random numbers**: trial `k` uses the same start/goal pair at
//! every mounting point (drawn from a counter-based generator keyed by `(seed, k)`), so that
//! differences between mounting points are not sampling noise between different pairs.

mod effort;
pub mod file;
mod pairs;

pub use pairs::trial_pair;
#[cfg(test)]
use pairs::uniform;

pub use crate::analysis::shards::Shard;

use crate::model::InputError;
use serde::{Deserialize, Serialize};

use crate::analysis::domain::DomainMap;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::{Configuration, Mount, RobotParams, paper_problem};
use crate::plan::PlanningProblem;
use crate::planners::Planner;
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::{NfaOptions, NormalFormPlanner};

/// `steps` equally spaced values from `min` to `max`, both included (`min` alone when
/// `steps = 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// First value \[m\].
    pub min: f64,
    /// Last value \[m\].
    pub max: f64,
    /// Number of values, at least 1.
    pub steps: usize,
}

impl Span {
    /// A validated span: finite ends, `min <= max`, `steps >= 1`.
    pub fn new(name: &str, min: f64, max: f64, steps: usize) -> Result<Self, Error> {
        if !(min.is_finite() && max.is_finite() && min <= max) {
            return Err(Error::from(InputError::InvalidParameter {
                name: name.to_string(),
                value: if min.is_finite() { max } else { min },
                expected: "finite MIN,MAX with MIN <= MAX",
            }));
        }
        if steps == 0 || (steps == 1 && min < max) {
            return Err(Error::from(InputError::InvalidParameter {
                name: format!("{name} steps"),
                value: steps as f64,
                expected: "at least 2 steps for a range, 1 for a single value",
            }));
        }
        Ok(Self { min, max, steps })
    }

    /// The `i`-th value, `min (1 - t) + max t` with `t = i / (steps - 1)`: symmetric ranges hit
    /// 0 exactly in the middle (where Eqs. 11-12 apply).
    pub fn value(&self, i: usize) -> f64 {
        if self.steps == 1 {
            return self.min;
        }
        let t = i as f64 / (self.steps - 1) as f64;
        self.min * (1.0 - t) + self.max * t
    }
}

/// What a sweep computes.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepOptions {
    /// Values of `a` \[m\].
    pub a: Span,
    /// Values of `b` \[m\].
    pub b: Span,
    /// Grid size of each domain map; default 256.
    pub grid: usize,
    /// Random start/goal pairs per point; default 100.
    pub trials: usize,
    /// Seed of the pairs; default 0.
    pub seed: u64,
    /// NFA samples per plan; default 201 (the verification evaluates the plan exactly at every
    /// integrator stage, so the sample count only warm-starts Newton's method).
    pub samples: usize,
    /// Horizon of every plan \[s\]; default 10.
    pub horizon: f64,
    /// Largest verified final error of a success \[rad\]; default 1e-9.
    pub tolerance: f64,
    /// `(phi, theta_1..theta_n)`: the configuration whose component is measured and the start
    /// of the reference problem; default the paper's `q0`.
    pub start: Vec<f64>,
    /// The goal checked for connection with `start` and of the reference problem; default the
    /// paper's `qd`.
    pub goal: Vec<f64>,
    /// Also rate the global normal form (beyond the paper; band steering where needed, so each
    /// trial costs milliseconds more); default false.
    pub global: bool,
    /// Map the domain of Eq. (14) and rate the NFA (2-link arms only); default true.
    pub nfa: bool,
    /// Plan the reference problem `start -> goal` in `horizon` with the minimum-effort planner at
    /// every point and record its effort (any arm); default false.
    pub effort: bool,
}

impl Default for SweepOptions {
    fn default() -> Self {
        let (start, goal, horizon) = paper_problem();
        let span = Span { min: -0.3, max: 0.3, steps: 41 };
        Self {
            a: span,
            b: span,
            grid: 256,
            trials: 100,
            seed: 0,
            samples: 201,
            horizon,
            tolerance: 1e-9,
            start: start.to_array().to_vec(),
            goal: goal.to_array().to_vec(),
            global: false,
            nfa: true,
            effort: false,
        }
    }
}

/// Most NFA plans of one sweep (points x trials x the transformations rated): about a day of
/// one thread at a millisecond per plan (docs/spec.md §3, "Budgets").
pub const MAX_SWEEP_PLANS: f64 = 1e8;

impl SweepOptions {
    /// Checks the request against the budgets before any work: at least one trial per point,
    /// at most [`MAX_SWEEP_PLANS`] plans, one domain map within the memory budget
    /// ([`crate::analysis::domain::check_map_memory`]).
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.nfa || self.effort) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "metric".into(),
                value: 0.0,
                expected: "at least one metric: the NFA's domain and success rate (2-link arms) or the effort",
            }));
        }
        if self.trials == 0 {
            return Err(Error::from(InputError::InvalidParameter {
                name: "trials".into(),
                value: 0.0,
                expected: "at least 1 trial per mounting point (a success rate of no trials is no rate)",
            }));
        }
        let rated = f64::from(u8::from(self.nfa)) * (1.0 + f64::from(u8::from(self.global)));
        let plans = self.points() as f64 * (self.trials as f64 * rated + f64::from(u8::from(self.effort)));
        if plans > MAX_SWEEP_PLANS {
            return Err(Error::from(InputError::TooMuchWork {
                what: format!("{} mounting points x {} trials", self.points(), self.trials),
                work: plans,
                limit: MAX_SWEEP_PLANS,
                unit: if self.effort { "plans (NFA and minimum-effort)" } else { "NFA plans" },
                hint: "fewer points or trials".into(),
            }));
        }
        if !(3..=crate::analysis::domain::MAX_GRID).contains(&self.grid) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "grid".into(),
                value: self.grid as f64,
                expected: "a grid size between 3 and 8192",
            }));
        }
        if self.start.len() != self.goal.len() || self.start.len() < 2 {
            return Err(Error::from(InputError::InvalidParameter {
                name: "goal".into(),
                value: self.goal.len() as f64,
                expected: "a start and a goal of n + 1 angles each (phi, theta_1..theta_n)",
            }));
        }
        if let Some(x) = self.start.iter().chain(&self.goal).find(|x| !x.is_finite()) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "start/goal".into(),
                value: *x,
                expected: "finite angles [rad]",
            }));
        }
        if self.nfa { crate::analysis::domain::check_map_memory(self.grid) } else { Ok(()) }
    }

    /// How many maps of this sweep may be built at once within the memory budget (at least 1,
    /// at most `threads`): the sweep runs on that many threads.
    pub fn concurrent_maps(&self, threads: usize) -> usize {
        if !self.nfa {
            return threads.max(1);
        }
        let map = self.grid as u128 * self.grid as u128 * crate::analysis::domain::BYTES_PER_CELL;
        let fit = (crate::plan::limits::MEMORY_LIMIT / map.max(1)).max(1);
        threads.min(usize::try_from(fit).unwrap_or(usize::MAX)).max(1)
    }

    /// Number of mounting points.
    pub fn points(&self) -> usize {
        self.a.steps * self.b.steps
    }

    /// The mounting point of `index` (row-major: `a` varies fastest).
    pub fn mount(&self, index: usize) -> (f64, f64) {
        (self.a.value(index % self.a.steps), self.b.value(index / self.a.steps))
    }
}

/// One mounting point's results: one CSV row. Columns are the field names; a metric that was
/// not computed is empty: the NFA's (`components` .. `global_rate`) without
/// [`SweepOptions::nfa`], `eq11_*`, `eq12_*` where those transformations do not apply
/// (`a, b != 0`), `global_*` without [`SweepOptions::global`], `planned`, `effort` without
/// [`SweepOptions::effort`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepRow {
    /// Point index (row-major, `a` fastest).
    pub index: usize,
    /// Number of points of the whole sweep.
    pub points: usize,
    /// `a` \[m\].
    pub a: f64,
    /// `b` \[m\].
    pub b: f64,
    /// Grid size of the domain map.
    pub grid: usize,
    /// Seed of the random pairs.
    pub seed: u64,
    /// Random pairs tried.
    pub trials: usize,
    /// Resolved components of the domain of Eq. (14).
    pub components: Option<usize>,
    /// Area share of the component of `start` (the paper's `q0` by default).
    pub start_component_fraction: Option<f64>,
    /// `start` and `goal` in one component.
    pub start_goal_connected: Option<bool>,
    /// Certified NFA plans with Eq. (14).
    pub eq14_successes: Option<usize>,
    /// `eq14_successes / trials`.
    pub eq14_rate: Option<f64>,
    /// Certified NFA plans with Eq. (12) (`a = b = 0` only).
    pub eq12_successes: Option<usize>,
    /// `eq12_successes / trials`.
    pub eq12_rate: Option<f64>,
    /// Certified NFA plans with Eq. (11) (`a = b = 0` only).
    pub eq11_successes: Option<usize>,
    /// `eq11_successes / trials`.
    pub eq11_rate: Option<f64>,
    /// Certified NFA plans with the global normal form (with `global` only).
    pub global_successes: Option<usize>,
    /// `global_successes / trials`.
    pub global_rate: Option<f64>,
    /// The minimum-effort planner certified a plan of the reference problem here.
    pub planned: Option<bool>,
    /// That plan's effort `integral |theta'|^2 dt` \[rad^2/s\] (empty without a certified plan).
    pub effort: Option<f64>,
}

impl SweepRow {
    /// The best NFA success rate over the transformations available at this point (`None`
    /// without the NFA's metric).
    pub fn best_rate(&self) -> Option<f64> {
        let eq14 = self.eq14_rate?;
        Some([self.eq12_rate, self.eq11_rate, self.global_rate].into_iter().flatten().fold(eq14, f64::max))
    }

    /// The transformation with [`SweepRow::best_rate`] (Eq. 14 on ties).
    pub fn best_transform(&self) -> Transform {
        let mut best = (self.eq14_rate.unwrap_or(0.0), Transform::Eq14);
        let rates = [
            (self.eq12_rate, Transform::Eq12),
            (self.eq11_rate, Transform::Eq11),
            (self.global_rate, Transform::Global),
        ];
        for (rate, t) in rates {
            if let Some(r) = rate.filter(|&r| r > best.0) {
                best = (r, t);
            }
        }
        best.1
    }
}

/// Successes of the NFA with `transform` over the trials: a plan that exists and is certified
/// (verified final error <= tolerance).
fn successes(robot: &RobotParams, transform: Transform, options: &SweepOptions) -> usize {
    let planner = NormalFormPlanner::new(NfaOptions {
        transform: Some(transform),
        samples: options.samples,
        tolerance: options.tolerance,
        ..Default::default()
    });
    (0..options.trials as u64)
        .filter(|&trial| {
            let (start, goal) = trial_pair(options.seed, trial);
            let problem =
                PlanningProblem { robot: *robot, start, goal, horizon: options.horizon, start_velocity: [0.0; 2] };
            planner.plan(&problem).is_ok_and(|planned| planned.plan.verification.certified)
        })
        .count()
}

/// Computes one point of the sweep for `arm` (its mount replaced by the point's; its declared
/// limits and shapes kept: the effort is that of a plan inside them, clear of the robot's own
/// bodies, as `plan` would make it).
pub fn run_point(arm: &Arm, options: &SweepOptions, index: usize) -> Result<SweepRow, Error> {
    let (a, b) = options.mount(index);
    let arm = Arm::new(arm.base, Mount::new(a, b)?, arm.links.clone())?
        .with_limits(arm.limits.clone())?
        .with_geometry(arm.geometry.clone())?;
    let mut row = SweepRow {
        index,
        points: options.points(),
        a,
        b,
        grid: options.grid,
        seed: options.seed,
        trials: options.trials,
        components: None,
        start_component_fraction: None,
        start_goal_connected: None,
        eq14_successes: None,
        eq14_rate: None,
        eq12_successes: None,
        eq12_rate: None,
        eq11_successes: None,
        eq11_rate: None,
        global_successes: None,
        global_rate: None,
        planned: None,
        effort: None,
    };
    if options.nfa {
        nfa_metrics(&nfa_robot(&arm)?, options, &mut row)?;
    }
    if options.effort {
        (row.planned, row.effort) = effort::metric(&arm, options)?;
    }
    Ok(row)
}

/// The paper's 2-link model of `arm`, for the NFA's metric; another arm is bad input naming the
/// reason.
pub fn nfa_robot(arm: &Arm) -> Result<RobotParams, Error> {
    arm.as_src().ok_or_else(|| {
        Error::from(InputError::InvalidParameter {
            name: "mount-sweep".into(),
            value: arm.joints() as f64,
            expected: "a 2-link arm with each centre of mass off its joint for the NFA's domain and success rate \
                       (the paper's normal form, Eq. 10, is for two joints): sweep the effort instead (--effort)",
        })
    })
}

/// The NFA's metrics at `robot`'s mount: the domain of Eq. (14) and the success rates.
fn nfa_metrics(robot: &RobotParams, options: &SweepOptions, row: &mut SweepRow) -> Result<(), Error> {
    let (start, goal) = (configuration(&options.start)?, configuration(&options.goal)?);
    let map = DomainMap::new(robot, Transform::Eq14, options.grid)?;
    let summary = map.summary(&start, &goal);
    let trials = options.trials;
    let rate = |s: usize| if trials == 0 { 0.0 } else { s as f64 / trials as f64 };
    let eq14 = successes(robot, Transform::Eq14, options);
    let (eq12, eq11) = if robot.mount.is_centred() {
        (Some(successes(robot, Transform::Eq12, options)), Some(successes(robot, Transform::Eq11, options)))
    } else {
        (None, None)
    };
    let global = options.global.then(|| successes(robot, Transform::Global, options));
    row.components = Some(summary.components);
    row.start_component_fraction = Some(summary.start_component_fraction);
    row.start_goal_connected = Some(summary.start_goal_connected);
    (row.eq14_successes, row.eq14_rate) = (Some(eq14), Some(rate(eq14)));
    (row.eq12_successes, row.eq12_rate) = (eq12, eq12.map(rate));
    (row.eq11_successes, row.eq11_rate) = (eq11, eq11.map(rate));
    (row.global_successes, row.global_rate) = (global, global.map(rate));
    Ok(())
}

/// A 2-link configuration of three angles.
fn configuration(q: &[f64]) -> Result<Configuration, Error> {
    match q {
        [phi, t1, t2] => Ok(Configuration::new(*phi, *t1, *t2)),
        _ => Err(Error::from(InputError::InvalidParameter {
            name: "start/goal".into(),
            value: q.len() as f64,
            expected: "3 angles (phi, theta1, theta2) for the 2-link robot's NFA metric",
        })),
    }
}

/// Runs the points of `shard` on rayon's threads (fewer when the maps are large:
/// [`SweepOptions::concurrent_maps`]), calling `progress` after each point, after checking the
/// budgets ([`SweepOptions::validate`]). Rows come back in index order.
pub fn run(
    arm: &Arm,
    options: &SweepOptions,
    shard: Shard,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<SweepRow>, Error> {
    use rayon::prelude::*;
    arm.validate()?;
    options.validate()?;
    if options.nfa {
        nfa_robot(arm)?;
    }
    if options.start.len() != arm.joints() + 1 {
        return Err(Error::from(InputError::InvalidParameter {
            name: "start".into(),
            value: options.start.len() as f64,
            expected: "n + 1 angles (phi, theta_1..theta_n) for this arm",
        }));
    }
    if options.effort {
        // Angles, ranges, horizon at once; the ends' clearance depends on the mount (`run_point`).
        effort::problem(options).validate(&Arm { geometry: Default::default(), ..arm.clone() })?;
    }
    let indices: Vec<usize> = shard.indices(options.points()).collect();
    let work = || {
        indices
            .par_iter()
            .map(|&i| {
                let row = run_point(arm, options, i);
                progress();
                row
            })
            .collect()
    };
    // Each thread holds one map: fewer threads when the maps are large (the memory budget).
    let threads = options.concurrent_maps(rayon::current_num_threads());
    if threads == rayon::current_num_threads() {
        return work();
    }
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.install(work),
        Err(_) => indices.iter().map(|&i| run_point(arm, options, i).inspect(|_| progress())).collect(),
    }
}

fn csv_error(path: &std::path::Path, e: csv::Error) -> Error {
    Error::from(InputError::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}

/// The rows as plain CSV (header = [`SweepRow`]'s field names, written even without rows; floats
/// in shortest round-trip form, so that reading and writing again reproduces the bytes). The
/// command line writes [`file::write`]'s checked file instead.
pub fn to_csv(rows: &[SweepRow]) -> Result<Vec<u8>, Error> {
    let path = std::path::Path::new("<csv>");
    let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
    w.write_record(file::COLUMNS).map_err(|e| csv_error(path, e))?;
    for row in rows {
        w.serialize(row).map_err(|e| csv_error(path, e))?;
    }
    w.into_inner().map_err(|e| {
        Error::from(InputError::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
    })
}

/// Reads rows written by [`to_csv`]; `path` only labels errors.
pub fn from_csv(bytes: &[u8], path: &std::path::Path) -> Result<Vec<SweepRow>, Error> {
    let mut r = csv::Reader::from_reader(bytes);
    r.deserialize().map(|row| row.map_err(|e| csv_error(path, e))).collect()
}

/// Merges shards into the whole sweep, in index order. Errors unless the shards come from one
/// sweep (same number of points, grid, seed and trials), agree where they overlap, and together
/// hold every point.
pub fn merge(parts: impl IntoIterator<Item = SweepRow>) -> Result<Vec<SweepRow>, Error> {
    let mut rows: Vec<SweepRow> = parts.into_iter().collect();
    rows.sort_by_key(|r| r.index);
    rows.dedup_by(|x, y| x == y);
    let Some(first) = rows.first().cloned() else {
        return Err(Error::from(InputError::InvalidParameter {
            name: "merge".into(),
            value: 0.0,
            expected: "at least one row",
        }));
    };
    let mismatch = |name: &str, value: f64| {
        Error::from(InputError::InvalidParameter {
            name: format!("merge: {name}"),
            value,
            expected: "shards of one sweep (same points, grid, seed, trials), each point once",
        })
    };
    for (i, r) in rows.iter().enumerate() {
        if r.points != first.points || r.grid != first.grid || r.seed != first.seed || r.trials != first.trials {
            return Err(mismatch("settings differ at index", r.index as f64));
        }
        if r.index != i {
            let what = if r.index < i { "two different rows for index" } else { "missing index" };
            return Err(mismatch(what, (if r.index < i { r.index } else { i }) as f64));
        }
    }
    if rows.len() != first.points {
        return Err(mismatch("missing index", rows.len() as f64));
    }
    Ok(rows)
}

/// The best mounting point by the NFA: the highest [`SweepRow::best_rate`], then the largest
/// start-component fraction, then the lowest index (`None` without the NFA's metric).
pub fn best(rows: &[SweepRow]) -> Option<&SweepRow> {
    rows.iter().filter(|r| r.best_rate().is_some()).reduce(|best, r| {
        let key = |r: &SweepRow| (r.best_rate(), r.start_component_fraction);
        if key(r) > key(best) { r } else { best }
    })
}

/// The mounting point of least certified effort (the lowest index on ties; `None` without the
/// effort metric or a certified plan).
pub fn least_effort(rows: &[SweepRow]) -> Option<&SweepRow> {
    rows.iter().filter(|r| r.effort.is_some()).reduce(|best, r| if r.effort < best.effort { r } else { best })
}

#[cfg(test)]
mod tests;
