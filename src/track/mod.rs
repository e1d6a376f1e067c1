//! Closed-loop execution (issue 12): a plan tracked on a robot that is not the model, reaching
//! the goal anyway.
//!
//! The planners' certificates integrate the model. A real robot differs from it (masses,
//! lengths, the mounting point), its actuators are noisy and limited, its sensors noisy, and its
//! controller digital. This module simulates that for any planar serial arm ([`plant`]: the
//! forward dynamics of an [`Arm`](crate::Arm) of `n` links, `2 (n + 1)` states, under a
//! zero-order-held torque) and closes the loop around a plan ([`ArmMotion`]: the `n`-joint
//! planners' plans, or a 2-link plan through [`TwoLinkMotion`]) with four controllers
//! ([`Controller`]), all built on a model:
//!
//! - `open`: the planned torques (Eq. 6) alone;
//! - `ct`: computed torque with PD on the joint angles ([`control::computed_torque`]), its
//!   feedforward corrected for the zero-order hold on the nominal model ([`hold`]). It cannot
//!   correct the base angle `phi` on another robot: only the holonomy of the joint path moves it;
//! - `replan`: `ct` plus receding-horizon re-planning ([`replan`], the `n`-joint minimum-effort
//!   planner) from the measured state to the goal in the remaining time, which steers `phi` back;
//! - `adaptive`: `replan` on a model whose momentum map (Eqs. 5, 8 for `n` links) is identified
//!   on line ([`identify`]), so that the re-plans aim right, and whose common factor the joint
//!   torques' work fixes ([`energy`]), so that the computed torque is the robot's.
//!
//! [`track()`] runs one of them; [`monte_carlo()`] runs many seeded trials in parallel, whole or
//! in shards whose checked files ([`trials_file`]) merge into the whole.
//!
//! ```
//! use freefloat::planners::arm::{ArmRequest, plan_arm};
//! use freefloat::planners::chain::ChainProblem;
//! use freefloat::track::{Controller, TrackOptions, track};
//! use freefloat::{Arm, Method, RobotParams};
//!
//! let arm = Arm::from_params(&RobotParams::src());
//! let problem = ChainProblem::rest_to_rest(
//!     [45.0_f64, 120.0, 80.0].map(f64::to_radians).to_vec(),
//!     [0.0_f64, 180.0, 140.0].map(f64::to_radians).to_vec(),
//!     10.0,
//! );
//! let planned = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
//! let options = TrackOptions { controller: Controller::Ct, rate: 200.0, ..Default::default() };
//! let run = track(&arm, &problem, &planned.plan, &arm, &options, 0).unwrap();
//! assert!(run.final_error < 1e-4);
//! ```

pub mod certificate;
pub mod control;
pub mod energy;
pub mod hold;
pub mod identify;
pub mod monte_carlo;
pub mod motion;
pub mod noise;
pub mod perturb;
pub mod plant;
pub mod replan;
pub mod run;
pub mod trials_file;

pub use certificate::{
    CLOSED_LOOP_TOLERANCE, ClosedLoopCertificate, arm_closed_loop_certificate, closed_loop_certificate,
};
pub use control::{Controller, Gains};
pub use hold::HoldCorrection;
pub use identify::IdentifyOptions;
pub use monte_carlo::{MonteCarloOptions, Summary, Trial, monte_carlo, summarise};
pub use motion::{ArmMotion, JointPoint, TwoLinkMotion, two_link};
pub use perturb::Perturbation;
pub use plant::Disturbances;
pub use replan::ReplanOptions;
pub use run::{
    BYTES_PER_TICK, Failure, History, HoldSummary, Identification, MAX_REPLANS, MAX_TICKS, TrackOptions, Tracked,
    check_run, hold_correction, track, track_with,
};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_clearance;
#[cfg(test)]
mod tests_hard;
#[cfg(test)]
mod tests_limits;
