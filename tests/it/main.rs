//! Integration tests: the command line as a user runs it.

mod animation;
mod arm;
mod arm_cli;
mod check;
mod cli;
mod first_hour;
mod geometry;
mod hard_set;
mod hostile;
mod hostile_files;
mod layout;
mod limits;
mod pictures;
mod precision;
mod properties;
mod reproduce;
mod sweep_cli;
mod track;
mod your_robot;
