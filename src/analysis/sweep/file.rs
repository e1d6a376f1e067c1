//! The sweep's file: a CSV table of [`SweepRow`]s under two comment lines that identify the run
//! and check the rows, so that `merge` can refuse whatever does not belong together.
//!
//! ```text
//! # freefloat-sweep v1 run=<hash> shard=K/N rows=<count> checksum=<hash>
//! # run: <every option of the sweep and the robot, in canonical form>
//! index,points,a,b,...,global_rate,check
//! 0,9,-0.3,-0.2,...,,<hash>
//! ```
//!
//! `run` is the hash of the `# run:` line's text; each row's `check` is the hash of `run` and the
//! row's other cells; `checksum` is the hash of `run`, the shard, the row count and every row's
//! check. The hash is 64-bit FNV-1a: it guards against files from another run, edited numbers and
//! lost or repeated rows (accidents, not an adversary, who could recompute it). A merged file is
//! written by the same routine with `shard=1/1`, so it equals the unsharded run byte for byte.

use std::path::{Path, PathBuf};

use super::{Shard, SweepOptions, SweepRow};
use crate::error::Error;
use crate::model::{InputError, RobotParams};

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

/// 64-bit FNV-1a of `bytes`, continuing from `state` (start with [`FNV_OFFSET`]).
///
/// ## Reference
/// G. Fowler, L. C. Noll, K.-P. Vo, D. Eastlake, *The FNV Non-Cryptographic Hash Algorithm*,
/// IETF draft-eastlake-fnv (2012-2024).
pub fn fnv1a(state: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(state, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3))
}

/// FNV-1a's initial state.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

fn hash(parts: &[&str]) -> u64 {
    parts.iter().fold(FNV_OFFSET, |h, p| fnv1a(fnv1a(h, p.as_bytes()), b"\x1f"))
}

/// The canonical description of a run: every option that changes a row and the robot (without
/// its mount, which the sweep chooses), floats in shortest round-trip form.
pub fn run_description(robot: &RobotParams, options: &SweepOptions) -> String {
    let o = options;
    let q = |c: crate::model::Configuration| format!("{:?},{:?},{:?}", c.phi, c.theta1, c.theta2);
    format!(
        "a={:?},{:?},{} b={:?},{:?},{} grid={} trials={} seed={} samples={} horizon={:?} tolerance={:?} \
         start={} goal={} global={} robot=l1:{:?},l2:{:?},d1:{:?},d2:{:?},M:{:?},I:{:?},m1:{:?},m2:{:?}",
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

/// One sweep file, read and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepFile {
    /// The `# run:` description.
    pub run: String,
    /// Which part of the run.
    pub shard: Shard,
    /// The rows, in index order.
    pub rows: Vec<SweepRow>,
}

fn file_error(path: &Path, line: Option<usize>, reason: impl Into<String>) -> Error {
    Error::from(InputError::SweepFile { path: path.to_path_buf(), line, reason: reason.into() })
}

/// The rows' CSV lines without the `check` cell (header included, first).
fn csv_lines(rows: &[SweepRow]) -> Result<Vec<String>, Error> {
    let csv_error = |e: csv::Error| file_error(Path::new("<csv>"), None, e.to_string());
    let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
    w.write_record(COLUMNS).map_err(csv_error)?;
    for row in rows {
        w.serialize(row).map_err(csv_error)?;
    }
    let bytes = w.into_inner().map_err(|e| file_error(Path::new("<csv>"), None, e.to_string()))?;
    let text = String::from_utf8(bytes).map_err(|e| file_error(Path::new("<csv>"), None, e.to_string()))?;
    Ok(text.lines().map(str::to_string).collect())
}

fn checksum(run_hash: &str, shard: Shard, checks: &[String]) -> u64 {
    let head = format!("{run_hash} {}/{} {}", shard.k, shard.n, checks.len());
    checks.iter().fold(hash(&[&head]), |h, c| fnv1a(h, c.as_bytes()))
}

/// The file of `shard` of the run `run` (see [`run_description`]): header lines, the CSV header
/// (always, even for a shard without points) and one checked row per point.
pub fn write(run: &str, shard: Shard, rows: &[SweepRow]) -> Result<Vec<u8>, Error> {
    let run_hash = format!("{:016x}", hash(&[run]));
    let lines = csv_lines(rows)?;
    let mut body = format!("{},check\n", lines[0]);
    let mut checks = Vec::with_capacity(rows.len());
    for line in &lines[1..] {
        let check = format!("{:016x}", hash(&[&run_hash, line]));
        body += &format!("{line},{check}\n");
        checks.push(check);
    }
    let sum = checksum(&run_hash, shard, &checks);
    let head = format!(
        "{MAGIC} run={run_hash} shard={}/{} rows={} checksum={sum:016x}\n# run: {run}\n",
        shard.k,
        shard.n,
        rows.len()
    );
    Ok((head + &body).into_bytes())
}

/// The value of `key=` in the header's words.
fn field<'a>(words: &[&'a str], key: &str) -> Option<&'a str> {
    words.iter().find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
}

/// Reads and checks one file: its header, every row's check, the row count and the checksum,
/// and the numbers of every row (finite, counts within the trials, rates equal to the counts
/// over the trials, indices of the shard). Errors name the file and the line.
pub fn read(bytes: &[u8], path: &Path) -> Result<SweepFile, Error> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| file_error(path, None, format!("not UTF-8 text (invalid byte at offset {})", e.valid_up_to())))?;
    let mut lines = text.lines();
    let not_sweep =
        || file_error(path, Some(1), format!("not a freefloat sweep file: the first line must start with `{MAGIC}`"));
    let head = lines.next().and_then(|l| l.strip_prefix(MAGIC)).ok_or_else(not_sweep)?;
    let words: Vec<&str> = head.split_whitespace().collect();
    let bad_head = |what: &str| file_error(path, Some(1), format!("damaged header: {what}"));
    let run_hash = field(&words, "run").ok_or_else(|| bad_head("no run="))?;
    let shard = field(&words, "shard").and_then(|s| Shard::parse(s).ok()).ok_or_else(|| bad_head("no shard=K/N"))?;
    let count: usize = field(&words, "rows").and_then(|s| s.parse().ok()).ok_or_else(|| bad_head("no rows=<count>"))?;
    let sum = field(&words, "checksum").ok_or_else(|| bad_head("no checksum="))?;
    let run = lines
        .next()
        .and_then(|l| l.strip_prefix("# run: "))
        .ok_or_else(|| file_error(path, Some(2), "the `# run:` line is missing"))?;
    if format!("{:016x}", hash(&[run])) != run_hash {
        return Err(file_error(path, Some(2), "the `# run:` line does not match the header's run hash (edited)"));
    }
    let header = format!("{},check", COLUMNS.join(","));
    if lines.next() != Some(header.as_str()) {
        return Err(file_error(path, Some(3), format!("the CSV header must be `{}`", crate::model::excerpt(&header))));
    }
    let mut rows = Vec::new();
    let mut checks = Vec::new();
    for (k, line) in lines.enumerate() {
        let number = k + 4;
        let (cells, check) =
            line.rsplit_once(',').ok_or_else(|| file_error(path, Some(number), "a row without its check cell"))?;
        if format!("{:016x}", hash(&[run_hash, cells])) != check {
            return Err(file_error(
                path,
                Some(number),
                "the row does not match its check (edited, or copied from another run)",
            ));
        }
        let row = parse_row(cells, path, number)?;
        check_row(&row, shard, path, number)?;
        rows.push(row);
        checks.push(check.to_string());
    }
    if rows.len() != count {
        return Err(file_error(path, None, format!("the header says {count} rows, the file has {}", rows.len())));
    }
    if format!("{:016x}", checksum(run_hash, shard, &checks)) != sum {
        return Err(file_error(path, Some(1), "the checksum does not match the rows (rows lost, added or moved)"));
    }
    Ok(SweepFile { run: run.to_string(), shard, rows })
}

fn parse_row(cells: &str, path: &Path, line: usize) -> Result<SweepRow, Error> {
    let text = format!("{}\n{cells}\n", COLUMNS.join(","));
    let mut r = csv::Reader::from_reader(text.as_bytes());
    match r.deserialize::<SweepRow>().next() {
        Some(Ok(row)) => Ok(row),
        Some(Err(e)) => Err(file_error(path, Some(line), format!("not a sweep row: {e}"))),
        None => Err(file_error(path, Some(line), "an empty row")),
    }
}

/// The numbers of a row: finite, within their ranges, rates equal to their counts over the
/// trials, and an index of this shard.
fn check_row(r: &SweepRow, shard: Shard, path: &Path, line: usize) -> Result<(), Error> {
    let bad = |what: String| Err(file_error(path, Some(line), format!("index {}: {what}", r.index)));
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
        if let Some(x) = x.filter(|x| !x.is_finite()) {
            return bad(format!("{name} = {x} is not a finite number"));
        }
    }
    if !(0.0..=1.0).contains(&r.start_component_fraction) {
        return bad(format!("start_component_fraction = {} is outside [0, 1]", r.start_component_fraction));
    }
    if r.index >= r.points || r.index % shard.n != shard.k - 1 {
        return bad(format!("the index is not one of shard {}/{} of {} points", shard.k, shard.n, r.points));
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
                    return bad(format!("{name}: {s} successes of {} trials do not give the rate {rate}", r.trials));
                }
            }
            _ => return bad(format!("{name}: a count without its rate, or a rate without its count")),
        }
    }
    Ok(())
}

/// Merges checked files into the whole sweep: every file of the same run (the same `# run:`
/// line) and the same number of shards, each shard exactly once, every point exactly once.
/// Returns the merged file (`shard = 1/1`), equal to the unsharded run's.
pub fn merge_files(files: Vec<(PathBuf, SweepFile)>) -> Result<SweepFile, Error> {
    let Some((first_path, first)) = files.first() else {
        return Err(file_error(Path::new("<merge>"), None, "no files to merge"));
    };
    let (first_path, run, n) = (first_path.clone(), first.run.clone(), first.shard.n);
    let mut seen: Vec<Option<&Path>> = vec![None; n];
    for (path, file) in &files {
        if file.run != run {
            return Err(file_error(
                path,
                Some(2),
                format!("from another run than {}: the `# run:` lines differ", first_path.display()),
            ));
        }
        if file.shard.n != n {
            return Err(file_error(
                path,
                Some(1),
                format!(
                    "shard {}/{} does not fit with {}'s {n} shards",
                    file.shard.k,
                    file.shard.n,
                    first_path.display()
                ),
            ));
        }
        let slot = &mut seen[file.shard.k - 1];
        if let Some(other) = slot {
            return Err(file_error(
                path,
                Some(1),
                format!("shard {}/{n} is given twice (also {})", file.shard.k, other.display()),
            ));
        }
        *slot = Some(path);
    }
    let missing: Vec<String> =
        seen.iter().enumerate().filter(|(_, p)| p.is_none()).map(|(k, _)| format!("{}/{n}", k + 1)).collect();
    drop(seen);
    if !missing.is_empty() {
        let list = if missing.len() > 8 {
            format!("{} and {} more", missing[..8].join(", "), missing.len() - 8)
        } else {
            missing.join(", ")
        };
        return Err(file_error(&first_path, None, format!("shards missing from the merge: {list}")));
    }
    let mut rows: Vec<SweepRow> = files.into_iter().flat_map(|(_, f)| f.rows).collect();
    rows.sort_by_key(|r| r.index);
    let points = rows.first().map_or(0, |r| r.points);
    let whole = rows.iter().enumerate().all(|(i, r)| r.index == i && r.points == points);
    if !whole || rows.len() != points {
        return Err(file_error(
            &first_path,
            None,
            format!("the shards hold {} rows, not the run's {points} points", rows.len()),
        ));
    }
    Ok(SweepFile { run, shard: Shard::ALL, rows })
}
