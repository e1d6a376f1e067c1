//! The closed-loop certificate of a plan: the nominal robot, tracking the plan with computed
//! torque ([`Controller::Ct`]) at 1 kHz, no noise, reaches the goal within 1e-6 rad. A plan whose
//! open-loop torque certificate fails (an unstable open-loop motion) but whose closed-loop one
//! holds is executable with feedback (docs/spec.md §2).

use serde::Serialize;

use super::control::Controller;
use super::motion::{ArmMotion, TwoLinkMotion, two_link};
use super::run::{TrackOptions, track};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::plan::{Motion, PlanningProblem};
use crate::planners::chain::ChainProblem;

/// Tolerance of the closed-loop certificate \[rad\].
pub const CLOSED_LOOP_TOLERANCE: f64 = 1e-6;

/// The closed-loop certificate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosedLoopCertificate {
    /// The controller (`ct`).
    pub controller: Controller,
    /// Its rate \[Hz\].
    pub rate: f64,
    /// `max_i |wrap(q_i(T) - qd_i)|` of the tracked nominal robot \[rad\].
    pub final_error: f64,
    /// [`CLOSED_LOOP_TOLERANCE`] \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// `max |tau_k|` applied per joint [N m].
    pub peak_torque: Vec<f64>,
    /// Wall time \[s\].
    pub seconds: f64,
}

/// Tracks `motion` on the nominal robot of `problem` (a 2-link plan, [`TwoLinkMotion`]) with
/// computed torque at 1 kHz: [`arm_closed_loop_certificate`] of the 2-link arm.
pub fn closed_loop_certificate(
    problem: &PlanningProblem,
    motion: &(dyn Motion + Sync),
) -> Result<ClosedLoopCertificate, Error> {
    let (arm, chain) = two_link(problem);
    arm_closed_loop_certificate(&arm, &chain, &TwoLinkMotion(motion))
}

/// Tracks `motion` (planned for `problem` on `arm`) on the nominal arm with computed torque at
/// 1 kHz, no noise.
pub fn arm_closed_loop_certificate(
    arm: &Arm,
    problem: &ChainProblem,
    motion: &dyn ArmMotion,
) -> Result<ClosedLoopCertificate, Error> {
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let tracked = track(arm, problem, motion, arm, &options, 0)?;
    Ok(ClosedLoopCertificate {
        controller: Controller::Ct,
        rate: options.rate,
        final_error: tracked.final_error,
        tolerance: CLOSED_LOOP_TOLERANCE,
        certified: tracked.final_error <= CLOSED_LOOP_TOLERANCE,
        peak_torque: tracked.peak_torque,
        seconds: tracked.seconds,
    })
}
