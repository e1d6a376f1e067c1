//! Integration tests: the command line as a user runs it.

mod arm;
mod cli;
mod hostile;
mod layout;
mod properties;
mod reproduce;
mod track;
