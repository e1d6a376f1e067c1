//! Statistics and termination of iterative solvers (as argmin's `TerminationReason`).

use serde::Serialize;

use super::ode::OdeStats;

/// Why an iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The residual reached the tolerance.
    Converged,
    /// The iteration limit was reached first.
    MaxIterations,
    /// The end point or the residual became non-finite.
    NonFinite,
    /// The linear system of an update was singular (for the ECSA: `J J^T + lambda^2 I` not
    /// positive definite, only possible with zero damping).
    SingularJacobian,
}

impl std::fmt::Display for Termination {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Termination::Converged => "converged",
            Termination::MaxIterations => "iteration limit reached",
            Termination::NonFinite => "non-finite end point",
            Termination::SingularJacobian => "singular Jacobian",
        })
    }
}

/// Statistics of an iterative solver (e.g. the ECSA's Jacobian pseudo-inverse iteration).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IterationStats {
    /// Updates made.
    pub iterations: usize,
    /// Final residual (for the ECSA `max_i |wrap(K_i(c) - q_di)|` \[rad\]).
    pub residual: f64,
    /// The residual tolerance \[rad\].
    pub tolerance: f64,
    /// The residual before each update and after the last one \[rad\]: `iterations + 1` entries.
    pub residual_history: Vec<f64>,
    /// Why the iteration stopped.
    pub termination: Termination,
    /// Integrator work over all evaluations (e.g. of the ECSA's `K` and `J`).
    pub ode: OdeStats,
}
