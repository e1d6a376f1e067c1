//! Every path into the freefloat library that is not a crate-root re-export, in one place, so
//! that a move of the library's modules touches this file only. The rest of the bindings use
//! `freefloat::{...}` root re-exports, or these names through `crate::compat`.

pub use freefloat::domain::{DomainMap, DomainSummary};
pub use freefloat::dynamics::add_torques;
pub use freefloat::io::PlanReport;
pub use freefloat::system::momentum;
