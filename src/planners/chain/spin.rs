//! Spin goals: on a heavy base a joint's turn turns the base a little, and spinning one joint
//! whole turns is the cheap way to turn it far (docs/spec.md §2, `optimal`). The goal
//! representatives of [`ChainPlanner::prepare`] have at most a turn or two further on each
//! joint; these have as many as the holonomy (Eq. 7) needs.

use std::f64::consts::TAU;

use super::seeds::Line;
use super::{ChainPlanner, ChainProblem};

/// The most whole turns of one joint that a spin goal ([`ChainPlanner::spin_goals`]) takes.
pub const MAX_SPIN_TURNS: i32 = 64;

impl ChainPlanner {
    /// The goals where one joint spins whole turns beyond `near` (the other joints' goals as
    /// `near`'s): for each base target of `phi_targets`, the turns `k` of joint `j` that the
    /// holonomy (Eq. 7) needs to end on it, `k = -(phid - phi0 + h) / c`, with `h` the straight
    /// line's holonomy to `near` and `c` the base's turn per turn of joint `j` (the connection's
    /// `a_j` over one turn of the joint at `near`, by the trapezoidal rule, exact to rounding
    /// for a smooth periodic integrand), both whole numbers around it, where that is more turns
    /// than the other representatives have (`tried`) and at most [`MAX_SPIN_TURNS`]. On a
    /// heavy base a joint's turn turns the base a little, and spinning is the cheap way to turn
    /// it far: on a 2000 kg base with the paper's arm, the base 90 deg round took theta1 36
    /// turns at effort 5130 rad^2/s, against 36275 by coils (a loop's area turns the base only
    /// as the curvature allows). Costs `16 n` evaluations of the connection and one line's
    /// holonomy.
    pub(super) fn spin_goals(
        &self,
        problem: &ChainProblem,
        near: &[f64],
        phi_targets: &[f64],
        tried: i32,
    ) -> Vec<Vec<f64>> {
        const NODES: usize = 16;
        let line = Line {
            start: problem.start[1..].to_vec(),
            end: near.to_vec(),
            initial_velocity: problem.initial_velocity.clone(),
            horizon: problem.horizon,
        };
        let h = line.holonomy(&self.connection);
        let mut out: Vec<Vec<f64>> = Vec::new();
        for j in (0..near.len()).filter(|&j| self.arm.limits.joint(j).position.is_none()) {
            let (mut theta, mut rate) = (near.to_vec(), vec![0.0; near.len()]);
            rate[j] = 1.0;
            let mean = (0..NODES)
                .map(|i| {
                    theta[j] = near[j] + TAU * i as f64 / NODES as f64;
                    self.connection.value(&theta, &rate)
                })
                .sum::<f64>()
                / NODES as f64;
            let per_turn = TAU * mean;
            if !(per_turn.abs() > 1e-12) {
                continue;
            }
            for &phi_end in phi_targets {
                let k = -(phi_end - problem.start[0] + h) / per_turn;
                if !(k.abs() > f64::from(tried) && k.abs() <= f64::from(MAX_SPIN_TURNS)) {
                    continue;
                }
                for whole in [k.floor(), k.ceil()] {
                    let mut g = near.to_vec();
                    g[j] += TAU * whole;
                    if whole.abs() > f64::from(tried) && !out.contains(&g) {
                        out.push(g);
                    }
                }
            }
        }
        out
    }
}
