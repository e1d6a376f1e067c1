//! Criterion benches of closed-loop execution (issue 12; docs/spec.md §5): one 10 s run of the
//! paper's problem at 1 kHz per controller, and of the adaptive controller at a = 1, b = -1
//! (target: <= 0.5 s), of `ct` and `adaptive` on the 3-link example arm, and of `adaptive` on
//! problem 0 of issue 22's hard set (target: <= 0.5 s); and of one trial of a Monte Carlo run of
//! `adaptive` on each (the plan's hold correction computed once per run, as `monte_carlo` does:
//! issue 22's per-run figure, target <= 0.25 s at the paper's mounts and <= 0.5 s on the hard
//! set). Before timing, the
//! final errors of `ct` and `replan` on the nominal robot without noise are printed for the
//! paper's five cases and for a = 1, b = -1 (target: <= 1e-8 rad); they are reported, not gated.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::planners::arm::{ArmPlan, ArmRequest, plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::{PlannerOptions, planner};
use freefloat::track::{
    ArmMotion, Controller, Disturbances, Perturbation, TrackOptions, TwoLinkMotion, hold_correction, track, track_with,
    two_link,
};
use freefloat::{Arm, Method, Mount, NfaOptions, PlanningProblem, RobotParams, Transform};

fn problem(a: f64, b: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid"))
}

/// The minimum-effort plan of `problem` for `arm` (the n-joint pipeline).
fn optimal(arm: &Arm, problem: &ChainProblem) -> ArmPlan {
    plan_arm(arm, Method::Optimal, &ArmRequest::new(problem.clone())).expect("plan").plan
}

fn nominal_errors() {
    for (name, a, transform) in [
        ("fig04 eq11", 0.0, Transform::Eq11),
        ("fig05 eq12", 0.0, Transform::Eq12),
        ("fig06 eq14 a=b=0.1", 0.1, Transform::Eq14),
        ("fig07 eq14 a=b=0.2", 0.2, Transform::Eq14),
        ("fig08 eq14 a=b=0.3", 0.3, Transform::Eq14),
    ] {
        let p = problem(a, a);
        let options = PlannerOptions {
            nfa: NfaOptions { transform: Some(transform), ..Default::default() },
            ..Default::default()
        };
        let planned = planner(Method::Nfa, &options).plan(&p).expect("plan");
        let (arm, chain) = two_link(&p);
        errors(name, &arm, &chain, &TwoLinkMotion(planned.motion.as_ref()));
    }
    let (arm, chain) = two_link(&problem(1.0, -1.0));
    errors("optimal a=1 b=-1", &arm, &chain, &optimal(&arm, &chain));
}

fn errors(name: &str, arm: &Arm, problem: &ChainProblem, plan: &dyn ArmMotion) {
    let mut line = format!("nominal, no noise, {name}:");
    for controller in [Controller::Open, Controller::Ct, Controller::Replan] {
        let o = TrackOptions { controller, ..Default::default() };
        let run = track(arm, problem, plan, arm, &o, 0).expect("run");
        line += &format!(" {} {:.2e}", controller.name(), run.final_error);
    }
    eprintln!("{line} rad");
}

fn three_link() -> (Arm, ChainProblem) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml");
    let arm = Arm::load(std::path::Path::new(path)).expect("the example arm");
    let rad = |v: [f64; 4]| v.map(f64::to_radians).to_vec();
    (arm, ChainProblem::rest_to_rest(rad([0.0, 60.0, -30.0, -30.0]), rad([30.0, 120.0, 40.0, -60.0]), 10.0))
}

/// Problem 0 of issue 22's hard set (`tests/fixtures/hard_set.csv`): a 25-turn plan at
/// `|mount|` 1.9 m with a 175 deg base turn, the slowest of the set to track.
fn hard_problem() -> (Arm, ChainProblem) {
    let text = include_str!("../tests/fixtures/hard_set.csv");
    let row = text.lines().find(|l| l.starts_with("0,")).expect("problem 0");
    let v: Vec<f64> = row.split(',').map(|x| x.parse().expect("a number")).collect();
    let arm = Arm { mount: Mount { a: v[1], b: v[2] }, ..Arm::from_params(&RobotParams::src()) };
    (arm, ChainProblem::rest_to_rest(v[3..6].to_vec(), v[6..9].to_vec(), 10.0))
}

fn bench_track(c: &mut Criterion) {
    nominal_errors();
    let mut group = c.benchmark_group("track");
    group.sample_size(10).measurement_time(Duration::from_secs(8));
    let disturbances = Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() };
    let paper = |a, b| two_link(&problem(a, b));
    for (name, (arm, chain), controllers) in [
        ("", paper(0.1, 0.1), &Controller::ALL[..]),
        ("_a1_b-1", paper(1.0, -1.0), &[Controller::Adaptive][..]),
        ("_3link", three_link(), &[Controller::Ct, Controller::Adaptive][..]),
        ("_hard0", hard_problem(), &[Controller::Adaptive][..]),
    ] {
        let plan = optimal(&arm, &chain);
        let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&arm, 1).expect("robot");
        for &controller in controllers {
            let o = TrackOptions { controller, disturbances: disturbances.clone(), ..Default::default() };
            group.bench_function(format!("run_10s_1kHz{name}/{}", controller.name()), |bench| {
                bench.iter(|| black_box(track(&arm, &chain, &plan, &truth, &o, 1).expect("run")))
            });
            // One trial of a Monte Carlo run: the hold correction is the plan's, computed once
            // per run of trials (`monte_carlo`), not per trial.
            if controller == Controller::Adaptive {
                let correction = hold_correction(&arm, &chain, &plan, &o).expect("correction");
                group.bench_function(format!("trial_10s_1kHz{name}/adaptive"), |bench| {
                    bench.iter(|| {
                        black_box(track_with(&arm, &chain, &plan, correction.as_ref(), &truth, &o, 1).expect("run"))
                    })
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench_track);
criterion_main!(benches);
