//! The Normal Form Approach (Sec. 2, Fig. 1): feedback to the chained form (10), steering there,
//! and the inverse map back to the robot.

pub mod motion;
pub mod normal_form;
pub mod planner;
pub mod steering;

pub use motion::NfaMotion;
pub use planner::{NfaDetails, NfaOptions, NormalFormPlanner};

#[cfg(test)]
mod tests;
