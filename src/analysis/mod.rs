//! Analyses over many plans or configurations: the domains of existence of the feedback
//! transformations (Sec. 6, item 3; Figs. 13-14) and the mounting-point sweep.

pub mod domain;
pub mod sweep;
