//! Criterion benches of closed-loop execution (issue 12; docs/spec.md §5): one 10 s run of the
//! paper's problem at 1 kHz per controller, and of the adaptive controller at a = 1, b = -1
//! (target: <= 0.5 s). Before timing, the final errors
//! of `ct` and `replan` on the nominal robot without noise are printed for the paper's five
//! cases and for a = 1, b = -1 (target: <= 1e-8 rad); they are reported, not gated.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::planners::{PlannerOptions, planner};
use freefloat::track::{Controller, Disturbances, Perturbation, TrackOptions, track};
use freefloat::{Method, Mount, NfaOptions, PlanningProblem, RobotParams, Transform};

fn problem(a: f64, b: f64) -> PlanningProblem {
    PlanningProblem::paper(RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid"))
}

/// The paper's five NFA cases (Figs. 4-8) and the optimal plan at a = 1, b = -1.
fn cases() -> Vec<(&'static str, PlanningProblem, Method, Option<Transform>)> {
    vec![
        ("fig04 eq11", problem(0.0, 0.0), Method::Nfa, Some(Transform::Eq11)),
        ("fig05 eq12", problem(0.0, 0.0), Method::Nfa, Some(Transform::Eq12)),
        ("fig06 eq14 a=b=0.1", problem(0.1, 0.1), Method::Nfa, Some(Transform::Eq14)),
        ("fig07 eq14 a=b=0.2", problem(0.2, 0.2), Method::Nfa, Some(Transform::Eq14)),
        ("fig08 eq14 a=b=0.3", problem(0.3, 0.3), Method::Nfa, Some(Transform::Eq14)),
        ("optimal a=1 b=-1", problem(1.0, -1.0), Method::Optimal, None),
    ]
}

fn nominal_errors() {
    for (name, p, method, transform) in cases() {
        let options = PlannerOptions { nfa: NfaOptions { transform, ..Default::default() }, ..Default::default() };
        let planned = planner(method, &options).plan(&p).expect("plan");
        let mut line = format!("nominal, no noise, {name}:");
        for controller in [Controller::Open, Controller::Ct, Controller::Replan] {
            let o = TrackOptions { controller, ..Default::default() };
            let run = track(&p, planned.motion.as_ref(), &p.robot, &o, 0).expect("run");
            line += &format!(" {} {:.2e}", controller.name(), run.final_error);
        }
        eprintln!("{line} rad");
    }
}

fn bench_track(c: &mut Criterion) {
    nominal_errors();
    let mut group = c.benchmark_group("track");
    group.sample_size(10).measurement_time(Duration::from_secs(8));
    let disturbances = Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() };
    for (name, a, b, controllers) in
        [("", 0.1, 0.1, &Controller::ALL[..]), ("_a1_b-1", 1.0, -1.0, &[Controller::Adaptive][..])]
    {
        let p = problem(a, b);
        let planned = planner(Method::Optimal, &PlannerOptions::default()).plan(&p).expect("plan");
        let truth = Perturbation { relative: 0.05, mount: 0.01 }.apply(&p.robot, 1).expect("robot");
        for &controller in controllers {
            let o = TrackOptions { controller, disturbances, ..Default::default() };
            group.bench_function(format!("run_10s_1kHz{name}/{}", controller.name()), |bench| {
                bench.iter(|| black_box(track(&p, planned.motion.as_ref(), &truth, &o, 1).expect("run")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_track);
criterion_main!(benches);
