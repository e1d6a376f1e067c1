//! Tests of the `n`-joint ECSA: agreement with the 2-joint ECSA at n = 2, certified plans at
//! n = 3 and 7, the exact gradient of `phi(T)` against num-dual and central differences, the
//! quadrature rule's convergence, and bad input.

use std::path::Path;

use nalgebra::{DVector, SVector};
use num_dual::{Derivative, DualSVec64};
use proptest::prelude::*;

use super::*;
use crate::model::arm::{Base, Link};
use crate::model::{Mount, RobotParams};
use crate::plan::PlanningProblem;
use crate::planners::ecsa::EcsaPlanner;

fn three_link() -> Arm {
    let text = include_str!("../../../examples/robots/three_link.toml");
    Arm::from_toml(text, Path::new("examples/robots/three_link.toml")).unwrap()
}

/// A 7-link arm (the chain planner's test arm): links 0.3 m down to 0.15 m, 1.5 down to 0.3 kg.
fn seven_link() -> Arm {
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

fn deg(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// At n = 2 with the SRC robot (a = b = 0.1) and the paper's problem, the 2-link front-end
/// [`EcsaPlanner`] is the engine with the pseudo-inverse solver: the same coefficients bit for
/// bit, the same iterations, and the engine's certified plan ends where the front-end's map does.
#[test]
fn two_link_front_end_is_the_engine() {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let arm = Arm::from_params(&robot);
    let (q0, qd, horizon) = crate::model::paper_problem();
    let problem = ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon);
    for window in [Window::None, Window::SinSquared] {
        for harmonics in [1, 2] {
            let options = EcsaOptions::default().with_window(window).with_harmonics(harmonics).unwrap();
            let two = EcsaPlanner::new(options).solve(&PlanningProblem::paper(robot)).unwrap();
            let planner = ChainEcsaPlanner::new(arm.clone(), options).with_solver(ChainSolver::PseudoInverse);
            let plan = planner.plan(&problem).unwrap();
            let s = &plan.stats;
            assert_eq!(s.iteration.termination, Termination::Converged);
            assert_eq!(s.iteration.iterations, two.stats.iterations);
            assert_eq!(s.coefficients, two.coefficients, "{window:?} H = {harmonics}");
            assert!(plan.verification.certified && plan.verification.final_error <= 1e-9);
            let reached = two.reached.to_array();
            let dq = plan.verification.reached.iter().zip(reached).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(dq < 1e-9, "{window:?} H = {harmonics}: end points differ by {dq}");
        }
    }
}

/// How far `c` is from the row space of `J(c)` (the first-order condition of `min |c|^2` on
/// `K(c) = q_d`: `c = -J^T mu`), relative to `|c|`.
fn off_row_space(planner: &ChainEcsaPlanner, problem: &ChainProblem, c: &[f64]) -> f64 {
    let k = planner.end_point(&problem.start, problem.horizon, c, 256).unwrap();
    let (j, c) = (&k.jacobian, DVector::from_column_slice(c));
    let mu = (j * j.transpose()).cholesky().unwrap().solve(&(j * &c));
    (&c - j.transpose() * mu).norm() / c.norm()
}

/// The minimum-norm solver on the paper's problem (n = 2), where the pseudo-inverse iteration
/// converges from the line: both are solutions of `K(c) = q_d`, the minimum-norm one is
/// stationary for `|c|^2` (`c` in the row space of `J` to 1e-7, the Hessian's forward
/// differences being 1e-7) and no longer than the pseudo-inverse's.
#[test]
fn minimum_norm_on_the_paper_problem() {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let arm = Arm::from_params(&robot);
    let (q0, qd, horizon) = crate::model::paper_problem();
    let problem = ChainProblem::rest_to_rest(q0.to_array().to_vec(), qd.to_array().to_vec(), horizon);
    for window in [Window::None, Window::SinSquared] {
        let options = EcsaOptions::default().with_window(window);
        let pinv = ChainEcsaPlanner::new(arm.clone(), options).with_solver(ChainSolver::PseudoInverse);
        let p = pinv.plan(&problem).unwrap().stats;
        let planner = ChainEcsaPlanner::new(arm.clone(), options);
        let plan = planner.plan(&problem).unwrap();
        let s = &plan.stats;
        let norm = |c: &[f64]| c.iter().map(|x| x * x).sum::<f64>().sqrt();
        let off =
            (off_row_space(&planner, &problem, &s.coefficients), off_row_space(&planner, &problem, &p.coefficients));
        eprintln!(
            "paper {window:?}: |c| {:.6} (pseudo-inverse {:.6}), effort {:.6} ({:.6}), {} iterations in {} steps ({}),              off the row space {:.1e} ({:.1e})",
            norm(&s.coefficients),
            norm(&p.coefficients),
            s.effort,
            p.effort,
            s.iteration.iterations,
            s.continuation_steps,
            p.iteration.iterations,
            off.0,
            off.1
        );
        assert_eq!(s.solver, ChainSolver::MinimumNorm);
        assert!(plan.verification.certified && plan.verification.final_error <= 1e-9);
        assert!(off.0 < 1e-7, "{off:?}");
        assert!(norm(&s.coefficients) <= norm(&p.coefficients) * (1.0 + 1e-12));
    }
}

/// Certified plans for the 3-link example arm (the CLI test's problem) and a 7-link arm, both
/// windows, by the minimum-norm solver; the samples start at `q0` and end at `qd` (`phi` modulo
/// 2 pi: the wrapped residual lets the iteration settle on any representative), the windowed
/// plans at rest. `c` is stationary for `|c|^2` (as above) and no longer than the
/// pseudo-inverse iteration's solution of the same equation, when that converges.
#[test]
fn plans_three_and_seven_links() {
    let cases = [
        (three_link(), deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0])),
        (
            seven_link(),
            deg(&[0.0, 10.0, 20.0, -10.0, 30.0, 0.0, -20.0, 15.0]),
            deg(&[25.0, 40.0, -10.0, 20.0, 0.0, 30.0, 10.0, -15.0]),
        ),
    ];
    for (arm, start, goal) in cases {
        let n = arm.joints();
        let problem = ChainProblem::rest_to_rest(start.clone(), goal.clone(), 10.0);
        for window in [Window::None, Window::SinSquared] {
            let planner = ChainEcsaPlanner::new(arm.clone(), EcsaOptions::default().with_window(window));
            let clock = Instant::now();
            let plan = planner.plan(&problem).unwrap();
            let seconds = clock.elapsed().as_secs_f64();
            let s = &plan.stats;
            let pinv = planner.clone().with_solver(ChainSolver::PseudoInverse).solve(&problem);
            let norm = |c: &[f64]| c.iter().map(|x| x * x).sum::<f64>().sqrt();
            let off = off_row_space(&planner, &problem, &s.coefficients);
            eprintln!(
                "n = {n} {window:?}: {} iterations in {} steps, residual {:.1e}, verified {:.2e}, pieces {}, \
                 change {:.1e}, effort {:.4} (pseudo-inverse {:?}), off the row space {off:.1e}, {:.1} ms, history {:?}",
                s.iteration.iterations,
                s.continuation_steps,
                s.iteration.residual,
                plan.verification.final_error,
                s.quadrature_pieces,
                s.quadrature_change,
                s.effort,
                pinv.as_ref().map(|p| p.effort).ok(),
                seconds * 1e3,
                s.iteration.residual_history
            );
            assert!(off < 1e-7, "{off}");
            if let Ok(p) = &pinv {
                assert!(norm(&s.coefficients) <= norm(&p.coefficients) * (1.0 + 1e-12));
            }
            assert!(plan.verification.certified && plan.verification.final_error <= 1e-9);
            assert!(plan.verification.max_abs_momentum < 1e-9, "{}", plan.verification.max_abs_momentum);
            let samples = plan.sample(101);
            let (first, last) = (&samples[0], &samples[100]);
            assert!((first.phi - start[0]).abs() < 1e-15);
            assert!(wrap_angle(last.phi - goal[0]).abs() < 1e-9, "{} vs {}", last.phi, goal[0]);
            for i in 0..n {
                assert!((first.theta[i] - start[i + 1]).abs() < 1e-15);
                assert!((last.theta[i] - goal[i + 1]).abs() < 1e-9);
                if window == Window::SinSquared {
                    assert!(first.rate[i].abs() < 1e-12 && last.rate[i].abs() < 1e-12);
                }
            }
            // The acceleration is the rate's time derivative.
            let (t, h) = (3.7, 1e-5);
            let (a, b) = (plan.at(t + h), plan.at(t - h));
            let mid = plan.at(t);
            for i in 0..n {
                let fd = (a.rate[i] - b.rate[i]) / (2.0 * h);
                assert!((mid.acceleration[i] - fd).abs() < 1e-7, "{} vs {fd}", mid.acceleration[i]);
            }
        }
    }
}

/// `phi(T)` with num-dual over the coefficients through the model's
/// [`Arm::momentum_coefficients`] (no [`Connection`]), on the same quadrature nodes.
fn phi_dual<const P: usize>(arm: &Arm, basis: &Basis, start: &[f64], c: &[f64], pieces: usize) -> (f64, Vec<f64>) {
    let (n, m) = (arm.joints(), basis.terms());
    assert_eq!(P, n * m);
    let h = basis.horizon() / pieces as f64;
    let mut phi = DualSVec64::<P>::from_re(start[0]);
    let r = GaussLegendre::new(NODES);
    for piece in 0..pieces {
        for (x, w) in r.nodes.iter().zip(&r.weights) {
            let t = piece as f64 * h + 0.5 * h * (1.0 + x);
            let (b, anti) = (basis.values(t), basis.antiderivatives(t));
            let mut theta = Vec::new();
            let mut u = Vec::new();
            for i in 0..n {
                let (mut dt, mut du) = (SVector::<f64, P>::zeros(), SVector::<f64, P>::zeros());
                let (mut th, mut ui) = (start[i + 1], 0.0);
                for j in 0..m {
                    th += c[i * m + j] * anti[j];
                    ui += c[i * m + j] * b[j];
                    dt[i * m + j] = anti[j];
                    du[i * m + j] = b[j];
                }
                theta.push(DualSVec64::new(th, Derivative::some(dt)));
                u.push(DualSVec64::new(ui, Derivative::some(du)));
            }
            phi += arm.base_rate(&theta, &u) * (0.5 * h * w);
        }
    }
    (phi.re, phi.eps.unwrap_generic(nalgebra::Const::<P>, nalgebra::U1).iter().copied().collect())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// The Jacobian's `phi` row equals num-dual's gradient through the model (relative 1e-10,
    /// same rule) and a central difference of the map (step 1e-6, agreement 1e-6 relative to
    /// the row's size: the difference's truncation is O(h^2) ~ 1e-12, its rounding ~ 1e-10);
    /// the `theta` rows are `A_j(T)`.
    #[test]
    fn gradient_matches_num_dual_and_differences(
        seed in proptest::collection::vec(-1.0f64..1.0, 4 * 9),
        harmonics in 1usize..=2,
        windowed in any::<bool>(),
    ) {
        let arm = three_link();
        let window = if windowed { Window::SinSquared } else { Window::None };
        let options = EcsaOptions::default().with_window(window).with_harmonics(harmonics).unwrap();
        let planner = ChainEcsaPlanner::new(arm.clone(), options);
        let horizon = 6.0;
        let basis = Basis::new(harmonics, horizon, window).unwrap();
        let m = basis.terms();
        let c: Vec<f64> = seed[..3 * m].iter().map(|x| 0.3 * x).collect();
        let start = [seed[33], seed[34], seed[35], -seed[33]];
        let pieces = 8;
        let k = planner.end_point(&start, horizon, &c, pieces).unwrap();
        let (re, d) = if m == 3 {
            phi_dual::<9>(&arm, &basis, &start, &c, pieces)
        } else {
            phi_dual::<15>(&arm, &basis, &start, &c, pieces)
        };
        prop_assert!((re - k.q[0]).abs() < 1e-12, "{} vs {}", re, k.q[0]);
        let scale = k.jacobian.row(0).amax().max(1e-3);
        for p in 0..3 * m {
            // base_rate is -g, phi = phi0 + int(base_rate): same sign as the row.
            prop_assert!((d[p] - k.jacobian[(0, p)]).abs() < 1e-10 * scale, "p = {}: {} vs {}", p, d[p], k.jacobian[(0, p)]);
            let h = 1e-6;
            let (mut cp, mut cm) = (c.clone(), c.clone());
            cp[p] += h;
            cm[p] -= h;
            let fp = planner.end_point_map(&start, horizon, &cp, pieces).unwrap()[0];
            let fm = planner.end_point_map(&start, horizon, &cm, pieces).unwrap()[0];
            let fd = (fp - fm) / (2.0 * h);
            prop_assert!((fd - k.jacobian[(0, p)]).abs() < 1e-6 * scale, "p = {}: {} vs {}", p, fd, k.jacobian[(0, p)]);
        }
        let ends = basis.integrals();
        for i in 0..3 {
            for p in 0..3 * m {
                let expected = if p / m == i { ends[p % m] } else { 0.0 };
                prop_assert!((k.jacobian[(i + 1, p)] - expected).abs() < 1e-15);
            }
        }
    }
}

/// The quadrature rule: at the 3-link solution, `phi(T)` with the plan's pieces and with 2x
/// and 4x agree to 1e-12 rad, and the sampled `phi(T)` is the map's.
#[test]
fn quadrature_converges() {
    let arm = three_link();
    let problem = ChainProblem::rest_to_rest(deg(&[0.0, 60.0, -30.0, -30.0]), deg(&[30.0, 120.0, 40.0, -60.0]), 10.0);
    let planner = ChainEcsaPlanner::new(arm, EcsaOptions::default());
    let plan = planner.plan(&problem).unwrap();
    let s = &plan.stats;
    let phi = |pieces| planner.end_point_map(&problem.start, 10.0, &s.coefficients, pieces).unwrap()[0];
    let p = s.quadrature_pieces;
    let (a, b, c) = (phi(p), phi(2 * p), phi(4 * p));
    eprintln!("pieces {p}: phi(T) {a:.15} / {b:.15} / {c:.15}");
    assert!((a - b).abs() < 1e-12 && (a - c).abs() < 1e-12);
    assert!((plan.phi(10.0) - a).abs() < 1e-13);
}

/// Wrong lengths, a moving start, harmonics out of range and an iteration limit are typed
/// errors.
#[test]
fn bad_input_is_typed() {
    let arm = three_link();
    let planner = ChainEcsaPlanner::new(arm.clone(), EcsaOptions::default());
    let invalid = |r: Result<_, Error>| matches!(r, Err(Error::Input(InputError::InvalidParameter { .. })));
    assert!(invalid(planner.end_point(&[0.0; 3], 10.0, &[0.0; 9], 8).map(|_| ())));
    assert!(invalid(planner.end_point(&[0.0; 4], 10.0, &[0.0; 8], 8).map(|_| ())));
    assert!(invalid(planner.end_point_map(&[0.0; 4], 10.0, &[0.0; 10], 8).map(|_| ())));
    let good = ChainProblem::rest_to_rest(vec![0.0; 4], vec![0.2, 0.1, 0.1, 0.1], 10.0);
    let short = ChainProblem::rest_to_rest(vec![0.0; 3], vec![0.2, 0.1, 0.1], 10.0);
    assert!(invalid(planner.plan(&short).map(|_| ())));
    let moving = ChainProblem { initial_velocity: vec![0.1, 0.0, 0.0], ..good.clone() };
    assert!(invalid(planner.plan(&moving).map(|_| ())));
    let options = EcsaOptions { harmonics: 0, ..EcsaOptions::default() };
    assert!(invalid(ChainEcsaPlanner::new(arm.clone(), options).plan(&good).map(|_| ())));
    let capped = ChainEcsaPlanner::new(arm, EcsaOptions::default().with_max_iterations(0));
    match capped.plan(&good) {
        Err(Error::EcsaFailed { stats }) => {
            assert_eq!(stats.termination, Termination::MaxIterations);
            assert_eq!(stats.residual_history.len(), 1);
        }
        other => panic!("expected EcsaFailed, got {other:?}"),
    }
}
