//! A plan as ROS 2 messages (docs/spec.md §3, "ROS 2"): the joints as a
//! `trajectory_msgs/JointTrajectory` (what `plan --format joint-trajectory` prints and
//! `ros2 topic pub` reads), and the base as its companion, a
//! `trajectory_msgs/MultiDOFJointTrajectory` of one floating joint `base` in the frame
//! `inertial` (origin at the system's centre of mass): per point the base's centre of mass as the
//! translation and `phi` as a rotation about `z`, with the base's twist.
//!
//! The same rows serve the 2-link robot's [`Plan`] and any arm's [`ArmPlanned`].

use crate::error::Error;
use crate::model::arm::Arm;
use crate::plan::Plan;
use crate::plan::ros::{
    Duration, Header, JointTrajectory, JointTrajectoryPoint, MultiDOFJointTrajectory, MultiDOFJointTrajectoryPoint,
    Quaternion, Transform, Twist, Vector3,
};
use crate::planners::arm::ArmPlanned;

/// The frame of the base's trajectory: inertial, origin at the system's centre of mass.
pub const BASE_FRAME: &str = "inertial";

/// The name of the base's floating joint in the companion message.
pub const BASE_JOINT: &str = "base";

/// A plan's samples, SI units and radians.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionRows {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// `(phi, theta_1..theta_n)` per sample \[rad\].
    pub q: Vec<Vec<f64>>,
    /// `(phi', theta_1'..theta_n')` per sample \[rad/s\] (`phi'` from zero momentum).
    pub dq: Vec<Vec<f64>>,
    /// `theta''` per sample \[rad/s^2\], when the plan has them.
    pub ddtheta: Option<Vec<Vec<f64>>>,
    /// Joint torques per sample [N m], when computed.
    pub tau: Option<Vec<Vec<f64>>>,
    /// The base's centre of mass `(x, y)` \[m\] and its velocity \[m/s\], inertial frame.
    pub base: Vec<([f64; 2], [f64; 2])>,
}

/// The base's centre of mass and its velocity at `q` moving at `dq` (`n + 1` values each).
fn base_point(arm: &Arm, q: &[f64], dq: &[f64]) -> ([f64; 2], [f64; 2]) {
    let frames = arm.bodies(q);
    let mut v = [0.0, 0.0];
    for (column, rate) in frames.base_jacobian.iter().zip(dq) {
        v = [v[0] + column[0] * rate, v[1] + column[1] * rate];
    }
    (frames.base, v)
}

impl MotionRows {
    /// The samples of a 2-link plan (its robot as the arm of [`Arm::from_params`]).
    pub fn from_plan(plan: &Plan) -> Self {
        let arm = Arm::from_params(&plan.problem.robot);
        let tr = &plan.trajectory;
        let q: Vec<Vec<f64>> = tr.q.iter().map(|q| q.to_vec()).collect();
        let dq: Vec<Vec<f64>> = tr.dq.iter().map(|q| q.to_vec()).collect();
        Self {
            t: tr.t.clone(),
            base: q.iter().zip(&dq).map(|(q, dq)| base_point(&arm, q, dq)).collect(),
            ddtheta: tr.ddq.as_ref().map(|a| a.iter().map(|a| a[1..].to_vec()).collect()),
            tau: tr.tau.as_ref().map(|t| t.iter().map(|t| t.to_vec()).collect()),
            q,
            dq,
        }
    }

    /// The samples of an arm's plan.
    pub fn from_arm(planned: &ArmPlanned) -> Self {
        let arm = &planned.arm;
        let rows = &planned.trajectory;
        let q: Vec<Vec<f64>> =
            rows.iter().map(|p| std::iter::once(p.phi).chain(p.theta.iter().copied()).collect()).collect();
        let dq: Vec<Vec<f64>> = rows
            .iter()
            .map(|p| std::iter::once(arm.base_rate(&p.theta, &p.rate)).chain(p.rate.iter().copied()).collect())
            .collect();
        Self {
            t: rows.iter().map(|p| p.t).collect(),
            base: q.iter().zip(&dq).map(|(q, dq)| base_point(arm, q, dq)).collect(),
            ddtheta: Some(rows.iter().map(|p| p.acceleration.clone()).collect()),
            tau: planned.torques.as_ref().map(|t| t.tau.clone()),
            q,
            dq,
        }
    }
}

/// The joints' motion as a `JointTrajectory` with `joint_names` (one per joint): positions,
/// velocities, accelerations when the plan has them, efforts with torques, `time_from_start`
/// rounded to the nanosecond. A time out of [`Duration`]'s range is bad input.
pub fn joint_trajectory(rows: &MotionRows, joint_names: &[String]) -> Result<JointTrajectory, Error> {
    let mut points = Vec::with_capacity(rows.t.len());
    for (i, &t) in rows.t.iter().enumerate() {
        points.push(JointTrajectoryPoint {
            positions: rows.q[i][1..].to_vec(),
            velocities: rows.dq[i][1..].to_vec(),
            accelerations: rows.ddtheta.as_ref().map_or_else(Vec::new, |a| a[i].clone()),
            effort: rows.tau.as_ref().map_or_else(Vec::new, |tau| tau[i].clone()),
            time_from_start: Duration::from_seconds(t)?,
        });
    }
    Ok(JointTrajectory { header: Header::default(), joint_names: joint_names.to_vec(), points })
}

/// The base's motion as a `MultiDOFJointTrajectory` of the joint [`BASE_JOINT`] in the frame
/// [`BASE_FRAME`]: translation = the base's centre of mass (`z = 0`), rotation = `phi` about
/// `z`, velocity = its linear velocity and `phi'` about `z`; no accelerations.
pub fn base_trajectory(rows: &MotionRows) -> Result<MultiDOFJointTrajectory, Error> {
    let mut points = Vec::with_capacity(rows.t.len());
    for (i, &t) in rows.t.iter().enumerate() {
        let ([x, y], [vx, vy]) = rows.base[i];
        points.push(MultiDOFJointTrajectoryPoint {
            transforms: vec![Transform {
                translation: Vector3 { x, y, z: 0.0 },
                rotation: Quaternion::about_z(rows.q[i][0]),
            }],
            velocities: vec![Twist {
                linear: Vector3 { x: vx, y: vy, z: 0.0 },
                angular: Vector3 { x: 0.0, y: 0.0, z: rows.dq[i][0] },
            }],
            accelerations: Vec::new(),
            time_from_start: Duration::from_seconds(t)?,
        });
    }
    Ok(MultiDOFJointTrajectory {
        header: Header { frame_id: BASE_FRAME.into(), ..Header::default() },
        joint_names: vec![BASE_JOINT.into()],
        points,
    })
}
