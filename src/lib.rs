#![doc = include_str!("../README.md")]
//!
//! # The pipeline
//! Motion planning with the Normal Form Approach, after K. Tchoń, J. Ratajczak et al.,
//! *Normal form approach in the motion planning of space robots: a case study*:
//!
//! 1. [`model`]: the robot ([`RobotParams`]) and its lumped constants (Sec. 3.1);
//! 2. [`system`]: the driftless system (7) at zero angular momentum;
//! 3. [`normal_form`]: the feedback transformations (11), (12), (14) to the chained form (10);
//! 4. [`steering`]: polynomial controls of the chained form (Sec. 5);
//! 5. [`plan`]: the inverse map back to `q` (Sec. 6) and the plan with its certificate;
//! 6. [`ode`]: the adaptive integrator that verifies every plan;
//! 7. [`ecsa`]: the paper's reference method, the Endogenous Configuration Space Approach;
//! 8. [`domain`]: where each transformation exists on the joint torus (Sec. 6, item 3; Figs. 13-14),
//!    and [`sweep`]: the mounting-point design tool;
//! 9. [`dynamics`]: the Lagrangian (3), exact inverse dynamics (6) along any [`Motion`] and the
//!    forward-dynamics certificate of the torques.

pub mod chebyshev;
pub mod domain;
pub mod dynamics;
pub mod ecsa;
pub mod error;
pub mod io;
pub mod model;
pub mod normal_form;
pub mod ode;
pub mod optimal;
pub mod plan;
pub mod plot;
pub mod quadrature;
pub mod report;
pub mod steering;
pub mod sweep;
pub mod system;

pub use dynamics::{TorqueOptions, TorquePlan, TorqueReport, torque_plan};
pub use ecsa::{EcsaOptions, EcsaPlanner, Window};
pub use error::{Error, Singularity};
pub use model::{Configuration, Lumped, Mount, RobotParams, paper_problem};
pub use normal_form::{NormalForm, Transform};
pub use plan::{Motion, NfaOptions, NormalFormPlanner, Plan, Planner, PlanningProblem, Trajectory};

/// The scalar type of every formula: `f64` or a (nested) dual number of `num-dual`, so that
/// exact derivatives come from forward-mode automatic differentiation.
pub trait Scalar: num_dual::DualNum<Primitive = f64> + Copy {}
impl<T: num_dual::DualNum<Primitive = f64> + Copy> Scalar for T {}
