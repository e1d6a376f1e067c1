//! The sweep's file: a CSV table of [`SweepRow`]s under two comment lines that identify the run
//! and check the rows, so that `merge` can refuse whatever does not belong together (the format
//! and its checks are [`crate::analysis::shards`]'s).
//!
//! ```text
//! # freefloat-sweep v2 run=<hash> shard=K/N rows=<count> checksum=<hash>
//! # run: <every option of the sweep and the robot, in canonical form>
//! index,points,a,b,...,global_rate,planned,effort,check
//! 0,9,-0.3,-0.2,...,,,,<hash>
//! ```
//!
//! A merged file is written by the same routine with `shard=1/1`, so it equals the unsharded run
//! byte for byte.

use std::path::{Path, PathBuf};

use super::{Shard, SweepOptions, SweepRow};
use crate::analysis::shards::{self, FileKind, ShardFile, finite};
use crate::error::Error;
use crate::model::arm::Arm;

/// The first words of a sweep file (v2: the metrics optional, the effort columns; a v1 file of
/// an earlier freefloat is refused as another format).
pub const MAGIC: &str = "# freefloat-sweep v2";

/// The CSV columns: [`SweepRow`]'s fields, then the row's `check`.
pub const COLUMNS: [&str; 20] = [
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
    "planned",
    "effort",
];

/// The canonical description of a run: every option that changes a row and the arm (without
/// its mount, which the sweep chooses), floats in shortest round-trip form.
pub fn run_description(arm: &Arm, options: &SweepOptions) -> String {
    let o = options;
    let list = |v: &[f64]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(",");
    let links: Vec<String> =
        arm.links.iter().map(|l| format!("l:{:?},d:{:?},m:{:?},i:{:?}", l.length, l.com, l.mass, l.inertia)).collect();
    format!(
        "a={:?},{:?},{} b={:?},{:?},{} grid={} trials={} seed={} samples={} horizon={:?} tolerance={:?} \
         start={} goal={} global={} nfa={} effort={} robot=M:{:?},I:{:?};{}",
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
        list(&o.start),
        list(&o.goal),
        o.global,
        o.nfa,
        o.effort,
        arm.base.mass,
        arm.base.inertia,
        links.join(";"),
    ) + &constraints(arm)
}

/// The arm's declared limits and shapes in the run's description, where it has any (JSON;
/// nothing for an arm without, so that its description is as before): shards of one robot with
/// other limits or shapes plan other problems.
fn constraints(arm: &Arm) -> String {
    // Serialising plain numbers, vectors and enums does not fail.
    let json = |v: Result<String, serde_json::Error>| v.unwrap_or_default();
    let mut text = String::new();
    if !arm.limits.is_empty() {
        text += &format!(" limits={}", json(serde_json::to_string(&arm.limits)));
    }
    if !arm.geometry.is_empty() {
        text += &format!(" geometry={}", json(serde_json::to_string(&arm.geometry)));
    }
    text
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
        ("start_component_fraction", r.start_component_fraction),
        ("eq14_rate", r.eq14_rate),
        ("eq12_rate", r.eq12_rate),
        ("eq11_rate", r.eq11_rate),
        ("global_rate", r.global_rate),
        ("effort", r.effort),
    ];
    for (name, x) in floats {
        x.map_or(Ok(()), |x| finite(name, x)).map_err(at)?;
    }
    if let Some(f) = r.start_component_fraction
        && !(0.0..=1.0).contains(&f)
    {
        return Err(at(format!("start_component_fraction = {f} is outside [0, 1]")));
    }
    let nfa = [r.components.is_some(), r.start_component_fraction.is_some(), r.start_goal_connected.is_some()];
    if nfa.iter().any(|&x| x != r.eq14_rate.is_some()) {
        return Err(at("the NFA's columns are partly empty".into()));
    }
    match (r.planned, r.effort) {
        (None, None) | (Some(false), None) => {}
        (Some(true), Some(e)) if e >= 0.0 => {}
        _ => return Err(at("planned and effort disagree (a certified plan has a non-negative effort)".into())),
    }
    if r.index >= r.points || !shard.holds(r.index) {
        return Err(at(format!("the index is not one of shard {}/{} of {} points", shard.k, shard.n, r.points)));
    }
    let rates = [
        ("eq14", r.eq14_successes, r.eq14_rate),
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
