//! Analyses over many plans or configurations: the domains of existence of the feedback
//! transformations (Sec. 6, item 3; Figs. 13-14), the mounting-point sweep, and the checked
//! files of runs cut into shards.

pub mod check;
pub mod domain;
pub mod shards;
pub mod sweep;
