#![doc = include_str!("../README.md")]
//!
//! # The pipeline
//! Motion planning with the Normal Form Approach, after K. Tchoń, J. Ratajczak et al.,
//! *Normal form approach in the motion planning of space robots: a case study*. The folders
//! follow the pipeline, each layer importing only the ones above it in this list:
//!
//! 1. [`scalar`], [`numerics`]: the scalar type of every formula (exact derivatives by dual
//!    numbers), the adaptive integrator, quadrature and Chebyshev interpolation — nothing
//!    robot-specific;
//! 2. [`model`]: the robot ([`RobotParams`]), its lumped constants (Sec. 3.1) and the driftless
//!    system (7) at zero angular momentum ([`model::system`]);
//! 3. [`dynamics`]: the Lagrangian (3), the inertia matrix, inverse and forward dynamics (6);
//! 4. [`error`]: the error type of the planners, wrapping the layers' own errors;
//! 5. [`plan`]: planning problems, motions, plans with their certificates at the velocity and
//!    torque levels;
//! 6. [`planners`]: the [`Planner`] trait and its implementations, [`planners::nfa`] (the
//!    feedback transformations (11), (12), (14) to the chained form (10), steering, the inverse
//!    map) and [`planners::ecsa`] (the paper's reference method);
//! 7. [`analysis`]: where each transformation exists on the joint torus (Figs. 13-14) and the
//!    mounting-point design sweep;
//! 8. [`report`]: pictures, the JSON/CSV reports, the summary and the report page of
//!    `freefloat reproduce`.

// The command line names the library `freefloat::`, as any user of it does.
extern crate self as freefloat;

pub mod analysis;
/// The command line of the `freefloat` binary, in the library so that the Python package's
/// `freefloat` command is the same program (`cli::main_from`); not a stable API.
/// (Its doc comments are clap's help texts, with `[default: ..]` and `[[link]]` brackets that
/// are not links.)
#[doc(hidden)]
#[allow(rustdoc::broken_intra_doc_links, rustdoc::private_intra_doc_links)]
pub mod cli;
pub mod dynamics;
pub mod error;
pub mod model;
pub mod numerics;
pub mod plan;
pub mod planners;
pub mod report;
pub mod scalar;
pub mod track;

pub use error::{Error, Singularity};
pub use model::arm::{Arm, Base, Link};
pub use model::{Configuration, Lumped, Mount, RobotParams, paper_problem};
pub use plan::{Method, Motion, Plan, PlanningProblem, Trajectory};
pub use plan::{TorqueOptions, TorquePlan, TorqueReport, torque_plan};
pub use planners::ecsa::{EcsaOptions, EcsaPlanner, Window};
pub use planners::nfa::normal_form::{NormalForm, Transform};
pub use planners::nfa::{NfaOptions, NormalFormPlanner};
pub use planners::{Details, Planned, Planner};
pub use scalar::Scalar;
