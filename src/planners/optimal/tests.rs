//! Tests of the optimal planner: properties of the returned plans (certified, stationary, never
//! worse than the NFA's path), the paper's cases against the best efforts known, and coverage of
//! random start/goal pairs at random mounts, across sigma = 0.

use super::discrete::{Discretisation, Targets};
use super::holonomy::{connection, energy_local, holonomy_local, kinetic_energy};
use super::*;
use crate::model::system::shape;
use crate::model::{Configuration, Mount, RobotParams};
use crate::planners::nfa::NormalFormPlanner;
use nalgebra::DVector;
use proptest::prelude::*;

fn robot(a: f64, b: f64) -> RobotParams {
    RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap()
}

fn paper(a: f64, b: f64) -> PlanningProblem {
    PlanningProblem::paper(robot(a, b))
}

/// A deterministic xorshift64* generator (no new dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The free variables of a motion's coefficients on its own discretisation.
fn discretisation_of(
    planner: &OptimalPlanner,
    problem: &PlanningProblem,
    m: &OptimalMotion,
) -> (Discretisation, DVector<f64>) {
    let targets = Targets {
        start: [problem.start.theta1, problem.start.theta2],
        initial_velocity: problem.start_velocity,
        end: m.stats.theta_end,
        phi_start: problem.start.phi,
        phi_end: m.stats.phi_end,
    };
    let o = &planner.options;
    let disc = Discretisation::new(
        problem.robot.lumped(),
        o.cost,
        m.basis().clone(),
        targets,
        o.smooth_ends,
        m.stats.quadrature_nodes,
    )
    .unwrap();
    let r = if o.smooth_ends { 3 } else { 2 };
    let c = m.coefficients();
    let nf = c[0].len() - 2 * r;
    let x = DVector::from_fn(2 * nf, |i, _| c[i % 2][r + i / 2]);
    (disc, x)
}

/// The B-spline derivatives match central differences of the values; the basis is a partition
/// of unity; end conditions hold.
#[test]
fn spline_derivatives_and_end_conditions() {
    for degree in [3, 5] {
        let basis = spline::SplineBasis::graded(degree, 7.0, 6, 3).unwrap();
        let n = basis.len();
        let c: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        for t in [0.001, 0.3, 1.7, 3.5, 6.99] {
            let h = 1e-6;
            let (m, p, q) = (basis.evaluate(&c, t - h), basis.evaluate(&c, t + h), basis.evaluate(&c, t));
            assert!(((p[0] - m[0]) / (2.0 * h) - q[1]).abs() < 1e-6 * (1.0 + q[1].abs()), "{degree} {t}");
            assert!(((p[1] - m[1]) / (2.0 * h) - q[2]).abs() < 1e-5 * (1.0 + q[2].abs()), "{degree} {t}");
            let ones = vec![1.0; n];
            assert!((basis.evaluate(&ones, t)[0] - 1.0).abs() < 1e-14);
        }
        let (head, tail) = basis.end_coefficients(&[0.3, -0.2, 0.5], &[1.1, 0.0, 0.0][..3]);
        let mut c = vec![0.4; n];
        c[..head.len()].copy_from_slice(&head);
        c[n - tail.len()..].copy_from_slice(&tail);
        let (a, b) = (basis.evaluate(&c, 0.0), basis.evaluate(&c, 7.0));
        assert!((a[0] - 0.3).abs() < 1e-14 && (a[1] + 0.2).abs() < 1e-12 && (a[2] - 0.5).abs() < 1e-9, "{a:?}");
        assert!((b[0] - 1.1).abs() < 1e-14 && b[1].abs() < 1e-12 && b[2].abs() < 1e-9, "{b:?}");
    }
}

/// The hand-written derivatives of the holonomy integrand equal num-dual's Hessian of the same
/// function; the energy density equals `1/2 q'^T M q'` with the crate's inertia matrix and
/// `phi'` from zero momentum.
#[test]
fn holonomy_derivatives_match_dual_numbers() {
    use num_dual::{Dual2SVec64, hessian};
    let mut rng = Rng(7);
    for _ in 0..50 {
        let k = robot(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)).lumped();
        let v = nalgebra::SVector::<f64, 4>::from([
            rng.uniform(-7.0, 7.0),
            rng.uniform(-7.0, 7.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
        ]);
        let local = holonomy_local(&k, [v[0], v[1]], [v[2], v[3]]);
        let (f, g, h) = hessian(
            |x: nalgebra::SVector<Dual2SVec64<4>, 4>| {
                let (a, b) = connection(&k, x[0], x[1]);
                a * x[2] + b * x[3]
            },
            &v,
        );
        assert!((local.value - f).abs() < 1e-14 * (1.0 + f.abs()));
        for i in 0..4 {
            assert!((local.gradient[i] - g[i]).abs() < 1e-12 * (1.0 + g[i].abs()), "{i}");
            for j in 0..4 {
                assert!((local.hessian[i][j] - h[(i, j)]).abs() < 1e-12 * (1.0 + h[(i, j)].abs()), "{i}{j}");
            }
        }
        // Energy against the inertia matrix of crate::dynamics.
        let m = crate::dynamics::inertia_matrix(&k, v[0], v[1]);
        let s = shape(&k, v[0], v[1]);
        let dphi = -(s.G * v[2] + s.H * v[3]) / s.F;
        let dq = nalgebra::Vector3::new(dphi, v[2], v[3]);
        let e = 0.5 * dq.dot(&(m * dq));
        let ours = kinetic_energy(&k, [v[0], v[1]], [v[2], v[3]]);
        assert!((e - ours).abs() < 1e-12 * (1.0 + e.abs()), "{e} vs {ours}");
        assert!((energy_local(&k, [v[0], v[1]], [v[2], v[3]]).value - e).abs() < 1e-12 * (1.0 + e));
    }
}

/// KKT at the returned plan, with derivatives by central differences of the discrete sums
/// (independent of the analytic ones): `|grad f + lambda grad c| <= 1e-5 |grad f|`, `c ~ 0`.
#[test]
fn returned_plan_is_a_kkt_point() {
    for (a, b) in [(0.0, 0.0), (0.2, 0.2), (1.0, -1.0)] {
        let planner = OptimalPlanner::default();
        let problem = paper(a, b);
        let m = planner.motion(&problem).unwrap();
        let (disc, x) = discretisation_of(&planner, &problem, &m);
        let e = disc.evaluate(&x, 0);
        assert!(e.c.abs() <= 1e-11, "({a}, {b}): c = {}", e.c);
        let n = x.len();
        let mut gf = DVector::zeros(n);
        let mut gc = DVector::zeros(n);
        for i in 0..n {
            let h = 1e-6 * (1.0 + x[i].abs());
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[i] += h;
            xm[i] -= h;
            let (ep, em) = (disc.evaluate(&xp, 0), disc.evaluate(&xm, 0));
            gf[i] = (ep.f - em.f) / (2.0 * h);
            gc[i] = (ep.c - em.c) / (2.0 * h);
        }
        let lambda = -gc.dot(&gf) / gc.dot(&gc);
        let r = &gf + &gc * lambda;
        let rel = r.amax() / gf.amax();
        assert!(rel < 1e-5, "({a}, {b}): relative stationarity {rel:.2e}");
        assert!(
            (lambda - m.stats.multiplier).abs() < 1e-3 * (1.0 + lambda.abs()),
            "{lambda} vs {}",
            m.stats.multiplier
        );
    }
}

/// The effort `integral |u|^2` of a motion by Gauss–Legendre quadrature of its controls.
/// Integrates piece by piece between the motion's breakpoints (none for the NFA: 400 pieces).
fn effort_of(motion: &dyn Motion) -> f64 {
    integral_of(motion, |t| {
        let u = motion.controls(t).unwrap();
        u[0] * u[0] + u[1] * u[1]
    })
}

/// `integral_0^T f dt`, 16 Gauss–Legendre nodes on each piece between breakpoints (or 400
/// equal pieces when the motion has none).
fn integral_of(motion: &dyn Motion, f: impl Fn(f64) -> f64) -> f64 {
    let rule = crate::numerics::quadrature::GaussLegendre::new(16);
    let mut b = motion.breakpoints();
    if b.is_empty() {
        return rule.integrate_composite(0.0, motion.horizon(), 400, f);
    }
    b.insert(0, 0.0);
    b.push(motion.horizon());
    b.windows(2).map(|w| rule.integrate(w[0], w[1], &f)).sum()
}

/// The optimum is never above the NFA's effort, where the NFA plans.
#[test]
fn effort_never_above_the_nfa() {
    for (a, b) in [(0.0, 0.0), (0.1, 0.1), (0.2, 0.2), (0.3, 0.3), (1.0, -1.0), (0.5, 0.5)] {
        let problem = paper(a, b);
        let Ok(nfa) = NormalFormPlanner::default().motion(&problem) else { continue };
        let nfa_effort = effort_of(&nfa);
        let m = OptimalPlanner::default().motion(&problem).unwrap();
        assert!(m.stats.effort <= nfa_effort * (1.0 + 1e-9), "({a}, {b}): {} > NFA {nfa_effort}", m.stats.effort);
    }
}

/// The paper's problem within 1% of the best efforts known (IPOPT: 0.3819, 0.2199, 0.4315,
/// 0.6598, 165-179; best known 0.3814, 0.2195, 0.4308, 0.6588, 132.5), certified.
#[test]
fn paper_cases_reach_the_best_known_efforts() {
    for (a, b, best) in
        [(0.0, 0.0, 0.3814), (0.1, 0.1, 0.2195), (0.2, 0.2, 0.4308), (0.3, 0.3, 0.6588), (1.0, -1.0, 132.5)]
    {
        let (plan, m) = OptimalPlanner::default().plan_with_motion(&paper(a, b)).unwrap();
        assert!(plan.certified().is_ok(), "({a}, {b}): {:?}", plan.verification);
        assert!(m.stats.effort <= 1.01 * best, "({a}, {b}): effort {} vs best known {best}", m.stats.effort);
        assert!((effort_of(&m) - m.stats.effort).abs() < 1e-6 * m.stats.effort);
    }
}

/// phi(T) of the motion (holonomy quadrature) equals the integration of system (7).
#[test]
fn holonomy_equals_the_ode_integration() {
    for (a, b) in [(0.0, 0.0), (0.3, 0.3), (1.0, -1.0)] {
        let problem = paper(a, b);
        let (plan, m) = OptimalPlanner::default().plan_with_motion(&problem).unwrap();
        let phi = m.at(problem.horizon).unwrap().q.phi;
        assert!(
            (phi - plan.verification.reached.phi).abs() < 1e-10,
            "({a}, {b}): {phi} vs {}",
            plan.verification.reached.phi
        );
        assert!(plan.verification.max_path_deviation < 1e-10);
    }
}

/// The sampled trajectory (joints by Horner's rule on each span's Taylor coefficients, `phi`
/// accumulated from sample to sample) against an independent evaluation: the joints of the
/// spline by de Boor's algorithm (`SplineBasis::evaluate`) to 1e-12 relative (the same
/// polynomial, a few ulps of rounding apart; 1e-11 for the accelerations, whose basis functions
/// are of size `h^-2` on the graded end spans `h`, where both evaluations round more), and `phi`
/// by the 24-node rule on every knot span from `phi(0)` with the paper's [`connection`] (Eq. 8)
/// to 1e-12 rad (the accuracy asked of the motion's base
/// angle); `at` gives the samples' joints exactly. Cubic plans at three mounts and a quintic one
/// (smooth ends), at sample counts that put many samples in a span, about one, and fewer (2, 7).
#[test]
#[allow(clippy::float_cmp)] // exactness is the property tested: the joints of at() and the samples
fn sampled_trajectory_matches_de_boor_and_the_fine_rule() {
    let smooth = OptimalOptions { smooth_ends: true, ..Default::default() };
    let cases = [
        (paper(0.1, 0.1), OptimalOptions::default()),
        (paper(1.0, -1.0), OptimalOptions::default()),
        (paper(0.0, 0.0), OptimalOptions::default()),
        (paper(0.2, 0.2), smooth),
    ];
    let rule = crate::numerics::quadrature::GaussLegendre::new(motion::MOTION_NODES);
    for (problem, options) in cases {
        let m = OptimalPlanner::new(options).motion(&problem).unwrap();
        let (basis, c, k) = (m.basis(), m.coefficients(), problem.robot.lumped());
        let b = basis.breakpoints();
        let integrand = |t: f64| {
            let ([th1, w1, _], [th2, w2, _]) = (basis.evaluate(&c[0], t), basis.evaluate(&c[1], t));
            let (a, bb) = connection(&k, th1, th2);
            a * w1 + bb * w2
        };
        let phi_ref = |t: f64| {
            let s = basis.interval(t);
            let whole: f64 = (0..s).map(|i| rule.integrate(b[i], b[i + 1], integrand)).sum();
            problem.start.phi - whole - rule.integrate(b[s], t, integrand)
        };
        for samples in [2, 7, 33, 257, 513, 769, 1001] {
            let tr = m.trajectory(&problem, samples).unwrap();
            let ddq = tr.ddq.as_ref().unwrap();
            for (i, &t) in tr.t.iter().enumerate() {
                let (q, dq, ddq) = (tr.q[i], tr.dq[i], ddq[i]);
                assert!((q[0] - phi_ref(t)).abs() <= 1e-12, "{samples} samples, t {t}: {} vs {}", q[0], phi_ref(t));
                for j in 0..2 {
                    let want = basis.evaluate(&c[j], t);
                    let got = [q[j + 1], dq[j + 1], ddq[j + 1]];
                    for ((g, w), tolerance) in got.iter().zip(want).zip([1e-12, 1e-12, 1e-11]) {
                        let close = (g - w).abs() <= tolerance * (1.0 + w.abs());
                        assert!(close, "t {t}, joint {j}: {got:?} vs {want:?}");
                    }
                }
                let exact = m.at(t).unwrap();
                assert_eq!([exact.q.theta1, exact.q.theta2, exact.u[0], exact.u[1]], [q[1], q[2], dq[1], dq[2]]);
            }
        }
    }
}

/// The problem's start velocity is honoured exactly, and the plan is certified at both levels:
/// the torque certificate starts from that velocity (it used to start from rest, and failed).
#[test]
fn initial_velocity_is_honoured() {
    let u0 = [0.3, -0.2];
    let problem = paper(0.2, 0.2).with_start_velocity(u0).unwrap();
    let planner = OptimalPlanner::new(OptimalOptions::default());
    let (plan, m) = planner.plan_with_motion(&problem).unwrap();
    assert!(plan.certified().is_ok(), "{:?}", plan.verification);
    let mut planned = crate::planners::Planner::plan(&planner, &problem).unwrap();
    let torques = planned.add_torques(&crate::plan::TorqueOptions::default()).unwrap();
    assert!(torques.certificate.certified, "{:?}", torques.certificate);
    let (p0, p1) = (m.at(0.0).unwrap(), m.at(10.0).unwrap());
    for ((got, want), end) in p0.u.iter().zip(u0).zip(p1.u) {
        assert!((got - want).abs() < 1e-10, "{:?}", p0.u);
        assert!(end.abs() < 1e-12, "{:?}", p1.u);
    }
}

/// `smooth_ends` gives `theta''(0) = theta''(T) = 0` (and rest at both ends), certified.
#[test]
fn smooth_ends_have_zero_acceleration() {
    let options = OptimalOptions { smooth_ends: true, ..Default::default() };
    for (a, b) in [(0.0, 0.0), (0.2, 0.2)] {
        let (plan, m) = OptimalPlanner::new(options.clone()).plan_with_motion(&paper(a, b)).unwrap();
        assert!(plan.certified().is_ok(), "{:?}", plan.verification);
        for t in [0.0, 10.0] {
            let p = m.at(t).unwrap();
            assert!(p.u.iter().chain(&p.du).all(|x| x.abs() < 1e-9), "t = {t}: {p:?}");
        }
        assert_eq!(m.stats.degree, 5);
    }
}

/// The energy cost plans and certifies, and its energy is not above the effort plan's energy.
#[test]
fn energy_cost_plans() {
    let problem = paper(0.2, 0.2);
    let options = OptimalOptions { cost: Cost::Energy, ..Default::default() };
    let (plan, m) = OptimalPlanner::new(options).plan_with_motion(&problem).unwrap();
    assert!(plan.certified().is_ok(), "{:?}", plan.verification);
    let effort_plan = OptimalPlanner::default().motion(&problem).unwrap();
    let k = problem.robot.lumped();
    let energy = |m: &OptimalMotion| {
        integral_of(m, |t| {
            let p = m.at(t).unwrap();
            kinetic_energy(&k, [p.q.theta1, p.q.theta2], p.u)
        })
    };
    // The optimiser's 8-node rule is not exact for the (non-polynomial) energy density.
    assert!((energy(&m) - m.stats.cost).abs() < 1e-6 * m.stats.cost);
    assert!(energy(&m) <= energy(&effort_plan) * (1.0 + 1e-9));
}

/// sigma (Eq. 9) at a joint configuration.
fn sigma(k: &crate::model::Lumped, theta1: f64, theta2: f64) -> f64 {
    shape(k, theta1, theta2).sigma
}

/// Pairs whose sigma differs in sign at start and goal: planned and certified, the path crossing
/// sigma = 0 (the NFA cannot: its domain excludes sigma = 0).
#[test]
fn pairs_across_sigma_zero_are_certified() {
    let mut rng = Rng(2024);
    let (mut done, mut failed) = (0, 0);
    while done < 12 {
        let (a, b) = (rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
        let k = robot(a, b).lumped();
        let start = Configuration::new(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
        let goal = Configuration::new(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
        if sigma(&k, start.theta1, start.theta2) * sigma(&k, goal.theta1, goal.theta2) >= 0.0 {
            continue;
        }
        done += 1;
        let problem = PlanningProblem::new(robot(a, b), start, goal, 8.0).unwrap();
        let plan = match OptimalPlanner::default().plan(&problem).map(|p| p.plan) {
            Ok(plan) => plan,
            Err(e) => {
                assert!(matches!(e, Error::OptimalFailed { .. }), "{e}");
                failed += 1;
                continue;
            }
        };
        assert!(plan.certified().is_ok(), "{problem:?}: {:?}", plan.verification);
        let signs: Vec<f64> = plan.trajectory.q.iter().map(|q| sigma(&k, q[1], q[2]).signum()).collect();
        assert!(signs.windows(2).any(|w| w[0] * w[1] < 0.0), "no crossing of sigma = 0");
    }
    assert!(failed <= 2, "{failed} of 12 pairs across sigma = 0 not planned");
}

/// Plans the first `count` of the seeded random pairs (SRC robot, mounts |a|, |b| <= 1.5,
/// horizons T in [5, 15] s) and returns how many cross sigma = 0 and the failures.
fn plan_random_pairs(count: usize) -> (usize, Vec<String>) {
    let mut rng = Rng(11);
    let options = OptimalOptions { samples: 2, ..Default::default() };
    let planner = OptimalPlanner::new(options);
    let (mut crossing, mut failures) = (0, Vec::new());
    for _ in 0..count {
        let (a, b) = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
        let start = Configuration::new(rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2));
        let goal = Configuration::new(rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2));
        let horizon = rng.uniform(5.0, 15.0);
        let k = robot(a, b).lumped();
        if sigma(&k, start.theta1, start.theta2) * sigma(&k, goal.theta1, goal.theta2) < 0.0 {
            crossing += 1;
        }
        let problem = PlanningProblem::new(robot(a, b), start, goal, horizon).unwrap();
        match planner.plan(&problem).map(|p| p.plan) {
            Ok(plan) if plan.verification.certified => {}
            other => failures.push(format!("{problem:?}: {:?}", other.map(|p| p.verification))),
        }
    }
    (crossing, failures)
}

/// Coverage: the first 60 of the random pairs, all planned and certified to 1e-9 rad.
#[test]
fn random_pairs_are_certified() {
    let (crossing, failures) = plan_random_pairs(60);
    assert!(crossing >= 10, "only {crossing} pairs across sigma = 0");
    assert!(failures.is_empty(), "{} of 60 failed:\n{}", failures.len(), failures.join("\n"));
}

/// Coverage: all 300 random pairs planned and certified to 1e-9 rad (about 25 s in release on
/// two shared cores; run with `cargo test --release -- --ignored random_pairs_are_all_certified`).
#[test]
#[ignore = "slow: 300 plans, some of them coils of many turns"]
fn random_pairs_are_all_certified() {
    let (crossing, failures) = plan_random_pairs(300);
    assert!(crossing >= 50, "only {crossing} pairs across sigma = 0");
    assert!(failures.is_empty(), "{} of 300 failed:\n{}", failures.len(), failures.join("\n"));
}

/// Every random pair ends in a certified plan or a typed [`Error::OptimalFailed`] (never an
/// uncertified plan passed off as a success, never a panic); at small mounts all are certified.
#[test]
fn random_pairs_are_certified_or_fail_cleanly() {
    let mut rng = Rng(5);
    let options = OptimalOptions { samples: 2, ..Default::default() };
    let planner = OptimalPlanner::new(options);
    for i in 0..60 {
        let m = if i < 30 { 0.3 } else { 1.5 };
        let (a, b) = (rng.uniform(-m, m), rng.uniform(-m, m));
        let start = Configuration::new(rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2));
        let goal = Configuration::new(rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2), rng.uniform(-3.2, 3.2));
        let problem = PlanningProblem::new(robot(a, b), start, goal, rng.uniform(5.0, 15.0)).unwrap();
        match planner.plan(&problem).map(|p| p.plan) {
            Ok(plan) => assert!(plan.verification.certified, "{problem:?}: {:?}", plan.verification),
            Err(e) => {
                assert!(i >= 30, "small mount not planned: {problem:?}: {e}");
                assert!(matches!(e, Error::OptimalFailed { .. }), "{e}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any valid problem gives a certified plan or a typed error, never a panic or a
    /// non-finite number.
    #[test]
    fn random_problems_plan_or_fail_cleanly(
        a in -1.5..1.5f64, b in -1.5..1.5f64,
        q0 in proptest::array::uniform3(-7.0..7.0f64), qd in proptest::array::uniform3(-7.0..7.0f64),
        horizon in 2.0..20.0f64, u0 in proptest::array::uniform2(-0.5..0.5f64),
    ) {
        let problem = PlanningProblem::new(robot(a, b), Configuration::from_array(q0), Configuration::from_array(qd), horizon)
            .and_then(|p| p.with_start_velocity(u0)).unwrap();
        let options = OptimalOptions { samples: 11, ..Default::default() };
        match OptimalPlanner::new(options).plan_with_motion(&problem) {
            Ok((plan, m)) => {
                prop_assert!(plan.verification.final_error.is_finite());
                prop_assert!(m.stats.effort.is_finite() && m.stats.kkt_residual.is_finite());
                prop_assert!(plan.trajectory.q.iter().flatten().all(|x| x.is_finite()));
            }
            // A plan whose certificate misses the tolerance is a typed error with its numbers
            // (the case kept in proptest-regressions, a = -0.77, b = -0.21, T = 18.3 s, missed
            // it by the integrator's error alone until the verdict near the tolerance was a
            // second, tighter integration's: chain::tests).
            Err(Error::NotCertified { final_error, tolerance, .. }) => {
                prop_assert!(final_error.is_finite() && final_error > tolerance);
            }
            Err(e) => prop_assert!(matches!(e, Error::OptimalFailed { .. }), "{e}"),
        }
    }
}
