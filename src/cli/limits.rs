//! `--limit KEY=VALUE` (issue 20; docs/spec.md §3): the robot's limits from the command line,
//! over the robot file's. Degrees as every angle at the command line; torques in N m.
//!
//! | key | value |
//! | --- | --- |
//! | `thetaK.position`, `phi.position` | `LO:HI` \[deg\] |
//! | `thetaK.velocity` | \[deg/s\] |
//! | `thetaK.torque` | \[N m\] |
//! | `thetaK.acceleration` | \[deg/s^2\] |
//! | `thetaK`, `phi` (no quantity) | `none`: drop every limit of the joint (of the base) |
//!
//! `K` counts the joints from 1; `all.QUANTITY` sets (or with `none` drops) the quantity of every
//! joint; any quantity takes `none` too. The flags apply in the order given.

use clap::Args;
use freefloat::model::InputError;
use freefloat::model::arm::collision::Geometry;
use freefloat::model::arm::{Arm, JointLimits, Limits};
use freefloat::numerics::ode::OdeOptions;
use freefloat::plan::certificate::verify_on_arm;
use freefloat::plan::limit_use::{LimitReport, Quantity};
use freefloat::report::numbers::{number, rounded};

/// The `--limit` flags (flattened into the robot's flags).
#[derive(Debug, Args, Clone, Default)]
pub struct LimitArgs {
    /// A limit over the robot file's, KEY=VALUE, repeatable (docs/spec.md §3): e.g.
    /// theta2.position=-120:120 [deg], theta2.velocity=20 [deg/s], theta2.torque=50 [N m],
    /// theta2.acceleration=90 [deg/s^2], phi.position=-30:60 [deg], all.velocity=30,
    /// theta2=none (drops the joint's limits).
    #[arg(long = "limit", value_name = "KEY=VALUE", allow_hyphen_values = true)]
    pub limit: Vec<String>,
}

/// The flag's error: exit 2 naming the flag, the text and what is expected.
fn bad(text: &str, expected: &'static str) -> anyhow::Error {
    freefloat::Error::from(InputError::InvalidText {
        name: "--limit".into(),
        text: super::config::quote(text),
        expected,
    })
    .into()
}

const EXPECTED_KEY: &str = "KEY=VALUE with KEY thetaK.QUANTITY, all.QUANTITY or phi.position (K from 1; QUANTITY \
                            position, velocity, torque or acceleration), or thetaK=none / phi=none";

/// What one joint's `QUANTITY=VALUE` does.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Change {
    Position(Option<[f64; 2]>),
    Velocity(Option<f64>),
    Torque(Option<f64>),
    Acceleration(Option<f64>),
    Everything,
}

impl Change {
    fn apply(self, j: &mut JointLimits) {
        match self {
            Change::Position(p) => j.position = p,
            Change::Velocity(v) => j.velocity = v,
            Change::Torque(t) => j.torque = t,
            Change::Acceleration(a) => j.acceleration = a,
            Change::Everything => *j = JointLimits::default(),
        }
    }
}

/// A positive finite number of `value`, scaled to SI by `scale`; `none` is `None`.
fn positive(flag: &str, value: &str, scale: f64, expected: &'static str) -> anyhow::Result<Option<f64>> {
    if value == "none" {
        return Ok(None);
    }
    match value.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(x * scale)),
        _ => Err(bad(flag, expected)),
    }
}

/// `LO:HI` \[deg\] as a range \[rad\] with `LO < HI`; `none` is `None`.
fn range(flag: &str, value: &str) -> anyhow::Result<Option<[f64; 2]>> {
    const EXPECTED: &str = "a position range LO:HI in deg with LO < HI, both finite (or none)";
    if value == "none" {
        return Ok(None);
    }
    let Some((lo, hi)) = value.split_once(':') else { return Err(bad(flag, EXPECTED)) };
    match (lo.trim().parse::<f64>(), hi.trim().parse::<f64>()) {
        (Ok(lo), Ok(hi)) if lo.is_finite() && hi.is_finite() && lo < hi => Ok(Some([lo.to_radians(), hi.to_radians()])),
        _ => Err(bad(flag, EXPECTED)),
    }
}

/// `limits` of an `n`-joint arm with the flags applied in order.
pub fn apply(mut limits: Limits, n: usize, flags: &[String]) -> anyhow::Result<Limits> {
    for flag in flags {
        let Some((key, value)) = flag.split_once('=') else { return Err(bad(flag, EXPECTED_KEY)) };
        let (who, quantity) = match key.split_once('.') {
            Some((who, q)) => (who.trim(), Some(q.trim())),
            None => (key.trim(), None),
        };
        let value = value.trim();
        if who == "phi" {
            limits.base = match quantity {
                Some("position") | None if value == "none" => None,
                Some("position") => range(flag, value)?,
                _ => return Err(bad(flag, "phi.position=LO:HI in deg or phi=none: the base has a range only")),
            };
            continue;
        }
        let change = match quantity {
            None if value == "none" => Change::Everything,
            None => return Err(bad(flag, EXPECTED_KEY)),
            Some("position") => Change::Position(range(flag, value)?),
            Some("velocity") => {
                Change::Velocity(positive(flag, value, 1f64.to_radians(), "a velocity limit > 0 in deg/s (or none)")?)
            }
            Some("torque") => Change::Torque(positive(flag, value, 1.0, "a torque limit > 0 in N m (or none)")?),
            Some("acceleration") => Change::Acceleration(positive(
                flag,
                value,
                1f64.to_radians(),
                "an acceleration limit > 0 in deg/s^2 (or none)",
            )?),
            Some(_) => return Err(bad(flag, EXPECTED_KEY)),
        };
        let joints: Vec<usize> = if who == "all" {
            (0..n).collect()
        } else {
            match who.strip_prefix("theta").and_then(|k| k.parse::<usize>().ok()) {
                Some(k) if (1..=n).contains(&k) => vec![k - 1],
                Some(_) => return Err(bad(flag, "a joint theta1 .. thetaN of this arm (N its number of links)")),
                None => return Err(bad(flag, EXPECTED_KEY)),
            }
        };
        if limits.joints.is_empty() {
            limits.joints = vec![JointLimits::default(); n];
        }
        for k in joints {
            change.apply(&mut limits.joints[k]);
        }
    }
    if limits.joints.iter().all(JointLimits::is_empty) {
        limits.joints.clear();
    }
    Ok(limits)
}

/// `arm` with the flags applied over its own limits.
pub fn with_flags(arm: Arm, args: &LimitArgs) -> anyhow::Result<Arm> {
    if args.limit.is_empty() {
        return Ok(arm);
    }
    let limits = apply(arm.limits.clone(), arm.joints(), &args.limit)?;
    Ok(arm.with_limits(limits)?)
}

/// The table's line of the most-used limit (empty without limits): e.g. `limits  theta2
/// velocity at 97.1 % (17.5 of 18 deg/s at t = 4.2 s), 12 limits  INSIDE`.
pub fn table_line(report: &LimitReport) -> String {
    let Some(u) = report.most_used() else { return String::new() };
    let (scale, unit) = match u.quantity {
        Quantity::Position => (1f64.to_degrees(), "deg"),
        Quantity::Velocity => (1f64.to_degrees(), "deg/s"),
        Quantity::Acceleration => (1f64.to_degrees(), "deg/s^2"),
        Quantity::Torque => (1.0, "N m"),
    };
    let limit = match u.quantity {
        Quantity::Position => format!("range {}:{}", number(u.limit[0] * scale), number(u.limit[1] * scale)),
        _ => format!("limit {}", number(u.limit[1] * scale)),
    };
    format!(
        "  limits                   most used {} {} at {} % ({} {unit} at t = {} s, {limit}), {} limit(s)  {}\n",
        u.name,
        u.quantity.name(),
        rounded(100.0 * u.used, 4),
        rounded(u.value * scale, 6),
        rounded(u.time, 4),
        report.uses.len(),
        if report.inside { "INSIDE" } else { "OUTSIDE: NOT CERTIFIED" }
    )
}

/// The checks of a 2-link plan that its planner's certificate cannot make (the 2-link robot's
/// parameters carry neither shapes nor limits; the NFA's plans, which the n-joint pipeline does
/// not serve): its motion integrated once more on the robot as an arm, `limited` (the robot
/// file's 2-link arm with its limits) or the parameters' arm, with `geometry`. The clearance goes
/// into the plan's verification (so that [`freefloat::planners::Planned::certified`] refuses a
/// collision); the use of the limits is returned when `limited` is given. Nothing is integrated
/// without shapes or limits.
pub fn two_link_checks(
    limited: Option<&Arm>,
    geometry: Geometry,
    planned: &mut freefloat::planners::Planned,
) -> anyhow::Result<Option<LimitReport>> {
    if limited.is_none() && geometry.is_empty() {
        return Ok(None);
    }
    let problem = &planned.plan.problem;
    let arm = limited.cloned().unwrap_or_else(|| Arm::from_params(&problem.robot)).with_geometry(geometry)?;
    let tolerance = planned.plan.verification.tolerance;
    let v = verify_on_arm(planned.motion.as_ref(), problem, &arm, &OdeOptions::default(), tolerance)?;
    planned.plan.verification.clearance = v.clearance;
    Ok(limited.map(|_| v.limits.unwrap_or_else(LimitReport::empty)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flags(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn limit_flags_set_and_drop_limits_in_si() {
        let limits = apply(
            Limits::default(),
            3,
            &flags(&[
                "theta2.position=-120:120",
                "theta2.velocity=20",
                "theta2.torque=50",
                "theta2.acceleration=90",
                "phi.position=-30:60",
                "all.velocity=30",
                "theta3.velocity=none",
            ]),
        )
        .unwrap();
        let r = |d: f64| d.to_radians();
        assert_eq!(limits.base, Some([r(-30.0), r(60.0)]));
        assert_eq!(limits.joints[0], JointLimits { velocity: Some(r(30.0)), ..JointLimits::default() });
        assert_eq!(
            limits.joints[1],
            JointLimits {
                position: Some([r(-120.0), r(120.0)]),
                velocity: Some(r(30.0)),
                torque: Some(50.0),
                acceleration: Some(r(90.0))
            }
        );
        assert!(limits.joints[2].is_empty());
        let dropped = apply(limits, 3, &flags(&["theta1=none", "theta2=none", "phi=none"])).unwrap();
        assert!(dropped.is_empty() && dropped.joints.is_empty(), "{dropped:?}");
    }

    #[test]
    fn bad_limit_flags_name_the_flag_and_what_is_expected() {
        for (text, expected) in [
            ("theta2.velocity", "KEY=VALUE"),
            ("theta4.velocity=1", "theta1 .. thetaN"),
            ("theta0.velocity=1", "theta1 .. thetaN"),
            ("elbow.velocity=1", "KEY=VALUE"),
            ("theta1.speed=1", "QUANTITY"),
            ("theta1.velocity=-1", "deg/s"),
            ("theta1.torque=inf", "N m"),
            ("theta1.position=10:-10", "LO < HI"),
            ("theta1.position=10", "LO:HI"),
            ("phi.velocity=3", "the base has a range only"),
            ("theta1=3", "KEY=VALUE"),
        ] {
            let e = apply(Limits::default(), 3, &flags(&[text])).expect_err(text);
            let message = format!("{e:#}");
            assert!(message.contains("--limit") && message.contains(expected), "{text}: {message}");
        }
    }
}
