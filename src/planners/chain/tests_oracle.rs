//! An independent oracle for the constrained minimum (issue 20 item 3): a direct transcription
//! of the problem on a uniform grid, solved by an augmented Lagrangian with L-BFGS inner steps
//! from several random starts. It shares no code with the planner's SQP, its splines or its
//! connection: the joint path is piecewise linear, the base follows the arm's own
//! [`Arm::base_rate`] (Eq. 7) by the midpoint rule, the torques are the inverse dynamics at the
//! nodes with finite-difference rates (rest at both ends), every limit a penalised row. Its
//! solver is [`super::tests_oracle_solver`].

use super::horizon::uses;
use super::tests::three_link;
use super::tests_oracle_solver::{augmented_lagrangian, penalty};
use super::*;
use crate::dynamics::arm::ArmDynamics;
use crate::model::arm::{JointLimits, Limits};

/// The transcribed problem: `N` intervals of width `h`, the interior nodes' angles free.
pub(super) struct Transcription<'a> {
    pub(super) arm: &'a Arm,
    pub(super) dynamics: ArmDynamics,
    pub(super) start: Vec<f64>,
    pub(super) goal: Vec<f64>,
    pub(super) horizon: f64,
    pub(super) intervals: usize,
    /// The distance every pair of the robot's own bodies keeps at the interior nodes \[m\].
    pub(super) keep: Option<f64>,
}

impl Transcription<'_> {
    fn n(&self) -> usize {
        self.arm.joints()
    }

    fn h(&self) -> f64 {
        self.horizon / self.intervals as f64
    }

    /// The node angles (start and goal included) of the free variables `x`.
    pub(super) fn nodes(&self, x: &[f64]) -> Vec<Vec<f64>> {
        let n = self.n();
        let mut out = vec![self.start[1..].to_vec()];
        out.extend(x.chunks(n).map(|c| c.to_vec()));
        out.push(self.goal[1..].to_vec());
        out
    }

    /// The base's rotation over interval `[a, b]` by the midpoint rule.
    fn base_step(&self, a: &[f64], b: &[f64]) -> f64 {
        let h = self.h();
        let mid: Vec<f64> = a.iter().zip(b).map(|(p, q)| 0.5 * (p + q)).collect();
        let rate: Vec<f64> = a.iter().zip(b).map(|(p, q)| (q - p) / h).collect();
        h * self.arm.base_rate(&mid, &rate)
    }

    /// The torques at node `k` from its neighbours (rest at both ends).
    fn torque(&self, prev: Option<&[f64]>, at: &[f64], next: Option<&[f64]>) -> Vec<f64> {
        let h = self.h();
        let n = self.n();
        let (mut w, mut a) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            let before = prev.map_or(0.0, |p| (at[j] - p[j]) / h);
            let after = next.map_or(0.0, |q| (q[j] - at[j]) / h);
            // One-sided at the ends: the rest velocity at the node, the half-interval's mean.
            (w[j], a[j]) = match (prev, next) {
                (Some(_), Some(_)) => (0.5 * (before + after), (after - before) / h),
                (None, _) => (0.0, after / (0.5 * h)),
                (_, None) => (0.0, -before / (0.5 * h)),
            };
        }
        self.dynamics.inverse(at, &w, &a).tau.iter().copied().collect()
    }

    /// The scaled rows `g <= 0` of node `k`'s limits: its torques, the velocity of the interval
    /// after it, its position.
    fn node_rows(&self, q: &[Vec<f64>], k: usize) -> Vec<f64> {
        let (n, h) = (self.n(), self.h());
        let l = |j: usize| self.arm.limits.joint(j);
        let mut out = Vec::new();
        let tau = if (0..n).any(|j| l(j).torque.is_some()) {
            let prev = (k > 0).then(|| q[k - 1].as_slice());
            let next = q.get(k + 1).map(|v| v.as_slice());
            self.torque(prev, &q[k], next)
        } else {
            vec![0.0; n]
        };
        for j in 0..n {
            if let Some(t) = l(j).torque {
                out.extend([tau[j] / t - 1.0, -tau[j] / t - 1.0]);
            }
            if let (Some(v), Some(next)) = (l(j).velocity, q.get(k + 1)) {
                let rate = (next[j] - q[k][j]) / h;
                out.extend([rate / v - 1.0, -rate / v - 1.0]);
            }
            if let Some([lo, hi]) = l(j).position {
                out.extend([(q[k][j] - hi) / (hi - lo), (lo - q[k][j]) / (hi - lo)]);
            }
        }
        out.extend(super::tests_clearance_oracle::clearance_rows(self, q, k));
        out
    }

    /// Every node's rows, concatenated, then the base range's rows ([`Self::base_rows`]).
    fn rows(&self, q: &[Vec<f64>]) -> Vec<f64> {
        let mut out: Vec<f64> = (0..q.len()).flat_map(|k| self.node_rows(q, k)).collect();
        let mut phi = vec![self.start[0]];
        for w in q.windows(2) {
            phi.push(phi[phi.len() - 1] + self.base_step(&w[0], &w[1]));
        }
        out.extend(self.base_rows(&phi[1..]));
        out
    }

    /// The scaled rows of the base range at the base angles `phi` of nodes 1, 2, .. (two each;
    /// none without a base range).
    fn base_rows(&self, phi: &[f64]) -> Vec<f64> {
        let Some([lo, hi]) = self.arm.limits.base else { return Vec::new() };
        phi.iter().flat_map(|p| [(p - hi) / (hi - lo), (lo - p) / (hi - lo)]).collect()
    }

    /// Effort, holonomy residual and the limits' rows at `x`.
    pub(super) fn evaluate(&self, x: &[f64]) -> (f64, f64, Vec<f64>) {
        let q = self.nodes(x);
        let h = self.h();
        let mut effort = 0.0;
        let mut phi = self.start[0];
        for w in q.windows(2) {
            effort += w[0].iter().zip(&w[1]).map(|(a, b)| (b - a) * (b - a)).sum::<f64>() / h;
            phi += self.base_step(&w[0], &w[1]);
        }
        (effort, phi - self.goal[0], self.rows(&q))
    }

    /// The augmented Lagrangian `E + lambda c + r c^2 / 2 + sum (max(0, z + r g)^2 - z^2) / 2r`.
    pub(super) fn lagrangian(&self, x: &[f64], lambda: f64, z: &[f64], r: f64) -> f64 {
        let (e, c, g) = self.evaluate(x);
        e + lambda * c + 0.5 * r * c * c + penalty(&g, z, r)
    }

    /// Its gradient by central differences, each node's angles moving only the terms next to it
    /// (the intervals on either side, the rows of the node and its neighbours).
    pub(super) fn gradient(&self, x: &[f64], lambda: f64, z: &[f64], r: f64) -> Vec<f64> {
        let (n, h, intervals) = (self.n(), self.h(), self.intervals);
        let mut q = self.nodes(x);
        let steps: Vec<f64> = q.windows(2).map(|w| self.base_step(&w[0], &w[1])).collect();
        let c = self.start[0] + steps.iter().sum::<f64>() - self.goal[0];
        let mut offsets = vec![0];
        for k in 0..q.len() {
            offsets.push(offsets[k] + self.node_rows(&q, k).len());
        }
        // The base angle at every node; moving node `k` shifts it at nodes `k..` alike, so the
        // base range's rows there (after the nodes' rows, two per node from node 1) all move.
        let mut phi = vec![self.start[0]];
        for s in &steps {
            phi.push(phi[phi.len() - 1] + s);
        }
        let base = offsets[q.len()];
        let per_node = self.base_rows(&phi[..1]).len();
        let mut out = Vec::with_capacity(x.len());
        for k in 1..intervals {
            for j in 0..n {
                let x0 = q[k][j];
                let step = 1e-6 * (1.0 + x0.abs());
                let mut local = |v: f64| {
                    q[k][j] = v;
                    let mut value = 0.0;
                    let mut cc = c - steps[k - 1] - steps[k];
                    let mut moved = [0.0; 2];
                    for (s, i) in [k - 1, k].into_iter().enumerate() {
                        value += q[i].iter().zip(&q[i + 1]).map(|(a, b)| (b - a) * (b - a)).sum::<f64>() / h;
                        moved[s] = self.base_step(&q[i], &q[i + 1]);
                        cc += moved[s];
                    }
                    value += lambda * cc + 0.5 * r * cc * cc;
                    for m in k - 1..=k + 1 {
                        value += penalty(&self.node_rows(&q, m), &z[offsets[m]..offsets[m + 1]], r);
                    }
                    if per_node > 0 {
                        // Node k's base angle moves with the interval before it, the later ones
                        // with both.
                        let (first, rest) = (moved[0] - steps[k - 1], cc - c);
                        let phi: Vec<f64> =
                            phi[k..].iter().enumerate().map(|(i, p)| p + if i == 0 { first } else { rest }).collect();
                        value += penalty(&self.base_rows(&phi), &z[base + per_node * (k - 1)..], r);
                    }
                    value
                };
                let (up, down) = (local(x0 + step), local(x0 - step));
                q[k][j] = x0;
                out.push((up - down) / (2.0 * step));
            }
        }
        out
    }
}

/// The oracle's constrained minimum effort: the least effort over `starts` random starts of a
/// feasible (holonomy within 1e-6 rad, every row within a relative 1e-5 of its limit, which moves
/// the effort by about as much, far below the test's 1 %) augmented-Lagrangian solution;
/// infinity when none is feasible.
fn oracle(arm: &Arm, problem: &ChainProblem, intervals: usize, starts: usize) -> f64 {
    oracle_from(arm, problem, intervals, starts, None)
}

/// The oracle's least feasible effort from `starts` random starts and, with `from`, also from
/// that plan's joint path sampled at the nodes: a local check by an independent method (a plan
/// at a constrained minimum is not improved by more than the two transcriptions' difference).
pub(super) fn oracle_from(
    arm: &Arm,
    problem: &ChainProblem,
    intervals: usize,
    starts: usize,
    from: Option<&ChainPlan>,
) -> f64 {
    let t = Transcription {
        arm,
        dynamics: ArmDynamics::new(arm),
        start: problem.start.clone(),
        goal: problem.goal.clone(),
        horizon: problem.horizon,
        intervals,
        keep: None,
    };
    let n = arm.joints();
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut random = move || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let mut best = f64::INFINITY;
    for start in 0..starts + usize::from(from.is_some()) {
        // The straight line plus two random sine modes per joint (0.5 rad at most), clipped
        // into the ranges; or the given plan.
        let amplitude: Vec<[f64; 2]> = (0..n).map(|_| [0.5 * random(), 0.5 * random()]).collect();
        let mut x = Vec::new();
        if let Some(plan) = from.filter(|_| start == starts) {
            for k in 1..intervals {
                x.extend(plan.at(problem.horizon * k as f64 / intervals as f64).theta);
            }
        } else {
            for k in 1..intervals {
                let s = k as f64 / intervals as f64;
                for (j, [a1, a2]) in amplitude.iter().enumerate() {
                    let line = t.start[j + 1] + s * (t.goal[j + 1] - t.start[j + 1]);
                    let wave = a1 * (std::f64::consts::PI * s).sin() + a2 * (std::f64::consts::TAU * s).sin();
                    let v = line + wave;
                    x.push(match arm.limits.joint(j).position {
                        Some([lo, hi]) => v.clamp(lo + 1e-3, hi - 1e-3),
                        None => v,
                    });
                }
            }
        }
        let (x, r) = augmented_lagrangian(&t, x);
        let (e, c, g) = t.evaluate(&x);
        let worst = g.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v));
        eprintln!("  oracle start: effort {e:.6}, holonomy residual {c:.1e} rad, largest row {worst:.1e}, r {r:.0e}");
        if c.abs() <= 1e-6 && worst <= 1e-5 {
            best = best.min(e);
        }
    }
    best
}

pub(super) fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// `arm` with every joint's `quantity` limited to `fraction` of the unconstrained plan's use
/// (positions: the range of the joint that swings furthest beyond its start and goal, cut to
/// `fraction` of that excursion).
fn tightened(arm: &Arm, plan: &ChainPlan, problem: &ChainProblem, quantities: &[&str], fraction: f64) -> Arm {
    let n = arm.joints();
    let mut joints = vec![JointLimits::default(); n];
    let mut peak = vec![[0.0_f64; 2]; n];
    let mut range = vec![[f64::INFINITY, f64::NEG_INFINITY]; n];
    for k in 0..=2000 {
        let p = plan.at(plan.horizon() * k as f64 / 2000.0);
        let tau = crate::dynamics::arm::inverse_dynamics(arm, &p.theta, &p.rate, &p.acceleration).tau;
        for j in 0..n {
            peak[j] = [peak[j][0].max(p.rate[j].abs()), peak[j][1].max(tau[j].abs())];
            range[j] = [range[j][0].min(p.theta[j]), range[j][1].max(p.theta[j])];
        }
    }
    // The excursion of each joint beyond its start and goal, below and above.
    let excursion = |j: usize| {
        let (a, b) = (problem.start[j + 1], problem.goal[j + 1]);
        [a.min(b), a.max(b), a.min(b) - range[j][0], range[j][1] - a.max(b)]
    };
    let widest = (0..n).max_by(|&a, &b| {
        let (ea, eb) = (excursion(a), excursion(b));
        ea[2].max(ea[3]).total_cmp(&eb[2].max(eb[3]))
    });
    for (j, l) in joints.iter_mut().enumerate() {
        for q in quantities {
            match *q {
                "velocity" => l.velocity = Some(fraction * peak[j][0]),
                "torque" => l.torque = Some(fraction * peak[j][1]),
                // The range of the joint that swings furthest past its ends only.
                _ if Some(j) == widest => {
                    let [lo, hi, below, above] = excursion(j);
                    l.position = Some([lo - fraction * below - 1e-3, hi + fraction * above + 1e-3]);
                }
                _ => {}
            }
        }
    }
    arm.clone().with_limits(Limits { joints, base: None }).expect("valid limits")
}

/// On a constrained problem of the 3-link example (a torque limit at a fraction of the
/// unconstrained plan's use so that it must bind), the planner's certified effort is at most 1 %
/// above the oracle's.
#[test]
fn the_constrained_minimum_matches_an_independent_oracle() {
    against_the_oracle(&[(&["torque"][..], 0.7)]);
}

/// [`the_constrained_minimum_matches_an_independent_oracle`] with a velocity limit, and velocity
/// with torque.
#[test]
fn the_constrained_minimum_matches_the_oracle_with_a_velocity_limit() {
    against_the_oracle(&[(&["velocity"][..], 0.8), (&["velocity", "torque"][..], 0.85)]);
}

/// The planner against the oracle on the 3-link example with the limits `cases` (quantities, and
/// the fraction of the unconstrained plan's use they are set to).
fn against_the_oracle(cases: &[(&[&str], f64)]) {
    let free = three_link();
    let problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0]), 10.0)
    };
    let unconstrained = ChainPlanner::new(free.clone(), ChainOptions::default()).plan(&problem).expect("free plan");
    for &(quantities, fraction) in cases {
        let arm = tightened(&free, &unconstrained, &problem, quantities, fraction);
        let planner = ChainPlanner::new(arm.clone(), ChainOptions::default());
        let (before, _) = uses(&planner, &unconstrained);
        assert!(before.expect("limits").used > 1.0, "{quantities:?}: the free plan breaks the limit");
        let plan = planner.plan(&problem).expect("a constrained plan");
        assert!(plan.verification.certified, "{quantities:?}: certified");
        let (after, _) = uses(&planner, &plan);
        let reference = oracle(&arm, &problem, 40, 3);
        eprintln!(
            "{quantities:?} at {fraction}: planner {:.6}, oracle {reference:.6}, free {:.6}, binding {after:?}",
            plan.effort(),
            unconstrained.effort()
        );
        assert!(reference.is_finite(), "{quantities:?}: the oracle found a feasible point");
        assert!(plan.effort() <= 1.01 * reference, "{quantities:?}: {} vs oracle {reference}", plan.effort());
        assert!(plan.effort() >= unconstrained.effort() * (1.0 - 1e-9), "{quantities:?}: above the free minimum");
    }
}

/// The fourth problem, where a position range binds: SPART's 4-link example with the tight
/// limits (+-2 rad, 0.3 rad/s, 50 N m) of `tests_limits::tight_limits_bind_and_hold`, whose
/// unconstrained plan leaves theta2's range. The planner's certified effort is at most 1 % above
/// the oracle's.
#[test]
fn a_binding_position_range_matches_an_independent_oracle() {
    // Without the example's shapes: the oracle knows no clearance.
    let free = Arm::from_urdf_str(include_str!("../../../examples/robots/spart_like_4dof.urdf"), "spart.urdf".as_ref())
        .expect("the example URDF");
    let free = Arm { geometry: Default::default(), ..free };
    let joint =
        JointLimits { position: Some([-2.0, 2.0]), velocity: Some(0.3), torque: Some(50.0), acceleration: None };
    let tight = free.clone().with_limits(Limits { joints: vec![joint; 4], base: None }).expect("valid limits");
    let problem = ChainProblem {
        wrap: false,
        ..ChainProblem::rest_to_rest(deg(&[0.0, 20.0, -30.0, 40.0, 10.0]), deg(&[30.0, 60.0, 30.0, -20.0, 40.0]), 30.0)
    };
    let unconstrained = ChainPlanner::new(free, ChainOptions::default()).plan(&problem).expect("free plan");
    let planner = ChainPlanner::new(tight.clone(), ChainOptions::default());
    let (before, _) = uses(&planner, &unconstrained);
    let before = before.expect("limits");
    assert!(before.quantity == "position" && before.used > 1.0, "the free plan leaves a range: {before:?}");
    let plan = planner.plan(&problem).expect("a constrained plan");
    assert!(plan.verification.certified, "certified");
    let (after, _) = uses(&planner, &plan);
    let reference = oracle(&tight, &problem, 48, 2);
    eprintln!("tight SPART: planner {:.6}, oracle {reference:.6}, binding {after:?}", plan.effort());
    assert!(reference.is_finite(), "the oracle found a feasible point");
    assert!(plan.effort() <= 1.01 * reference, "{} vs oracle {reference}", plan.effort());
}

/// The 20 constrained problems of the 3-link example (see
/// [`twenty_constrained_problems_against_the_oracle`]): the arm with its limits, the problem and
/// the limited quantities; `None` where the unconstrained planner has no plan to tighten from.
fn twenty_cases() -> Vec<Option<(Arm, ChainProblem, &'static [&'static str])>> {
    let free = three_link();
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut random = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let cases: [(&[&str], f64); 4] =
        [(&["torque"], 0.7), (&["velocity"], 0.8), (&["velocity", "torque"], 0.85), (&["position"], 0.5)];
    (0..20)
        .map(|k| {
            let jitter = |base: [f64; 4], random: &mut dyn FnMut() -> f64| -> Vec<f64> {
                base.iter().map(|b| (b + 60.0 * random()).to_radians()).collect()
            };
            let start = jitter([0.0, 60.0, -30.0, -30.0], &mut random);
            let goal = jitter([30.0, 120.0, 40.0, -60.0], &mut random);
            let problem = ChainProblem { wrap: false, ..ChainProblem::rest_to_rest(start, goal, 10.0) };
            let (quantities, fraction) = cases[k % cases.len()];
            let unconstrained = ChainPlanner::new(free.clone(), ChainOptions::default()).plan(&problem).ok()?;
            Some((tightened(&free, &unconstrained, &problem, quantities, fraction), problem, quantities))
        })
        .collect()
}

/// Binding position ranges (issue 20): on cases 7, 11, 15 and 19 of the twenty (the oracle
/// feasible on each; at stop 40 the SQP stalled on 7, 15 and 19, the search failed on 11 and
/// found another minimum on 15) the planner returns a certified plan inside every limit, its
/// range binding, converged, and within 1 % of the oracle's random starts (or below).
#[test]
fn binding_position_ranges_give_a_certified_plan_inside_them() {
    let cases = twenty_cases();
    for k in [7, 11, 15, 19] {
        let (arm, problem, quantities) = cases[k].clone().expect("a free plan");
        assert_eq!(quantities, ["position"]);
        let plan = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem).expect("a plan");
        assert!(plan.verification.certified, "case {k}: {:?}", plan.verification);
        let limits = plan.verification.limits.as_ref().expect("the limits' use");
        assert!(limits.inside, "case {k}: {limits:?}");
        let used = limits.most_used().expect("a range").used;
        assert!(used > 0.99, "case {k}: the range binds ({used})");
        assert!(plan.stats.converged, "case {k}: {:?}", plan.stats);
        let reference = oracle(&arm, &problem, 40, 3);
        assert!(plan.effort() <= 1.01 * reference, "case {k}: {} vs oracle {reference}", plan.effort());
    }
}

/// Issue 20's measure: the planner against the oracle on 20 constrained problems of the 3-link
/// example it was not tuned on (random starts and goals within 60 deg of the example's, 10 s;
/// torque, velocity, both, or the widest joint's range at a fraction of the free plan's use, in
/// turn). The reference is the oracle's best from its random starts and from the planner's own
/// path (polished by the oracle: a plan the independent method improves by more than the
/// transcriptions' difference is not at a constrained minimum). Each ratio is printed; all 20
/// within 1 % of the reference (or below it), and no problem where the oracle finds a
/// feasible point and the planner none. `FREEFLOAT_ORACLE_CASES=3,7` runs only those cases.
#[test]
#[ignore = "slow (about 90 s in release, far longer in a debug build); measured: 20 of 20 within 1 % of the oracle or below it (stop 40: 17, stop 39: 14; 19 from stop 46 to 47, case 13 at 1.0151: the oracle's polish from the plan, 7.122378, is the plan's own basin, to which the planner's SQP returns from it; the gap was the end spans of a plan at its velocity limit from rest, graded to h/64 since: 7.230016 -> 7.121680, 0.9997); the largest ratio case 4's 1.0062; case 11 at 0.75 (a certified 21.5 against the oracle's 28.8); on case 17 neither finds a feasible point (the planner's certificate fails); on 9 and 10 the oracle's polish from the plan finds none, so their reference is its random starts (none feasible on 9)"]
fn twenty_constrained_problems_against_the_oracle() {
    let (mut within, mut misses, mut ratios) = (0, Vec::new(), Vec::new());
    let only: Option<Vec<usize>> = std::env::var("FREEFLOAT_ORACLE_CASES")
        .ok()
        .map(|v| v.split(',').filter_map(|k| k.trim().parse().ok()).collect());
    for (k, case) in twenty_cases().into_iter().enumerate() {
        if only.as_ref().is_some_and(|o| !o.contains(&k)) {
            continue;
        }
        let Some((arm, problem, quantities)) = case else {
            misses.push(format!("{k}: no free plan"));
            continue;
        };
        let planner = ChainPlanner::new(arm.clone(), ChainOptions::default());
        let reference = oracle(&arm, &problem, 40, 3);
        let clock = std::time::Instant::now();
        let plan = planner.plan(&problem);
        let ms = 1e3 * clock.elapsed().as_secs_f64();
        match plan {
            Ok(plan) if plan.verification.certified => {
                // The independent optimiser's best: from its random starts, or polished from the
                // planner's own path (a local check).
                let polished = oracle_from(&arm, &problem, 40, 0, Some(&plan));
                let reference = reference.min(polished);
                let ratio = plan.effort() / reference;
                eprintln!(
                    "{k} {quantities:?}: planner {:.6} ({ms:.0} ms), oracle {reference:.6} (polished {polished:.6}), ratio {ratio:.5}",
                    plan.effort()
                );
                // Where the oracle finds no feasible point the planner's certified plan is not
                // judged (counted within, as a failure of both is below), and has no ratio.
                if reference.is_finite() {
                    ratios.push(ratio);
                }
                if ratio <= 1.01 {
                    within += 1;
                } else {
                    misses.push(format!("{k} {quantities:?}: ratio {ratio:.4}"));
                }
            }
            other => {
                eprintln!("{k} {quantities:?}: planner failed ({:?}), oracle {reference:.6}", other.err());
                if reference.is_finite() {
                    misses.push(format!("{k} {quantities:?}: the planner failed, the oracle {reference:.6}"));
                } else {
                    within += 1;
                }
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    eprintln!("within 1 %: {within} of 20; ratios {ratios:.4?}; misses {misses:?}");
    assert!(within == 20 && !misses.iter().any(|m| m.contains("failed")), "{misses:?}");
}
