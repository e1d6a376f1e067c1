//! Every path into the freefloat library that is not a crate-root re-export, in one place, so
//! that a move of the library's modules touches this file only. The rest of the bindings use
//! `freefloat::{...}` root re-exports, or these names through `crate::compat`.

pub use freefloat::analysis::domain::{DomainMap, DomainSummary};
pub use freefloat::model::InputError;
pub use freefloat::model::kinematics::Elbow;
pub use freefloat::model::system::momentum;
pub use freefloat::planners::optimal::{Cost, OptimalOptions};
pub use freefloat::planners::{PlannerOptions, plan_to_pose, planner};
pub use freefloat::report::io::PlanReport;
