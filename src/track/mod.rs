//! Closed-loop execution (issue 12): a plan tracked on a robot that is not the model, reaching
//! the goal anyway.
//!
//! The planners' certificates integrate the model. A real robot differs from it (masses,
//! lengths, the mounting point), its actuators are noisy and limited, its sensors noisy, and its
//! controller digital. This module simulates that ([`plant`]: the 6-state forward dynamics of
//! Sec. 3.1 under a zero-order-held torque) and closes the loop around a plan with four
//! controllers ([`Controller`]), all built on a model:
//!
//! - `open`: the planned torques (Eq. 6) alone;
//! - `ct`: computed torque with PD on the joint angles ([`control::computed_torque`]), its
//!   feedforward corrected for the zero-order hold on the nominal model ([`hold`]). It cannot
//!   correct the base angle `phi` on another robot: only the holonomy of the joint path moves it;
//! - `replan`: `ct` plus receding-horizon re-planning ([`replan`]) from the measured state to the
//!   goal in the remaining time, which steers `phi` back;
//! - `adaptive`: `replan` on a model whose momentum map (Eqs. 5, 8) is identified on line
//!   ([`identify`]), so that the re-plans aim right.
//!
//! [`track()`] runs one of them; [`monte_carlo()`] runs many seeded trials in parallel, whole or
//! in shards whose checked files ([`trials_file`]) merge into the whole.
//!
//! ```
//! use freefloat::planners::{PlannerOptions, planner};
//! use freefloat::track::{Controller, TrackOptions, track};
//! use freefloat::{Method, PlanningProblem, RobotParams};
//!
//! let problem = PlanningProblem::paper(RobotParams::src());
//! let planned = planner(Method::Optimal, &PlannerOptions::default()).plan(&problem).unwrap();
//! let options = TrackOptions { controller: Controller::Ct, rate: 200.0, ..Default::default() };
//! let run = track(&problem, planned.motion.as_ref(), &problem.robot, &options, 0).unwrap();
//! assert!(run.final_error < 1e-4);
//! ```

pub mod certificate;
pub mod control;
pub mod hold;
pub mod identify;
pub mod monte_carlo;
pub mod noise;
pub mod perturb;
pub mod plant;
pub mod replan;
pub mod run;
pub mod trials_file;

pub use certificate::{CLOSED_LOOP_TOLERANCE, ClosedLoopCertificate, closed_loop_certificate};
pub use control::{Controller, Gains};
pub use hold::HoldCorrection;
pub use identify::IdentifyOptions;
pub use monte_carlo::{MonteCarloOptions, Summary, Trial, monte_carlo, summarise};
pub use perturb::Perturbation;
pub use plant::Disturbances;
pub use replan::ReplanOptions;
pub use run::{
    BYTES_PER_TICK, Failure, History, HoldSummary, Identification, MAX_REPLANS, MAX_TICKS, TrackOptions, Tracked,
    hold_correction, track, track_with,
};

#[cfg(test)]
mod tests;
