//! The sweep's file: a CSV table of [`SweepRow`]s under two comment lines that identify the run
//! and check the rows, so that `merge` can refuse whatever does not belong together (the format
//! and its checks are [`crate::analysis::shards`]'s).
//!
//! ```text
//! # freefloat-sweep v1 run=<hash> shard=K/N rows=<count> checksum=<hash>
//! # run: <every option of the sweep and the robot, in canonical form>
//! index,points,a,b,...,global_rate,check
//! 0,9,-0.3,-0.2,...,,<hash>
//! ```
//!
//! A merged file is written by the same routine with `shard=1/1`, so it equals the unsharded run
//! byte for byte.

use std::path::{Path, PathBuf};

use super::{Shard, SweepOptions, SweepRow};
use crate::analysis::shards::{self, FileKind, ShardFile, finite};
use crate::error::Error;
use crate::model::RobotParams;

/// The first words of a sweep file.
pub const MAGIC: &str = "# freefloat-sweep v1";

/// The CSV columns: [`SweepRow`]'s fields, then the row's `check`.
pub const COLUMNS: [&str; 18] = [
    "index",
    "points",
    "a",
    "b",
    "grid",
    "seed",
    "trials",
    "components",
    "start_component_fraction",
    "start_goal_connected",
    "eq14_successes",
    "eq14_rate",
    "eq12_successes",
    "eq12_rate",
    "eq11_successes",
    "eq11_rate",
    "global_successes",
    "global_rate",
];

/// The canonical description of a run: every option that changes a row and the robot (without
/// its mount, which the sweep chooses), floats in shortest round-trip form. The links' own
/// inertias follow only when one is not zero, so that runs of point-mass robots keep the
/// identity they had before link inertias existed.
pub fn run_description(robot: &RobotParams, options: &SweepOptions) -> String {
    let o = options;
    let q = |c: crate::model::Configuration| format!("{:?},{:?},{:?}", c.phi, c.theta1, c.theta2);
    let inertias = if robot.i1 == 0.0 && robot.i2 == 0.0 {
        String::new()
    } else {
        format!(",i1:{:?},i2:{:?}", robot.i1, robot.i2)
    };
    format!(
        "a={:?},{:?},{} b={:?},{:?},{} grid={} trials={} seed={} samples={} horizon={:?} tolerance={:?} \
         start={} goal={} global={} robot=l1:{:?},l2:{:?},d1:{:?},d2:{:?},M:{:?},I:{:?},m1:{:?},m2:{:?}{inertias}",
        o.a.min,
        o.a.max,
        o.a.steps,
        o.b.min,
        o.b.max,
        o.b.steps,
        o.grid,
        o.trials,
        o.seed,
        o.samples,
        o.horizon,
        o.tolerance,
        q(o.start),
        q(o.goal),
        o.global,
        robot.l1,
        robot.l2,
        robot.d1,
        robot.d2,
        robot.base_mass,
        robot.base_inertia,
        robot.m1,
        robot.m2,
    )
}

/// The sweep file's kind: [`MAGIC`] and [`COLUMNS`].
pub const KIND: FileKind = FileKind { magic: MAGIC, name: "sweep", columns: &COLUMNS };

/// One sweep file, read and checked.
pub type SweepFile = ShardFile<SweepRow>;

/// The file of `shard` of the run `run` (see [`run_description`]): header lines, the CSV header
/// (always, even for a shard without points) and one checked row per point.
pub fn write(run: &str, shard: Shard, rows: &[SweepRow]) -> Result<Vec<u8>, Error> {
    shards::write(&KIND, run, shard, rows)
}

/// Reads and checks one file: its header, every row's check, the row count and the checksum,
/// and the numbers of every row (finite, counts within the trials, rates equal to the counts
/// over the trials, indices of the shard). Errors name the file and the line.
pub fn read(bytes: &[u8], path: &Path) -> Result<SweepFile, Error> {
    shards::read(&KIND, bytes, path, |row, _, shard| check_row(row, shard))
}

/// The numbers of a row: finite, within their ranges, rates equal to their counts over the
/// trials, and an index of this shard.
fn check_row(r: &SweepRow, shard: Shard) -> Result<(), String> {
    let at = |what: String| format!("index {}: {what}", r.index);
    let floats = [
        ("a", Some(r.a)),
        ("b", Some(r.b)),
        ("start_component_fraction", Some(r.start_component_fraction)),
        ("eq14_rate", Some(r.eq14_rate)),
        ("eq12_rate", r.eq12_rate),
        ("eq11_rate", r.eq11_rate),
        ("global_rate", r.global_rate),
    ];
    for (name, x) in floats {
        x.map_or(Ok(()), |x| finite(name, x)).map_err(at)?;
    }
    if !(0.0..=1.0).contains(&r.start_component_fraction) {
        return Err(at(format!("start_component_fraction = {} is outside [0, 1]", r.start_component_fraction)));
    }
    if r.index >= r.points || !shard.holds(r.index) {
        return Err(at(format!("the index is not one of shard {}/{} of {} points", shard.k, shard.n, r.points)));
    }
    let rates = [
        ("eq14", Some(r.eq14_successes), Some(r.eq14_rate)),
        ("eq12", r.eq12_successes, r.eq12_rate),
        ("eq11", r.eq11_successes, r.eq11_rate),
        ("global", r.global_successes, r.global_rate),
    ];
    for (name, successes, rate) in rates {
        match (successes, rate) {
            (None, None) => {}
            (Some(s), Some(rate)) => {
                let expected = if r.trials == 0 { 0.0 } else { s as f64 / r.trials as f64 };
                if s > r.trials || rate.to_bits() != expected.to_bits() {
                    return Err(at(format!(
                        "{name}: {s} successes of {} trials do not give the rate {rate}",
                        r.trials
                    )));
                }
            }
            _ => return Err(at(format!("{name}: a count without its rate, or a rate without its count"))),
        }
    }
    Ok(())
}

/// Merges checked files into the whole sweep: every file of the same run (the same `# run:`
/// line) and the same number of shards, each shard exactly once, every point exactly once.
/// Returns the merged file (`shard = 1/1`), equal to the unsharded run's.
pub fn merge_files(files: Vec<(PathBuf, SweepFile)>) -> Result<SweepFile, Error> {
    shards::merge_files(
        files,
        |r| r.index,
        |_, rows| {
            let points = rows.first().map_or(0, |r| r.points);
            let whole = rows.iter().enumerate().all(|(i, r)| r.index == i && r.points == points);
            if !whole || rows.len() != points {
                return Err(format!("the shards hold {} rows, not the run's {points} points", rows.len()));
            }
            Ok(())
        },
    )
}
