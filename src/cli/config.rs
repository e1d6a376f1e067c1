//! Raw flags checked into bounded values (docs/spec.md §3): every number the command line takes
//! is parsed into a checked type with an upper bound, and every request's memory is estimated
//! before anything is allocated. Errors name the flag as the user wrote it (exit code 2).

use freefloat::model::{InputError, excerpt};

pub use freefloat::plan::limits::MEMORY_LIMIT;

/// Memory of one mounting point of a sweep \[bytes\]: its row and its CSV line (generous).
pub const BYTES_PER_POINT: u128 = 1024;

/// Accepted `--max-velocity` caps \[rad/s\].
pub const MAX_VELOCITY_RANGE: (f64, f64) = (1e-3, 1e3);

/// Largest number of values of `a` or `b` in a sweep (`--steps`).
pub const MAX_STEPS: u32 = 100_000;

fn bad(name: &str, value: f64, expected: &'static str) -> anyhow::Error {
    freefloat::Error::from(InputError::InvalidParameter { name: name.into(), value, expected }).into()
}

/// `--samples N`: the library's bound ([`freefloat::plan::limits::check_samples`]).
pub fn samples(n: u64) -> anyhow::Result<usize> {
    Ok(freefloat::plan::limits::check_samples("--samples", n)?)
}

/// `--tolerance RAD`: the library's bound ([`freefloat::plan::limits::check_tolerance`]).
pub fn tolerance(x: f64) -> anyhow::Result<f64> {
    Ok(freefloat::plan::limits::check_tolerance("--tolerance", x)?)
}

/// `--time T`: within [`freefloat::plan::HORIZON_RANGE`].
pub fn time(t: f64) -> anyhow::Result<f64> {
    if t.is_infinite() && t > 0.0 {
        anyhow::bail!(
            "--time auto: the shortest horizon is searched by `plan` for an arm with velocity, acceleration or \
             torque limits (docs/spec.md §3); give the horizon T in s here"
        );
    }
    freefloat::plan::check_horizon("--time", t)?;
    Ok(t)
}

/// `--max-velocity`: within [`MAX_VELOCITY_RANGE`].
pub fn max_velocity(v: Option<f64>) -> anyhow::Result<Option<f64>> {
    let (min, max) = MAX_VELOCITY_RANGE;
    match v {
        Some(v) if !(v.is_finite() && (min..=max).contains(&v)) => {
            Err(bad("--max-velocity", v, "a cap from 1e-3 to 1e3 rad/s (docs/spec.md §3)"))
        }
        v => Ok(v),
    }
}

/// Largest `|angle|` of `--from`/`--to` \[deg\]: [`freefloat::plan::MAX_ANGLE`] in degrees.
pub fn max_angle_deg() -> f64 {
    freefloat::plan::MAX_ANGLE.to_degrees()
}

/// `--from`/`--to PHI,TH1,TH2` in degrees, each within [`max_angle_deg`].
pub fn angles(flag: &str, text: &str) -> anyhow::Result<freefloat::Configuration> {
    let q = super::parse_list::<3>(flag, text)?;
    for x in q {
        if x.abs() > max_angle_deg() {
            return Err(bad(flag, x, "angles with |angle| <= 572957 deg (1e4 rad, docs/spec.md §2)"));
        }
    }
    Ok(freefloat::Configuration::from_degrees(q[0], q[1], q[2]))
}

/// `count` angles in degrees of `flag` (`PHI,TH1,..,THn` of an `n = count - 1`-link arm), in
/// radians, each within [`max_angle_deg`]; the wrong count is bad input naming the flag.
pub fn arm_angles(flag: &str, text: &str, count: usize) -> anyhow::Result<Vec<f64>> {
    let values = super::parse_numbers(flag, text)?;
    let n = count.saturating_sub(1);
    if values.len() != count {
        anyhow::bail!(
            "{flag} takes {count} comma-separated angles for this {n}-link arm (PHI,TH1,..,TH{n} in deg), got {}{}",
            values.len(),
            if values.len() == 3 { "; the default is the 2-link paper's problem" } else { "" }
        );
    }
    if let Some(&x) = values.iter().find(|x| x.abs() > max_angle_deg()) {
        return Err(freefloat::Error::from(freefloat::model::InputError::InvalidParameter {
            name: flag.into(),
            value: x,
            expected: "angles with |angle| <= 572957 deg (1e4 rad, docs/spec.md §2)",
        })
        .into());
    }
    Ok(values.iter().map(|x| x.to_radians()).collect())
}

/// `--steps NA[,NB]`: one or two counts from 1 to [`MAX_STEPS`]; `(NA, NB)`.
pub fn steps(text: &str) -> anyhow::Result<(usize, usize)> {
    let invalid = || -> anyhow::Error {
        freefloat::Error::from(InputError::InvalidText {
            name: "--steps".into(),
            text: text.to_string(),
            expected: "NA or NA,NB: whole numbers from 1 to 100000",
        })
        .into()
    };
    let counts: Vec<u32> = text
        .split(',')
        .map(|s| s.trim().parse::<u32>().ok().filter(|n| (1..=MAX_STEPS).contains(n)).ok_or_else(invalid))
        .collect::<anyhow::Result<_>>()?;
    match counts[..] {
        [n] => Ok((n as usize, n as usize)),
        [na, nb] => Ok((na as usize, nb as usize)),
        _ => Err(invalid()),
    }
}

/// The memory of a sweep of `points` mounting points, checked against [`MEMORY_LIMIT`].
pub fn sweep_points(na: usize, nb: usize) -> anyhow::Result<()> {
    let points = na as u128 * nb as u128;
    let bytes = points * BYTES_PER_POINT;
    if bytes > MEMORY_LIMIT {
        return Err(freefloat::Error::from(InputError::TooMuchMemory {
            what: format!("--steps {na},{nb} ({points} mounting points)"),
            bytes,
            limit: MEMORY_LIMIT,
            hint: format!("at most {} points", MEMORY_LIMIT / BYTES_PER_POINT),
        })
        .into());
    }
    Ok(())
}

/// The text of a flag as an error quotes it: cut to a few dozen characters.
pub fn quote(text: &str) -> String {
    excerpt(text)
}

/// The path as the file system resolves it, for comparing outputs: the file itself when it
/// exists (symbolic links followed), else its resolved directory joined with its name.
fn resolved(path: &std::path::Path) -> std::path::PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    match (dir.canonicalize(), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => path.to_path_buf(),
    }
}

/// The output files of one command, `(flag, path)`, on distinct paths (after resolving `.`,
/// `..` and symbolic links): two outputs on one path would overwrite each other (exit 2).
pub fn distinct_outputs(outputs: &[(&str, Option<&std::path::Path>)]) -> anyhow::Result<()> {
    let given: Vec<(&str, &std::path::Path, std::path::PathBuf)> =
        outputs.iter().filter_map(|(flag, p)| p.map(|p| (*flag, p, resolved(p)))).collect();
    for (i, (flag, path, r)) in given.iter().enumerate() {
        if let Some((first, _, _)) = given[..i].iter().find(|(_, _, q)| q == r) {
            return Err(anyhow::Error::from(freefloat::Error::from(InputError::InvalidText {
                name: (*flag).into(),
                text: path.display().to_string(),
                expected: "another file than the command's other outputs (two outputs on one path overwrite each other)",
            }))
            .context(format!("{flag} and {first} name the same file")));
        }
    }
    Ok(())
}

/// The output files of one command, `(flag, path)`, apart from its input files `(what, path)`
/// (after resolving `.`, `..` and symbolic links): writing an output onto an input would replace
/// a file freefloat did not write, e.g. the trajectory `check` reads or a shard `merge` reads
/// (exit 2, before any work).
pub fn outputs_apart_from_inputs(
    outputs: &[(&str, Option<&std::path::Path>)],
    inputs: &[(&str, &std::path::Path)],
) -> anyhow::Result<()> {
    let inputs: Vec<(&str, std::path::PathBuf)> = inputs.iter().map(|(what, p)| (*what, resolved(p))).collect();
    for (flag, path) in outputs.iter().filter_map(|(flag, p)| p.map(|p| (*flag, p))) {
        let r = resolved(path);
        if let Some((what, _)) = inputs.iter().find(|(_, q)| *q == r) {
            return Err(anyhow::Error::from(freefloat::Error::from(InputError::InvalidText {
                name: flag.into(),
                text: path.display().to_string(),
                expected: "a file other than the command's inputs (writing it would replace an input; choose another name)",
            }))
            .context(format!("{flag} names an input of the command ({what})")));
        }
    }
    Ok(())
}

/// A CSV output `--out FILE.csv` (any case) of `command`, else bad input naming it.
pub fn csv_out(command: &str, path: &std::path::Path) -> anyhow::Result<()> {
    if path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
        return Ok(());
    }
    Err(anyhow::Error::from(freefloat::Error::from(InputError::InvalidText {
        name: "--out".into(),
        text: path.display().to_string(),
        expected: "a file name ending in .csv",
    }))
    .context(format!("{command} writes CSV")))
}

/// `--method`'s value as the library's [`freefloat::Method`].
impl From<super::args::MethodArg> for freefloat::Method {
    fn from(m: super::args::MethodArg) -> Self {
        match m {
            super::args::MethodArg::Nfa => freefloat::Method::Nfa,
            super::args::MethodArg::Ecsa => freefloat::Method::Ecsa,
            super::args::MethodArg::Optimal => freefloat::Method::Optimal,
        }
    }
}

/// `--time`: a number of seconds, or `auto`, kept as `+inf` (no horizon is infinite:
/// [`time`] refuses it for every command but `plan` of an arm, which searches).
pub(super) fn parse_time(text: &str) -> Result<f64, String> {
    if text.trim().eq_ignore_ascii_case("auto") {
        return Ok(f64::INFINITY);
    }
    match text.trim().parse::<f64>() {
        Ok(t) if t.is_infinite() => Err(format!("`{text}` is not a horizon: give T in s (1e-3 to 1e6) or `auto`")),
        Ok(t) => Ok(t),
        Err(_) => Err(format!("`{text}` is neither a horizon in s nor `auto`")),
    }
}
