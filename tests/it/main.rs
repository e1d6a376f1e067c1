//! Integration tests: the command line as a user runs it.

mod cli;
mod layout;
mod properties;
mod reproduce;
mod track;
