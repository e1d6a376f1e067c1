//! The closed loop against the planners' certificates and against each other, for the paper's
//! 2-link robot (the `n = 2` arm) and for arms of more links.

use super::*;
use crate::Method;
use crate::model::arm::{Arm, Base, Link};
use crate::model::{Mount, RobotParams};
use crate::plan::PlanningProblem;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;
use crate::planners::{Planned, PlannerOptions, planner};

/// The paper's robot at mount `(a, b)`, its problem, and the minimum-effort plan for it.
fn paper(a: f64, b: f64) -> (Arm, ChainProblem, ArmPlanned) {
    let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
    let (arm, problem) = two_link(&PlanningProblem::paper(robot));
    let planned = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    (arm, problem, planned)
}

/// The paper's case of Fig. 6: the NFA with Eq. (14) at a = b = 0.1 (a 2-link plan).
fn fig06() -> (PlanningProblem, Planned) {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let problem = PlanningProblem::paper(robot);
    let planned = planner(Method::Nfa, &PlannerOptions::default()).plan(&problem).unwrap();
    (problem, planned)
}

/// Tracks the 2-link plan `planned` of `problem` on `truth`.
fn track_two_link(problem: &PlanningProblem, planned: &Planned, truth: &Arm, o: &TrackOptions) -> Tracked {
    let (arm, chain) = two_link(problem);
    track(&arm, &chain, &TwoLinkMotion(planned.motion.as_ref()), truth, o, 0).unwrap()
}

/// The perturbed setting of issue 12: 5 % parameters, 1 cm mount, 1 % torque noise, 1e-5
/// measurement noise.
fn noisy(controller: Controller) -> TrackOptions {
    let disturbances = Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() };
    TrackOptions { controller, disturbances, ..Default::default() }
}

fn example(name: &str) -> Arm {
    Arm::load(std::path::Path::new(&format!("{}/examples/robots/{name}", env!("CARGO_MANIFEST_DIR")))).unwrap()
}

/// A rest-to-rest problem of `arm` from `from` to `to` (degrees) in 10 s, and its plan.
fn arm_problem(arm: &Arm, from: &[f64], to: &[f64]) -> (ChainProblem, ArmPlanned) {
    let rad = |v: &[f64]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    let problem = ChainProblem::rest_to_rest(rad(from), rad(to), 10.0);
    let planned = plan_arm(arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    (problem, planned)
}

#[test]
fn open_loop_on_the_model_reproduces_the_torque_certificate() {
    let (arm, problem, _) = paper(0.1, 0.1);
    let request = ArmRequest { torques: true, ..ArmRequest::new(problem.clone()) };
    let planned = plan_arm(&arm, Method::Optimal, &request).unwrap();
    let certificate = &planned.torques.as_ref().unwrap().certificate;
    // The zero-order hold costs O(dt^2): at 16 kHz it is below 1e-8 rad.
    let options = TrackOptions { controller: Controller::Open, rate: 16_000.0, ..Default::default() };
    let run = track(&arm, &problem, &planned.plan, &arm, &options, 0).unwrap();
    let reached: Vec<f64> = problem.goal.iter().zip(&run.final_errors).map(|(g, e)| g + e).collect();
    let gap = reached
        .iter()
        .zip(&certificate.reached)
        .map(|(a, b)| crate::model::wrap_angle(a - b).abs())
        .fold(0.0, f64::max);
    assert!(gap < 1e-8, "open loop ends {gap:.3e} rad from the certificate's q(T)");
    assert!((run.final_error - certificate.final_error).abs() < 1e-8);
}

#[test]
fn computed_torque_on_the_model_reaches_the_goal() {
    let (problem, planned) = fig06();
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let run = track_two_link(&problem, &planned, &Arm::from_params(&problem.robot), &options);
    assert!(run.final_error < 1e-8, "ct on the model ends {:.3e} rad off", run.final_error);
}

#[test]
fn replan_beats_ct_and_adaptive_beats_replan_on_a_perturbed_robot() {
    let (arm, problem, planned) = paper(0.1, 0.1);
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&arm, 3).unwrap();
    let error = |c| track(&arm, &problem, &planned.plan, &truth, &noisy(c), 3).unwrap().final_error;
    let (ct, replan, adaptive) = (error(Controller::Ct), error(Controller::Replan), error(Controller::Adaptive));
    assert!(replan < ct && adaptive < replan, "ct {ct:.3e}, replan {replan:.3e}, adaptive {adaptive:.3e}");
    assert!(adaptive < 1e-3);
}

/// The regressor is exact: `r . x` equals the first row of the arm's inertia matrix times `q'`
/// (the angular momentum, Eq. 5) at random states of random arms of 1 to 6 links, to round-off.
#[test]
fn the_regressor_times_the_parameters_is_the_momentum() {
    let mut noise = noise::Noise::new(11, 0);
    let mut u = |lo: f64, hi: f64| lo + (hi - lo) * noise.uniform();
    for trial in 0..60 {
        let n = 1 + trial % 6;
        let links: Vec<Link> = (0..n)
            .map(|_| {
                let length = u(0.2, 1.5);
                Link { length, com: u(0.0, length), mass: u(0.5, 8.0), inertia: u(0.0, 0.3) }
            })
            .collect();
        let arm = Arm::new(
            Base { mass: u(5.0, 50.0), inertia: u(0.1, 3.0) },
            Mount::new(u(-1.0, 1.0), u(-1.0, 1.0)).unwrap(),
            links,
        )
        .unwrap();
        let x = identify::parameters(&arm);
        assert_eq!(x.len(), identify::parameter_count(n));
        for _ in 0..5 {
            let q: Vec<f64> = (0..=n).map(|_| u(-7.0, 7.0)).collect();
            let dq: Vec<f64> = (0..=n).map(|_| u(-3.0, 3.0)).collect();
            let r = identify::regressor(&plant::State { q: q.clone(), dq: dq.clone() });
            let (f, g) = arm.momentum_coefficients(&q[1..]);
            let momentum = f * dq[0] + g.iter().zip(&dq[1..]).map(|(g, w)| g * w).sum::<f64>();
            let rx: f64 = r.iter().zip(&x).map(|(r, x)| r * x).sum();
            let scale = f * dq.iter().map(|w| w.abs()).sum::<f64>();
            assert!((rx - momentum).abs() <= 1e-12 * scale, "n = {n}: {rx} against {momentum}");
        }
    }
}

/// At `n = 2` the parameters are the paper's lumped constants `(A, B, C, D a, D b, E a, E b,
/// I_P)` of Sec. 3.1 (closed forms of `Lumped`, link inertias folded in), in that order.
#[test]
fn two_link_parameters_are_the_papers_constants() {
    let robot =
        RobotParams { i1: 0.03, i2: 0.01, ..RobotParams::src().with_mount(Mount::new(0.3, -0.2).unwrap()).unwrap() };
    let k = robot.lumped();
    let paper = [k.A, k.B, k.C, k.D * k.a, k.D * k.b, k.E * k.a, k.E * k.b, k.IP];
    let x = identify::parameters(&Arm::from_params(&robot));
    for (i, (x, p)) in x.iter().zip(paper).enumerate() {
        assert!((x - p).abs() <= 1e-13 * p.abs().max(1.0), "{}: {x} against the paper's {p}", i);
    }
}

/// Noise-free measurements of the true arm moving with zero momentum along a joint path that
/// excites every parameter: the estimate, and the arm fitted to it, recover the true parameters
/// up to their common factor; for the paper's robot and for the 3-link example.
#[test]
fn identification_recovers_the_true_constants_without_noise() {
    let src = Arm::from_params(&RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap());
    let three = Arm { mount: Mount::new(0.1, 0.05).unwrap(), ..example("three_link.toml") };
    for nominal in [src, three] {
        let n = nominal.joints();
        let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&nominal, 5).unwrap();
        // Three links have 13 parameters to the paper robot's 8: a longer memory (20 s, the
        // whole run, against the default 5 s) gives the data the weight over the prior pull.
        let forgetting_time = if n == 2 { IdentifyOptions::default().forgetting_time } else { 20.0 };
        let options = IdentifyOptions { forgetting_time, ..Default::default() };
        let mut id = identify::Identifier::new(&nominal, options);
        let dt = 1e-3;
        let (amplitude, frequency, phase) = ([2.0, 1.5, 1.2], [0.7, 1.3, 1.9], [0.0, 1.0, -0.5]);
        for i in 0..20_000 {
            let t = i as f64 * dt;
            let theta: Vec<f64> = (0..n).map(|j| phase[j] + amplitude[j] * (frequency[j] * t).sin()).collect();
            let u: Vec<f64> = (0..n).map(|j| amplitude[j] * frequency[j] * (frequency[j] * t).cos()).collect();
            let mut q = vec![0.0];
            q.extend(&theta);
            let mut dq = vec![truth.base_rate(&theta, &u)];
            dq.extend(&u);
            id.update(&plant::State { q, dq }, dt);
        }
        let unit = |c: &[f64]| {
            let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
            c.iter().map(|x| x / norm).collect::<Vec<_>>()
        };
        let gap = |a: &[f64], b: &[f64]| unit(a).iter().zip(unit(b)).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        let estimate = id.estimate();
        let truth_c = identify::parameters(&truth);
        let nominal_gap = gap(&truth_c, &identify::parameters(&nominal));
        let estimate_gap = gap(&truth_c, &estimate);
        assert!(estimate_gap < 1e-5, "{n} links: estimate {estimate_gap:.2e} (nominal {nominal_gap:.2e})");
        let (fitted, residual) = identify::fit_arm(&estimate, &nominal).unwrap();
        let fitted_gap = gap(&truth_c, &identify::parameters(&fitted));
        assert!(residual < 1e-4 && fitted_gap < 1e-5, "{n} links: fit {fitted_gap:.2e}, residual {residual:.2e}");
        assert!(identify::momentum_map_error(&fitted, &truth) < 1e-5);
    }
}

/// In an `adaptive` run the identified model's momentum map is closer to the truth than the
/// nominal one.
#[test]
fn adaptive_run_improves_the_momentum_map() {
    let (arm, problem, planned) = paper(0.1, 0.1);
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&arm, 5).unwrap();
    let options = TrackOptions { controller: Controller::Adaptive, ..Default::default() };
    let id = track(&arm, &problem, &planned.plan, &truth, &options, 5).unwrap().identification.unwrap();
    assert!(id.identified_map_error < 0.7 * id.nominal_map_error, "{id:?}");
    assert_eq!(id.names.len(), 8);
}

#[test]
fn a_replanning_failure_is_counted_not_fatal() {
    let (arm, problem, planned) = paper(0.1, 0.1);
    let mut options = TrackOptions { controller: Controller::Replan, rate: 200.0, ..Default::default() };
    options.replan.rate = 10.0;
    // No plan meets this acceptance tolerance: every re-plan fails, the first plan stays.
    options.replan.accept = 1e-300;
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&arm, 3).unwrap();
    let run = track(&arm, &problem, &planned.plan, &truth, &options, 0).unwrap();
    assert_eq!(run.replans, 0);
    assert!(run.replan_failures > 90, "{} failures", run.replan_failures);
    // The run goes on as `ct` on the first plan.
    let ct = TrackOptions { controller: Controller::Ct, ..options };
    let ct = track(&arm, &problem, &planned.plan, &truth, &ct, 0).unwrap();
    assert!((run.final_error - ct.final_error).abs() < 1e-12);
}

/// On the model, without noise, the plan is followed to within the threshold: no re-plan is
/// due, and `replan` ends where `ct` does.
#[test]
fn replan_on_the_model_reaches_the_goal() {
    let (problem, planned) = fig06();
    let options = TrackOptions { controller: Controller::Replan, ..Default::default() };
    let run = track_two_link(&problem, &planned, &Arm::from_params(&problem.robot), &options);
    assert!(run.final_error < 1e-8, "replan on the model ends {:.3e} rad off", run.final_error);
}

/// Arms of three and four links on their nominal model, without noise: `ct` and `replan` end at
/// the goal within 1e-8 rad (the hold correction of `n` joints), without a re-plan.
#[test]
fn n_link_tracking_on_the_model_reaches_the_goal() {
    let cases = [
        (example("three_link.toml"), vec![0.0, 60.0, -30.0, -30.0], vec![30.0, 120.0, 40.0, -60.0]),
        // The file's own limits and shapes (issues 20, 21) are not this test's subject (its
        // links pass through the base's box on this path: a collision, so a failed trial).
        (
            Arm { limits: Default::default(), geometry: Default::default(), ..example("spart_like_4dof.urdf") },
            vec![0.0, 20.0, -20.0, 30.0, -10.0],
            vec![20.0, 60.0, 10.0, -20.0, 30.0],
        ),
    ];
    for (arm, from, to) in cases {
        let (problem, planned) = arm_problem(&arm, &from, &to);
        for controller in [Controller::Ct, Controller::Replan] {
            let o = TrackOptions { controller, ..Default::default() };
            let run = track(&arm, &problem, &planned.plan, &arm, &o, 0).unwrap();
            assert!(
                run.final_error <= 1e-8,
                "{} links, {}: {:.3e} rad off",
                arm.joints(),
                controller.name(),
                run.final_error
            );
            assert_eq!(run.replans, 0);
            assert_eq!((run.final_errors.len(), run.peak_torque.len()), (arm.joints() + 1, arm.joints()));
        }
    }
}

/// A plant at its torque limit applies exactly the clamp of the commanded torque, joint by
/// joint (no noise, no bias), and a run under a low limit never applies more.
#[test]
fn a_plant_at_its_torque_limit_saturates_exactly() {
    let arm = example("three_link.toml");
    let limit = 0.2;
    let disturbances = Disturbances { torque_limit: limit, ..Default::default() };
    let mut plant = plant::Plant::new(&arm, &[0.0, 0.5, -0.3, 0.2], disturbances.clone(), 0);
    for command in [[0.5, -0.1, -7.0], [0.2, -0.2, 0.19999], [1e9, -1e9, 0.0]] {
        let applied = plant.step(&command, 1e-3, 1);
        let clamp: Vec<f64> = command.iter().map(|t| t.clamp(-limit, limit)).collect();
        assert_eq!(applied.tau, clamp, "command {command:?}");
        assert_eq!(applied.saturated, command.iter().any(|t| t.abs() > limit));
    }
    let (arm, problem, planned) = paper(0.1, 0.1);
    let options = TrackOptions { controller: Controller::Ct, rate: 200.0, disturbances, ..Default::default() };
    let run = track(&arm, &problem, &planned.plan, &arm, &options, 0).unwrap();
    assert!(run.saturated_fraction > 0.0 && run.peak_torque.iter().all(|t| *t <= limit));
}

/// A Monte Carlo run on the 3-link example: every trial runs on its own perturbed arm, and the
/// summary is finite.
#[test]
fn monte_carlo_on_a_three_link_arm() {
    let arm = example("three_link.toml");
    let (problem, planned) = arm_problem(&arm, &[0.0, 60.0, -30.0, -30.0], &[30.0, 120.0, 40.0, -60.0]);
    let options = TrackOptions {
        rate: 200.0,
        replan: ReplanOptions { rate: 10.0, ..Default::default() },
        ..noisy(Controller::Ct)
    };
    let mc = MonteCarloOptions {
        trials: 4,
        perturbation: Perturbation { relative: 0.02, mount: 0.005 },
        controllers: vec![Controller::Open, Controller::Ct, Controller::Replan],
        ..Default::default()
    };
    let (trials, summaries) = monte_carlo(&arm, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
    assert_eq!(trials.len(), 12);
    for s in &summaries {
        assert_eq!((s.trials, s.failed), (4, 0), "{s:?}");
        for q in [s.median_error, s.p95_error, s.max_error] {
            assert!(q.is_some_and(f64::is_finite), "{s:?}");
        }
    }
    // Feedback and re-planning beat the open loop on the median.
    assert!(summaries[2].median_error < summaries[0].median_error, "{summaries:?}");
}

#[test]
fn invalid_options_are_input_errors() {
    let bad = [
        TrackOptions { rate: 0.0, ..Default::default() },
        TrackOptions { rate: f64::NAN, ..Default::default() },
        TrackOptions { gains: Some(Gains { kp: -1.0, kd: 1.0 }), ..Default::default() },
        TrackOptions { disturbances: Disturbances { torque_noise: -0.1, ..Default::default() }, ..Default::default() },
        TrackOptions { disturbances: Disturbances { torque_limit: 0.0, ..Default::default() }, ..Default::default() },
        TrackOptions { replan: ReplanOptions { rate: 2000.0, ..Default::default() }, ..Default::default() },
    ];
    for options in bad {
        assert!(options.validate().is_err_and(|e| e.is_bad_input()), "{options:?}");
    }
    assert!(Perturbation { relative: 0.7, mount: 0.0 }.validate().is_err());
    // Pieces that do not fit together: a bias of the wrong length, a true arm of other links.
    let (arm, problem, planned) = paper(0.1, 0.1);
    let biased = TrackOptions {
        disturbances: Disturbances { torque_bias: vec![0.1; 3], ..Default::default() },
        ..Default::default()
    };
    assert!(track(&arm, &problem, &planned.plan, &arm, &biased, 0).is_err_and(|e| e.is_bad_input()));
    let three = example("three_link.toml");
    let ct = TrackOptions { controller: Controller::Ct, ..Default::default() };
    assert!(track(&arm, &problem, &planned.plan, &three, &ct, 0).is_err_and(|e| e.is_bad_input()));
    assert!(track(&three, &problem, &planned.plan, &three, &ct, 0).is_err_and(|e| e.is_bad_input()));
}

/// The trials file: a diverged run is written without a non-finite number and read back as
/// infinite; rows edited with their checks recomputed are refused for their numbers; every
/// option of the run changes its description.
#[test]
fn trials_file_round_trip_and_row_checks() {
    use crate::analysis::shards::{self, Shard};
    let (arm, problem) = two_link(&PlanningProblem::paper(RobotParams::src()));
    let options = TrackOptions::default();
    let mc = MonteCarloOptions { trials: 4, controllers: vec![Controller::Open, Controller::Ct], ..Default::default() };
    let run = trials_file::run_description(&arm, &problem, &options, &mc, "optimal");
    let trial = |trial, controller, final_error: f64| Trial {
        trial,
        controller,
        final_error,
        failure: (!final_error.is_finite()).then_some("diverged"),
        replans: 3,
        replan_failures: 1,
        clearance: None,
    };
    let shard = Shard { k: 2, n: 2 };
    let trials = vec![
        trial(1, Controller::Open, f64::INFINITY),
        trial(1, Controller::Ct, 1.25e-7),
        trial(3, Controller::Open, f64::NAN),
        trial(3, Controller::Ct, 0.5),
    ];
    let bytes = trials_file::write(&run, shard, &trials).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(!text.to_lowercase().contains("inf") && !text.contains("NaN"), "{text}");
    assert!(text.contains("\n1,open,,true,3,1,"), "{text}");
    let p = std::path::Path::new("t.csv");
    let back = trials_file::read(&bytes, p).unwrap();
    let read: Vec<Trial> = back.rows.iter().map(Trial::from).collect();
    assert!(read[0].final_error.is_infinite() && read[2].final_error.is_infinite());
    assert_eq!(read[1], trials[1]);
    let summary = trials_file::RunSummary::parse(&back.run).unwrap();
    assert_eq!((summary.trials, summary.controllers.clone()), (4, mc.controllers.clone()));
    let s = summarise(&summary.controllers, &read, summary.success_tolerance);
    assert_eq!((s[0].successes, s[1].successes), (0, 1));
    // Rows whose numbers are wrong, written with valid checks.
    let kind = &trials_file::KIND;
    let row = |trial, final_error, diverged: bool| trials_file::TrialRow {
        trial,
        controller: Controller::Ct,
        final_error,
        diverged: if diverged { trials_file::Ended::Diverged } else { trials_file::Ended::Horizon },
        replans: 0,
        replan_failures: 0,
        min_clearance: None,
        clearance_between: None,
        clearance_time: None,
        clearance_required: None,
    };
    for (bad, what) in [
        (row(1, Some(-1.0), false), "negative"),
        (row(1, Some(0.1), true), "exactly when"),
        (row(1, None, false), "exactly when"),
        (row(2, Some(0.1), false), "not a trial of shard 2/2"),
        (row(5, Some(0.1), false), "not a trial of shard 2/2"),
    ] {
        let e = trials_file::read(&shards::write(kind, &run, shard, &[bad]).unwrap(), p).unwrap_err().to_string();
        assert!(e.contains("line 4") && e.contains(what), "{e}");
    }
    let adaptive = trials_file::TrialRow { controller: Controller::Adaptive, ..row(1, Some(0.1), false) };
    let e = trials_file::read(&shards::write(kind, &run, shard, &[adaptive]).unwrap(), p).unwrap_err().to_string();
    assert!(e.contains("not a controller of the run"), "{e}");
    // Each option is part of the run's identity.
    let mut changed = Vec::new();
    let with = |f: &dyn Fn(&mut TrackOptions, &mut MonteCarloOptions)| {
        let (mut o, mut m) = (options.clone(), mc.clone());
        f(&mut o, &mut m);
        trials_file::run_description(&arm, &problem, &o, &m, "optimal")
    };
    changed.push(with(&|_, m| m.seed = 1));
    changed.push(with(&|_, m| m.trials = 5));
    changed.push(with(&|_, m| m.success_tolerance = 1e-4));
    changed.push(with(&|_, m| m.controllers = vec![Controller::Open]));
    changed.push(with(&|_, m| m.perturbation.relative = 0.01));
    changed.push(with(&|_, m| m.perturbation.mount = 0.01));
    changed.push(with(&|_, m| m.truth = Some(Arm::from_params(&RobotParams::src()))));
    changed.push(with(&|o, _| o.disturbances.torque_bias = vec![0.1, 0.0]));
    changed.push(with(&|o, _| o.rate = 500.0));
    changed.push(with(&|o, _| o.gains = Some(Gains { kp: 100.0, ..o.gains() })));
    changed.push(with(&|o, _| o.replan.rate = 20.0));
    changed.push(with(&|o, _| o.replan.planner.coarse_spans = 5));
    changed.push(with(&|o, _| o.identify.forgetting_time = 2.0));
    changed.push(with(&|o, _| o.disturbances.torque_limit = 5.0));
    changed.push(with(&|o, _| o.disturbances.q_noise = 1e-5));
    changed.push(with(&|_, m| m.shard = Shard { k: 1, n: 3 }));
    assert!(changed[..changed.len() - 1].iter().all(|c| *c != run));
    assert_eq!(changed.last(), Some(&run), "the shard is not part of the run");
    assert!(!run.contains("inf") && !run.contains('\n'), "{run}");
}

/// A Monte Carlo run of more than `MAX_TRIALS` trials (or of none) is bad input, refused before
/// any trial runs (each trial keeps its result).
#[test]
fn trial_counts_are_bounded() {
    use crate::track::monte_carlo::{MAX_TRIALS, MonteCarloOptions, monte_carlo};
    let (problem, planned) = fig06();
    let (arm, chain) = two_link(&problem);
    for trials in [0, MAX_TRIALS + 1] {
        let mc = MonteCarloOptions { trials, ..Default::default() };
        let ran = std::sync::atomic::AtomicUsize::new(0);
        let motion = TwoLinkMotion(planned.motion.as_ref());
        let result = monte_carlo(&arm, &chain, &motion, &TrackOptions::default(), &mc, &|| {
            ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        });
        assert!(result.is_err_and(|e| e.is_bad_input()), "{trials} trials");
        assert_eq!(ran.into_inner(), 0);
    }
}

/// The zero-order hold's error on the model is O(dt^2) (see [`hold`]), and the hold correction
/// removes it: at a = 1, b = -1, whose optimal plan has steep end layers, `ct` and `replan` on
/// the nominal robot end at the goal to round-off, and `replan` finds nothing to re-plan.
#[test]
fn hold_correction_brings_the_nominal_loop_to_the_goal() {
    let (arm, problem, planned) = paper(1.0, -1.0);
    let plain = |rate: f64| {
        let o = TrackOptions { controller: Controller::Ct, rate, hold_correction: false, ..Default::default() };
        track(&arm, &problem, &planned.plan, &arm, &o, 0).unwrap().final_error
    };
    let (e1, e2) = (plain(1000.0), plain(2000.0));
    assert!(e1 > 1e-8, "the hold's error at 1 kHz ({e1:.3e} rad) is what the correction is for");
    assert!((3.0..5.0).contains(&(e1 / e2)), "halving dt divides the hold's error by {:.2}, not ~4", e1 / e2);
    for controller in [Controller::Ct, Controller::Replan] {
        let o = TrackOptions { controller, ..Default::default() };
        let run = track(&arm, &problem, &planned.plan, &arm, &o, 0).unwrap();
        assert!(run.final_error <= 1e-10, "{} ends {:.3e} rad off", controller.name(), run.final_error);
        assert_eq!(run.replans, 0, "{} re-planned on the model", controller.name());
        assert!(run.final_velocity.iter().all(|v| v.abs() <= 1e-9), "not at rest: {:?}", run.final_velocity);
        let hold = run.hold_correction.expect("a correction");
        assert!(hold.error_before > 1e-8 && hold.error_after <= 1e-10);
        // The correction is a feedforward for the hold's lag (mostly the final layer's
        // velocity), not a new plan: below the plan's own accelerations. The loop follows a
        // feedforward `c` as an offset of about `c / kp`, so the correction grows with the
        // stiffness: 1.2e-1 of the peak at the default kp = 40000 (below 1e-2 at kp = 2500).
        let peak = (0..=1000)
            .map(|i| planned.plan.joints_at(problem.horizon * i as f64 / 1000.0).unwrap().acceleration)
            .fold(0.0_f64, |m, a| a.iter().fold(m, |m, x| m.max(x.abs())));
        assert!(hold.peak_acceleration < 0.25 * peak, "{:.3e} against {peak:.3e}", hold.peak_acceleration);
    }
    let open = TrackOptions { controller: Controller::Open, ..Default::default() };
    assert!(track(&arm, &problem, &planned.plan, &arm, &open, 0).unwrap().hold_correction.is_none());
}
