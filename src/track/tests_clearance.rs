//! The clearance of closed-loop trials (issue 21 item 6): the least clearance of the true
//! motion, the same as the plan certificate's on the nominal model, and a trial that comes
//! closer than the clearance (or hits an obstacle) is a failure, in the summary and the trials
//! file.

use super::*;
use crate::Method;
use crate::model::arm::Arm;
use crate::model::arm::collision::{Body, Geometry};
use crate::model::geometry::Shape;
use crate::model::{Mount, RobotParams};
use crate::plan::PlanningProblem;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;

/// The paper's robot at a = b = 0.1 and its problem.
fn paper() -> (Arm, ChainProblem) {
    let robot = RobotParams::src().with_mount(Mount::new(0.1, 0.1).unwrap()).unwrap();
    two_link(&PlanningProblem::paper(robot))
}

/// `arm` with a 2 cm capsule along each link and the circular `obstacles` `(x, y, r)`.
fn shaped(arm: &Arm, obstacles: &[(f64, f64, f64)], clearance: f64) -> Arm {
    let links = arm.links.iter().map(|l| vec![Shape::capsule([0.0, 0.0], [l.length, 0.0], 0.02).unwrap()]).collect();
    let obstacles = obstacles.iter().map(|&(x, y, r)| Shape::circle([x, y], r).unwrap()).collect();
    arm.clone().with_geometry(Geometry { links, obstacles, clearance, ..Default::default() }).unwrap()
}

/// The plan's tool point at `t` \[m\].
fn tool_at(arm: &Arm, planned: &ArmPlanned, t: f64) -> [f64; 2] {
    arm.tool_point(&planned.plan.q(t).unwrap())
}

/// With shapes and an obstacle the motion passes at a distance, a trial on the nominal robot
/// (`ct`, no noise) reports the least clearance that the plan's certificate finds on the model
/// (the same motion up to the tracking error, ~1e-8 rad here), for the same pair of bodies;
/// asking for more clearance than the motion keeps makes the same trial a failure.
#[test]
fn a_trial_on_the_model_reports_the_certificates_clearance() {
    let (arm, problem) = paper();
    let free = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    // 0.25 m beyond the tool's position at mid-motion, away from the centre of mass.
    let p = tool_at(&arm, &free, 0.5 * problem.horizon);
    let scale = 1.0 + 0.25 / p[0].hypot(p[1]);
    let model = shaped(&arm, &[(p[0] * scale, p[1] * scale, 0.05)], 0.0);
    let planned = plan_arm(&model, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    planned.certified().unwrap();
    let certified = planned.verification().clearance.expect("the model has shapes");
    assert!(certified.min > 0.05, "the motion passes the obstacle at a distance: {certified:?}");
    assert!(certified.time > 1.0 && certified.time < 9.0, "in mid-motion: {certified:?}");
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let run = track(&model, &problem, &planned.plan, &model, &options, 0).unwrap();
    assert!(run.failure.is_none() && run.final_error < 1e-6, "{:?} {}", run.failure, run.final_error);
    let tracked = run.clearance.expect("the trial reports its clearance");
    assert!(
        (tracked.min - certified.min).abs() < 1e-6,
        "trial {} m against the certificate's {} m",
        tracked.min,
        certified.min
    );
    assert_eq!((tracked.a, tracked.b), (certified.a, certified.b));
    assert!((tracked.time - certified.time).abs() < 0.05, "{tracked:?} against {certified:?}");
    assert!(tracked.holds() && tracked.required == 0.0);

    // More clearance than the motion keeps: the same trial fails, at the least clearance.
    let demanding = shaped(&arm, &[(p[0] * scale, p[1] * scale, 0.05)], certified.min + 0.01);
    let run = track(&demanding, &problem, &planned.plan, &demanding, &options, 0).unwrap();
    let failure = run.failure.expect("under the clearance");
    assert_eq!(failure.reason, "collision");
    let c = run.clearance.unwrap();
    assert!(!c.holds() && c.min > 0.0 && (failure.t - c.time).abs() < 1e-12, "{c:?} {failure:?}");
    assert!(run.final_error.is_infinite());
}

/// An obstacle on the planned path of the end effector (unknown to the planner): the trial
/// collides with it, stops there as a failure named `collision` with a negative clearance
/// between link 2 and the obstacle, is counted in the Monte Carlo summary's
/// `collision_failures` (not its `limit_failures`) and round-trips through the trials file.
#[test]
fn a_trial_that_collides_is_a_failure() {
    let (arm, problem) = paper();
    let planned = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    let t_hit = 0.5 * problem.horizon;
    let p = tool_at(&arm, &planned, t_hit);
    let model = shaped(&arm, &[(p[0], p[1], 0.05)], 0.0);
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let run = track(&model, &problem, &planned.plan, &arm, &options, 0).unwrap();
    let failure = run.failure.expect("the end effector runs into the obstacle");
    assert_eq!(failure.reason, "collision");
    assert!(failure.t > 0.0 && failure.t < t_hit, "it touches before its centre: {failure:?}");
    let c = run.clearance.unwrap();
    assert!(c.min < 0.0 && (c.a, c.b) == (Body::Link(2), Body::Obstacle(1)), "{c:?}");
    assert!(run.final_error.is_infinite() && run.diverged_at.is_none());

    let mc = MonteCarloOptions { trials: 2, controllers: vec![Controller::Ct], ..Default::default() };
    let (trials, summaries) = monte_carlo(&model, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
    assert!(trials.iter().all(|t| t.failure == Some("collision") && t.clearance.is_some_and(|c| c.min < 0.0)));
    let s = &summaries[0];
    assert_eq!((s.failed, s.collision_failures, s.limit_failures, s.successes), (2, 2, 0, 0));
    assert!(s.min_clearance.is_some_and(|m| m < 0.0));
    let words = trials_file::run_description(&model, &problem, &options, &mc, "optimal");
    assert!(words.contains("/geometry:"), "shapes change the rows, so the run: {words}");
    let bytes = trials_file::write(&words, mc.shard, &trials).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(text.contains("\n0,ct,,collision,") && text.contains("link 2/obstacle 1"), "{text}");
    let back = trials_file::read(&bytes, std::path::Path::new("t.csv")).unwrap();
    let read: Vec<Trial> = back.rows.iter().map(Trial::from).collect();
    assert_eq!(read, trials, "the clearance cells round-trip");
    assert_eq!(summarise(&mc.controllers, &read, mc.success_tolerance), summaries);
}

/// Without shapes nothing changes: no clearance, the trials file's clearance cells empty.
#[test]
fn a_model_without_shapes_reports_no_clearance() {
    let (arm, problem) = paper();
    let planned = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    let options = TrackOptions { controller: Controller::Ct, ..Default::default() };
    let run = track(&arm, &problem, &planned.plan, &arm, &options, 0).unwrap();
    assert!(run.clearance.is_none() && run.failure.is_none());
    let mc = MonteCarloOptions { trials: 1, controllers: vec![Controller::Open], ..Default::default() };
    let (trials, summaries) = monte_carlo(&arm, &problem, &planned.plan, &options, &mc, &|| {}).unwrap();
    assert!(trials[0].clearance.is_none() && summaries[0].min_clearance.is_none());
    let words = trials_file::run_description(&arm, &problem, &options, &mc, "optimal");
    let text = String::from_utf8(trials_file::write(&words, mc.shard, &trials).unwrap()).unwrap();
    assert!(!words.contains("geometry") && text.contains(",,,,"), "{text}");
}

/// The plan and every re-plan keep the margin beyond the clearance ([`ReplanOptions::margin`]),
/// and the run is judged at the clearance itself: on a perturbed robot (5 % in every parameter,
/// 1 cm in the mount) the plan that goes round an obstacle on the unconstrained path at the
/// margin ends within 1e-3 rad without touching, its re-plans (warm-started with the clearance
/// rows) accepted. Without shapes the planning model is the model and a margin given is refused;
/// a negative margin is refused.
#[test]
fn the_plans_keep_the_margin_and_the_run_is_judged_at_the_clearance() {
    let (arm, problem) = paper();
    assert_eq!(TrackOptions::default().replan.planning_model(&arm, &problem), arm, "no shapes, no margin");
    let free = plan_arm(&arm, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    // An obstacle 6 cm beyond the tool at mid-motion: the unconstrained plan's last link, a
    // capsule of 2 cm, reaches 1 cm into it.
    let p = tool_at(&arm, &free, 0.5 * problem.horizon);
    let scale = 1.0 + 0.06 / p[0].hypot(p[1]);
    let model = shaped(&arm, &[(p[0] * scale, p[1] * scale, 0.05)], 0.0);
    let options = TrackOptions::default();
    let margin = options.replan.margin;
    let planning = options.replan.planning_model(&model, &problem);
    assert!((planning.geometry.clearance - margin).abs() < 1e-15, "{}", planning.geometry.clearance);
    let planned = plan_arm(&planning, Method::Optimal, &ArmRequest::new(problem.clone())).unwrap();
    planned.certified().unwrap();
    let kept = planned.verification().clearance.unwrap();
    assert!(kept.min >= margin && kept.b == Body::Obstacle(1), "the plan keeps the margin: {kept:?}");
    let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&model, 1).unwrap();
    let run = track(&model, &problem, &planned.plan, &truth, &options, 1).unwrap();
    let c = run.clearance.unwrap();
    assert!(run.failure.is_none() && run.final_error < 1e-3, "{:?} {}", run.failure, run.final_error);
    assert!(c.holds() && c.required == 0.0, "judged at the clearance: {c:?}");
    assert!(
        run.replans > 0 && 10 * run.replan_failures <= run.replans,
        "{} re-plans, {} failed",
        run.replans,
        run.replan_failures
    );

    assert!(ReplanOptions::check_margin(&model, Some(0.05)).is_ok() && ReplanOptions::check_margin(&arm, None).is_ok());
    assert!(ReplanOptions::check_margin(&arm, Some(0.0)).is_ok(), "a margin of 0 is none, for any robot");
    let e = ReplanOptions::check_margin(&arm, Some(0.05)).unwrap_err().to_string();
    assert!(e.contains("margin") && e.contains("no shapes"), "a margin without shapes is refused: {e}");
    let bad = TrackOptions { replan: ReplanOptions { margin: -0.01, ..Default::default() }, ..Default::default() };
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("margin"), "{e}");
}
