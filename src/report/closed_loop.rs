//! Fig. 20 (beyond the paper): the plan in closed loop on robots that are not the model
//! (issue 22, items 4 and 5; docs/spec.md §5). Each controller's success rate and final-error
//! distribution on the paper's problem at a = b = 0.1 m and on a hard public problem, and the
//! success of `adaptive` as the actuators' torque limit tightens below the plan's peak.
//!
//! Every trial is a [`monte_carlo()`] trial with the disturbances of issue 22's measurements
//! ([`closed_loop_options`]): 5 % parameters, 1 cm mount, 1 % torque noise, 1e-5 rad and
//! 1e-5 rad/s sensor noise, 1 kHz, seed 1. `reproduce` runs [`CLOSED_LOOP_TRIALS`] per controller
//! and case, so that it stays under a minute; `reproduce --trials 1000` runs the full version.

use serde::Serialize;

use super::html::{escape, head_cell};
use super::plot::{Bound, Panel, PlanFigure, Series};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::{Mount, RobotParams};
use crate::plan::Method;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;
use crate::track::monte_carlo::MAX_TRIALS;
use crate::track::{Controller, Disturbances, MonteCarloOptions, Perturbation, Summary, TrackOptions, monte_carlo};

/// The figure's file name.
pub const CLOSED_LOOP_FIGURE: &str = "fig20";

/// Trials per controller and case of a default `reproduce` (the torque curve takes half as many
/// per point, [`curve_trials`]).
pub const CLOSED_LOOP_TRIALS: usize = 20;

/// The torque limits of the curve, as fractions of the plan's peak `max_j max_t |tau_j|`.
pub const TORQUE_FRACTIONS: [f64; 7] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0];

/// A trial succeeds when its final error is at most this \[rad\] (the Monte Carlo's default).
pub const SUCCESS_TOLERANCE: f64 = 1e-3;

/// One problem of the figure: a 2-link SRC robot at a mount, rest to rest in 10 s.
struct Problem {
    id: &'static str,
    label: &'static str,
    mount: [f64; 2],
    start_deg: [f64; 3],
    goal_deg: [f64; 3],
}

/// The paper's problem at the paper's mount a = b = 0.1 m (Figs. 6 and 10), and issue 22's
/// public hard case (joint travel about 1900 deg, a 70 deg base turn).
const PROBLEMS: [Problem; 2] = [
    Problem {
        id: "paper",
        label: "paper's problem, a = b = 0.1 m",
        mount: [0.1, 0.1],
        start_deg: [45.0, 120.0, 80.0],
        goal_deg: [0.0, 180.0, 140.0],
    },
    Problem {
        id: "hard",
        label: "hard case, a = 1.3 m, b = -0.9 m",
        mount: [1.3, -0.9],
        start_deg: [10.0, 40.0, -70.0],
        goal_deg: [80.0, -30.0, 60.0],
    },
];

/// Trials per point of the torque curve for `trials` per controller and case: half, at least 1
/// (a saturated run costs about twice an unsaturated one).
pub fn curve_trials(trials: usize) -> usize {
    trials.div_ceil(2)
}

/// The closed loop and the Monte Carlo of every trial of Fig. 20 (`trials` each).
pub fn closed_loop_options(trials: usize) -> (TrackOptions, MonteCarloOptions) {
    let track = TrackOptions {
        disturbances: Disturbances { torque_noise: 0.01, q_noise: 1e-5, dq_noise: 1e-5, ..Default::default() },
        ..Default::default()
    };
    let mc = MonteCarloOptions {
        trials,
        seed: 1,
        perturbation: Perturbation { relative: 0.05, mount: 0.01 },
        controllers: Controller::ALL.to_vec(),
        success_tolerance: SUCCESS_TOLERANCE,
        ..Default::default()
    };
    (track, mc)
}

/// Checks the trial count of `reproduce --trials` before any work: 1 to [`MAX_TRIALS`].
pub fn check_trials(trials: usize) -> Result<(), Error> {
    if (1..=MAX_TRIALS).contains(&trials) {
        return Ok(());
    }
    Err(InputError::InvalidParameter {
        name: "trials".into(),
        value: trials as f64,
        expected: "1 to 1e6 closed-loop trials per controller and case (Fig. 20)",
    }
    .into())
}

/// One problem's Monte Carlo: every controller on the same trials.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosedLoopCase {
    /// `paper` or `hard`.
    pub id: &'static str,
    /// The problem, in words.
    pub label: &'static str,
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Start `(phi, theta1, theta2)` \[deg\].
    pub start_deg: [f64; 3],
    /// Goal `(phi, theta1, theta2)` \[deg\].
    pub goal_deg: [f64; 3],
    /// The tracked plan's effort `integral |u|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// The tracked plan's peak joint torque over its samples \[N m\].
    pub peak_torque: f64,
    /// The final error of the full dynamics under the planned torques alone, from rest \[rad\]
    /// (the torque level's certificate: open loop on the model itself).
    pub torque_final_error: f64,
    /// Each controller's summary, in [`Controller::ALL`]'s order.
    pub controllers: Vec<Summary>,
    /// Each controller's final errors \[rad\], sorted (a failed run is infinite): the figure's
    /// curves (not in `summary.json`, whose numbers are finite).
    #[serde(skip)]
    pub errors: Vec<Vec<f64>>,
}

/// One point of the torque curve: `adaptive` with every joint's torque saturated at `limit`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TorquePoint {
    /// `limit` over the plan's peak torque.
    pub fraction: f64,
    /// The saturation of every joint \[N m\].
    pub limit: f64,
    /// `adaptive`'s summary there.
    pub adaptive: Summary,
}

/// Fig. 20's numbers (`summary.json`'s `closed_loop`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosedLoop {
    /// Trials per controller and case.
    pub trials: usize,
    /// Trials per point of the torque curve ([`curve_trials`]).
    pub curve_trials: usize,
    /// The Monte Carlo's seed.
    pub seed: u64,
    /// Both problems.
    pub cases: Vec<ClosedLoopCase>,
    /// The curve on the paper's problem, one point per [`TORQUE_FRACTIONS`].
    pub torque_curve: Vec<TorquePoint>,
}

/// The arm, problem and plan of one of [`PROBLEMS`].
fn planned(p: &Problem) -> Result<(Arm, ChainProblem, ArmPlanned), Error> {
    let arm = Arm { mount: Mount::new(p.mount[0], p.mount[1])?, ..Arm::from_params(&RobotParams::src()) };
    let rad = |q: [f64; 3]| q.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    let problem = ChainProblem::rest_to_rest(rad(p.start_deg), rad(p.goal_deg), 10.0);
    // The velocity level is the tracked reference and must hold; the open-loop torques' own
    // certificate is reported (`torque_final_error`), not required: the controllers close the loop.
    let planned = plan_arm(&arm, Method::Optimal, &ArmRequest { torques: true, ..ArmRequest::new(problem.clone()) })?;
    ArmPlanned { torques: None, ..planned.clone() }.certified()?;
    Ok((arm, problem, planned))
}

fn sorted_errors(trials: &[crate::track::Trial], c: Controller) -> Vec<f64> {
    let mut e: Vec<f64> = trials
        .iter()
        .filter(|t| t.controller == c)
        .map(|t| if t.final_error.is_nan() { f64::INFINITY } else { t.final_error })
        .collect();
    e.sort_by(f64::total_cmp);
    e
}

/// Runs Fig. 20's Monte Carlo runs with `trials` each; `progress(what, seconds, status)` after
/// each of the `2 + TORQUE_FRACTIONS.len()` runs ([`closed_loop_jobs`]).
pub fn closed_loop(trials: usize, progress: &(dyn Fn(&str, f64, &str) + Sync)) -> Result<ClosedLoop, Error> {
    check_trials(trials)?;
    let (track, mc) = closed_loop_options(trials);
    let mut cases = Vec::new();
    let mut curve = Vec::new();
    for (k, p) in PROBLEMS.iter().enumerate() {
        let clock = std::time::Instant::now();
        let (arm, problem, planned) = planned(p)?;
        let peak = planned.torques.as_ref().map_or(f64::NAN, |t| t.max_abs_torque.iter().copied().fold(0.0, f64::max));
        let (all, summaries) = monte_carlo(&arm, &problem, &planned.plan, &track, &mc, &|| {})?;
        let rates: Vec<String> =
            summaries.iter().map(|s| format!("{} {:.0} %", s.controller.name(), 100.0 * s.success_rate)).collect();
        progress(
            &format!("{CLOSED_LOOP_FIGURE:<14} closed loop, {}", p.id),
            clock.elapsed().as_secs_f64(),
            &rates.join(", "),
        );
        cases.push(ClosedLoopCase {
            id: p.id,
            label: p.label,
            mount: p.mount,
            start_deg: p.start_deg,
            goal_deg: p.goal_deg,
            effort: planned.stats().map_or(f64::NAN, |s| s.effort),
            peak_torque: peak,
            torque_final_error: planned.torques.as_ref().map_or(f64::NAN, |t| t.certificate.final_error),
            errors: Controller::ALL.iter().map(|&c| sorted_errors(&all, c)).collect(),
            controllers: summaries,
        });
        if k > 0 {
            continue;
        }
        for fraction in TORQUE_FRACTIONS {
            let clock = std::time::Instant::now();
            let limit = fraction * peak;
            let saturated = TrackOptions {
                disturbances: Disturbances { torque_limit: limit, ..track.disturbances.clone() },
                ..track.clone()
            };
            let only = MonteCarloOptions {
                trials: curve_trials(trials),
                controllers: vec![Controller::Adaptive],
                ..mc.clone()
            };
            let (_, s) = monte_carlo(&arm, &problem, &planned.plan, &saturated, &only, &|| {})?;
            let what = format!("{CLOSED_LOOP_FIGURE:<14} torque limit {:.0} % of the peak", 100.0 * fraction);
            progress(&what, clock.elapsed().as_secs_f64(), &format!("adaptive {:.0} %", 100.0 * s[0].success_rate));
            curve.push(TorquePoint { fraction, limit, adaptive: s[0] });
        }
    }
    Ok(ClosedLoop { trials, curve_trials: curve_trials(trials), seed: mc.seed, cases, torque_curve: curve })
}

/// The number of progress calls of [`closed_loop`].
pub fn closed_loop_jobs() -> usize {
    PROBLEMS.len() + TORQUE_FRACTIONS.len()
}

/// The disturbances, in words.
const DISTURBANCES: &str = "5 % parameters, 1 cm mount, 1 % torque noise, 1e-5 rad and rad/s sensor noise, \
                            1 kHz, seed 1; success: final error ≤ 1e-3 rad";

/// Fig. 20: the quantiles of each controller's final error on both problems, the torque curve,
/// and the success rates in words.
pub fn closed_loop_figure(c: &ClosedLoop) -> PlanFigure {
    let threshold = || Bound { value: SUCCESS_TOLERANCE.log10(), label: "success: 1e-3 rad".into(), series: None };
    let mut panels: Vec<Panel> = c
        .cases
        .iter()
        .map(|case| Panel {
            title: format!("Final error, {}", case.label),
            x_label: "share of the trials [%]".into(),
            y_label: "log10 final error [rad]".into(),
            series: Controller::ALL
                .iter()
                .zip(&case.errors)
                .map(|(ctrl, e)| Series {
                    label: ctrl.name().into(),
                    points: e
                        .iter()
                        .enumerate()
                        .map(|(i, x)| (100.0 * (i as f64 + 0.5) / e.len() as f64, x.log10()))
                        .filter(|p| p.1.is_finite())
                        .collect(),
                })
                .collect(),
            bounds: vec![threshold()],
            ..Default::default()
        })
        .collect();
    panels.push(Panel {
        title: format!("adaptive under a torque limit, {}", PROBLEMS[0].label),
        x_label: "torque limit / plan's peak |τ|".into(),
        y_label: "success [%]".into(),
        series: vec![Series {
            label: "adaptive".into(),
            points: c.torque_curve.iter().map(|p| (p.fraction, 100.0 * p.adaptive.success_rate)).collect(),
        }],
        include_zero: true,
        bounds: vec![Bound { value: 95.0, label: "95 %".into(), series: None }],
        ..Default::default()
    });
    let mut text = vec![format!("{} trials per controller and case, the same trials for each:", c.trials)];
    for case in &c.cases {
        text.push(format!("{}:", case.label));
        let rates: Vec<String> = case
            .controllers
            .iter()
            .map(|s| format!("{} {:.1} %", s.controller.name(), 100.0 * s.success_rate))
            .collect();
        text.push(format!("  {}", rates.join(", ")));
    }
    panels.push(Panel { title: "Success rates".into(), text, ..Default::default() });
    PlanFigure {
        title: "Fig. 20 (beyond the paper): the plan in closed loop on perturbed robots".into(),
        panels,
        caption: vec![
            format!("Every trial: {DISTURBANCES}."),
            format!(
                "Quantiles: each controller's trials sorted by final error (a failed run is not drawn); the torque \
             limit saturates every joint (adaptive, {} trials a point).",
                c.curve_trials
            ),
        ],
    }
}

/// Fig. 20 in words (the page).
pub fn closed_loop_text(c: &ClosedLoop) -> String {
    format!(
        "Each plan tracked in closed loop on {} perturbed robots per controller ({DISTURBANCES}): open loop (the \
         planned torques alone), ct (computed torque with PD around the plan), replan (ct re-planning at 5 Hz on \
         the nominal model) and adaptive (replan on a model identified on line). Top: the final errors' \
         quantiles; bottom left: adaptive's success as a torque limit on every joint tightens below the plan's \
         peak ({} trials a point). `freefloat reproduce --trials 1000` runs the full version.",
        c.trials, c.curve_trials
    )
}

fn rows(c: &ClosedLoop) -> Vec<[String; 7]> {
    let e = |x: Option<f64>| x.map_or("-".to_string(), |x| super::numbers::scientific(x, 2));
    let row = |what: String, s: &Summary| {
        [
            what,
            s.controller.name().to_string(),
            format!("{:.1} %", 100.0 * s.success_rate),
            e(s.median_error),
            e(s.p95_error),
            e(s.max_error),
            format!("{}", s.replan_failures),
        ]
    };
    let mut out: Vec<[String; 7]> =
        c.cases.iter().flat_map(|case| case.controllers.iter().map(|s| row(case.label.to_string(), s))).collect();
    for p in &c.torque_curve {
        out.push(row(
            format!("torque limit {:.0} % of {:.3} N m", 100.0 * p.fraction, p.limit / p.fraction),
            &p.adaptive,
        ));
    }
    out
}

const HEADS: [&str; 7] =
    ["problem", "controller", "success", "median [rad]", "p95 [rad]", "max [rad]", "failed re-plans"];

/// The `closed loop` section of `summary.md`.
pub fn closed_loop_markdown(c: &ClosedLoop) -> String {
    let mut s = format!("\n## Closed loop (Fig. 20)\n\n{}\n\n", closed_loop_text(c));
    s += &format!("| {} |\n|{}\n", HEADS.join(" | "), " --- |".repeat(HEADS.len()));
    for r in rows(c) {
        s += &format!("| {} |\n", r.join(" | "));
    }
    s
}

/// The `closed loop` table of `report.html`.
pub fn closed_loop_html(c: &ClosedLoop) -> String {
    let mut s =
        format!("<p>{}</p>\n<div class=\"scroll\"><table>\n<tr>", escape(&closed_loop_text(c).replace('`', "")));
    for h in HEADS {
        s += &head_cell(h);
    }
    s += "</tr>\n";
    for r in rows(c) {
        s += "<tr>";
        for (k, cell) in r.iter().enumerate() {
            let class = if k < 2 { " class=\"left\"" } else { "" };
            s += &format!("<td{class}>{}</td>", escape(cell));
        }
        s += "</tr>\n";
    }
    s += "</table></div>\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::summarise;

    /// A trial count of 0 or over the Monte Carlo's bound is refused before any work.
    #[test]
    fn trial_counts_out_of_range_are_refused() {
        assert!(check_trials(1).is_ok() && check_trials(MAX_TRIALS).is_ok());
        for bad in [0, MAX_TRIALS + 1] {
            let e = check_trials(bad).expect_err("refused").to_string();
            assert!(e.contains("trials") && e.contains("Fig. 20"), "{e}");
        }
        assert_eq!((curve_trials(1), curve_trials(20), curve_trials(21)), (1, 10, 11));
    }

    /// The figure draws each controller's sorted errors as finite quantiles (a failed run, of
    /// infinite error, is left out, never drawn as a non-finite point), and its success panel
    /// says the summaries' rates.
    #[test]
    fn the_figure_draws_finite_quantiles_and_the_rates() {
        let trial = |i: usize, c: Controller, e: f64| crate::track::Trial {
            trial: i,
            controller: c,
            final_error: e,
            failure: (!e.is_finite()).then_some("diverged"),
            replans: 0,
            replan_failures: 0,
            clearance: None,
        };
        let errors = [1e-5, 2e-4, f64::INFINITY, 3e-3];
        let trials: Vec<_> = Controller::ALL
            .iter()
            .flat_map(|&c| errors.iter().enumerate().map(move |(i, &e)| trial(i, c, e)))
            .collect();
        let summaries = summarise(&Controller::ALL, &trials, SUCCESS_TOLERANCE);
        let case = ClosedLoopCase {
            id: "paper",
            label: PROBLEMS[0].label,
            mount: PROBLEMS[0].mount,
            start_deg: PROBLEMS[0].start_deg,
            goal_deg: PROBLEMS[0].goal_deg,
            effort: 1.0,
            peak_torque: 2.0,
            torque_final_error: 0.0,
            controllers: summaries.clone(),
            errors: Controller::ALL.iter().map(|&c| sorted_errors(&trials, c)).collect(),
        };
        let curve = vec![TorquePoint { fraction: 0.5, limit: 1.0, adaptive: summaries[3] }];
        let c = ClosedLoop { trials: 4, curve_trials: 2, seed: 1, cases: vec![case], torque_curve: curve };
        let figure = closed_loop_figure(&c);
        let quantiles = &figure.panels[0];
        assert_eq!(quantiles.series.len(), 4);
        for s in &quantiles.series {
            let finite = &s.points;
            assert!(finite.iter().all(|p| p.0.is_finite() && p.1.is_finite()), "{finite:?}");
            assert_eq!(finite.len(), 3, "the failed run is not drawn: {:?}", s.points);
            assert!(finite.windows(2).all(|w| w[0].0 < w[1].0 && w[0].1 <= w[1].1), "{:?}", s.points);
        }
        // 2 of 4 trials within 1e-3 rad.
        assert!(figure.panels.iter().any(|p| p.text.iter().any(|l| l.contains("adaptive 50.0 %"))));
        assert!(closed_loop_markdown(&c).contains("| 50.0 % |"));
    }
}
