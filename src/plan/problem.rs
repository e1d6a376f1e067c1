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

impl PlanningProblem {
    /// A validated problem: robot valid, angles finite, `T` finite and positive.
    pub fn new(robot: RobotParams, start: Configuration, goal: Configuration, horizon: f64) -> Result<Self, Error> {
        robot.validate()?;
        for (name, q) in [("start", start), ("goal", goal)] {
            for (axis, x) in ["phi", "theta1", "theta2"].iter().zip(q.to_array()) {
                if !x.is_finite() {
                    return Err(Error::from(InputError::InvalidParameter {
                        name: format!("{name}.{axis}"),
                        value: x,
                        expected: "a finite angle",
                    }));
                }
            }
        }
        if !(horizon.is_finite() && horizon > 0.0) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "time".into(),
                value: horizon,
                expected: "a positive, finite horizon [s]",
            }));
        }
        Ok(Self { robot, start, goal, horizon })
    }

    /// The paper's problem (Sec. 5) for `robot`: `q0 = (45, 120, 80)` deg,
    /// `qd = (0, 180, 140)` deg, `T = 10` s.
    pub fn paper(robot: RobotParams) -> Self {
        let (start, goal, horizon) = crate::model::paper_problem();
        Self { robot, start, goal, horizon }
    }
}
