//! Tests of the chain planner: agreement with the two-joint planner at n = 2, the one-joint
//! holonomy property, certified rest-to-rest plans at n = 3 and 7, KKT optimality and bad input.

use nalgebra::DVector;

use super::discrete::Targets;
use super::*;
use crate::error::Error;
use crate::model::arm::{Base, Link};
use crate::model::{Mount, RobotParams};
use crate::plan::{Motion, PlanningProblem};
use crate::planners::optimal::OptimalPlanner;
use crate::planners::optimal::sqp::Discretised;

/// The 3-link arm of the benchmark: base 15 kg, 0.5 kg m^2, mount (0.2, 0), links 0.4/0.35/0.25 m
/// with the centre of mass at half length, 2.0/1.5/0.8 kg, slender rods.
pub(crate) fn three_link() -> Arm {
    let links = [(0.4, 2.0), (0.35, 1.5), (0.25, 0.8)]
        .map(|(l, m)| Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 })
        .to_vec();
    Arm {
        base: Base { mass: 15.0, inertia: 0.5 },
        mount: Mount { a: 0.2, b: 0.0 },
        links,
        limits: Default::default(),
        geometry: Default::default(),
    }
}

/// A 7-link arm: links of 0.3 m down to 0.15 m, masses 1.5 down to 0.3 kg, slender rods.
pub(crate) fn seven_link() -> Arm {
    let links = (0..7)
        .map(|i| {
            let (l, m) = (0.3 - 0.025 * i as f64, 1.5 - 0.2 * i as f64);
            Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 }
        })
        .collect();
    Arm {
        base: Base { mass: 20.0, inertia: 0.8 },
        mount: Mount { a: 0.2, b: 0.1 },
        links,
        limits: Default::default(),
        geometry: Default::default(),
    }
}

fn src_arm(a: f64, b: f64) -> (RobotParams, Arm) {
    let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
    (robot, Arm::from_params(&robot))
}

fn paper_chain_problem() -> ChainProblem {
    let (q0, qd, horizon) = crate::model::paper_problem();
    ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon)
}

/// At n = 2 with point-mass links the chain planner's discretisation is the two-joint planner's:
/// warm-started from the two-joint plan on the same basis (32 spans, 16 nodes) its SQP converges
/// to the same effort (relative 1e-6); and its own search finds a certified plan of at most that
/// effort (at a = 1, b = -1 a lower one: 72.54 against 91.72 rad^2/s, from the line beside its
/// coil refined as an extra finalist, which the two-joint planner does not refine there).
#[test]
fn chain_matches_the_two_joint_planner() {
    for (a, b) in [(0.1, 0.1), (1.0, -1.0)] {
        let (robot, arm) = src_arm(a, b);
        let two = OptimalPlanner::default().motion(&PlanningProblem::paper(robot)).unwrap();
        let e2 = two.stats.effort;
        let planner = ChainPlanner::new(arm, ChainOptions::default());
        let problem = paper_chain_problem();
        let plan = planner.plan(&problem).unwrap();
        let e1 = plan.effort();
        assert!(plan.verification.certified && plan.verification.final_error <= 1e-9);
        assert!(e1 <= e2 * (1.0 + 1e-6), "({a}, {b}): chain {e1} above two-joint {e2}");
        // The two-joint optimum is a converged point of the chain discretisation.
        let targets = Targets {
            start: problem.start[1..].to_vec(),
            initial_velocity: vec![0.0; 2],
            end: two.stats.theta_end.to_vec(),
            phi_start: problem.start[0],
            phi_end: two.stats.phi_end,
        };
        let tables = tables::Tables::default();
        let disc = planner.discretise(&problem, targets, 32, 16, &tables).unwrap();
        let x0 = disc
            .project(|t, out| {
                let q = two.at(t).unwrap().q;
                out.copy_from_slice(&[q.theta1, q.theta2]);
            })
            .unwrap();
        let r =
            crate::planners::optimal::sqp::solve(&disc, x0, &Default::default(), Some(two.stats.multiplier)).unwrap();
        assert!(r.converged(), "({a}, {b}): {:?}", r.termination);
        assert!((r.f - e2).abs() <= 1e-6 * e2, "({a}, {b}): warm-started chain {} vs two-joint {e2}", r.f);
    }
}

/// Rest-to-rest plans of a 3-link and a 7-link arm in T = 10 s, certified to 1e-9 rad with the
/// plan's momentum within 1e-12 along the integration.
#[test]
fn chain_three_and_seven_links_are_certified() {
    let cases = [
        (three_link(), vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6]),
        (seven_link(), vec![0.0, 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.6], vec![0.4, -0.3, 0.5, 0.1, 0.7, 0.2, -0.5, 0.0]),
    ];
    for (arm, start, goal) in cases {
        let n = arm.joints();
        let plan = ChainPlanner::new(arm, ChainOptions::default())
            .plan(&ChainProblem::rest_to_rest(start, goal.clone(), 10.0))
            .unwrap();
        let v = &plan.verification;
        assert!(v.certified && v.final_error <= 1e-9, "n = {n}: {v:?}");
        assert!(v.max_abs_momentum <= 1e-12, "n = {n}: momentum {}", v.max_abs_momentum);
        let end = plan.at(10.0);
        assert!(end.rate.iter().all(|u| u.abs() < 1e-12), "n = {n}: not at rest");
        assert!(plan.at(0.0).rate.iter().all(|u| u.abs() < 1e-12));
    }
}

/// One joint: `a(theta) dtheta` is exact, so `phi(T)` is fixed by `theta(T)`. An inconsistent
/// goal is [`Error::HolonomyFixed`] naming the reachable `phi`, which equals
/// `phi0 - integral_{theta0}^{thetad} G/F dtheta` of the model (quadrature); that goal plans,
/// certified, along a path that is not the line (the certificate integrates the spline).
#[test]
fn chain_one_joint_phi_is_fixed_by_theta() {
    let arm = super::connection::tests::arm(1);
    let (phi0, theta0, thetad) = (0.2, 0.3, 1.7);
    // The model's holonomy by 64-point Gauss–Legendre along theta.
    let rule = crate::numerics::quadrature::GaussLegendre::new(64);
    let expected = phi0
        - rule.integrate(theta0, thetad, |t| {
            let (f, g) = arm.momentum_coefficients(&[t]);
            g[0] / f
        });
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let problem = ChainProblem::rest_to_rest(vec![phi0, theta0], vec![expected + 0.1, thetad], 4.0);
    match planner.plan(&problem) {
        Err(Error::HolonomyFixed { reachable, gap, .. }) => {
            assert!((reachable - expected).abs() <= 1e-12, "{reachable} vs {expected}");
            assert!((gap - 0.1).abs() <= 1e-9);
        }
        other => panic!("expected HolonomyFixed, got {other:?}"),
    }
    let err = planner.plan(&problem).unwrap_err();
    assert!(err.is_bad_input() && err.to_string().contains("fixed by the joint angle"), "{err}");
    let plan = planner.plan(&ChainProblem { goal: vec![expected, thetad], ..problem }).unwrap();
    assert!(plan.verification.certified && plan.verification.final_error <= 1e-9, "{:?}", plan.verification);
    assert!(plan.verification.max_abs_momentum <= 1e-12);
}

/// The returned plan is a KKT point of its discretisation: the Lagrangian's gradient vanishes
/// (relative 1e-5 in the effort's metric: the SQP's acceptance, 100 times its 1e-7 tolerance at
/// the rounding floor), and small feasible perturbations (tangent step, then back to the constraint
/// along its gradient) never lower the effort.
#[test]
fn chain_plan_is_a_constrained_minimum() {
    let arm = three_link();
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let problem = ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0);
    let plan = planner.plan(&problem).unwrap();
    let end = plan.at(10.0);
    let targets = Targets {
        start: problem.start[1..].to_vec(),
        initial_velocity: vec![0.0; 3],
        end: end.theta.clone(),
        phi_start: problem.start[0],
        phi_end: end.phi,
    };
    let tables = tables::Tables::default();
    let disc = planner.discretise(&problem, targets, plan.stats.spans, plan.stats.quadrature_nodes, &tables).unwrap();
    let x = disc
        .project(|t, out| {
            for (o, c) in out.iter_mut().zip(plan.coefficients()) {
                *o = plan.basis().evaluate(c, t)[0];
            }
        })
        .unwrap();
    let e = disc.evaluate(&x, 2);
    let lambda = plan.stats.multiplier;
    let r = &e.grad_f + &e.grad_c * lambda;
    // In the effort's metric S (the SQP's): |r|_{S^-1} relative to |grad f|_{S^-1}.
    let chol = disc.effort_cholesky().unwrap();
    let dual = |v: &DVector<f64>| v.dot(&chol.solve(v)).max(0.0).sqrt();
    let kkt = dual(&r) / dual(&e.grad_f).max(1.0);
    assert!(kkt <= 1e-5, "relative |grad L| = {kkt:e} (Euclidean {:e})", r.norm());
    assert!((e.f - plan.effort()).abs() <= 1e-9 * plan.effort());
    let mut state = 12345u64;
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let g = e.grad_c.clone();
    for _ in 0..20 {
        let d = DVector::from_fn(x.len(), |_, _| uniform());
        let d = &d - &g * (g.dot(&d) / g.dot(&g));
        let scale = 1e-3 / d.norm().max(1e-300);
        let mut y = &x + d * scale;
        for _ in 0..20 {
            let ey = disc.evaluate(&y, 1);
            if ey.c.abs() <= 1e-14 {
                break;
            }
            y -= &ey.grad_c * (ey.c / ey.grad_c.dot(&ey.grad_c));
        }
        let ey = disc.evaluate(&y, 0);
        assert!(ey.c.abs() <= 1e-12, "perturbation not restored: c = {:e}", ey.c);
        assert!(ey.f >= e.f * (1.0 - 1e-12), "feasible perturbation lowers the effort: {} < {}", ey.f, e.f);
    }
}

/// Wrong lengths, non-finite values, a zero horizon and a bad initial velocity are input
/// errors, before any planning.
#[test]
fn chain_bad_problems_are_input_errors() {
    let planner = ChainPlanner::new(three_link(), ChainOptions::default());
    let good = ChainProblem::rest_to_rest(vec![0.0; 4], vec![0.1; 4], 10.0);
    let bad = [
        ChainProblem { start: vec![0.0; 3], ..good.clone() },
        ChainProblem { goal: vec![0.1; 5], ..good.clone() },
        ChainProblem { goal: vec![0.1, f64::NAN, 0.1, 0.1], ..good.clone() },
        ChainProblem { start: vec![0.0, 0.0, f64::INFINITY, 0.0], ..good.clone() },
        ChainProblem { horizon: 0.0, ..good.clone() },
        ChainProblem { horizon: f64::NAN, ..good.clone() },
        ChainProblem { initial_velocity: vec![0.0; 2], ..good.clone() },
        ChainProblem { initial_velocity: vec![0.0, f64::NAN, 0.0], ..good.clone() },
    ];
    for p in bad {
        let err = planner.plan(&p).unwrap_err();
        assert!(matches!(err, Error::Input(_)) && err.is_bad_input(), "{p:?}: {err}");
    }
    assert!(planner.plan(&good).is_ok());
}

/// Options out of their ranges are input errors naming the option, before any planning: the
/// clearance a plan keeps beyond the arm's (`clearance_reserve`, `clearance_rise`: a clearance
/// in [0, 1] m, rising over a finite time >= 0 s).
#[test]
fn chain_bad_options_are_input_errors_naming_them() {
    let good = ChainProblem::rest_to_rest(vec![0.0; 4], vec![0.1; 4], 10.0);
    let rise = |extra, over| ChainOptions { clearance_rise: ClearanceRise { extra, over }, ..ChainOptions::default() };
    let bad = [
        ("clearance_reserve", ChainOptions { clearance_reserve: -0.01, ..ChainOptions::default() }),
        ("clearance_reserve", ChainOptions { clearance_reserve: f64::NAN, ..ChainOptions::default() }),
        ("clearance_rise", rise(-0.01, 1.0)),
        ("clearance_rise", rise(1.5, 1.0)),
        ("clearance_rise", rise(f64::NAN, 1.0)),
        ("clearance_rise", rise(0.01, -1.0)),
        ("clearance_rise", rise(0.01, f64::INFINITY)),
        ("clearance_rise", rise(0.01, f64::NAN)),
    ];
    for (name, options) in bad {
        let err = ChainPlanner::new(three_link(), options).plan(&good).unwrap_err();
        assert!(err.is_bad_input() && err.to_string().contains(name), "{name}: {err}");
    }
    assert!(ChainPlanner::new(three_link(), rise(0.01, 0.4)).plan(&good).is_ok());
}

/// A non-zero initial velocity is honoured: `theta'(0) = u0`, at rest at T, certified.
#[test]
fn chain_initial_velocity_is_honoured() {
    let planner = ChainPlanner::new(three_link(), ChainOptions::default());
    let u0 = vec![0.2, -0.1, 0.3];
    let problem = ChainProblem {
        initial_velocity: u0.clone(),
        ..ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0)
    };
    let plan = planner.plan(&problem).unwrap();
    let (start, end) = (plan.at(0.0), plan.at(10.0));
    for (j, u) in u0.iter().enumerate() {
        assert!((start.rate[j] - u).abs() <= 1e-12 && end.rate[j].abs() <= 1e-12);
    }
    assert!(plan.verification.certified);
}

/// The discretisation's gradients and Hessians equal central differences of its values and
/// gradients (3-link arm, a curved path).
#[test]
fn chain_discretisation_derivatives_match_differences() {
    let planner = ChainPlanner::new(three_link(), ChainOptions::default());
    let problem = ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0);
    let targets = Targets {
        start: problem.start[1..].to_vec(),
        initial_velocity: vec![0.1, 0.0, -0.2],
        end: problem.goal[1..].to_vec(),
        phi_start: 0.3,
        phi_end: -0.2,
    };
    let tables = tables::Tables::default();
    let disc = planner.discretise(&problem, targets, 4, 8, &tables).unwrap();
    let x = disc.project(|t, out| {
        out.copy_from_slice(&[0.5 + 0.9 * (t / 3.0).sin(), -0.4 + 0.7 * (t / 2.0).cos(), 0.8 - 0.1 * t])
    });
    let x = x.unwrap();
    let e = disc.evaluate(&x, 2);
    let h = 1e-6;
    for i in 0..x.len() {
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[i] += h;
        xm[i] -= h;
        let (ep, em) = (disc.evaluate(&xp, 1), disc.evaluate(&xm, 1));
        let gc = (ep.c - em.c) / (2.0 * h);
        let gf = (ep.f - em.f) / (2.0 * h);
        assert!((gc - e.grad_c[i]).abs() <= 1e-7 * (1.0 + gc.abs()), "grad_c[{i}]: {gc} vs {}", e.grad_c[i]);
        assert!((gf - e.grad_f[i]).abs() <= 1e-7 * (1.0 + gf.abs()), "grad_f[{i}]: {gf} vs {}", e.grad_f[i]);
        for k in 0..x.len() {
            let hc = (ep.grad_c[k] - em.grad_c[k]) / (2.0 * h);
            let hf = (ep.grad_f[k] - em.grad_f[k]) / (2.0 * h);
            assert!(
                (hc - e.hess_c[(i, k)]).abs() <= 1e-6 * (1.0 + hc.abs()),
                "hess_c[{i}, {k}]: {hc} vs {}",
                e.hess_c[(i, k)]
            );
            assert!(
                (hf - e.hess_f_or(disc.effort_hessian())[(i, k)]).abs() <= 1e-6 * (1.0 + hf.abs()),
                "hess_f[{i}, {k}]"
            );
        }
    }
}

/// The torque level of a 3-link plan: the base row of the inverse dynamics vanishes along the
/// plan, and the full dynamics integrated with the planned torques reaches the goal to 1e-9 rad
/// (measured 1.0e-12) with the angular momentum kept within 1e-10 (measured 6.5e-14).
#[test]
fn chain_torques_reproduce_the_plan() {
    use crate::plan::torques::{certify_chain_torques, chain_torques_at};
    let arm = three_link();
    let planner = ChainPlanner::new(arm.clone(), ChainOptions::default());
    let problem = ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0);
    let plan = planner.plan(&problem).unwrap();
    for k in 0..=20 {
        let id = chain_torques_at(&arm, &plan, 0.5 * k as f64);
        assert!(id.base_residual.abs() <= 1e-10, "base residual {}", id.base_residual);
        assert!(id.tau.iter().all(|x| x.is_finite()));
    }
    let c = certify_chain_torques(&arm, &plan, &problem.start, &problem.goal, &Default::default(), 1e-9).unwrap();
    assert!(c.certified, "{c:?}");
    assert!(c.max_abs_momentum <= 1e-10, "momentum {}", c.max_abs_momentum);
}

/// A warm start from a certified plan's own path returns that plan (the same minimum, a
/// fraction of the search's work), whatever representative search would have tried first; a
/// warm start ending at no representative falls back to the full search, or fails where no
/// search may follow ([`ChainOptions::warm_start_only`]); a malformed one is bad input.
#[test]
fn chain_warm_start_from_the_plan_returns_it() {
    let arm = three_link();
    let problem = ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0);
    let cold = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem).unwrap();
    let points = cold.sample(129);
    let path = WarmStart {
        t: points.iter().map(|p| p.t).collect(),
        theta: points.iter().map(|p| p.theta.clone()).collect(),
        rate: points.iter().map(|p| p.rate.clone()).collect(),
    };
    let warm_options = ChainOptions { warm_start: Some(path.clone()), ..ChainOptions::default() };
    let warm = ChainPlanner::new(arm.clone(), warm_options).plan(&problem).unwrap();
    assert!(warm.verification.certified);
    assert!((warm.effort() - cold.effort()).abs() <= 1e-6 * cold.effort(), "{} vs {}", warm.effort(), cold.effort());
    assert_eq!(warm.stats.seeds, 1, "the warm start alone");
    let mut elsewhere = path.clone();
    for row in elsewhere.theta.iter_mut() {
        row[0] += 1.0;
    }
    let fallback = ChainOptions { warm_start: Some(elsewhere.clone()), ..ChainOptions::default() };
    let searched = ChainPlanner::new(arm.clone(), fallback).plan(&problem).unwrap();
    assert!((searched.effort() - cold.effort()).abs() <= 1e-9 * cold.effort());
    // Without the search (a re-plan's), the own path still gives the plan, the other none.
    let only =
        |path: WarmStart| ChainOptions { warm_start: Some(path), warm_start_only: true, ..ChainOptions::default() };
    let alone = ChainPlanner::new(arm.clone(), only(path.clone())).plan(&problem).unwrap();
    assert!((alone.effort() - warm.effort()).abs() <= 1e-12 * warm.effort());
    let failed = ChainPlanner::new(arm.clone(), only(elsewhere)).plan(&problem);
    assert!(matches!(failed, Err(Error::OptimalFailed { termination: "warm_start", .. })), "{failed:?}");
    let broken = WarmStart { t: vec![0.0], theta: vec![vec![f64::NAN; 3]], rate: vec![vec![0.0; 3]] };
    let bad = ChainOptions { warm_start: Some(broken), ..ChainOptions::default() };
    assert!(matches!(ChainPlanner::new(arm, bad).plan(&problem), Err(Error::Input(_))));
}

/// [`ChainPlan::sample`] carries the base angle from sample to sample: at every sample it is
/// [`ChainPlan::phi`] (the holonomy integral from the breakpoint before it) to 1e-12 rad, and
/// the joints are [`ChainPlan::at`]'s exactly, at sample counts that put several samples in a
/// span, about one, and fewer than one (2 and 7), on the 3-link and 7-link arms.
#[test]
#[allow(clippy::float_cmp)] // exactness is the property tested: the last sample at T, the joints at()'s
fn sampled_base_angles_agree_with_phi() {
    let three = ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0);
    let seven = ChainProblem::rest_to_rest(
        vec![0.0, 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.6],
        vec![0.4, -0.3, 0.5, 0.1, 0.7, 0.2, -0.5, 0.0],
        10.0,
    );
    for (arm, problem) in [(three_link(), three), (seven_link(), seven)] {
        let plan = ChainPlanner::new(arm, ChainOptions::default()).plan(&problem).expect("a plan");
        for samples in [2, 7, 33, 1001] {
            let points = plan.sample(samples);
            assert_eq!(points.len(), samples);
            assert_eq!(points[samples - 1].t, plan.horizon());
            for p in &points {
                let exact = plan.at(p.t);
                assert!((p.phi - exact.phi).abs() <= 1e-12, "{samples} samples, t {}: {} vs {}", p.t, p.phi, exact.phi);
                assert_eq!((&p.theta, &p.rate, &p.acceleration), (&exact.theta, &exact.rate, &exact.acceleration));
            }
        }
    }
}

/// A long motion over several turns (CI's proptest case: a = -0.77, b = -0.21, T = 18.3 s, a
/// moving start): the integrator at rtol = atol = 1e-12 ends 1.03e-9 rad off, over the default
/// tolerance, while the plan is right (5e-13 rad at 1e-15). The verdict near the tolerance is the
/// second, tighter pass's: certified, with its final error; and a goal 2e-9 rad away from where the
/// motion truly ends is refused by the same second pass, at 2e-9 (it does not hide a real miss).
#[test]
fn a_verdict_near_the_tolerance_is_the_tighter_integrations() {
    use crate::numerics::ode::OdeOptions;
    use crate::plan::certificate::verify_chain;
    let robot = RobotParams::src().with_mount(Mount::new(-0.7708190867849999, -0.20503622375799277).unwrap()).unwrap();
    let arm = Arm::from_params(&robot);
    let problem = ChainProblem {
        start: vec![-6.5703059571037175, 2.1434786145117997, 3.703724126470981],
        goal: vec![-5.890409360165055, 3.2354243729747294, 2.189518257268296],
        horizon: 18.27603367684202,
        initial_velocity: vec![-0.11231380365989471, 0.25813072870767645],
        wrap: true,
    };
    let plan = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem).expect("certified");
    let v = &plan.verification;
    assert!(v.certified && v.final_error < 1e-11, "{}", v.final_error);
    let ode = OdeOptions::default();
    let once = crate::plan::certificate::integrate_once(&arm, &plan, &problem.start, &ode).unwrap();
    let first = crate::plan::certificate::final_error(&once.reached, &problem.goal);
    assert!(first > 1e-9, "the first pass alone misses: {first}");
    let mut off = plan.verification.reached.clone();
    off[0] += 2e-9;
    let miss = verify_chain(&arm, &plan, &problem.start, &off, &ode, 1e-9).unwrap();
    assert!(!miss.certified && (miss.final_error - 2e-9).abs() < 1e-10, "{}", miss.final_error);
}
