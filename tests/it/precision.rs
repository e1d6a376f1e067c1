//! Numbers in the human-readable outputs have sensible precision (issue 15): no float noise
//! (`53.58170147727351`, `180.0000`), no exponent where fixed notation reads better (`1.21e0`,
//! `6.1e-2`, `0.000e0`). JSON and CSV keep full precision: they are for machines.

use std::process::Command;

/// The words of `text` that are numbers in decimal or scientific notation (integers excluded).
fn decimals(text: &str) -> Vec<String> {
    text.split(|c: char| c.is_whitespace() || "(),;[]|=/<>:".contains(c))
        .map(|w| w.trim_end_matches(['.', '%']))
        .filter(|w| w.chars().any(|c| c.is_ascii_digit()) && w.contains(['.', 'e', 'E']) && w.parse::<f64>().is_ok())
        .map(str::to_string)
        .collect()
}

/// Why `word` (a number) reads badly, if it does: more than 6 significant digits, or an
/// exponent from -2 to 3, with a sign or with a leading zero (fixed notation reads better there,
/// or the exponent is padded).
fn flaw(word: &str) -> Option<&'static str> {
    let lower = word.to_ascii_lowercase();
    let (mantissa, exponent) = match lower.split_once('e') {
        Some((m, e)) => (m, Some(e)),
        None => (lower.as_str(), None),
    };
    if let Some(e) = exponent {
        if e.starts_with('+') || e.starts_with('0') || e.starts_with("-0") {
            return Some("a padded or signed exponent");
        }
        if e.parse::<i32>().is_ok_and(|e| (-2..=3).contains(&e)) {
            return Some("an exponent where fixed notation reads better");
        }
    }
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    if mantissa.contains('.') && digits.trim_start_matches('0').len() > 6 {
        return Some("more than 6 significant digits");
    }
    None
}

/// What a person reads of a run: stdout and stderr, except `mount-sweep`'s stdout (its CSV, for
/// machines).
fn output(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs");
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    let machine = args.first() == Some(&"mount-sweep") && !args.contains(&"--help");
    let stdout = if machine { String::new() } else { String::from_utf8_lossy(&o.stdout).into_owned() };
    stdout + &String::from_utf8_lossy(&o.stderr)
}

/// The scanner itself: it flags what issue 15 lists and passes what reads well.
#[test]
fn the_scanner_flags_noise_and_needless_exponents() {
    for bad in ["53.58170147727351", "180.0000", "1.21e0", "6.1e-2", "0.000e0", "+1.180e-2", "1e+10", "1e-09"] {
        assert!(flaw(bad).is_some(), "{bad}");
    }
    for good in ["53.5817", "0.382435", "1.339e-12", "0.061", "1e-9", "+4.349e-9", "1.0", "1e300"] {
        assert_eq!(flaw(good), None, "{good}");
    }
    assert_eq!(
        decimals("horizon 10 s, error 1.3e-12 rad (tolerance 1e-9). q = (45, 120.5)"),
        ["1.3e-12", "1e-9", "120.5"]
    );
}

/// `plan` (the optimal planner, the ECSA, with torques), `compare`, `domain` and `track` (single
/// runs and Monte Carlo) print no number with float noise or a needless exponent, nor does any
/// `--help`.
#[test]
fn tables_print_numbers_with_sensible_precision() {
    let runs: [&[&str]; 10] = [
        &["plan"],
        &["plan", "--method", "ecsa"],
        &["plan", "--method", "nfa", "--torques", "--samples", "201"],
        &["plan", "--time", "53.58170147727351", "--samples", "201"],
        &["compare"],
        &["domain", "--grid", "240"],
        &["track"],
        &["track", "--controller", "open,ct", "--perturb", "0.05"],
        &["track", "--controller", "open,ct", "--perturb", "0.05", "--trials", "3"],
        &["mount-sweep", "--steps", "2", "--grid", "32", "--trials", "2", "--samples", "51"],
    ];
    let mut flaws = Vec::new();
    for args in runs {
        for word in decimals(&output(args)) {
            if let Some(why) = flaw(&word) {
                flaws.push(format!("{args:?}: {word} ({why})"));
            }
        }
    }
    for command in ["plan", "compare", "domain", "mount-sweep", "track", "reproduce"] {
        for word in decimals(&output(&[command, "--help"])) {
            if let Some(why) = flaw(&word) {
                flaws.push(format!("{command} --help: {word} ({why})"));
            }
        }
    }
    assert!(flaws.is_empty(), "{flaws:#?}");
}

/// Error messages print their numbers the same way (they used to say `(45.0000, 120.0000,
/// 0.0000) deg` and `value 0.000e0`).
#[test]
fn error_messages_print_numbers_with_sensible_precision() {
    let runs: [&[&str]; 3] = [
        &["plan", "--method", "nfa", "--transform", "eq12", "--from", "45,120,0"],
        &["plan", "--tolerance", "1e-15"],
        &["plan", "--robot", "/no/such/robot.toml"],
    ];
    let mut flaws = Vec::new();
    for args in runs {
        let o = Command::new(env!("CARGO_BIN_EXE_freefloat")).args(args).output().expect("the binary runs");
        assert!(!o.status.success(), "{args:?} should fail");
        let text = String::from_utf8_lossy(&o.stderr);
        for word in decimals(&text) {
            if let Some(why) = flaw(&word) {
                flaws.push(format!("{args:?}: {word} ({why}) in {text}"));
            }
        }
    }
    assert!(flaws.is_empty(), "{flaws:#?}");
}
