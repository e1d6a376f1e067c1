//! What a joint trajectory made by any other tool does to a free-floating robot
//! (`freefloat check`, docs/spec.md §3): the base's attitude along it at zero angular momentum
//! (Eq. 7 for `n` joints, [`Arm::base_rate`]), integrated by the velocity-level certificate's
//! routine ([`verify_chain_observed`], the adaptive integrator at 1e-12), the base's position,
//! the final error against an optional goal, the joint torques by inverse dynamics (Eq. 6), and,
//! on that one integration, the use of every limit the robot declares and the least clearance of
//! its bodies and the obstacles (issues 20, 21: the certificate's checks).
//!
//! The points are joined as a ROS 2 joint_trajectory_controller joins them ([`Interpolation`]);
//! the trajectory is checked and matched to the robot's joints by name ([`input`]).

pub mod input;
pub mod motion;

use std::time::Instant;

use serde::Serialize;

pub use input::{MAX_POINTS, TRAJECTORY_FILE_LIMIT, TrajectoryInput, read_trajectory, samples_from_message};
pub use motion::{InterpolatedMotion, Interpolation, JointSamples};

use crate::dynamics::arm::inverse_dynamics;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::{InputError, wrap_angle};
use crate::numerics::ode::{OdeOptions, OdeStats};
use crate::plan::certificate::{collision, verify_chain_observed};
use crate::plan::clearance::ClearanceReport;
use crate::plan::limit_use::LimitReport;

/// How to check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckOptions {
    /// Largest accepted final error against the goal \[rad\] (default 1e-9, as `plan`'s).
    pub tolerance: f64,
    /// The integrator (default rtol = atol = 1e-12, the certificate's).
    pub ode: OdeOptions,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self { tolerance: 1e-9, ode: OdeOptions::default() }
    }
}

/// The base along the trajectory, at every point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaseTrack {
    /// Times of the points \[s\].
    pub t: Vec<f64>,
    /// The base's attitude `phi` \[rad\], counter-clockwise, integrated at zero momentum.
    pub phi: Vec<f64>,
    /// The base's centre of mass `(x, y)` \[m\], inertial frame, the system's centre of mass at
    /// the origin.
    pub position: Vec<[f64; 2]>,
}

/// What the trajectory does to the robot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// Number of joints `n`.
    pub joints: usize,
    /// The robot's joint names, in the order of every per-joint array below.
    pub joint_names: Vec<String>,
    /// Number of points.
    pub points: usize,
    /// Time of the last point \[s\].
    pub time: f64,
    /// How the points are joined.
    pub interpolation: Interpolation,
    /// `q(0) = (phi_0, theta(0))` \[rad\].
    pub start: Vec<f64>,
    /// `q(T)` reached by the integration \[rad\] (its joints are the last point's, to the
    /// integrator's accuracy).
    pub reached: Vec<f64>,
    /// The goal `(phi, theta)` \[rad\], when given.
    pub goal: Option<Vec<f64>>,
    /// `wrap(q_i(T) - goal_i)` per coordinate, base first \[rad\], when a goal is given.
    pub final_errors: Option<Vec<f64>>,
    /// The largest `|final_errors|` \[rad\].
    pub final_error: Option<f64>,
    /// The coordinate of [`CheckReport::final_error`]: `base phi` or ``joint `NAME` ``.
    pub worst: Option<String>,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// The goal is reached within the tolerance (true without a goal).
    pub holds: bool,
    /// The base at every point.
    pub base: BaseTrack,
    /// Largest `|theta_k'|` over the points, per joint \[rad/s\].
    pub max_abs_velocity: Vec<f64>,
    /// Largest `|tau_k|` over the points by inverse dynamics (Eq. 6), per joint [N m].
    pub max_abs_torque: Vec<f64>,
    /// Largest `|base row of (6)|` over the points [N m] (zero up to rounding).
    pub max_abs_base_residual: f64,
    /// Largest angular momentum of the interpolant along the integration [kg m^2/s] (the
    /// integration's consistency).
    pub max_abs_momentum: f64,
    /// Integrator work.
    pub stats: OdeStats,
    /// The use of every limit the robot declares (its file's and `--limit`'s), along the same
    /// integrated motion and between its steps ([`crate::plan::limit_use`], the certificate's
    /// check); `None` for a robot without limits.
    pub limits: Option<LimitReport>,
    /// The least clearance between the robot's bodies and the obstacles along that motion
    /// ([`crate::plan::clearance`]); `None` for a robot without shapes.
    pub clearance: Option<ClearanceReport>,
    /// Wall time of the check \[s\].
    pub seconds: f64,
}

impl CheckReport {
    /// `Ok` when the goal is reached (or none was given), the motion keeps the clearance and
    /// stays inside every declared limit; else [`Error::GoalMissed`] naming the coordinate
    /// farthest off, [`Error::Collision`] or [`Error::LimitExceeded`], in that order.
    pub fn holds(&self) -> Result<(), Error> {
        if let (false, Some(final_error), Some(worst)) = (self.holds, self.final_error, &self.worst) {
            return Err(Error::GoalMissed { element: worst.clone(), final_error, tolerance: self.tolerance });
        }
        collision(self.clearance.as_ref())?;
        self.limits.as_ref().map_or(Ok(()), LimitReport::check)
    }
}

/// Checks the motion of `arm` through `samples` (the robot's joint order, names `joint_names`)
/// from the base's attitude `base_start` \[rad\], against `goal` (`n + 1` angles, base first,
/// \[rad\]) when given.
pub fn check(
    arm: &Arm,
    joint_names: &[String],
    samples: &JointSamples,
    base_start: f64,
    goal: Option<&[f64]>,
    options: &CheckOptions,
) -> Result<CheckReport, Error> {
    let clock = Instant::now();
    let n = arm.joints();
    let bad = |name: &str, value: f64, expected: &'static str| {
        Error::from(InputError::InvalidParameter { name: name.into(), value, expected })
    };
    if joint_names.len() != n || samples.positions.first().map(Vec::len) != Some(n) {
        return Err(bad(
            "joints",
            samples.positions.first().map_or(0, Vec::len) as f64,
            "one value per joint of the robot",
        ));
    }
    if goal.is_some_and(|g| g.len() != n + 1) {
        return Err(bad("--to", goal.map_or(0, <[f64]>::len) as f64, "n + 1 angles PHI,TH1,..,THn"));
    }
    if !base_start.is_finite() {
        return Err(bad("--from", base_start, "a finite base angle"));
    }
    let motion = InterpolatedMotion::new(arm, samples);
    let mut start = vec![base_start];
    start.extend_from_slice(&samples.positions[0]);
    let last = samples.positions.len() - 1;
    let target: Vec<f64> = match goal {
        Some(g) => g.to_vec(),
        None => std::iter::once(base_start).chain(samples.positions[last].iter().copied()).collect(),
    };
    let mut base = BaseTrack {
        t: Vec::with_capacity(samples.t.len()),
        phi: Vec::with_capacity(samples.t.len()),
        position: Vec::with_capacity(samples.t.len()),
    };
    let mut q = vec![0.0; n + 1];
    let mut at_point = |t: f64, state: &[f64]| {
        q.copy_from_slice(state);
        base.t.push(t);
        base.phi.push(state[0]);
        base.position.push(arm.bodies(&q).base);
    };
    let verification =
        verify_chain_observed(arm, &motion, &start, &target, &options.ode, options.tolerance, &mut at_point)?;
    let (mut max_abs_velocity, mut max_abs_torque, mut residual) = (vec![0.0_f64; n], vec![0.0_f64; n], 0.0_f64);
    for (i, &t) in samples.t.iter().enumerate() {
        let (theta, rate, acceleration) = motion.state_on(motion.segment_of_point(i), t);
        let id = inverse_dynamics(arm, &theta, &rate, &acceleration);
        for j in 0..n {
            max_abs_velocity[j] = max_abs_velocity[j].max(rate[j].abs());
            max_abs_torque[j] = max_abs_torque[j].max(id.tau[j].abs());
        }
        residual = residual.max(id.base_residual.abs());
    }
    let finite = verification.reached.iter().all(|x| x.is_finite())
        && max_abs_torque.iter().all(|x| x.is_finite())
        && base.position.iter().flatten().all(|x| x.is_finite());
    if !finite {
        return Err(Error::from(crate::numerics::ode::OdeError { t: samples.t[last], reason: "non-finite state" }));
    }
    let coordinate = |i: usize| if i == 0 { "base phi".to_string() } else { format!("joint `{}`", joint_names[i - 1]) };
    let (final_errors, final_error, worst) = match goal {
        Some(g) => {
            let errors: Vec<f64> = verification.reached.iter().zip(g).map(|(r, g)| wrap_angle(r - g)).collect();
            let (i, e) =
                errors.iter().map(|e| e.abs()).enumerate().fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            (Some(errors), Some(e), Some(coordinate(i)))
        }
        None => (None, None, None),
    };
    Ok(CheckReport {
        joints: n,
        joint_names: joint_names.to_vec(),
        points: samples.t.len(),
        time: samples.t[last],
        interpolation: motion.interpolation(),
        start,
        reached: verification.reached.clone(),
        goal: goal.map(<[f64]>::to_vec),
        holds: final_error.is_none_or(|e| e <= options.tolerance),
        final_errors,
        final_error,
        worst,
        tolerance: options.tolerance,
        base,
        max_abs_velocity,
        max_abs_torque,
        max_abs_base_residual: residual,
        max_abs_momentum: verification.max_abs_momentum,
        stats: verification.stats,
        limits: verification.limits.clone(),
        clearance: verification.clearance,
        seconds: clock.elapsed().as_secs_f64(),
    })
}
