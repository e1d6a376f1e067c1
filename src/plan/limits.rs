//! The bounds of every request (docs/spec.md §3, "Budgets"): one place, checked by the library's
//! option types (`validate`) and so by every front end, the command line and Python alike. A
//! front end may call a check early with its own name for the value (`--samples`, `samples`);
//! the bound and the message are the same.

use crate::error::Error;
use crate::model::InputError;

/// The most memory a request may need \[bytes\] (1 GiB): beyond it, freefloat refuses up front
/// with the estimate instead of growing until the system kills it.
pub const MEMORY_LIMIT: u128 = 1 << 30;

/// Memory of one trajectory sample, everything counted \[bytes\]: the trajectory's 15 columns,
/// the planners' work arrays, and the CSV or JSON text of the sample (generous).
pub const BYTES_PER_SAMPLE: u128 = 1024;

/// Most samples of a trajectory: [`MEMORY_LIMIT`] / [`BYTES_PER_SAMPLE`] = 1,048,576.
pub const MAX_SAMPLES: u64 = (MEMORY_LIMIT / BYTES_PER_SAMPLE) as u64;

/// Largest verified final error a certificate may accept \[rad\].
pub const MAX_TOLERANCE: f64 = 1e-3;

fn bad(name: &str, value: f64, expected: &'static str) -> Error {
    Error::from(InputError::InvalidParameter { name: name.into(), value, expected })
}

/// `n` samples of a trajectory, named `name` in the error: at least 2 (both ends), at most
/// [`MAX_SAMPLES`] (the memory of [`BYTES_PER_SAMPLE`] each within [`MEMORY_LIMIT`]).
pub fn check_samples(name: &str, n: u64) -> Result<usize, Error> {
    if n < 2 {
        return Err(bad(name, n as f64, "at least 2 samples (both ends of the trajectory)"));
    }
    check_memory(&format!("{name} {n}"), u128::from(n) * BYTES_PER_SAMPLE, &format!("at most {MAX_SAMPLES} samples"))?;
    usize::try_from(n).map_err(|_| bad(name, n as f64, "a count this machine can address"))
}

/// A certificate's tolerance \[rad\], named `name` in the error: finite, positive, at most
/// [`MAX_TOLERANCE`].
pub fn check_tolerance(name: &str, x: f64) -> Result<f64, Error> {
    if x.is_finite() && x > 0.0 && x <= MAX_TOLERANCE {
        Ok(x)
    } else {
        Err(bad(name, x, "a positive tolerance of at most 1e-3 rad (docs/spec.md §2)"))
    }
}

/// `bytes`, the estimated memory of `what`, within [`MEMORY_LIMIT`]; else
/// [`InputError::TooMuchMemory`] with the estimate and `hint` (what is accepted).
pub fn check_memory(what: &str, bytes: u128, hint: &str) -> Result<(), Error> {
    if bytes > MEMORY_LIMIT {
        return Err(Error::from(InputError::TooMuchMemory {
            what: what.to_string(),
            bytes,
            limit: MEMORY_LIMIT,
            hint: hint.to_string(),
        }));
    }
    Ok(())
}
