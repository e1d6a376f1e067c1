//! The report of a plan for any planar serial arm (docs/spec.md §3, "any arm"): the JSON object
//! of `plan --format json`, and the one CSV writer of every plan ([`rows_csv`]), with `n` joint
//! columns, the base and the end effector.

use std::path::PathBuf;

use serde::Serialize;

use num_dual::Dual64;

use crate::error::Error;
use crate::model::InputError;
use crate::plan::Trajectory;
use crate::planners::arm::ArmPlanned;

/// The sampled motion: `n + 1` columns `(phi, theta_1..theta_n)` per row, SI units, radians; the
/// task-space keys as the 2-link robot's trajectory ([`crate::plan::Trajectory`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArmTrajectory {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// `q = (phi, theta_1..theta_n)` \[rad\].
    pub q: Vec<Vec<f64>>,
    /// `q'` \[rad/s\] (the base's from zero angular momentum, Eq. 7).
    pub dq: Vec<Vec<f64>>,
    /// `q''` \[rad/s^2\] (the base's the time derivative of Eq. 7).
    pub ddq: Vec<Vec<f64>>,
    /// `theta''` \[rad/s^2\] (`ddq` without the base's column).
    pub ddtheta: Vec<Vec<f64>>,
    /// Joint torques [N m] (with `--torques`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau: Option<Vec<Vec<f64>>>,
    /// The base's centre of mass `(xb, yb)` \[m\], inertial frame, the system's centre of mass at
    /// the origin (its angle is `q[0]`).
    pub base: Vec<[f64; 2]>,
    /// The tool's pose `(xe, ye, psie)` \[m, m, rad\] ([`crate::model::arm::Arm::task_point`]).
    pub end_effector: Vec<[f64; 3]>,
    /// Its velocity `(xe', ye', psie')` \[m/s, m/s, rad/s\].
    pub end_effector_velocity: Vec<[f64; 3]>,
}

pub use crate::planners::to_pose::{PoseBranch, PoseGoal};

/// The sampled trajectory of `planned`, with the task space by
/// [`crate::model::arm::Arm::task_point`] and the base's acceleration by a dual number through
/// Eq. 7.
pub fn trajectory(planned: &ArmPlanned) -> ArmTrajectory {
    let arm = &planned.arm;
    let rows = &planned.trajectory;
    let mut tr = ArmTrajectory {
        t: rows.iter().map(|p| p.t).collect(),
        q: Vec::with_capacity(rows.len()),
        dq: Vec::with_capacity(rows.len()),
        ddq: Vec::with_capacity(rows.len()),
        ddtheta: rows.iter().map(|p| p.acceleration.clone()).collect(),
        tau: planned.torques.as_ref().map(|t| t.tau.clone()),
        base: Vec::with_capacity(rows.len()),
        end_effector: Vec::with_capacity(rows.len()),
        end_effector_velocity: Vec::with_capacity(rows.len()),
    };
    for p in rows {
        // phi'' = d/dt (-(G . theta') / F): theta + eps theta', theta' + eps theta''.
        let theta: Vec<Dual64> = p.theta.iter().zip(&p.rate).map(|(x, v)| Dual64::new(*x, *v)).collect();
        let rate: Vec<Dual64> = p.rate.iter().zip(&p.acceleration).map(|(v, a)| Dual64::new(*v, *a)).collect();
        let dphi = arm.base_rate(&theta, &rate);
        let q: Vec<f64> = std::iter::once(p.phi).chain(p.theta.iter().copied()).collect();
        let dq: Vec<f64> = std::iter::once(dphi.re).chain(p.rate.iter().copied()).collect();
        let task = arm.task_point(&q, &dq);
        tr.base.push(task.base);
        tr.end_effector.push(task.end_effector);
        tr.end_effector_velocity.push(task.end_effector_velocity);
        tr.ddq.push(std::iter::once(dphi.eps).chain(p.acceleration.iter().copied()).collect());
        tr.q.push(q);
        tr.dq.push(dq);
    }
    tr
}

/// The rows of the CSV of every plan, any arm and any method (docs/spec.md §3): `n + 1`
/// coordinates per row; the columns that a plan does not fill are empty cells.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryRows {
    /// Number of joints `n`.
    pub joints: usize,
    /// Times \[s\].
    pub t: Vec<f64>,
    /// `(phi, theta_1..theta_n)` \[rad\].
    pub q: Vec<Vec<f64>>,
    /// `q'` \[rad/s\].
    pub dq: Vec<Vec<f64>>,
    /// `q''` \[rad/s^2\], when computed.
    pub ddq: Option<Vec<Vec<f64>>>,
    /// The NFA's chained-form state `z` (2-link NFA plans only).
    pub z: Option<Vec<[f64; 3]>>,
    /// Joint torques [N m], when computed.
    pub tau: Option<Vec<Vec<f64>>>,
    /// The base's centre of mass \[m\].
    pub base: Vec<[f64; 2]>,
    /// The end-effector pose \[m, m, rad\].
    pub end_effector: Vec<[f64; 3]>,
    /// Its velocity \[m/s, m/s, rad/s\].
    pub end_effector_velocity: Vec<[f64; 3]>,
}

impl TrajectoryRows {
    /// The rows of an arm's plan.
    pub fn from_arm(planned: &ArmPlanned) -> Self {
        let tr = trajectory(planned);
        Self {
            joints: planned.arm.joints(),
            t: tr.t,
            q: tr.q,
            dq: tr.dq,
            ddq: Some(tr.ddq),
            z: None,
            tau: tr.tau,
            base: tr.base,
            end_effector: tr.end_effector,
            end_effector_velocity: tr.end_effector_velocity,
        }
    }

    /// The rows of a 2-link plan's trajectory (the NFA's, the ECSA's, the optimal planner's).
    pub fn from_trajectory(tr: &Trajectory) -> Self {
        let rows = |v: &[[f64; 3]]| v.iter().map(|r| r.to_vec()).collect();
        Self {
            joints: 2,
            t: tr.t.clone(),
            q: rows(&tr.q),
            dq: rows(&tr.dq),
            ddq: tr.ddq.as_deref().map(rows),
            z: tr.z.clone(),
            tau: tr.tau.as_ref().map(|t| t.iter().map(|r| r.to_vec()).collect()),
            base: tr.base.clone(),
            end_effector: tr.end_effector.clone(),
            end_effector_velocity: tr.end_effector_velocity.clone(),
        }
    }

    /// The header: `t, phi, theta1..thetan, dphi, dtheta1..dthetan, ddphi, ddtheta1..ddthetan`,
    /// at `n = 2` the NFA's `z1, z2, z3`, then `tau1..taun, xb, yb, xe, ye, psie, dxe, dye, dpsie`
    /// (at `n = 2` [`crate::report::io::CSV_HEADER`]).
    pub fn header(&self) -> Vec<String> {
        let n = self.joints;
        let joints = |prefix: &'static str| (1..=n).map(move |k| format!("{prefix}{k}"));
        let mut header = vec!["t".to_string(), "phi".into()];
        header.extend(joints("theta"));
        header.push("dphi".into());
        header.extend(joints("dtheta"));
        header.push("ddphi".into());
        header.extend(joints("ddtheta"));
        if n == 2 {
            header.extend(["z1", "z2", "z3"].map(String::from));
        }
        header.extend(joints("tau"));
        header.extend(["xb", "yb", "xe", "ye", "psie", "dxe", "dye", "dpsie"].map(String::from));
        header
    }
}

/// The CSV of `rows` ([`TrajectoryRows::header`]): one row per sample, SI units, radians,
/// `{:.17e}` (round trip exact), empty cells where a column does not apply. The one writer of
/// every plan's CSV.
pub fn rows_csv(rows: &TrajectoryRows) -> Result<Vec<u8>, Error> {
    let n = rows.joints;
    let header = rows.header();
    let mut w = csv::Writer::from_writer(Vec::new());
    let csv_error = |reason: String| {
        Error::from(InputError::Io { path: PathBuf::from("<csv>"), source: std::io::Error::other(reason) })
    };
    w.write_record(&header).map_err(|e| csv_error(e.to_string()))?;
    let cell = |x: Option<f64>| x.map(|v| format!("{v:.17e}")).unwrap_or_default();
    for i in 0..rows.t.len() {
        let mut row = Vec::with_capacity(header.len());
        row.push(cell(Some(rows.t[i])));
        row.extend((0..=n).map(|j| cell(rows.q[i].get(j).copied())));
        row.extend((0..=n).map(|j| cell(rows.dq[i].get(j).copied())));
        row.extend((0..=n).map(|j| cell(rows.ddq.as_ref().and_then(|a| a[i].get(j).copied()))));
        if n == 2 {
            row.extend((0..3).map(|j| cell(rows.z.as_ref().map(|z| z[i][j]))));
        }
        row.extend((0..n).map(|j| cell(rows.tau.as_ref().and_then(|a| a[i].get(j).copied()))));
        row.extend((0..2).map(|j| cell(rows.base.get(i).map(|p| p[j]))));
        row.extend((0..3).map(|j| cell(rows.end_effector.get(i).map(|p| p[j]))));
        row.extend((0..3).map(|j| cell(rows.end_effector_velocity.get(i).map(|p| p[j]))));
        w.write_record(&row).map_err(|e| csv_error(e.to_string()))?;
    }
    w.into_inner().map_err(|e| csv_error(e.to_string()))
}

/// The CSV of an arm's plan: [`rows_csv`] of [`TrajectoryRows::from_arm`].
pub fn arm_csv(planned: &ArmPlanned) -> Result<Vec<u8>, Error> {
    rows_csv(&TrajectoryRows::from_arm(planned))
}
