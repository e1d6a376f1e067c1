//! `summary.json` and `summary.md`: one row per case, the domain table (Figs. 13-14) and the
//! mount sweep (Fig. 16), the paper's wall times beside ours.

use serde::Serialize;

use super::cases::{Case, CaseOutcome, PaperSeconds};
use crate::analysis::domain::{DomainMap, DomainSummary};
use crate::analysis::sweep::{Span, SweepOptions, SweepRow};
use crate::error::Error;
use crate::model::{Mount, RobotParams};
use crate::plan::{Method, PlanningProblem};
use crate::planners::nfa::NfaOptions;
use crate::planners::nfa::normal_form::Transform;
use crate::planners::{Planned, PlannerOptions, planner};
use crate::report::plot::DomainOverlay;

/// Wall time of each stage of a case \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StageSeconds {
    /// The velocity plan.
    pub plan: f64,
    /// Inverse dynamics at the samples.
    pub torques: f64,
    /// Verification of the velocity plan (integration of Eq. 7).
    pub verify: f64,
    /// The torque certificate (forward dynamics from rest).
    pub torque_verify: f64,
}

/// One row of `summary.json` / `summary.md`: one case. Numbers are `null` only for a case
/// without a plan (then `error` says why).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SummaryRow {
    /// The case's identifier.
    pub id: String,
    /// Its figure, if any.
    pub figure: Option<String>,
    /// `nfa` or `ecsa`.
    pub method: String,
    /// Transformation (NFA) or window (ECSA).
    pub variant: String,
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Verified final error of the velocity plan \[rad\].
    pub final_error: Option<f64>,
    /// Its tolerance \[rad\].
    pub tolerance: Option<f64>,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// Final error of the forward dynamics from rest under the planned torques \[rad\].
    pub torque_final_error: Option<f64>,
    /// Its tolerance \[rad\].
    pub torque_tolerance: Option<f64>,
    /// `torque_final_error <= torque_tolerance`.
    pub torque_certified: bool,
    /// `[max |u1|, max |u2|]` \[rad/s\].
    pub max_abs_u: Option<[f64; 2]>,
    /// `u(0)` \[rad/s\]: zero when the plan starts at rest.
    pub u_start: Option<[f64; 2]>,
    /// `[max |tau1|, max |tau2|]` [N m].
    pub max_abs_torque: Option<[f64; 2]>,
    /// ECSA iterations (`null` for the NFA).
    pub iterations: Option<usize>,
    /// Our wall time per stage.
    pub seconds: Option<StageSeconds>,
    /// The paper's reported wall times (Sec. 6), where it reports them.
    pub paper_seconds: Option<PaperSeconds>,
    /// Why there is no plan.
    pub error: Option<String>,
}

impl SummaryRow {
    /// The row of a case, planned or not.
    pub fn new(case: &Case, outcome: Result<&CaseOutcome, &Error>) -> Self {
        let mut row = Self {
            id: case.id.into(),
            figure: case.figure.map(Into::into),
            method: case.method_name().into(),
            variant: case.variant().into(),
            mount: [case.a, case.b],
            final_error: None,
            tolerance: None,
            certified: false,
            torque_final_error: None,
            torque_tolerance: None,
            torque_certified: false,
            max_abs_u: None,
            u_start: None,
            max_abs_torque: None,
            iterations: None,
            seconds: None,
            paper_seconds: case.paper_seconds(),
            error: None,
        };
        match outcome {
            Ok(o) => {
                let v = &o.plan.verification;
                let c = &o.torques.certificate;
                row.final_error = Some(v.final_error);
                row.tolerance = Some(v.tolerance);
                row.certified = v.certified;
                row.torque_final_error = Some(c.final_error);
                row.torque_tolerance = Some(c.tolerance);
                row.torque_certified = c.certified;
                row.max_abs_u = Some(o.plan.max_abs_u);
                row.u_start = o.plan.trajectory.dq.first().map(|dq| [dq[1], dq[2]]);
                row.max_abs_torque = Some(o.torques.max_abs_torque);
                row.iterations = o.plan.iterations;
                row.seconds = Some(StageSeconds {
                    plan: o.plan.seconds.plan,
                    torques: o.torques.seconds.torques,
                    verify: o.plan.seconds.verify,
                    torque_verify: o.torques.seconds.verify,
                });
            }
            Err(e) => row.error = Some(e.to_string()),
        }
        row
    }
}

/// The domain-map figures: `fig13` (a = b = 0.1, 0.2) and `fig14` (a = b = 0.3; a = 1, b = -1),
/// Eq. (14), as in the paper.
pub const DOMAIN_FIGURES: [(&str, [(f64, f64); 2]); 2] =
    [("fig13", [(0.1, 0.1), (0.2, 0.2)]), ("fig14", [(0.3, 0.3), (1.0, -1.0)])];

/// Grid of the domain maps of Figs. 13-14 (cells per side of the torus).
pub const DOMAIN_GRID: usize = 720;

/// One domain map of Figs. 13-14 with what its picture shows over it.
#[derive(Debug, Clone)]
pub struct DomainPanel {
    /// The map of Eq. (14).
    pub map: DomainMap,
    /// `q0`, `qd`, the Eq. (14) plan's path (when there is one) and a note.
    pub overlay: DomainOverlay,
    /// The summary row.
    pub row: DomainRow,
}

/// One row of the domain table: a map of Eq. (14) and the Eq. (14) plan across it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DomainRow {
    /// `fig13` or `fig14`.
    pub figure: String,
    /// The map's summary (components, start-component fraction, connection of `q0`, `qd`).
    #[serde(flatten)]
    pub summary: DomainSummary,
    /// Verified final error of the Eq. (14) plan from `q0` to `qd` \[rad\], when there is one.
    pub eq14_final_error: Option<f64>,
    /// Why there is no Eq. (14) plan.
    pub eq14_error: Option<String>,
    /// Wall time of the map \[s\].
    pub seconds: f64,
}

impl DomainRow {
    /// The Eq. (14) plan in words: its final error, or why there is none.
    pub fn plan_text(&self) -> String {
        match (self.eq14_final_error, &self.eq14_error) {
            (Some(x), _) => format!("final error {} rad", super::numbers::scientific(x, 2)),
            (None, Some(err)) => format!("none: {err}"),
            _ => "-".into(),
        }
    }
}

/// The domain map of Eq. (14) at `(a, b)` on the paper's problem, with the Eq. (14) plan's path.
pub fn domain_panel(figure: &str, a: f64, b: f64) -> Result<DomainPanel, Error> {
    let robot = RobotParams::src().with_mount(Mount::new(a, b)?)?;
    let problem = PlanningProblem::paper(robot);
    let clock = std::time::Instant::now();
    let map = DomainMap::new(&robot, Transform::Eq14, DOMAIN_GRID)?;
    let seconds = clock.elapsed().as_secs_f64();
    let summary = map.summary(&problem.start, &problem.goal);
    let options = PlannerOptions {
        nfa: NfaOptions { transform: Some(Transform::Eq14), ..Default::default() },
        ..Default::default()
    };
    let (final_error, error, path, note) = match planner(Method::Nfa, &options).plan(&problem) {
        Ok(Planned { plan, .. }) => {
            let e = plan.verification.final_error;
            let path = plan.trajectory.q.iter().map(|q| (q[1], q[2])).collect();
            (
                Some(e),
                None,
                Some(path),
                format!("Eq. (14) plan q0 -> qd: verified final error {} rad", super::numbers::scientific(e, 1)),
            )
        }
        Err(e) => {
            let note = format!(
                "no Eq. (14) plan q0 -> qd ({}); the global normal form plans it: Fig. 15",
                if summary.start_goal_connected { "planner failed" } else { "q0 and qd in different components" }
            );
            (None, Some(e.to_string()), None, note)
        }
    };
    let overlay = DomainOverlay { start: Some(problem.start), goal: Some(problem.goal), path, plan_note: Some(note) };
    let row = DomainRow { figure: figure.into(), summary, eq14_final_error: final_error, eq14_error: error, seconds };
    Ok(DomainPanel { map, overlay, row })
}

/// The coarse mounting-point sweep of Fig. 16: `a, b` in \[-0.5, 0.5\] m, 11 x 11 points,
/// domain grid 96, 40 random start/goal pairs per point (seed 0), 101 samples per plan.
pub fn sweep_options() -> SweepOptions {
    let span = Span { min: -0.5, max: 0.5, steps: 11 };
    SweepOptions { a: span, b: span, grid: 96, trials: 40, samples: 101, ..Default::default() }
}

/// The summary of Fig. 16.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepSummary {
    /// `fig16`.
    pub figure: String,
    /// Mounting points.
    pub points: usize,
    /// Values of `a` \[m\]: `[min, max]`, in `steps` steps.
    pub a: [f64; 2],
    /// Values of `b` \[m\]: `[min, max]`, in `steps` steps.
    pub b: [f64; 2],
    /// Values per axis.
    pub steps: usize,
    /// Grid of each domain map.
    pub grid: usize,
    /// Random start/goal pairs per point.
    pub trials: usize,
    /// The best point `(a, b)` \[m\] and its success rate (best transformation).
    pub best: Option<(f64, f64, f64)>,
    /// Mean over the points of the best success rate.
    pub mean_rate: f64,
    /// Share of the points where the paper's `q0` and `qd` lie in one component of Eq. (14).
    pub connected_share: f64,
    /// Wall time \[s\].
    pub seconds: f64,
}

impl SweepSummary {
    /// The summary of `rows` computed with `options` in `seconds`.
    pub fn new(options: &SweepOptions, rows: &[SweepRow], seconds: f64) -> Self {
        let n = rows.len().max(1) as f64;
        Self {
            figure: "fig16".into(),
            points: rows.len(),
            a: [options.a.min, options.a.max],
            b: [options.b.min, options.b.max],
            steps: options.a.steps,
            grid: options.grid,
            trials: options.trials,
            best: crate::analysis::sweep::best(rows).map(|r| (r.a, r.b, r.best_rate().unwrap_or(0.0))),
            mean_rate: rows.iter().filter_map(SweepRow::best_rate).sum::<f64>() / n,
            connected_share: rows.iter().filter(|r| r.start_goal_connected == Some(true)).count() as f64 / n,
            seconds,
        }
    }
}

pub(super) fn fmt_pair(x: [f64; 2], digits: usize) -> String {
    format!("{:.digits$}, {:.digits$}", x[0], x[1])
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "**NO**" }
}

/// `summary.md`: the case table, the domain table and the sweep, with the paper's times beside
/// ours.
pub fn summary_markdown(rows: &[SummaryRow], domains: &[DomainRow], sweep: Option<&SweepSummary>) -> String {
    let mut s = String::from("# freefloat reproduce: summary\n\n");
    s += "The paper's problem: q0 = (45, 120, 80) deg -> qd = (0, 180, 140) deg, T = 10 s, 1001 samples. ";
    s += "Velocity level certified when the verified final error (integration of Eq. 7) is <= 1e-9 rad; ";
    s += "torque level when the forward dynamics from rest under the planned torques ends within 1e-6 rad. ";
    s += "Times are wall times of this run; the paper's (Sec. 6, i7-6700HQ) are beside them.\n\n";
    s += "| case | method | a, b [m] | final error [rad] | certified | torque final error [rad] | torque certified \
          | peak \\|u1\\|, \\|u2\\| [rad/s] | u(0) [rad/s] | peak \\|tau1\\|, \\|tau2\\| [N m] | iterations \
          | plan [ms] | torques [ms] | verify [ms] | torque cert. [ms] | paper: plan / torques [s] |\n";
    s += &format!("|{}\n", "---|".repeat(16));
    let e = |x: Option<f64>| x.map_or("-".to_string(), |x| super::numbers::scientific(x, 2));
    let p = |x: Option<[f64; 2]>, d| x.map_or("-".to_string(), |x| fmt_pair(x, d));
    for r in rows {
        let ms = |f: fn(&StageSeconds) -> f64| r.seconds.as_ref().map_or("-".into(), |t| format!("{:.2}", f(t) * 1e3));
        s += &format!(
            "| {} | {} {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.id,
            r.method.to_uppercase(),
            r.variant,
            fmt_pair(r.mount, 1),
            e(r.final_error),
            yes_no(r.certified),
            e(r.torque_final_error),
            yes_no(r.torque_certified),
            p(r.max_abs_u, 4),
            p(r.u_start, 4),
            p(r.max_abs_torque, 4),
            r.iterations.map_or("-".into(), |i| i.to_string()),
            ms(|t| t.plan),
            ms(|t| t.torques),
            ms(|t| t.verify),
            ms(|t| t.torque_verify),
            r.paper_seconds.map_or("-".into(), |t| format!("{} / {}", t.plan, t.torques)),
        );
    }
    for r in rows.iter().filter(|r| r.error.is_some()) {
        s += &format!("\n{}: no plan: {}\n", r.id, r.error.as_deref().unwrap_or_default());
    }
    s += "\nNotes: the ECSA's plain series (Figs. 9-12) does not start at rest (u(0) != 0), so the forward \
          dynamics from rest cannot follow it: its torque level is not certified. The sin^2-windowed ECSA starts \
          and ends at rest. Fig. 15 (a = 1, b = -1, global normal form with band steering) is certified at the \
          velocity level; its open-loop torque plan is ill-conditioned (large, fast joint loops) and is not \
          certified at the torque level.\n";
    s += &format!("\n## Domains of Eq. (14) (Figs. 13-14), grid {DOMAIN_GRID} x {DOMAIN_GRID}\n\n");
    s += "| figure | a, b [m] | components | start-component fraction | q0, qd connected | Eq. (14) plan |\n";
    s += "|---|---|---|---|---|---|\n";
    for d in domains {
        s += &format!(
            "| {} | {} | {} | {:.2} % | {} | {} |\n",
            d.figure,
            fmt_pair(d.summary.mount, 1),
            d.summary.components,
            100.0 * d.summary.start_component_fraction,
            if d.summary.start_goal_connected { "yes" } else { "no" },
            d.plan_text()
        );
    }
    if let Some(w) = sweep {
        s += &format!(
            "\n## Mounting points (Fig. 16)\n\n{} points, a, b in [{}, {}] m, domain grid {}, {} random start/goal \
             pairs per point: mean best NFA success rate {:.1} %, q0 and qd connected by Eq. (14) at {:.1} % of the \
             points{} ({:.2} s).\n",
            w.points,
            w.a[0],
            w.a[1],
            w.grid,
            w.trials,
            100.0 * w.mean_rate,
            100.0 * w.connected_share,
            w.best
                .map_or(String::new(), |(a, b, r)| format!(", best a = {a:.2} m, b = {b:.2} m at {:.0} %", 100.0 * r)),
            w.seconds
        );
    }
    s
}
