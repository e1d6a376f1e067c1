//! The report of a plan for any planar serial arm (docs/spec.md §3, "any arm"): the JSON object
//! of `plan --format json`, and the one CSV writer of every plan ([`rows_csv`]), with `n` joint
//! columns, the base and the end effector.

use crate::plan::limit_use::LimitReport;
use std::path::PathBuf;

use serde::Serialize;

use num_dual::Dual64;

use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::plan::Method;
use crate::plan::Trajectory;
use crate::plan::certificate::ChainVerification;
use crate::plan::torques::ChainTorqueCertificate;
use crate::planners::arm::ArmPlanned;
use crate::planners::chain::ChainStats;
use crate::planners::ecsa::ChainEcsaStats;

/// Wall times \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArmSeconds {
    /// The plan and its velocity certificate.
    pub plan: f64,
    /// The torques and their certificate (0 without `--torques`).
    pub torques: f64,
}

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
    /// The tool's pose `(xe, ye, psie)` \[m, m, rad\] ([`Arm::task_point`]).
    pub end_effector: Vec<[f64; 3]>,
    /// Its velocity `(xe', ye', psie')` \[m/s, m/s, rad/s\].
    pub end_effector_velocity: Vec<[f64; 3]>,
}

pub use crate::planners::to_pose::{PoseBranch, PoseGoal};

/// The JSON report of an arm's plan.
#[derive(Debug, Clone, Serialize)]
pub struct ArmReport {
    /// `optimal` or `ecsa`.
    pub method: Method,
    /// Number of joints `n`.
    pub joints: usize,
    /// The arm (base, mount, links).
    pub robot: Arm,
    /// Horizon `T` \[s\].
    pub time: f64,
    /// Samples of the trajectory.
    pub samples: usize,
    /// `q(0)` \[rad\].
    pub start: Vec<f64>,
    /// `q(T)` asked for \[rad\].
    pub goal: Vec<f64>,
    /// Velocity-level final error \[rad\].
    pub final_error: f64,
    /// Its tolerance \[rad\].
    pub tolerance: f64,
    /// Every certificate computed holds.
    pub certified: bool,
    /// `q(T)` reached by the velocity-level integration \[rad\].
    pub reached: Vec<f64>,
    /// The velocity-level certificate in full.
    pub verification: ChainVerification,
    /// The least clearance of the verified motion, its pair and time (issue 21; none without
    /// shapes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance: Option<crate::plan::clearance::ClearanceReport>,
    /// Effort `integral |theta'|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// Largest `|theta_k'|` over the samples, per joint \[rad/s\].
    pub max_abs_u: Vec<f64>,
    /// The minimum-effort planner's account (iterations, KKT residual, spans, ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal: Option<ChainStats>,
    /// The ECSA's account (coefficients, iterations, residual, quadrature; with `--method ecsa`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ecsa: Option<ChainEcsaStats>,
    /// Largest `|tau_k|` per joint [N m] (with `--torques`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_abs_torque: Option<Vec<f64>>,
    /// Final error of the torque level \[rad\] (with `--torques`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torque_final_error: Option<f64>,
    /// The torque-level certificate (with `--torques`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torque_certificate: Option<ChainTorqueCertificate>,
    /// Wall times.
    pub seconds: ArmSeconds,
    /// What the reader must know: the tool frame, a stretched horizon (`--max-velocity`), the
    /// inverse kinematics of `--to-ee`.
    pub notes: Vec<String>,
    /// The goal pose of `--to-ee` and its branches.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub to_ee: Option<PoseGoal>,
    /// The use of each declared limit along the verified motion (issue 20; absent without
    /// limits): per joint and quantity the limit, its largest use, the value and the time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limits: Option<LimitReport>,
    /// The trajectory (only in `--out FILE.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<ArmTrajectory>,
}

impl ArmReport {
    /// The report of `planned` for the problem's `start` and `goal`, with the trajectory when
    /// `with_trajectory`.
    pub fn new(planned: &ArmPlanned, start: &[f64], goal: &[f64], with_trajectory: bool) -> Self {
        let v = planned.verification();
        let n = planned.arm.joints();
        let mut max_abs_u = vec![0.0_f64; n];
        for p in &planned.trajectory {
            for (m, r) in max_abs_u.iter_mut().zip(&p.rate) {
                *m = m.max(r.abs());
            }
        }
        let torques = planned.torques.as_ref();
        Self {
            method: planned.method,
            joints: n,
            robot: planned.arm.clone(),
            time: planned.plan.horizon(),
            samples: planned.trajectory.len(),
            start: start.to_vec(),
            goal: goal.to_vec(),
            final_error: v.final_error,
            tolerance: v.tolerance,
            certified: planned.certified().is_ok(),
            reached: v.reached.clone(),
            verification: v.clone(),
            clearance: v.clearance,
            effort: planned.effort(),
            max_abs_u,
            optimal: planned.stats().copied(),
            ecsa: planned.ecsa().cloned(),
            limits: (!planned.limits.uses.is_empty()).then(|| planned.limits.clone()),
            max_abs_torque: torques.map(|t| t.max_abs_torque.clone()),
            torque_final_error: torques.map(|t| t.certificate.final_error),
            torque_certificate: torques.map(|t| t.certificate.clone()),
            seconds: ArmSeconds { plan: planned.seconds, torques: torques.map_or(0.0, |t| t.seconds) },
            notes: Vec::new(),
            to_ee: None,
            trajectory: with_trajectory.then(|| trajectory(planned)),
        }
    }
}

/// The sampled trajectory of `planned`, with the task space by [`Arm::task_point`] and the base's
/// acceleration by a dual number through Eq. 7.
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
