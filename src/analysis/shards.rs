//! Shards of a long deterministic run and their checked files: a run cut into parts `K/N` run
//! anywhere, each written as a CSV table under two comment lines that identify the run and check
//! the rows, and merged back into exactly the unsharded file, refusing whatever does not belong.
//!
//! ```text
//! <magic> run=<hash> shard=K/N rows=<count> checksum=<hash>
//! # run: <every option of the run, in canonical form>
//! column,column,...,check
//! cell,cell,...,<hash>
//! ```
//!
//! `run` is the hash of the `# run:` line's text; each row's `check` is the hash of `run` and the
//! row's other cells; `checksum` is the hash of `run`, the shard, the row count and every row's
//! check. The hash is 64-bit FNV-1a: it guards against files from another run, edited numbers and
//! lost or repeated rows (accidents, not an adversary, who could recompute it). A merged file is
//! written by the same routine with `shard=1/1`, so it equals the unsharded run byte for byte.
//! `mount-sweep` ([`crate::analysis::sweep::file`]) and `track --trials`
//! ([`crate::track::trials_file`]) write such files.

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::error::Error;
use crate::model::InputError;

/// Part `k` of `n` of a run (`k` from 1): the items whose index is `k - 1` modulo `n`
/// (interleaved, so that every shard gets a similar mix of cheap and costly items).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This part, `1..=n`.
    pub k: usize,
    /// Number of parts.
    pub n: usize,
}

/// The largest number of shards `N` of a run, written (`--shard K/N`) or read (a file's
/// `shard=K/N`): far more than any cluster runs at once, and small enough that nothing that scales
/// with `N` (a merge's accounting of the shards) can grow large. A file claiming more is damaged.
pub const MAX_SHARDS: usize = 65_536;

impl Shard {
    /// The whole run.
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Parses `k/n` with `1 <= k <= n <= MAX_SHARDS` ([`MAX_SHARDS`]).
    pub fn parse(text: &str) -> Result<Self, Error> {
        let bad = || {
            Error::from(InputError::InvalidText {
                name: "--shard".into(),
                text: text.to_string(),
                expected: "K/N, two whole numbers with 1 <= K <= N <= 65536 (e.g. 2/8)",
            })
        };
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let (k, n): (usize, usize) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if k == 0 || k > n || n > MAX_SHARDS {
            return Err(bad());
        }
        Ok(Self { k, n })
    }

    /// The indices of this shard among `0..count`.
    pub fn indices(&self, count: usize) -> impl Iterator<Item = usize> + use<> {
        (self.k - 1..count).step_by(self.n)
    }

    /// True when `index` belongs to this shard.
    pub fn holds(&self, index: usize) -> bool {
        index % self.n == self.k - 1
    }
}

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

/// The kind of a shard file: its first words, its name in messages and its CSV columns (the row
/// type's fields, in order; the `check` column follows).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileKind {
    /// The first words of the file, e.g. `# freefloat-sweep v1`.
    pub magic: &'static str,
    /// What the file holds, for messages, e.g. `sweep`.
    pub name: &'static str,
    /// The CSV columns.
    pub columns: &'static [&'static str],
}

/// One shard file, read and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct ShardFile<R> {
    /// The `# run:` description.
    pub run: String,
    /// Which part of the run.
    pub shard: Shard,
    /// The rows, in file order.
    pub rows: Vec<R>,
}

/// The error of a damaged file, or of files that do not fit together: names the file, and the
/// line when one line is at fault.
pub fn file_error(path: &Path, line: Option<usize>, reason: impl Into<String>) -> Error {
    Error::from(InputError::ShardFile { path: path.to_path_buf(), line, reason: reason.into() })
}

/// The rows' CSV lines without the `check` cell (header included, first).
fn csv_lines<R: Serialize>(kind: &FileKind, rows: &[R]) -> Result<Vec<String>, Error> {
    let csv = Path::new("<csv>");
    let csv_error = |e: csv::Error| file_error(csv, None, e.to_string());
    let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
    w.write_record(kind.columns).map_err(csv_error)?;
    for row in rows {
        w.serialize(row).map_err(csv_error)?;
    }
    let bytes = w.into_inner().map_err(|e| file_error(csv, None, e.to_string()))?;
    let text = String::from_utf8(bytes).map_err(|e| file_error(csv, None, e.to_string()))?;
    Ok(text.lines().map(str::to_string).collect())
}

fn checksum(run_hash: &str, shard: Shard, checks: &[String]) -> u64 {
    let head = format!("{run_hash} {}/{} {}", shard.k, shard.n, checks.len());
    checks.iter().fold(hash(&[&head]), |h, c| fnv1a(h, c.as_bytes()))
}

/// The file of `shard` of the run `run`: header lines, the CSV header (always, even for a
/// shard without rows) and one checked row per item.
pub fn write<R: Serialize>(kind: &FileKind, run: &str, shard: Shard, rows: &[R]) -> Result<Vec<u8>, Error> {
    let run_hash = format!("{:016x}", hash(&[run]));
    let lines = csv_lines(kind, rows)?;
    let mut body = format!("{},check\n", lines[0]);
    let mut checks = Vec::with_capacity(rows.len());
    for line in &lines[1..] {
        let check = format!("{:016x}", hash(&[&run_hash, line]));
        body += &format!("{line},{check}\n");
        checks.push(check);
    }
    let sum = checksum(&run_hash, shard, &checks);
    let head = format!(
        "{} run={run_hash} shard={}/{} rows={} checksum={sum:016x}\n# run: {run}\n",
        kind.magic,
        shard.k,
        shard.n,
        rows.len()
    );
    Ok((head + &body).into_bytes())
}

/// The value of `key=` among the whitespace-separated words of `text` (a header, or a `# run:`
/// line of `key=value` words).
pub fn field<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.split_whitespace().find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
}

/// Reads and checks one file: its header, every row's check, the row count and the checksum;
/// `check_row` checks the numbers of each row (finite, within range, of this shard) and says what
/// is wrong. Errors name the file and the line.
pub fn read<R: DeserializeOwned>(
    kind: &FileKind,
    bytes: &[u8],
    path: &Path,
    check_row: impl Fn(&R, &str, Shard) -> Result<(), String>,
) -> Result<ShardFile<R>, Error> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| file_error(path, None, format!("not UTF-8 text (invalid byte at offset {})", e.valid_up_to())))?;
    let mut lines = text.lines();
    let not_ours = || {
        file_error(
            path,
            Some(1),
            format!("not a freefloat {} file: the first line must start with `{}`", kind.name, kind.magic),
        )
    };
    let head = lines.next().and_then(|l| l.strip_prefix(kind.magic)).ok_or_else(not_ours)?;
    let bad_head = |what: &str| file_error(path, Some(1), format!("damaged header: {what}"));
    let run_hash = field(head, "run").ok_or_else(|| bad_head("no run="))?;
    let shard = field(head, "shard")
        .and_then(|s| Shard::parse(s).ok())
        .ok_or_else(|| bad_head("no shard=K/N with 1 <= K <= N <= 65536"))?;
    let count: usize = field(head, "rows").and_then(|s| s.parse().ok()).ok_or_else(|| bad_head("no rows=<count>"))?;
    let sum = field(head, "checksum").ok_or_else(|| bad_head("no checksum="))?;
    let run = lines
        .next()
        .and_then(|l| l.strip_prefix("# run: "))
        .ok_or_else(|| file_error(path, Some(2), "the `# run:` line is missing"))?;
    if format!("{:016x}", hash(&[run])) != run_hash {
        return Err(file_error(path, Some(2), "the `# run:` line does not match the header's run hash (edited)"));
    }
    let header = format!("{},check", kind.columns.join(","));
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
        let row = parse_row(kind, cells, path, number)?;
        check_row(&row, run, shard).map_err(|what| file_error(path, Some(number), what))?;
        rows.push(row);
        checks.push(check.to_string());
    }
    if rows.len() != count {
        return Err(file_error(path, None, format!("the header says {count} rows, the file has {}", rows.len())));
    }
    if format!("{:016x}", checksum(run_hash, shard, &checks)) != sum {
        return Err(file_error(path, Some(1), "the checksum does not match the rows (rows lost, added or moved)"));
    }
    Ok(ShardFile { run: run.to_string(), shard, rows })
}

fn parse_row<R: DeserializeOwned>(kind: &FileKind, cells: &str, path: &Path, line: usize) -> Result<R, Error> {
    let text = format!("{}\n{cells}\n", kind.columns.join(","));
    let mut r = csv::Reader::from_reader(text.as_bytes());
    match r.deserialize::<R>().next() {
        Some(Ok(row)) => Ok(row),
        Some(Err(e)) => Err(file_error(path, Some(line), format!("not a {} row: {e}", kind.name))),
        None => Err(file_error(path, Some(line), "an empty row")),
    }
}

/// The error unless `x` is a finite number: `name = x is not a finite number`.
pub fn finite(name: &str, x: f64) -> Result<(), String> {
    if x.is_finite() { Ok(()) } else { Err(format!("{name} = {x} is not a finite number")) }
}

/// Merges checked files into the whole run: every file of the same run (the same `# run:`
/// line) and the same number of shards, each shard exactly once. The rows are sorted by `key`,
/// then `whole` checks that they are the run's, each item once (and says what is wrong).
/// Returns the merged file (`shard = 1/1`), equal to the unsharded run's.
pub fn merge_files<R, K: Ord>(
    files: Vec<(PathBuf, ShardFile<R>)>,
    key: impl Fn(&R) -> K,
    whole: impl Fn(&str, &[R]) -> Result<(), String>,
) -> Result<ShardFile<R>, Error> {
    let Some((first_path, first)) = files.first() else {
        return Err(file_error(Path::new("<merge>"), None, "no files to merge"));
    };
    let (first_path, run, n) = (first_path.clone(), first.run.clone(), first.shard.n);
    // The shards given, by part: at most one entry per file, never one per shard of the run.
    let mut seen: std::collections::BTreeMap<usize, &Path> = std::collections::BTreeMap::new();
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
        if let Some(other) = seen.insert(file.shard.k, path) {
            return Err(file_error(
                path,
                Some(1),
                format!("shard {}/{n} is given twice (also {})", file.shard.k, other.display()),
            ));
        }
    }
    if seen.len() < n {
        let list = missing_shards(seen.keys().copied(), n);
        return Err(file_error(&first_path, None, format!("shards missing from the merge: {list}")));
    }
    drop(seen);
    let mut rows: Vec<R> = files.into_iter().flat_map(|(_, f)| f.rows).collect();
    rows.sort_by_key(&key);
    whole(&run, &rows).map_err(|what| file_error(&first_path, None, what))?;
    Ok(ShardFile { run, shard: Shard::ALL, rows })
}

/// The shards of `1..=n` not among `given` (ascending), in words: `3/3`, or ranges
/// `2/10 to 5/10, 7/10`, at most eight ranges and then the count of the rest. Its work and memory
/// go with the shards given, not with `n`.
fn missing_shards(given: impl Iterator<Item = usize>, n: usize) -> String {
    let mut ranges: Vec<String> = Vec::new();
    let (mut next, mut missing, mut more) = (1, 0, 0);
    let mut gap = |from: usize, to: usize, ranges: &mut Vec<String>| {
        if from > to {
            return;
        }
        missing += to - from + 1;
        if ranges.len() == 8 {
            more += to - from + 1;
        } else if from == to {
            ranges.push(format!("{from}/{n}"));
        } else {
            ranges.push(format!("{from}/{n} to {to}/{n}"));
        }
    };
    for k in given {
        gap(next, k - 1, &mut ranges);
        next = k + 1;
    }
    gap(next, n, &mut ranges);
    let list = ranges.join(", ");
    if more > 0 { format!("{list} and {more} more ({missing} of {n} shards)") } else { list }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Missing shards as ranges, cut after eight (issue 24 item 3: `1/18446744073709551615`
    /// must not allocate per shard).
    #[test]
    fn missing_shards_are_ranges() {
        assert_eq!(missing_shards([1, 2].into_iter(), 3), "3/3");
        assert_eq!(missing_shards([1, 6].into_iter(), 10), "2/10 to 5/10, 7/10 to 10/10");
        let every_other = missing_shards((1..=40).map(|k| 2 * k - 1), 80);
        assert!(every_other.ends_with("16/80 and 32 more (40 of 80 shards)"), "{every_other}");
        assert_eq!(missing_shards([1].into_iter(), MAX_SHARDS), "2/65536 to 65536/65536");
        assert!(Shard::parse("1/65536").is_ok());
        for bad in ["1/65537", "1/18446744073709551615", "1/100000000", "0/1", "2/1"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
