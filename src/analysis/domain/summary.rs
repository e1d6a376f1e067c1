//! The summary of a domain map for a start and a goal (docs/spec.md §3; Sec. 6, item 3):
//! components, slivers, and whether `q0` and `qd` share a component.

use serde::Serialize;

use super::DomainMap;
use crate::model::Configuration;
use crate::planners::nfa::normal_form::Transform;

impl DomainMap {
    /// The summary of docs/spec.md §3 (`freefloat domain --format json`) for the start `q0` and goal `qd`.
    pub fn summary(&self, start: &Configuration, goal: &Configuration) -> DomainSummary {
        let start_component = self.component_at(start);
        let goal_component = self.component_at(goal);
        DomainSummary {
            mount: [self.robot.mount.a, self.robot.mount.b],
            grid: self.n,
            transform: self.transform,
            components: self.resolved_count(),
            component_fractions: self.components.iter().filter(|c| c.resolved).map(|c| c.fraction).collect(),
            slivers: self.components.len() - self.resolved_count(),
            sliver_fraction: self.components.iter().filter(|c| !c.resolved).map(|c| c.fraction).sum(),
            defined_fraction: self.defined_fraction(),
            start: start.to_array(),
            goal: goal.to_array(),
            start_component,
            goal_component,
            start_component_fraction: start_component.map_or(0.0, |c| self.components[c].fraction),
            start_goal_connected: start_component.is_some() && start_component == goal_component,
        }
    }
}

/// The report of `freefloat domain` (docs/spec.md §3), radians inside.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DomainSummary {
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Grid size `N` (the map has `N x N` cells).
    pub grid: usize,
    /// The transformation.
    pub transform: Transform,
    /// Number of connected components of the domain on the torus (resolved by the grid).
    pub components: usize,
    /// Area share of each resolved component, decreasing.
    pub component_fractions: Vec<f64>,
    /// Number of unresolved components (slivers, see [`Component::resolved`](super::Component::resolved)).
    pub slivers: usize,
    /// Their total area share.
    pub sliver_fraction: f64,
    /// Area share of the whole domain.
    pub defined_fraction: f64,
    /// `q0 = [phi, theta1, theta2]` \[rad\].
    pub start: [f64; 3],
    /// `qd` \[rad\].
    pub goal: [f64; 3],
    /// Index of `q0`'s component (into `component_fractions`, slivers after the resolved
    /// ones when they are smaller), null outside the domain.
    pub start_component: Option<usize>,
    /// Index of `qd`'s component, null outside the domain.
    pub goal_component: Option<usize>,
    /// Area share of `q0`'s component: where a plan from `q0` may go; 0 outside the domain.
    pub start_component_fraction: f64,
    /// `q0` and `qd` lie in the same component.
    pub start_goal_connected: bool,
}
