//! Planning for any planar serial arm (docs/spec.md §1–2): the one entry point that the command
//! line, the report and Python use for an arm that is not the paper's 2-link robot.
//!
//! The method is the minimum-effort planner for `n` joints ([`super::chain`]): the holonomy
//! constraint `phi(T) = phid` is one scalar for any `n` (Eq. 7 with `G = (G_1..G_n)`). The NFA's
//! chained form (Eq. 10) is the 2-link robot's, and the ECSA is implemented for 2 links; for other
//! arms both are refused with the reason. Every plan is certified at the velocity level (the
//! system integrated with the planned joint velocities), and with `torques` at the torque level
//! (the full dynamics, base unactuated, integrated with the planned torques, Eq. 6).

use std::time::Instant;

use serde::Serialize;

use super::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainPoint, ChainProblem, ChainStats};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::ode::OdeOptions;
use crate::plan::chain_certificate::ChainVerification;
use crate::plan::chain_torques::{ChainTorqueCertificate, certify_chain_torques, chain_torques_at};
use crate::plan::{Method, TorqueOptions};

/// What to plan for an arm, and how.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmRequest {
    /// The problem: `n + 1` start and goal angles \[rad\], the horizon, the start velocity.
    pub problem: ChainProblem,
    /// Samples of the reported trajectory, both ends included (at least 2).
    pub samples: usize,
    /// Tolerance of the velocity-level certificate \[rad\] (default 1e-9).
    pub tolerance: f64,
    /// Add the torque level: torques at the samples and their certificate.
    pub torques: bool,
}

/// The torque level of an arm's plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArmTorques {
    /// Joint torques at the samples [N m], one row per sample.
    pub tau: Vec<Vec<f64>>,
    /// Largest `|tau_k|` over the samples, per joint [N m].
    pub max_abs_torque: Vec<f64>,
    /// Largest `|base row of (6)|` over the samples [N m]: zero for a motion at zero momentum.
    pub max_abs_base_residual: f64,
    /// The forward-dynamics certificate.
    pub certificate: ChainTorqueCertificate,
    /// Wall time of the torques and their certificate \[s\].
    pub seconds: f64,
}

/// A certified plan for an arm.
#[derive(Debug, Clone)]
pub struct ArmPlanned {
    /// The arm.
    pub arm: Arm,
    /// The method (the optimal planner).
    pub method: Method,
    /// The planned motion, exact at any time.
    pub plan: ChainPlan,
    /// The trajectory at `samples` equally spaced times.
    pub trajectory: Vec<ChainPoint>,
    /// The torque level, when asked for.
    pub torques: Option<ArmTorques>,
    /// Wall time of the plan and its velocity certificate \[s\].
    pub seconds: f64,
}

impl ArmPlanned {
    /// The velocity-level certificate.
    pub fn verification(&self) -> &ChainVerification {
        &self.plan.verification
    }

    /// The planner's statistics (effort, peak velocity, iterations, optimality).
    pub fn stats(&self) -> &ChainStats {
        &self.plan.stats
    }

    /// `Ok` when every certificate computed holds, else [`Error::NotCertified`] naming the level.
    pub fn certified(&self) -> Result<(), Error> {
        let v = self.verification();
        if !v.certified {
            return Err(Error::NotCertified { final_error: v.final_error, tolerance: v.tolerance, level: "velocity" });
        }
        match &self.torques {
            Some(t) if !t.certificate.certified => Err(Error::NotCertified {
                final_error: t.certificate.final_error,
                tolerance: t.certificate.tolerance,
                level: "torque",
            }),
            _ => Ok(()),
        }
    }
}

/// Plans `request` for `arm` with `method` (only [`Method::Optimal`] serves arms other than the
/// 2-link robot; the others are bad input naming the reason), certifies it, and adds the torque
/// level when asked.
pub fn plan_arm(arm: &Arm, method: Method, request: &ArmRequest) -> Result<ArmPlanned, Error> {
    let refuse = |expected: &'static str| {
        Err(Error::from(InputError::InvalidParameter { name: "--method".into(), value: arm.joints() as f64, expected }))
    };
    match method {
        Method::Optimal => {}
        Method::Nfa => {
            return refuse(
                "the optimal method for this arm: the NFA's chained form (Eq. 10) is the 2-link robot's, \
                 and this arm has another number of links",
            );
        }
        Method::Ecsa => {
            return refuse("the optimal method for this arm: the ECSA is implemented for 2-link arms only");
        }
    }
    if request.samples < 2 {
        return Err(Error::from(InputError::InvalidParameter {
            name: "samples".into(),
            value: request.samples as f64,
            expected: "at least 2",
        }));
    }
    let clock = Instant::now();
    let options = ChainOptions { tolerance: request.tolerance, ..ChainOptions::default() };
    let plan = ChainPlanner::new(arm.clone(), options).plan(&request.problem)?;
    let trajectory = plan.sample(request.samples);
    let seconds = clock.elapsed().as_secs_f64();
    let torques = request.torques.then(|| arm_torques(arm, &plan, &trajectory, &request.problem)).transpose()?;
    Ok(ArmPlanned { arm: arm.clone(), method, plan, trajectory, torques, seconds })
}

/// The torques at the samples and the forward-dynamics certificate (tolerance and integrator
/// of the 2-link torque level, docs/spec.md §2).
fn arm_torques(
    arm: &Arm,
    plan: &ChainPlan,
    samples: &[ChainPoint],
    problem: &ChainProblem,
) -> Result<ArmTorques, Error> {
    let clock = Instant::now();
    let defaults = TorqueOptions::default();
    let n = arm.joints();
    let mut tau = Vec::with_capacity(samples.len());
    let (mut peak, mut residual) = (vec![0.0_f64; n], 0.0_f64);
    for p in samples {
        let id = chain_torques_at(arm, plan, p.t);
        for (m, t) in peak.iter_mut().zip(id.tau.iter()) {
            *m = m.max(t.abs());
        }
        residual = residual.max(id.base_residual.abs());
        tau.push(id.tau.iter().copied().collect());
    }
    let ode: OdeOptions = defaults.ode;
    let certificate = certify_chain_torques(arm, plan, &problem.start, &problem.goal, &ode, defaults.tolerance)?;
    Ok(ArmTorques {
        tau,
        max_abs_torque: peak,
        max_abs_base_residual: residual,
        certificate,
        seconds: clock.elapsed().as_secs_f64(),
    })
}
