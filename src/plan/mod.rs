//! Planning problems, planners and plans with their certificates (Secs. 2, 5 and 6).
//!
//! A [`Planner`](crate::Planner) turns a [`PlanningProblem`] into a
//! [`Planned`](crate::Planned): a [`Plan`] (a sampled
//! [`Trajectory`] with its [`Verification`], obtained by integrating the original system (7)
//! with the planned controls) and the exact [`Motion`] behind it, from which the torque level
//! ([`torques`]) and its certificate are computed. Both certificates are one routine for every
//! arm, `n = 2` included ([`certificate::verify_chain`], [`torques::certify_joint_torques`]).

pub mod certificate;
pub mod clearance;
pub mod limit_use;
pub mod limits;
pub mod motion;
pub mod problem;
pub mod ros;
pub mod torques;

use std::time::Instant;

use serde::Serialize;

pub use certificate::{JointMotion, MotionView, Verification, verify};
pub use motion::{Motion, MotionPoint, Trajectory, effort, max_abs_controls, peak_controls, travel};
pub use problem::{HORIZON_RANGE, MAX_ANGLE, PlanningProblem, check_horizon};
pub use torques::{
    TorqueCertificate, TorqueOptions, TorquePlan, TorqueReport, TorqueSeconds, add_torques, certify_torques,
    torque_plan, torques_at,
};

use crate::error::Error;
use crate::numerics::ode::OdeOptions;

/// Wall time of each stage \[s\].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Seconds {
    /// Planning (the velocity-level plan, sampled).
    pub plan: f64,
    /// Inverse dynamics, when torques were asked for.
    pub torques: Option<f64>,
    /// Verification (integration of system (7)).
    pub verify: f64,
}

/// The planning method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Normal Form Approach.
    Nfa,
    /// Endogenous Configuration Space Approach.
    Ecsa,
    /// Minimum-effort (or minimum-energy) steering of the joint path under the holonomy
    /// constraint of the base angle.
    Optimal,
}

impl Method {
    /// `nfa`, `ecsa` or `optimal`, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Nfa => "nfa",
            Method::Ecsa => "ecsa",
            Method::Optimal => "optimal",
        }
    }
}

/// A plan with its certificate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// The method used.
    pub method: Method,
    /// The problem solved.
    pub problem: PlanningProblem,
    /// The sampled trajectory.
    pub trajectory: Trajectory,
    /// `[max |u1|, max |u2|]` over `[0, T]` \[rad/s\]: the samples' largest, refined between
    /// them on the exact motion ([`peak_controls`]).
    pub max_abs_u: [f64; 2],
    /// Smallest `|sigma|` along the samples (domain margin).
    pub min_abs_sigma: f64,
    /// Smallest `|P|` along the samples (domain margin).
    pub min_abs_p: f64,
    /// Iterations (ECSA only).
    pub iterations: Option<usize>,
    /// Total variation of `(phi, theta1, theta2)` along the samples \[rad\].
    pub joint_travel: [f64; 3],
    /// The control effort `integral_0^T |u|^2 dt` \[rad^2/s\] ([`motion::effort`], or exact where
    /// the planner knows it).
    pub effort: f64,
    /// The velocity-level certificate.
    pub verification: Verification,
    /// Wall time per stage.
    pub seconds: Seconds,
}

impl Plan {
    /// Verifies `motion` (see [`verify`]) and assembles its plan from the sampled `trajectory`,
    /// the domain `margins` `(min |sigma|, min |P|)` and the planning time \[s\]: the fields every
    /// planner fills alike. `iterations` starts empty; the method's own fields
    /// are in its [`crate::planners::Details`].
    #[allow(clippy::too_many_arguments)]
    pub fn verified(
        method: Method,
        problem: &PlanningProblem,
        motion: &dyn Motion,
        trajectory: Trajectory,
        margins: (f64, f64),
        plan_seconds: f64,
        ode: &OdeOptions,
        tolerance: f64,
    ) -> Result<Plan, Error> {
        let clock = Instant::now();
        let verification = verify(motion, problem, ode, tolerance)?;
        let mut trajectory = trajectory;
        trajectory.add_task_space(&problem.robot);
        let verify_seconds = clock.elapsed().as_secs_f64();
        let max_abs_u = peak_controls(motion, &trajectory)?;
        Ok(Plan {
            method,
            problem: *problem,
            joint_travel: travel(&trajectory),
            effort: effort(&trajectory),
            max_abs_u,
            trajectory,
            min_abs_sigma: margins.0,
            min_abs_p: margins.1,
            iterations: None,
            verification,
            seconds: Seconds { plan: plan_seconds, torques: None, verify: verify_seconds },
        })
    }

    /// The plan if its velocity-level certificate holds, else [`Error::NotCertified`].
    pub fn certified(&self) -> Result<&Plan, Error> {
        let v = &self.verification;
        if v.certified {
            certificate::collision(v.clearance.as_ref())?;
            Ok(self)
        } else {
            Err(Error::NotCertified { final_error: v.final_error, tolerance: v.tolerance, level: "velocity" })
        }
    }
}

#[cfg(test)]
mod tests;
