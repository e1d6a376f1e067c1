//! The sweep's random start/goal pairs: common random numbers from a counter-based generator
//! keyed by `(seed, trial)`, so that trial `k` is the same pair at every mounting point.

use crate::model::Configuration;

/// SplitMix64's output function: a bijective 64-bit mix.
///
/// ## Reference
/// G. L. Steele, D. Lea, C. H. Flood, *Fast splittable pseudorandom number generators*, OOPSLA
/// 2014, doi:10.1145/2660193.2660195.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The `draw`-th uniform number in `[0, 1)` of trial `trial` under `seed`: counter-based, so any
/// trial can be drawn alone, in any order, on any machine.
pub(super) fn uniform(seed: u64, trial: u64, draw: u64) -> f64 {
    const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;
    let key = mix64(mix64(seed.wrapping_add(GAMMA)) ^ trial.wrapping_mul(GAMMA));
    let x = mix64(key.wrapping_add(draw.wrapping_add(1).wrapping_mul(GAMMA)));
    (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Trial `trial`'s start and goal: the start uniform on `[-pi, pi)^3`, the goal uniform on the
/// torus too, written as the representative nearest the start (each angle moves by less than
/// pi, the short way round).
pub fn trial_pair(seed: u64, trial: u64) -> (Configuration, Configuration) {
    use std::f64::consts::{PI, TAU};
    let angle = |draw| TAU * uniform(seed, trial, draw) - PI;
    let start = Configuration::new(angle(0), angle(1), angle(2));
    let goal = Configuration::new(start.phi + angle(3), start.theta1 + angle(4), start.theta2 + angle(5));
    (start, goal)
}
