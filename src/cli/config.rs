//! Raw flags checked into bounded values (docs/spec.md §3): every number the command line takes
//! is parsed into a checked type with an upper bound, and every request's memory is estimated
//! before anything is allocated. Errors name the flag as the user wrote it (exit code 2).

use freefloat::model::{InputError, excerpt};

/// The most memory a request may need \[bytes\]: beyond it, freefloat refuses up front instead of
/// growing until the system kills it.
pub const MEMORY_LIMIT: u128 = 1 << 30;

/// Memory of one trajectory sample, everything counted \[bytes\]: the trajectory's 15 columns,
/// the planners' work arrays, and the CSV or JSON text of the sample (generous).
pub const BYTES_PER_SAMPLE: u128 = 1024;

/// Memory of one mounting point of a sweep \[bytes\]: its row and its CSV line (generous).
pub const BYTES_PER_POINT: u128 = 1024;

/// Largest verified final error a certificate may accept \[rad\] (`--tolerance`).
pub const MAX_TOLERANCE: f64 = 1e-3;

/// Accepted `--max-velocity` caps \[rad/s\].
pub const MAX_VELOCITY_RANGE: (f64, f64) = (1e-3, 1e3);

/// Largest number of values of `a` or `b` in a sweep (`--steps`).
pub const MAX_STEPS: u32 = 100_000;

fn bad(name: &str, value: f64, expected: &'static str) -> anyhow::Error {
    freefloat::Error::from(InputError::InvalidParameter { name: name.into(), value, expected }).into()
}

/// `--samples N`: at least 2 (both ends), at most what [`MEMORY_LIMIT`] holds.
pub fn samples(n: u64) -> anyhow::Result<usize> {
    if n < 2 {
        return Err(bad("--samples", n as f64, "at least 2 samples (both ends of the trajectory)"));
    }
    let bytes = u128::from(n) * BYTES_PER_SAMPLE;
    if bytes > MEMORY_LIMIT {
        return Err(freefloat::Error::from(InputError::TooMuchMemory {
            what: format!("--samples {n}"),
            bytes,
            limit: MEMORY_LIMIT,
            hint: format!("at most {} samples", MEMORY_LIMIT / BYTES_PER_SAMPLE),
        })
        .into());
    }
    usize::try_from(n).map_err(|_| bad("--samples", n as f64, "a count this machine can address"))
}

/// `--tolerance RAD`: finite, positive, at most [`MAX_TOLERANCE`].
pub fn tolerance(x: f64) -> anyhow::Result<f64> {
    if x.is_finite() && x > 0.0 && x <= MAX_TOLERANCE {
        Ok(x)
    } else {
        Err(bad("--tolerance", x, "a positive tolerance of at most 1e-3 rad (docs/spec.md §2)"))
    }
}

/// `--time T`: within [`freefloat::plan::HORIZON_RANGE`].
pub fn time(t: f64) -> anyhow::Result<f64> {
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
