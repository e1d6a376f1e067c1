//! The Normal Form Approach (Sec. 2, Fig. 1): feedback to the chained form (10), steering there,
//! and the inverse map back to the robot.

pub mod normal_form;
pub mod steering;
