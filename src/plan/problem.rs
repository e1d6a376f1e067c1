//! The planning problem (Sec. 5; docs/spec.md, Sec. 2).

use serde::Serialize;

use crate::error::Error;
use crate::model::{Configuration, InputError, RobotParams};

/// Drive the robot from `start` to `goal` in time `horizon`, zero angular momentum, the joints
/// at rest at the goal and at `start_velocity` (zero unless set) at the start (docs/spec.md §2).
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
    /// `theta'(0)` \[rad/s\]: zero for the paper's rest-to-rest problem; a moving start (e.g.
    /// re-planning during a motion) only the optimal planner serves. The base then turns at
    /// `phi'(0) = -(G theta1'(0) + H theta2'(0)) / F` (Eq. 7).
    pub start_velocity: [f64; 2],
}

/// Accepted horizons `T` \[s\] (docs/spec.md §2): below, the controls grow as 1/T past any
/// use (and the integrator's work with them); above, the horizon is no longer a motion's.
pub const HORIZON_RANGE: (f64, f64) = (1e-3, 1e6);

/// Largest accepted `|theta'(0)|` of a moving start \[rad/s\].
pub const MAX_START_VELOCITY: f64 = 1e4;

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
        Ok(Self { robot, start, goal, horizon, start_velocity: [0.0; 2] })
    }

    /// The same problem starting with the joint velocities `velocity` \[rad/s\] (finite, with
    /// `|velocity| <=` [`MAX_START_VELOCITY`]).
    pub fn with_start_velocity(self, velocity: [f64; 2]) -> Result<Self, Error> {
        for (axis, v) in ["dtheta1", "dtheta2"].iter().zip(velocity) {
            if !(v.is_finite() && v.abs() <= MAX_START_VELOCITY) {
                return Err(Error::from(InputError::InvalidParameter {
                    name: format!("start velocity {axis}"),
                    value: v,
                    expected: "a finite joint velocity with |v| <= 1e4 rad/s (docs/spec.md §2)",
                }));
            }
        }
        Ok(Self { start_velocity: velocity, ..self })
    }

    /// True when the joints start at rest (the paper's problem).
    pub fn starts_at_rest(&self) -> bool {
        self.start_velocity.iter().all(|v| *v == 0.0)
    }

    /// Refuses a moving start for a `method` that plans from rest only (the NFA's polynomial
    /// steering and the ECSA's controls do not take an initial velocity).
    pub fn require_rest(&self, method: &str) -> Result<(), Error> {
        match self.start_velocity.iter().find(|v| **v != 0.0) {
            None => Ok(()),
            Some(&value) => Err(Error::from(InputError::InvalidParameter {
                name: "start velocity".into(),
                value,
                expected: match method {
                    "nfa" => "zero: the NFA plans from rest; the optimal planner takes a moving start",
                    _ => "zero: the ECSA plans from rest; the optimal planner takes a moving start",
                },
            })),
        }
    }

    /// The paper's problem (Sec. 5) for `robot`: `q0 = (45, 120, 80)` deg,
    /// `qd = (0, 180, 140)` deg, `T = 10` s.
    pub fn paper(robot: RobotParams) -> Self {
        let (start, goal, horizon) = crate::model::paper_problem();
        Self { robot, start, goal, horizon, start_velocity: [0.0; 2] }
    }
}
