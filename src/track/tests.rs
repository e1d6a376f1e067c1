//! The closed loop against the planners' certificates and against each other.

use super::*;
use crate::model::{Mount, RobotParams};
use crate::plan::{PlanningProblem, TorqueOptions};
use crate::planners::{Planned, PlannerOptions, planner};
use crate::{Method, Motion};

fn paper(a: f64, b: f64) -> (PlanningProblem, Planned) {
    let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
    let problem = PlanningProblem::paper(robot);
    let planned = planner(Method::Optimal, &PlannerOptions::default()).plan(&problem).unwrap();
    (problem, planned)
}

/// The paper's case of Fig. 6: the NFA with Eq. (14) at a = b = 0.1.
fn fig06() -> (PlanningProblem, Planned) {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let problem = PlanningProblem::paper(robot);
    let planned = planner(Method::Nfa, &PlannerOptions::default()).plan(&problem).unwrap();
    (problem, planned)
}

fn motion(p: &Planned) -> &(dyn Motion + Sync) {
    p.motion.as_ref()
}

/// The perturbed setting of issue 12: 5 % parameters, 1 cm mount, 1 % torque noise, 1e-5
/// measurement noise.
fn noisy(controller: Controller) -> TrackOptions {
    let disturbances = Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() };
    TrackOptions { controller, disturbances, ..Default::default() }
}

#[test]
fn open_loop_on_the_model_reproduces_the_torque_certificate() {
    let (problem, mut planned) = paper(0.1, 0.1);
    let report = planned.add_torques(&TorqueOptions::default()).unwrap();
    // The zero-order hold costs O(dt^2): at 16 kHz it is below 1e-8 rad.
    let options = TrackOptions { controller: Controller::Open, rate: 16_000.0, ..Default::default() };
    let run = track(&problem, motion(&planned), &problem.robot, &options, 0).unwrap();
    let gap = run_reached(&run, &problem).distance(&report.certificate.reached);
    assert!(gap < 1e-8, "open loop ends {gap:.3e} rad from the certificate's q(T)");
    assert!((run.final_error - report.certificate.final_error).abs() < 1e-8);
}

fn run_reached(run: &Tracked, problem: &PlanningProblem) -> crate::Configuration {
    let g = problem.goal.to_array();
    crate::Configuration::from_array(std::array::from_fn(|i| g[i] + run.final_errors[i]))
}

#[test]
fn computed_torque_on_the_model_reaches_the_goal() {
    let (problem, planned) = fig06();
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let run = track(&problem, motion(&planned), &problem.robot, &options, 0).unwrap();
    assert!(run.final_error < 1e-8, "ct on the model ends {:.3e} rad off", run.final_error);
}

#[test]
fn replan_beats_ct_and_adaptive_beats_replan_on_a_perturbed_robot() {
    let (problem, planned) = paper(0.1, 0.1);
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&problem.robot, 3).unwrap();
    let error = |c| track(&problem, motion(&planned), &truth, &noisy(c), 3).unwrap().final_error;
    let (ct, replan, adaptive) = (error(Controller::Ct), error(Controller::Replan), error(Controller::Adaptive));
    assert!(replan < ct && adaptive < replan, "ct {ct:.3e}, replan {replan:.3e}, adaptive {adaptive:.3e}");
    assert!(adaptive < 1e-3);
}

/// Noise-free measurements of the true robot moving with zero momentum along a joint path
/// that excites every constant: the estimate, and the robot fitted to it, recover the true
/// constants up to their common factor.
#[test]
fn identification_recovers_the_true_constants_without_noise() {
    use crate::model::system::velocity;
    let nominal = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&nominal, 5).unwrap();
    let kt = truth.lumped();
    let mut id = identify::Identifier::new(&nominal, IdentifyOptions::default());
    let dt = 1e-3;
    for i in 0..20_000 {
        let t = i as f64 * dt;
        let (th1, th2) = (2.0 * (0.7 * t).sin(), 1.0 + 1.5 * (1.3 * t).cos());
        let u = [1.4 * (0.7 * t).cos(), -1.95 * (1.3 * t).sin()];
        let dq = velocity(&kt, [0.0, th1, th2], u);
        id.update(&plant::State { q: crate::Configuration::new(0.0, th1, th2), dq }, dt);
    }
    let unit = |c: &identify::Constants| {
        let n = c.iter().map(|x| x * x).sum::<f64>().sqrt();
        c.map(|x| x / n)
    };
    let gap = |a: &identify::Constants, b: &identify::Constants| {
        unit(a).iter().zip(unit(b)).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    };
    let estimate = id.estimate();
    let truth_c = identify::constants(&kt);
    let nominal_gap = gap(&truth_c, &identify::constants(&nominal.lumped()));
    assert!(gap(&truth_c, &estimate) < 1e-5, "estimate {:.2e} (nominal {nominal_gap:.2e})", gap(&truth_c, &estimate));
    let (fitted, residual) = identify::fit_robot(&estimate, &nominal).unwrap();
    let fitted_c = identify::constants(&fitted.lumped());
    assert!(
        residual < 1e-4 && gap(&truth_c, &fitted_c) < 1e-5,
        "fit {:.2e}, residual {residual:.2e}",
        gap(&truth_c, &fitted_c)
    );
    assert!(identify::momentum_map_error(&fitted.lumped(), &kt) < 1e-5);
}

/// In an `adaptive` run the identified model's momentum map is closer to the truth than the
/// nominal one.
#[test]
fn adaptive_run_improves_the_momentum_map() {
    let (problem, planned) = paper(0.1, 0.1);
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&problem.robot, 5).unwrap();
    let options = TrackOptions { controller: Controller::Adaptive, ..Default::default() };
    let id = track(&problem, motion(&planned), &truth, &options, 5).unwrap().identification.unwrap();
    assert!(id.identified_map_error < 0.7 * id.nominal_map_error, "{id:?}");
}

#[test]
fn a_replanning_failure_is_counted_not_fatal() {
    let (problem, planned) = paper(0.1, 0.1);
    let mut options = TrackOptions { controller: Controller::Replan, rate: 200.0, ..Default::default() };
    options.replan.rate = 10.0;
    // No plan meets this acceptance tolerance: every re-plan fails, the first plan stays.
    options.replan.accept = 1e-300;
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&problem.robot, 3).unwrap();
    let run = track(&problem, motion(&planned), &truth, &options, 0).unwrap();
    assert_eq!(run.replans, 0);
    assert!(run.replan_failures > 90, "{} failures", run.replan_failures);
    // The run goes on as `ct` on the first plan.
    let ct = TrackOptions { controller: Controller::Ct, ..options };
    let ct = track(&problem, motion(&planned), &truth, &ct, 0).unwrap();
    assert!((run.final_error - ct.final_error).abs() < 1e-12);
}

/// On the model, without noise, the plan is followed to within the threshold: no re-plan is
/// due, and `replan` ends where `ct` does.
#[test]
fn replan_on_the_model_reaches_the_goal() {
    let (problem, planned) = fig06();
    let options = TrackOptions { controller: Controller::Replan, ..Default::default() };
    let run = track(&problem, motion(&planned), &problem.robot, &options, 0).unwrap();
    assert!(run.final_error < 1e-8, "replan on the model ends {:.3e} rad off", run.final_error);
}

#[test]
fn invalid_options_are_input_errors() {
    let bad = [
        TrackOptions { rate: 0.0, ..Default::default() },
        TrackOptions { rate: f64::NAN, ..Default::default() },
        TrackOptions { gains: Gains { kp: -1.0, kd: 1.0 }, ..Default::default() },
        TrackOptions { disturbances: Disturbances { torque_noise: -0.1, ..Default::default() }, ..Default::default() },
        TrackOptions { disturbances: Disturbances { torque_limit: 0.0, ..Default::default() }, ..Default::default() },
        TrackOptions { replan: ReplanOptions { rate: 2000.0, ..Default::default() }, ..Default::default() },
    ];
    for options in bad {
        assert!(options.validate().is_err_and(|e| e.is_bad_input()), "{options:?}");
    }
    assert!(Perturbation { relative: 0.7, mount: 0.0 }.validate().is_err());
}

#[test]
fn saturation_is_counted() {
    let (problem, planned) = paper(0.1, 0.1);
    let disturbances = Disturbances { torque_limit: 0.2, ..Default::default() };
    let options = TrackOptions { controller: Controller::Ct, rate: 200.0, disturbances, ..Default::default() };
    let run = track(&problem, motion(&planned), &problem.robot, &options, 0).unwrap();
    assert!(run.saturated_fraction > 0.0 && run.peak_torque.iter().all(|t| *t <= 0.2 + 1e-12));
}

/// The trials file: a diverged run is written without a non-finite number and read back as
/// infinite; rows edited with their checks recomputed are refused for their numbers; every
/// option of the run changes its description.
#[test]
fn trials_file_round_trip_and_row_checks() {
    use crate::analysis::shards::{self, Shard};
    let problem = PlanningProblem::paper(RobotParams::src());
    let options = TrackOptions::default();
    let mc = MonteCarloOptions { trials: 4, controllers: vec![Controller::Open, Controller::Ct], ..Default::default() };
    let run = trials_file::run_description(&problem, &options, &mc, "optimal");
    let trial =
        |trial, controller, final_error| Trial { trial, controller, final_error, replans: 3, replan_failures: 1 };
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
    let row = |trial, final_error, diverged| trials_file::TrialRow {
        trial,
        controller: Controller::Ct,
        final_error,
        diverged,
        replans: 0,
        replan_failures: 0,
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
        trials_file::run_description(&problem, &o, &m, "optimal")
    };
    changed.push(with(&|_, m| m.seed = 1));
    changed.push(with(&|_, m| m.trials = 5));
    changed.push(with(&|_, m| m.success_tolerance = 1e-4));
    changed.push(with(&|_, m| m.controllers = vec![Controller::Open]));
    changed.push(with(&|_, m| m.perturbation.relative = 0.01));
    changed.push(with(&|_, m| m.perturbation.mount = 0.01));
    changed.push(with(&|_, m| m.truth = Some(RobotParams::src())));
    changed.push(with(&|o, _| o.rate = 500.0));
    changed.push(with(&|o, _| o.gains.kp = 100.0));
    changed.push(with(&|o, _| o.replan.rate = 20.0));
    changed.push(with(&|o, _| o.replan.planner.samples = 3));
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
    for trials in [0, MAX_TRIALS + 1] {
        let mc = MonteCarloOptions { trials, ..Default::default() };
        let ran = std::sync::atomic::AtomicUsize::new(0);
        let result = monte_carlo(&problem, motion(&planned), &TrackOptions::default(), &mc, &|| {
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
    let (problem, planned) = paper(1.0, -1.0);
    let plain = |rate: f64| {
        let o = TrackOptions { controller: Controller::Ct, rate, hold_correction: false, ..Default::default() };
        track(&problem, motion(&planned), &problem.robot, &o, 0).unwrap().final_error
    };
    let (e1, e2) = (plain(1000.0), plain(2000.0));
    assert!(e1 > 1e-8, "the hold's error at 1 kHz ({e1:.3e} rad) is what the correction is for");
    assert!((3.0..5.0).contains(&(e1 / e2)), "halving dt divides the hold's error by {:.2}, not ~4", e1 / e2);
    for controller in [Controller::Ct, Controller::Replan] {
        let o = TrackOptions { controller, ..Default::default() };
        let run = track(&problem, motion(&planned), &problem.robot, &o, 0).unwrap();
        assert!(run.final_error <= 1e-10, "{} ends {:.3e} rad off", controller.name(), run.final_error);
        assert_eq!(run.replans, 0, "{} re-planned on the model", controller.name());
        assert!(run.final_velocity.iter().all(|v| v.abs() <= 1e-9), "not at rest: {:?}", run.final_velocity);
        let hold = run.hold_correction.expect("a correction");
        assert!(hold.error_before > 1e-8 && hold.error_after <= 1e-10);
        // The correction is a feedforward for the hold's lag (mostly the final layer's
        // velocity), not a new plan: far below the plan's own accelerations.
        let peak = (0..=1000)
            .map(|i| planned.motion.at(problem.horizon * i as f64 / 1000.0).unwrap().du)
            .fold(0.0_f64, |m, a| m.max(a[0].abs()).max(a[1].abs()));
        assert!(hold.peak_acceleration < 1e-2 * peak, "{:.3e} against {peak:.3e}", hold.peak_acceleration);
    }
    let open = TrackOptions { controller: Controller::Open, ..Default::default() };
    assert!(track(&problem, motion(&planned), &problem.robot, &open, 0).unwrap().hold_correction.is_none());
}
