//! Numbers as people read them (issue 15; `report::numbers` re-exports them, and the errors use
//! them too): at most six significant digits, no float noise (`53.5817`, not
//! `53.58170147727351`), fixed notation where it reads better than an exponent
//! (`1.21`, not `1.21e0`; `0.061`, not `6.1e-2`), scientific notation for the very small and the
//! very large (`1.339e-12`). Machine outputs (JSON, CSV) keep full precision and do not use these.

/// `x` with at most `digits` significant digits (1 to 17), no trailing zeros, scientific notation
/// below 1e-4 and from 1e6 in absolute value (`significant(53.58170147727351, 6) == "53.5817"`).
///
/// ```
/// use freefloat::numerics::format::significant;
///
/// assert_eq!(significant(53.58170147727351, 6), "53.5817");
/// assert_eq!(significant(1e-9, 6), "1e-9");
/// assert_eq!(significant(-0.0, 6), "0");
/// ```
pub fn significant(x: f64, digits: usize) -> String {
    let digits = digits.clamp(1, 17);
    let a = x.abs();
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return format!("{x}");
    }
    if !(1e-4..1e6).contains(&a) {
        let s = format!("{x:.prec$e}", prec = digits - 1);
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim(mantissa));
    }
    let decimals = (digits as i32 - 1 - a.log10().floor() as i32).clamp(0, 17) as usize;
    let s = trim(&format!("{x:.decimals$}"));
    if s == "-0" { "0".into() } else { s }
}

/// Trailing zeros (and a trailing point) of a decimal fraction removed.
fn trim(s: &str) -> String {
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s.to_string() }
}

/// A number as a table shows it: [`significant`] to 6 digits (`53.5817`, `0.2`, `1e-9`).
pub fn number(x: f64) -> String {
    significant(x, 6)
}

/// `x` rounded to `decimals` places and shown by [`number`]: `rounded(179.99999, 4) == "180"`,
/// `rounded(-1e-13, 4) == "0"`.
pub fn rounded(x: f64, decimals: i32) -> String {
    let scale = 10f64.powi(decimals.clamp(0, 12));
    let r = (x * scale).round() / scale;
    // `+ 0.0` turns -0 into 0.
    number(if r.is_finite() { r + 0.0 } else { x })
}

/// An error, a residual or a small quantity: fixed between 1e-3 and 1e4 (`1.21`, `0.061`, with
/// `digits + 1` significant digits), else scientific with `digits` decimals (`9.290e-13`).
pub fn scientific(x: f64, digits: usize) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&x.abs()) {
        significant(x, digits + 1)
    } else {
        format!("{x:.digits$e}")
    }
}

/// An error or residual: [`scientific`] with 3 decimals (`1.21`, not `1.210e0`; `9.290e-13`).
pub fn error_number(x: f64) -> String {
    scientific(x, 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_well() {
        assert_eq!(number(53.58170147727351), "53.5817");
        assert_eq!(number(10.0), "10");
        assert_eq!(number(0.1 + 0.2), "0.3");
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-2.5e-7), "-2.5e-7");
        assert_eq!(rounded(179.99999, 4), "180");
        assert_eq!(rounded(-1e-13, 4), "0");
        assert_eq!(rounded(123.456789, 4), "123.457");
        assert_eq!(error_number(1.21), "1.21");
        assert_eq!(error_number(9.29e-13), "9.290e-13");
        assert_eq!(scientific(6.1e-2, 1), "0.061");
        assert_eq!(scientific(0.0, 3), "0");
        assert_eq!(significant(1234.5678, 4), "1235");
    }
}
