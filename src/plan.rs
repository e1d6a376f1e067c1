//! Planning problems and plans.
