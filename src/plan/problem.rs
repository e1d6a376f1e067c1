//! The planning problem (Sec. 5; docs/spec.md, Sec. 2).

use serde::Serialize;

use crate::error::Error;
use crate::model::{Configuration, InputError, RobotParams};

/// Drive the robot from `start` to `goal` in time `horizon`, joint velocities zero at both
/// ends, zero angular momentum (docs/spec.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlanningProblem {
    /// The robot, with its mounting point.
    pub robot: RobotParams,
    /// `q0` \[rad\].
    pub start: Configuration,
    /// `qd` \[rad\], taken literally (not reduced modulo 2 pi).
    pub goal: Configuration,
    /// `T` \[s\].
    pub horizon: f64,
}

/// Accepted horizons `T` \[s\] (docs/spec.md §2): below, the controls grow as 1/T past any
/// use (and the integrator's work with them); above, the horizon is no longer a motion's.
pub const HORIZON_RANGE: (f64, f64) = (1e-3, 1e6);

/// Largest accepted `|angle|` of a start or goal \[rad\] (about 573,000 deg, 1592 turns).
pub const MAX_ANGLE: f64 = 1e4;

/// Checks a horizon against [`HORIZON_RANGE`], naming it `name` in the error.
pub fn check_horizon(name: &str, horizon: f64) -> Result<(), Error> {
    let (min, max) = HORIZON_RANGE;
    if horizon.is_finite() && (min..=max).contains(&horizon) {
        return Ok(());
    }
    Err(Error::from(InputError::InvalidParameter {
        name: name.into(),
        value: horizon,
        expected: "a horizon from 1e-3 s to 1e6 s (docs/spec.md §2)",
    }))
}

impl PlanningProblem {
    /// A validated problem: robot valid, angles finite with `|angle| <=` [`MAX_ANGLE`], `T` in
    /// [`HORIZON_RANGE`] (docs/spec.md §2).
    pub fn new(robot: RobotParams, start: Configuration, goal: Configuration, horizon: f64) -> Result<Self, Error> {
        robot.validate()?;
        for (name, q) in [("start", start), ("goal", goal)] {
            for (axis, x) in ["phi", "theta1", "theta2"].iter().zip(q.to_array()) {
                if !(x.is_finite() && x.abs() <= MAX_ANGLE) {
                    return Err(Error::from(InputError::InvalidParameter {
                        name: format!("{name}.{axis}"),
                        value: x,
                        expected: "a finite angle with |angle| <= 1e4 rad (docs/spec.md §2)",
                    }));
                }
            }
        }
        check_horizon("horizon", horizon)?;
        Ok(Self { robot, start, goal, horizon })
    }

    /// The paper's problem (Sec. 5) for `robot`: `q0 = (45, 120, 80)` deg,
    /// `qd = (0, 180, 140)` deg, `T = 10` s.
    pub fn paper(robot: RobotParams) -> Self {
        let (start, goal, horizon) = crate::model::paper_problem();
        Self { robot, start, goal, horizon }
    }
}
