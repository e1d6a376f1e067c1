//! The three methods side by side (issue 11, item 4): the minimum-effort planner, the NFA and the
//! ECSA on the paper's problem at the paper's mounting points and at `a = 1, b = -1`, each with its
//! effort, peaks, both certificates and times: `summary.*`'s `methods` table and Fig. 17.

use serde::Serialize;

use super::html::{escape, head_cell};
use crate::error::Error;
use crate::model::{Mount, RobotParams};
use crate::plan::{Method, PlanningProblem, TorqueOptions};
use crate::planners::{PlannerOptions, planner};

/// The mounting points `(a, b)` \[m\] compared: the paper's four and the one it calls impossible.
pub const METHOD_MOUNTS: [(f64, f64); 5] = [(0.0, 0.0), (0.1, 0.1), (0.2, 0.2), (0.3, 0.3), (1.0, -1.0)];

/// The methods compared, in the table's order.
pub const COMPARED_METHODS: [Method; 3] = [Method::Optimal, Method::Nfa, Method::Ecsa];

/// One row of the `methods` table: one method at one mounting point, with its default options
/// (the NFA's `auto` transformation, the ECSA's plain series). Numbers are `null` only without a
/// plan (then `error` says why).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodRow {
    /// `optimal`, `nfa` or `ecsa`.
    pub method: String,
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// The control effort `integral_0^T |u|^2 dt` \[rad^2/s\].
    pub effort: Option<f64>,
    /// `[max |u1|, max |u2|]` \[rad/s\].
    pub max_abs_u: Option<[f64; 2]>,
    /// `[max |tau1|, max |tau2|]` \[N m\].
    pub max_abs_torque: Option<[f64; 2]>,
    /// Verified final error of the velocity plan \[rad\].
    pub final_error: Option<f64>,
    /// The velocity-level certificate holds.
    pub certified: bool,
    /// Final error of the forward dynamics under the planned torques \[rad\].
    pub torque_final_error: Option<f64>,
    /// The torque-level certificate holds.
    pub torque_certified: bool,
    /// Wall time per stage \[s\]: `[plan, verify, torques, torque certificate]`.
    pub seconds: Option<[f64; 4]>,
    /// Why there is no plan.
    pub error: Option<String>,
}

impl MethodRow {
    /// Plans the paper's problem at `(a, b)` with `method` through [`planner`], with its default
    /// options, and adds the torque level.
    pub fn run(method: Method, (a, b): (f64, f64)) -> Self {
        let mut row = Self {
            method: method.name().into(),
            mount: [a, b],
            effort: None,
            max_abs_u: None,
            max_abs_torque: None,
            final_error: None,
            certified: false,
            torque_final_error: None,
            torque_certified: false,
            seconds: None,
            error: None,
        };
        let planned = || -> Result<_, Error> {
            let robot = RobotParams::src().with_mount(Mount::new(a, b)?)?;
            let mut planned = planner(method, &PlannerOptions::default()).plan(&PlanningProblem::paper(robot))?;
            let torques = planned.add_torques(&TorqueOptions::default())?;
            Ok((planned.plan, torques))
        };
        match planned() {
            Ok((plan, torques)) => {
                let (v, c) = (&plan.verification, &torques.certificate);
                row.effort = Some(plan.effort);
                row.max_abs_u = Some(plan.max_abs_u);
                row.max_abs_torque = Some(torques.max_abs_torque);
                row.final_error = Some(v.final_error);
                row.certified = v.certified;
                row.torque_final_error = Some(c.final_error);
                row.torque_certified = c.certified;
                row.seconds =
                    Some([plan.seconds.plan, plan.seconds.verify, torques.seconds.torques, torques.seconds.verify]);
            }
            Err(e) => row.error = Some(e.to_string()),
        }
        row
    }

    /// `max(|u1|, |u2|)` \[rad/s\].
    pub fn peak_u(&self) -> Option<f64> {
        self.max_abs_u.map(|u| u[0].max(u[1]))
    }

    /// `max(|tau1|, |tau2|)` \[N m\].
    pub fn peak_torque(&self) -> Option<f64> {
        self.max_abs_torque.map(|t| t[0].max(t[1]))
    }
}

/// Every `(method, mount)` job of the table: [`COMPARED_METHODS`] at each of [`METHOD_MOUNTS`].
pub fn method_jobs() -> Vec<(Method, (f64, f64))> {
    METHOD_MOUNTS.iter().flat_map(|&m| COMPARED_METHODS.iter().map(move |&method| (method, m))).collect()
}

fn cells(r: &MethodRow) -> [String; 9] {
    let e = |x: Option<f64>| x.map_or("-".to_string(), |x| super::numbers::scientific(x, 2));
    let g = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.4}"));
    let yes = |ok: bool| if ok { "yes" } else { "NO" }.to_string();
    let ms = |k: usize| r.seconds.map_or("-".to_string(), |s| format!("{:.1}", s[k] * 1e3));
    [
        g(r.effort),
        g(r.peak_u()),
        g(r.peak_torque()),
        format!("{} ({})", e(r.final_error), yes(r.certified)),
        format!("{} ({})", e(r.torque_final_error), yes(r.torque_certified)),
        ms(0),
        ms(1),
        ms(2),
        ms(3),
    ]
}

const HEADS: [&str; 11] = [
    "a, b [m]",
    "method",
    "effort [rad²/s]",
    "peak |u| [rad/s]",
    "peak |τ| [N m]",
    "final error [rad] (≤ 1e-9)",
    "torque final error [rad] (≤ 1e-6)",
    "plan [ms]",
    "verify [ms]",
    "torques [ms]",
    "torque cert. [ms]",
];

/// The `methods` section of `summary.md`.
pub fn methods_markdown(rows: &[MethodRow]) -> String {
    let mut s = String::from(
        "\n## Three methods (Fig. 17)\n\nThe paper's problem by the minimum-effort planner, the NFA (`auto`: Eq. (12) \
         or (14), else the global normal form) and the ECSA (plain series), default options; peaks are the \
         motion's, effort is the integral of |u|² dt.\n\n",
    );
    let heads: Vec<String> = HEADS.iter().map(|h| h.replace('|', "\\|")).collect();
    s += &format!("| {} |\n|{}\n", heads.join(" | "), " --- |".repeat(HEADS.len()));
    for r in rows {
        s += &format!("| {}, {} | {} | {} |\n", r.mount[0], r.mount[1], r.method, cells(r).join(" | "));
        if let Some(err) = &r.error {
            s += &format!("| | {}: no plan: {} |\n", r.method, err.replace('|', "/"));
        }
    }
    s
}

/// The `methods` table of `report.html`.
pub fn methods_html(rows: &[MethodRow]) -> String {
    let mut s = String::from("<div class=\"scroll\"><table>\n<tr>");
    for h in HEADS {
        s += &head_cell(h);
    }
    s += "</tr>\n";
    for r in rows {
        s += &format!(
            "<tr><td>{}, {}</td><td class=\"left\">{}</td>",
            r.mount[0],
            r.mount[1],
            escape(&r.method.to_uppercase())
        );
        for c in cells(r) {
            s += &format!("<td>{}</td>", escape(&c));
        }
        s += "</tr>\n";
        if let Some(err) = &r.error {
            s +=
                &format!("<tr><td class=\"left no\" colspan=\"11\">{}: no plan: {}</td></tr>\n", r.method, escape(err));
        }
    }
    s += "</table></div>\n";
    s
}
