//! The report of a plan for any planar serial arm (docs/spec.md §3, "any arm"): the JSON object
//! of `plan --format json` and the CSV trajectory, with `n` joint columns.

use std::path::PathBuf;

use serde::Serialize;

use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::plan::Method;
use crate::plan::chain_certificate::ChainVerification;
use crate::plan::chain_torques::ChainTorqueCertificate;
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

/// The sampled motion: `n + 1` columns `(phi, theta_1..theta_n)` per row, SI units, radians.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArmTrajectory {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// `q = (phi, theta_1..theta_n)` \[rad\].
    pub q: Vec<Vec<f64>>,
    /// `q'` \[rad/s\] (the base's from zero angular momentum, Eq. 7).
    pub dq: Vec<Vec<f64>>,
    /// `theta''` \[rad/s^2\].
    pub ddtheta: Vec<Vec<f64>>,
    /// Joint torques [N m] (with `--torques`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau: Option<Vec<Vec<f64>>>,
}

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
            effort: planned.effort(),
            max_abs_u,
            optimal: planned.stats().copied(),
            ecsa: planned.ecsa().cloned(),
            max_abs_torque: torques.map(|t| t.max_abs_torque.clone()),
            torque_final_error: torques.map(|t| t.certificate.final_error),
            torque_certificate: torques.map(|t| t.certificate.clone()),
            seconds: ArmSeconds { plan: planned.seconds, torques: torques.map_or(0.0, |t| t.seconds) },
            trajectory: with_trajectory.then(|| trajectory(planned)),
        }
    }
}

/// The sampled trajectory of `planned`.
pub fn trajectory(planned: &ArmPlanned) -> ArmTrajectory {
    let arm = &planned.arm;
    let rows = &planned.trajectory;
    ArmTrajectory {
        t: rows.iter().map(|p| p.t).collect(),
        q: rows.iter().map(|p| std::iter::once(p.phi).chain(p.theta.iter().copied()).collect()).collect(),
        dq: rows
            .iter()
            .map(|p| std::iter::once(arm.base_rate(&p.theta, &p.rate)).chain(p.rate.iter().copied()).collect())
            .collect(),
        ddtheta: rows.iter().map(|p| p.acceleration.clone()).collect(),
        tau: planned.torques.as_ref().map(|t| t.tau.clone()),
    }
}

/// The trajectory as CSV: `t, phi, theta1..thetan, dphi, dtheta1..dthetan, ddtheta1..ddthetan`
/// and, with torques, `tau1..taun`; one row per sample, SI units, radians.
pub fn arm_csv(planned: &ArmPlanned) -> Result<Vec<u8>, Error> {
    let n = planned.arm.joints();
    let tr = trajectory(planned);
    let mut header = vec!["t".to_string(), "phi".into()];
    header.extend((1..=n).map(|k| format!("theta{k}")));
    header.push("dphi".into());
    header.extend((1..=n).map(|k| format!("dtheta{k}")));
    header.extend((1..=n).map(|k| format!("ddtheta{k}")));
    if tr.tau.is_some() {
        header.extend((1..=n).map(|k| format!("tau{k}")));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    let csv_error = |reason: String| {
        Error::from(InputError::Io { path: PathBuf::from("<csv>"), source: std::io::Error::other(reason) })
    };
    w.write_record(&header).map_err(|e| csv_error(e.to_string()))?;
    for i in 0..tr.t.len() {
        let mut row = vec![tr.t[i]];
        row.extend(&tr.q[i]);
        row.extend(&tr.dq[i]);
        row.extend(&tr.ddtheta[i]);
        if let Some(tau) = &tr.tau {
            row.extend(&tau[i]);
        }
        w.write_record(row.iter().map(|x| format!("{x:.17e}"))).map_err(|e| csv_error(e.to_string()))?;
    }
    w.into_inner().map_err(|e| csv_error(e.to_string()))
}
