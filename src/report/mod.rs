//! The paper's results of Sec. 5 (Figs. 4-14), and two beyond it (Figs. 15-16), as plans,
//! figures, a summary and a self-contained report page: what `freefloat reproduce` writes.
//!
//! Every number here is computed by the planners on the paper's problem
//! ([`PlanningProblem::paper`]): nothing is copied from the paper except its reported wall
//! times ([`PaperSeconds`]), shown beside ours.
//!
//! ```
//! use freefloat::report::cases;
//!
//! let case = cases().into_iter().find(|c| c.id == "fig06").expect("Fig. 6 is a case");
//! let outcome = case.run().expect("the paper's case has a plan");
//! assert!(outcome.plan.verification.final_error <= 1e-9);
//! assert!(outcome.torques.certificate.certified);
//! ```

pub mod html;
pub mod io;
pub mod plot;

use serde::Serialize;

use crate::analysis::domain::{DomainMap, DomainSummary};
use crate::analysis::sweep::{Span, SweepOptions, SweepRow};
use crate::error::Error;
use crate::model::{Configuration, Mount, RobotParams};
use crate::plan::{Method, Plan, PlanningProblem, TorqueOptions, TorqueReport};
use crate::planners::ecsa::{EcsaOptions, EcsaSolution, Window};
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::{NfaDetails, NfaOptions};
use crate::planners::{Details, Planned, PlannerOptions, planner};
use crate::report::plot::{DomainOverlay, Panel, PlanFigure, Series};

/// How a case is planned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseMethod {
    /// The Normal Form Approach with this feedback transformation.
    Nfa(Transform),
    /// The ECSA (one harmonic, as in the paper) with this window of the controls.
    Ecsa(Window),
}

/// One planning case of the report: the paper's problem at a mounting point, by one method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// Short identifier, e.g. `fig06` or `ecsa-sin2-0.1`.
    pub id: &'static str,
    /// The figure that shows it (`fig04` ... `fig12`, `fig15`), if any.
    pub figure: Option<&'static str>,
    /// Mounting point `a` \[m\].
    pub a: f64,
    /// Mounting point `b` \[m\].
    pub b: f64,
    /// The method.
    pub method: CaseMethod,
}

/// The paper's reported wall times (Sec. 6; i7-6700HQ, "moderately optimized" code) \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PaperSeconds {
    /// Velocity level: the controls `u(t)`.
    pub plan: f64,
    /// The extra time for the torques.
    pub torques: f64,
}

/// Every case of the report: Figs. 4-8 (NFA), Figs. 9-12 (ECSA, the paper's plain series), the
/// ECSA with the `sin^2` window at the same mounting points (beyond the paper: starts and ends at
/// rest, so its torques can be certified from rest), and Fig. 15, the global normal form at
/// `a = 1, b = -1` (beyond the paper: the case the paper calls impossible).
pub fn cases() -> Vec<Case> {
    use CaseMethod::{Ecsa, Nfa};
    let case = |id, figure, a, b, method| Case { id, figure, a, b, method };
    vec![
        case("fig04", Some("fig04"), 0.0, 0.0, Nfa(Transform::Eq11)),
        case("fig05", Some("fig05"), 0.0, 0.0, Nfa(Transform::Eq12)),
        case("fig06", Some("fig06"), 0.1, 0.1, Nfa(Transform::Eq14)),
        case("fig07", Some("fig07"), 0.2, 0.2, Nfa(Transform::Eq14)),
        case("fig08", Some("fig08"), 0.3, 0.3, Nfa(Transform::Eq14)),
        case("fig09", Some("fig09"), 0.0, 0.0, Ecsa(Window::None)),
        case("fig10", Some("fig10"), 0.1, 0.1, Ecsa(Window::None)),
        case("fig11", Some("fig11"), 0.2, 0.2, Ecsa(Window::None)),
        case("fig12", Some("fig12"), 0.3, 0.3, Ecsa(Window::None)),
        case("ecsa-sin2-0.0", None, 0.0, 0.0, Ecsa(Window::SinSquared)),
        case("ecsa-sin2-0.1", None, 0.1, 0.1, Ecsa(Window::SinSquared)),
        case("ecsa-sin2-0.2", None, 0.2, 0.2, Ecsa(Window::SinSquared)),
        case("ecsa-sin2-0.3", None, 0.3, 0.3, Ecsa(Window::SinSquared)),
        case("fig15", Some("fig15"), 1.0, -1.0, Nfa(Transform::Global)),
    ]
}

/// A planned case: the plan (torques in its trajectory), its torque report and, for the ECSA,
/// the solution of the iteration.
#[derive(Debug, Clone)]
pub struct CaseOutcome {
    /// The case.
    pub case: Case,
    /// The velocity plan with `trajectory.tau` filled and its verification.
    pub plan: Plan,
    /// The torque level: peaks and the forward-dynamics certificate.
    pub torques: TorqueReport,
    /// The ECSA's solution (ECSA only).
    pub ecsa: Option<EcsaSolution>,
    /// The NFA's transformation, chained-form ends and steering (NFA only).
    pub nfa: Option<NfaDetails>,
}

impl Case {
    /// The robot: the paper's SRC manipulator at this mounting point.
    pub fn robot(&self) -> Result<RobotParams, Error> {
        Ok(RobotParams::src().with_mount(Mount::new(self.a, self.b)?)?)
    }

    /// The paper's problem for this robot.
    pub fn problem(&self) -> Result<PlanningProblem, Error> {
        Ok(PlanningProblem::paper(self.robot()?))
    }

    /// `nfa` or `ecsa`.
    pub fn method_name(&self) -> &'static str {
        match self.method {
            CaseMethod::Nfa(_) => "nfa",
            CaseMethod::Ecsa(_) => "ecsa",
        }
    }

    /// The transformation (NFA) or the window (ECSA) by name.
    pub fn variant(&self) -> &'static str {
        match self.method {
            CaseMethod::Nfa(t) => t.name(),
            CaseMethod::Ecsa(w) => w.name(),
        }
    }

    /// A one-line title, e.g. `Fig. 6: NFA with feedback (14), a = b = 0.1 m`.
    pub fn title(&self) -> String {
        let mount = if (self.a - self.b).abs() < 1e-12 {
            format!("a = b = {} m", self.a)
        } else {
            format!("a = {} m, b = {} m", self.a, self.b)
        };
        let method = match self.method {
            CaseMethod::Nfa(Transform::Global) => "NFA with the global normal form (beyond the paper)".to_string(),
            CaseMethod::Nfa(t) => format!("NFA with feedback ({})", &t.name()[2..]),
            CaseMethod::Ecsa(Window::None) => "ECSA (the paper's trigonometric controls)".to_string(),
            CaseMethod::Ecsa(Window::SinSquared) => "ECSA with the sin^2 window (beyond the paper)".to_string(),
        };
        match self.figure {
            Some(f) => format!("Fig. {}: {method}, {mount}", f.trim_start_matches("fig").trim_start_matches('0')),
            None => format!("{method}, {mount}"),
        }
    }

    /// The paper's reported wall times for this kind of case (Sec. 6), if it reports any.
    pub fn paper_seconds(&self) -> Option<PaperSeconds> {
        match self.method {
            CaseMethod::Nfa(Transform::Global) => None,
            CaseMethod::Nfa(_) if self.a == 0.0 && self.b == 0.0 => Some(PaperSeconds { plan: 0.2, torques: 0.15 }),
            CaseMethod::Nfa(_) => Some(PaperSeconds { plan: 1.3, torques: 0.4 }),
            CaseMethod::Ecsa(Window::None) => Some(PaperSeconds { plan: 1.5, torques: 0.5 }),
            CaseMethod::Ecsa(_) => None,
        }
    }

    /// Plans the case (1001 samples, accelerations on), verifies it, and adds the torque level
    /// with its forward-dynamics certificate (tolerance 1e-6 rad).
    pub fn run(&self) -> Result<CaseOutcome, Error> {
        let problem = self.problem()?;
        let mut options = PlannerOptions::default();
        let method = match self.method {
            CaseMethod::Nfa(transform) => {
                options.nfa = NfaOptions { transform: Some(transform), accelerations: true, ..Default::default() };
                Method::Nfa
            }
            CaseMethod::Ecsa(window) => {
                options.ecsa = EcsaOptions::default().with_window(window);
                Method::Ecsa
            }
        };
        let mut planned = planner(method, &options).plan(&problem)?;
        let torques = planned.add_torques(&TorqueOptions::default())?;
        let (nfa, ecsa) = match planned.details {
            Details::Nfa(details) => (Some(details), None),
            Details::Ecsa(solution) => (None, Some(solution)),
        };
        Ok(CaseOutcome { case: *self, plan: planned.plan, torques, ecsa, nfa })
    }
}

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
            (Some(x), _) => format!("final error {x:.2e} rad"),
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
            (Some(e), None, Some(path), format!("Eq. (14) plan q0 -> qd: verified final error {e:.1e} rad"))
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
            best: crate::analysis::sweep::best(rows).map(|r| (r.a, r.b, r.best_rate())),
            mean_rate: rows.iter().map(SweepRow::best_rate).sum::<f64>() / n,
            connected_share: rows.iter().filter(|r| r.start_goal_connected).count() as f64 / n,
            seconds,
        }
    }
}

fn fmt_pair(x: [f64; 2], digits: usize) -> String {
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
    let e = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.2e}"));
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

/// The four panels of a plan figure (as in the paper's Figs. 4-12), and a caption with both
/// certificates.
pub fn plan_figure(o: &CaseOutcome) -> PlanFigure {
    let tr = &o.plan.trajectory;
    let t = &tr.t;
    let column = |f: &dyn Fn(usize) -> f64| t.iter().enumerate().map(|(i, &t)| (t, f(i))).collect::<Vec<_>>();
    let series = |label: &str, f: &dyn Fn(usize) -> f64| Series { label: label.into(), points: column(f) };
    let x_label = "t [s]".to_string();
    let angles = Panel {
        title: "Base orientation and joint positions".into(),
        x_label: x_label.clone(),
        y_label: "angle [deg]".into(),
        series: vec![
            series("φ", &|i| tr.q[i][0].to_degrees()),
            series("θ1", &|i| tr.q[i][1].to_degrees()),
            series("θ2", &|i| tr.q[i][2].to_degrees()),
        ],
        text: vec![],
    };
    let second = match (&tr.z, &o.ecsa) {
        (Some(z), _) => Panel {
            title: format!("Normal-form variables z ({})", o.case.variant()),
            x_label: x_label.clone(),
            y_label: "z".into(),
            series: (0..3).map(|k| series(&format!("z{}", k + 1), &|i| z[i][k])).collect(),
            text: vec![],
        },
        (None, Some(s)) => Panel {
            title: "ECSA iteration".into(),
            text: vec![
                format!("Jacobian pseudo-inverse iterations: {}", s.stats.iterations),
                format!("end-point residual: {:.2e} rad", s.stats.residual),
                format!("controls: constant + {} harmonic(s), window {}", s.basis.harmonics(), o.case.variant()),
                "no normal form: no z variables".into(),
            ],
            ..Default::default()
        },
        _ => Panel { title: "(no z)".into(), ..Default::default() },
    };
    let controls = Panel {
        title: "Velocity controls u".into(),
        x_label: x_label.clone(),
        y_label: "u [rad/s]".into(),
        series: vec![series("u1 = θ1'", &|i| tr.dq[i][1]), series("u2 = θ2'", &|i| tr.dq[i][2])],
        text: vec![],
    };
    let torques = match &tr.tau {
        Some(tau) => Panel {
            title: "Joint torques τ".into(),
            x_label,
            y_label: "τ [N m]".into(),
            series: vec![series("τ1", &|i| tau[i][0]), series("τ2", &|i| tau[i][1])],
            text: vec![],
        },
        None => Panel { title: "(no torques)".into(), ..Default::default() },
    };
    let v = &o.plan.verification;
    let c = &o.torques.certificate;
    let verdict = |ok: bool| if ok { "certified" } else { "NOT certified" };
    let mut caption = vec![
        format!(
            "velocity level: verified final error {:.2e} rad (tolerance {:.0e}): {};  peak |u1|, |u2| = {} rad/s",
            v.final_error,
            v.tolerance,
            verdict(v.certified),
            fmt_pair(o.plan.max_abs_u, 4)
        ),
        format!(
            "torque level: forward dynamics from rest, final error {:.2e} rad (tolerance {:.0e}): {};  \
             peak |τ1|, |τ2| = {} N m",
            c.final_error,
            c.tolerance,
            verdict(c.certified),
            fmt_pair(o.torques.max_abs_torque, 4)
        ),
    ];
    if let Some(dq) = tr.dq.first().filter(|dq| dq[1].abs().max(dq[2].abs()) > 1e-9) {
        caption.push(format!(
            "u(0) = ({:.4}, {:.4}) rad/s: the plan does not start at rest, so the torque plan (from rest) cannot follow it",
            dq[1], dq[2]
        ));
    }
    if let Some(b) = o.nfa.and_then(|d| d.band) {
        caption.push(format!(
            "band steering: {} loops of amplitude {:.2} rad; the open-loop torque plan of such fast loops is ill-conditioned",
            b.loops, b.amplitude
        ));
    }
    PlanFigure { title: o.case.title(), panels: vec![angles, second, controls, torques], caption }
}

/// Where the robot's bodies are in the plane for a configuration \[m\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pose {
    /// Centre of mass of the base.
    pub base: [f64; 2],
    /// The mounting point (joint 1).
    pub joint1: [f64; 2],
    /// Joint 2 (the elbow).
    pub joint2: [f64; 2],
    /// The end of link 2 (the end-effector).
    pub tip: [f64; 2],
}

/// The pose of `robot` at `q`, with the system's centre of mass at the origin: Eq. (4) with zero
/// linear momentum (`p1 = p2 = 0`) keeps it there. The base's centre of mass `r_b` solves
/// `M r_b + m1 r_1 + m2 r_2 = 0`, where `r_1`, `r_2` are the links' centres of mass; link 1
/// points at the absolute angle `phi + theta1`, link 2 at `phi + theta1 + theta2` (Eq. 3).
pub fn pose(robot: &RobotParams, q: &Configuration) -> Pose {
    let RobotParams { l1, l2, d1, d2, base_mass, m1, m2, mount, .. } = *robot;
    let (sp, cp) = q.phi.sin_cos();
    let (s1, c1) = (q.phi + q.theta1).sin_cos();
    let (s12, c12) = (q.phi + q.theta1 + q.theta2).sin_cos();
    let mount_offset = [cp * mount.a - sp * mount.b, sp * mount.a + cp * mount.b];
    let mc = base_mass + m1 + m2;
    let base: [f64; 2] = std::array::from_fn(|i| {
        let (e1, e12) = if i == 0 { (c1, c12) } else { (s1, s12) };
        -((m1 + m2) * mount_offset[i] + (m1 * d1 + m2 * l1) * e1 + m2 * d2 * e12) / mc
    });
    let joint1 = [base[0] + mount_offset[0], base[1] + mount_offset[1]];
    let joint2 = [joint1[0] + l1 * c1, joint1[1] + l1 * s1];
    let tip = [joint2[0] + l2 * c12, joint2[1] + l2 * s12];
    Pose { base, joint1, joint2, tip }
}

/// Side lengths of the base rectangle drawn by the animation \[m\] (illustrative: the paper
/// gives the base's mass and inertia, not its shape).
pub const BASE_SIZE: [f64; 2] = [0.6, 0.5];

/// The animation data of a plan: poses at up to 501 of its samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Animation {
    /// The case's identifier.
    pub id: String,
    /// Its title.
    pub title: String,
    /// Mounting point `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Base rectangle \[m\] ([`BASE_SIZE`]).
    pub base_size: [f64; 2],
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Base orientation `phi` \[rad\] at each time.
    pub phi: Vec<f64>,
    /// Flattened poses: `[base x, base y, joint1 x, y, joint2 x, y, tip x, y]` per time \[m\].
    pub points: Vec<[f64; 8]>,
}

/// The animation of a planned case.
pub fn animation(o: &CaseOutcome) -> Animation {
    let tr = &o.plan.trajectory;
    let n = tr.t.len();
    let step = n.div_ceil(501).max(1);
    let mut indices: Vec<usize> = (0..n).step_by(step).collect();
    if n > 0 && indices.last() != Some(&(n - 1)) {
        indices.push(n - 1);
    }
    let round = |x: f64| (x * 1e5).round() / 1e5;
    let robot = &o.plan.problem.robot;
    let points = indices
        .iter()
        .map(|&i| {
            let p = pose(robot, &Configuration::from_array(tr.q[i]));
            [p.base, p.joint1, p.joint2, p.tip].concat().try_into().map(|a: [f64; 8]| a.map(round)).unwrap_or([0.0; 8])
        })
        .collect();
    Animation {
        id: o.case.id.into(),
        title: o.case.title(),
        mount: [robot.mount.a, robot.mount.b],
        base_size: BASE_SIZE,
        t: indices.iter().map(|&i| round(tr.t[i])).collect(),
        phi: indices.iter().map(|&i| round(tr.q[i][0])).collect(),
        points,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pose keeps the system's centre of mass at the origin and the links at their lengths.
    #[test]
    fn pose_has_the_centre_of_mass_at_the_origin() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        for q in [[0.3, 2.0, 1.4], [-1.0, 0.2, -2.5], [4.0, -3.0, 0.7]] {
            let p = pose(&robot, &Configuration::from_array(q));
            let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
            assert!((dist(p.joint1, p.joint2) - robot.l1).abs() < 1e-12);
            assert!((dist(p.joint2, p.tip) - robot.l2).abs() < 1e-12);
            assert!((dist(p.base, p.joint1) - 2f64.sqrt()).abs() < 1e-12);
            let at = |a: [f64; 2], b: [f64; 2], f: f64| [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])];
            let r1 = at(p.joint1, p.joint2, robot.d1 / robot.l1);
            let r2 = at(p.joint2, p.tip, robot.d2 / robot.l2);
            for i in 0..2 {
                let com = robot.base_mass * p.base[i] + robot.m1 * r1[i] + robot.m2 * r2[i];
                assert!(com.abs() < 1e-12, "{com}");
            }
        }
    }

    /// Every case's title names its figure and mounting point; the paper's times go with the
    /// paper's cases only.
    #[test]
    fn titles_and_paper_times() {
        let all = cases();
        assert_eq!(all.iter().filter(|c| c.figure.is_some()).count(), 10);
        let fig06 = all.iter().find(|c| c.id == "fig06").unwrap();
        assert_eq!(fig06.title(), "Fig. 6: NFA with feedback (14), a = b = 0.1 m");
        assert_eq!(fig06.paper_seconds(), Some(PaperSeconds { plan: 1.3, torques: 0.4 }));
        let fig15 = all.iter().find(|c| c.id == "fig15").unwrap();
        assert!(fig15.title().contains("a = 1 m, b = -1 m"));
        assert_eq!(fig15.paper_seconds(), None);
    }
}
