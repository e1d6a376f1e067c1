//! The cases of the report: the paper's problem at a mounting point, by one method (Figs. 4-12,
//! 15), planned through the [`crate::Planner`] trait with the torque level.

use serde::Serialize;

use crate::error::Error;
use crate::model::{Mount, RobotParams};
use crate::plan::{Method, Plan, PlanningProblem, TorqueOptions, TorqueReport};
use crate::planners::ecsa::{EcsaOptions, EcsaSolution, Window};
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::{NfaDetails, NfaOptions};
use crate::planners::{Details, PlannerOptions, planner};

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
            Details::Optimal(_) => (None, None),
        };
        Ok(CaseOutcome { case: *self, plan: planned.plan, torques, ecsa, nfa })
    }
}

/// What a figure shows, in words, with the verdict of its certificates.
pub fn description(outcome: &CaseOutcome) -> String {
    let case = &outcome.case;
    let title = case.title();
    let paper = title.split(':').next().unwrap_or_default();
    let verdict = match (outcome.plan.verification.certified, outcome.torques.certificate.certified) {
        (true, true) => "Both levels certified.",
        (true, false) => "Certified at the velocity level, not at the torque level (see the caption).",
        (false, _) => "NOT certified at the velocity level (see the caption).",
    };
    match case.method {
        CaseMethod::Nfa(Transform::Global) => format!(
            "Beyond the paper: a = 1 m, b = -1 m, where the paper calls the NFA impossible (q0 and qd lie in \
             different components of the domain of Eq. (14), Fig. 14 right). The global normal form plans it with \
             band steering; the open-loop torque plan of such fast loops is ill-conditioned. {verdict}"
        ),
        CaseMethod::Nfa(_) => format!(
            "As the paper's {paper}: base orientation and joint positions; normal-form variables z; velocity \
             controls u; torques τ from the inverse dynamics (6). {verdict}"
        ),
        CaseMethod::Ecsa(_) if case.figure.is_none() => format!(
            "Beyond the paper, no figure: the ECSA's controls times sin²(πt/T), so that the plan starts and ends at \
             rest like the NFA's; its torques are then certified from rest. {verdict}"
        ),
        CaseMethod::Ecsa(_) => format!(
            "As the paper's {paper}: base orientation and joint positions; velocity controls u (constant + first \
             harmonic: not zero at the ends); torques τ. The forward dynamics of the torque certificate starts \
             from rest, the plain series does not (the sin² window, in the summary, does). {verdict}"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
