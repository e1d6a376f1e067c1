//! The JSON report of a plan (docs/spec.md §3, "`plan --format json`"): one object for every arm
//! and every method, the same keys whichever pipeline made the plan. Its two constructors read
//! a 2-link plan ([`PlanReport::new`]: the NFA, the paper's ECSA, the 2-link front-end of the
//! minimum-effort planner) and an arm's plan ([`PlanReport::from_arm`]: any `n`); a key that does
//! not apply is `null` (e.g. `z0` outside the NFA, `min_abs_sigma` where `n != 2`).

use serde::Serialize;

use crate::model::arm::Arm;
use crate::plan::certificate::ChainVerification;
use crate::plan::limit_use::LimitReport;
use crate::plan::torques::ChainTorqueCertificate;
use crate::plan::{Method, Trajectory};
use crate::planners::arm::ArmPlanned;
use crate::planners::chain::{ChainPoint, ChainStats};
use crate::planners::ecsa::ChainEcsaStats;
use crate::planners::nfa::normal_form::Transform;
use crate::planners::nfa::steering::BandChoice;
use crate::planners::optimal::OptimalStats;
use crate::planners::{Details, Planned};
use crate::report::arm::{ArmTrajectory, PoseGoal, trajectory};
use crate::track::ClosedLoopCertificate;

/// Wall time per stage \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ReportSeconds {
    /// The plan (for an arm's plan, its velocity certificate included).
    pub plan: f64,
    /// The torque level and its certificate (with torques).
    pub torques: Option<f64>,
    /// The velocity certificate of a 2-link plan (`null` for an arm's plan: inside `plan`).
    pub verify: Option<f64>,
}

/// The ECSA's account: the 2-link ECSA's (the paper's iteration) or the `n`-joint one's.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum EcsaAccount {
    /// The 2-link ECSA (Sec. 4 of the paper).
    TwoLink(EcsaReport),
    /// The ECSA of an `n`-joint arm.
    Arm(ChainEcsaStats),
}

impl EcsaAccount {
    /// Harmonics `H` of the basis.
    pub fn harmonics(&self) -> usize {
        match self {
            Self::TwoLink(x) => x.harmonics,
            Self::Arm(x) => x.harmonics,
        }
    }

    /// The window of the series.
    pub fn window(&self) -> crate::planners::ecsa::Window {
        match self {
            Self::TwoLink(x) => x.window,
            Self::Arm(x) => x.window,
        }
    }

    /// The iteration's final residual \[rad\].
    pub fn residual(&self) -> f64 {
        match self {
            Self::TwoLink(x) => x.residual,
            Self::Arm(x) => x.iteration.residual,
        }
    }
}

/// The minimum-effort planner's account: its 2-link front-end's or the `n`-joint planner's.
#[derive(Debug, Clone, Copy, Serialize)]
#[serde(untagged)]
pub enum OptimalAccount {
    /// The 2-link front-end (`theta_end`, `phi_end`, `seeds`, `degree`).
    TwoLink(OptimalStats),
    /// The `n`-joint planner (`converged`, `peak_velocity`, `plan_seconds`).
    Arm(ChainStats),
}

/// The torque level's certificate of either pipeline.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum TorqueAccount {
    /// A 2-link plan's (the base row of Eq. 6 beside the forward dynamics).
    TwoLink(crate::plan::TorqueReport),
    /// An arm's plan's (the same keys: the peaks, the base row, the nested certificate).
    Arm(ArmTorqueAccount),
}

/// The torque level of an arm's plan in the report: the keys of the 2-link robot's
/// [`crate::plan::TorqueReport`] (issue 19 item 5: one report for every arm), `n` peaks.
#[derive(Debug, Clone, Serialize)]
pub struct ArmTorqueAccount {
    /// `max |tau_k|` over the samples, per joint [N m].
    pub max_abs_torque: Vec<f64>,
    /// Largest `|base row of (6)|` over the samples [N m]: zero for a motion at zero momentum.
    pub max_abs_base_residual: f64,
    /// The forward-dynamics certificate.
    pub certificate: ChainTorqueCertificate,
}

impl TorqueAccount {
    /// The forward-dynamics certificate holds.
    pub fn certified(&self) -> bool {
        match self {
            Self::TwoLink(t) => t.certificate.certified,
            Self::Arm(a) => a.certificate.certified,
        }
    }
}

/// The sampled trajectory (only in `--out FILE.json`): the 2-link plan's (with the NFA's `z`)
/// or an arm's (`n + 1` columns).
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum TrajectoryAccount {
    /// A 2-link plan's.
    TwoLink(Trajectory),
    /// An arm's plan's.
    Arm(ArmTrajectory),
}

/// The JSON report of a plan (docs/spec.md §3: every required key, radians inside).
#[derive(Debug, Clone, Serialize)]
pub struct PlanReport {
    /// `optimal`, `nfa` or `ecsa`.
    pub method: Method,
    /// The NFA's transformation (null for other methods).
    pub transform: Option<Transform>,
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Horizon \[s\].
    pub time: f64,
    /// Number of samples.
    pub samples: usize,
    /// Number of joints `n`.
    pub joints: usize,
    /// The arm (base, mount, links, limits).
    pub robot: Arm,
    /// Start `(phi, theta_1..theta_n)` \[rad\].
    pub start: Vec<f64>,
    /// Goal \[rad\].
    pub goal: Vec<f64>,
    /// Chained-form start (NFA only).
    pub z0: Option<[f64; 3]>,
    /// Chained-form goal (NFA only).
    pub zd: Option<[f64; 3]>,
    /// Verified final error of the velocity plan \[rad\].
    pub final_error: f64,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// Whether every certificate holds (velocity level, torque level with torques, clearance).
    pub certified: bool,
    /// `q(T)` reached by the verification \[rad\].
    pub reached: Vec<f64>,
    /// The velocity-level certificate in full (final error, reached, largest angular momentum,
    /// path deviation, integrator work).
    pub verification: ChainVerification,
    /// Largest deviation of the verification from the planned path \[rad\] (null where the motion
    /// does not know its configuration between stages).
    pub max_path_deviation: Option<f64>,
    /// The least clearance of the verified motion (issue 21; none without shapes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance: Option<crate::plan::clearance::ClearanceReport>,
    /// Largest `|theta_k'|` per joint \[rad/s\].
    pub max_abs_u: Vec<f64>,
    /// Smallest `|sigma|` along the samples (Eq. 9; 2-link arms only).
    pub min_abs_sigma: Option<f64>,
    /// Smallest `|P|` along the samples (Eq. 13; 2-link arms only).
    pub min_abs_p: Option<f64>,
    /// Largest `|tau_k|` per joint [N m] (with torques).
    pub max_abs_torque: Option<Vec<f64>>,
    /// Verified final error of the torque plan \[rad\] (with torques).
    pub torque_final_error: Option<f64>,
    /// The torque level's certificate (with torques).
    pub torque_certificate: Option<TorqueAccount>,
    /// Wall time per stage.
    pub seconds: ReportSeconds,
    /// Iterations: the ECSA's, or the minimum-effort planner's SQP iterations (null for the NFA).
    pub iterations: Option<usize>,
    /// Chained-form steering of the NFA: `polynomial` (Sec. 5) or `band` (global normal form).
    pub steering: Option<&'static str>,
    /// The band steering's choice `(N, A, eps, kappa)`, when used.
    pub band: Option<BandChoice>,
    /// Total variation of `(phi, theta_1..theta_n)` along the samples \[rad\].
    pub joint_travel: Vec<f64>,
    /// Control effort `integral_0^T |u|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// Accepted steps of the verification's integrator.
    pub verify_steps: usize,
    /// Joint velocities `[u(0), u(T)]` \[rad/s\]: zero for the NFA, not for the ECSA's plain
    /// trigonometric controls (docs/spec.md §6, item 8).
    pub controls_at_ends: [Vec<f64>; 2],
    /// The ECSA's account (ECSA only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ecsa: Option<EcsaAccount>,
    /// The minimum-effort planner's account (optimal only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal: Option<OptimalAccount>,
    /// The closed-loop certificate (2-link plans with torques).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_loop: Option<ClosedLoopCertificate>,
    /// What the reader must know: the tool frame, a stretched horizon, `--to-ee`'s choice.
    pub notes: Vec<String>,
    /// The goal pose of `--to-ee` and its branches.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub to_ee: Option<PoseGoal>,
    /// The use of each declared limit along the verified motion (issue 20; absent without
    /// limits).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limits: Option<LimitReport>,
    /// The trajectory (only in `--out FILE.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<TrajectoryAccount>,
}

impl PlanReport {
    /// The report of a 2-link plan (with its torque level, when computed), with the trajectory
    /// when `with_trajectory`.
    pub fn new(planned: &Planned, with_trajectory: bool) -> Self {
        let plan = &planned.plan;
        let p = &plan.problem;
        let nfa = match &planned.details {
            Details::Nfa(d) => Some(d),
            _ => None,
        };
        let v = &plan.verification;
        let reached = v.reached.to_array().to_vec();
        let mut report = Self {
            method: plan.method,
            transform: nfa.map(|d| d.transform),
            joints: 2,
            robot: Arm::from_params(&p.robot),
            mount: [p.robot.mount.a, p.robot.mount.b],
            time: p.horizon,
            samples: plan.trajectory.t.len(),
            start: p.start.to_array().to_vec(),
            goal: p.goal.to_array().to_vec(),
            z0: nfa.map(|d| d.z0),
            zd: nfa.map(|d| d.zd),
            final_error: v.final_error,
            tolerance: v.tolerance,
            certified: v.certified && crate::plan::certificate::collision(v.clearance.as_ref()).is_ok(),
            reached: reached.clone(),
            verification: ChainVerification {
                final_error: v.final_error,
                reached,
                max_abs_momentum: v.max_abs_momentum,
                max_path_deviation: Some(v.max_path_deviation),
                tolerance: v.tolerance,
                certified: v.certified,
                stats: v.stats,
                clearance: v.clearance,
                limits: None,
            },
            max_path_deviation: Some(v.max_path_deviation),
            clearance: v.clearance,
            max_abs_u: plan.max_abs_u.to_vec(),
            min_abs_sigma: Some(plan.min_abs_sigma),
            min_abs_p: Some(plan.min_abs_p),
            max_abs_torque: None,
            torque_final_error: None,
            torque_certificate: None,
            seconds: ReportSeconds { plan: plan.seconds.plan, torques: None, verify: Some(plan.seconds.verify) },
            iterations: plan.iterations,
            steering: nfa.map(|d| if d.band.is_some() { "band" } else { "polynomial" }),
            band: nfa.and_then(|d| d.band),
            joint_travel: plan.joint_travel.to_vec(),
            effort: plan.effort,
            verify_steps: v.stats.accepted,
            controls_at_ends: controls_at_ends(plan.trajectory.dq.iter().map(|dq| &dq[1..])),
            ecsa: None,
            optimal: match &planned.details {
                Details::Optimal(stats) => Some(OptimalAccount::TwoLink(*stats)),
                _ => None,
            },
            closed_loop: None,
            notes: Vec::new(),
            to_ee: None,
            limits: None,
            trajectory: with_trajectory.then(|| TrajectoryAccount::TwoLink(plan.trajectory.clone())),
        };
        if let Details::Ecsa(solution) = &planned.details {
            report.ecsa = Some(EcsaAccount::TwoLink(EcsaReport::new(solution)));
        }
        if let Some(torques) = &planned.torques {
            report.max_abs_torque = Some(torques.max_abs_torque.to_vec());
            report.torque_final_error = Some(torques.certificate.final_error);
            report.certified &= torques.certificate.certified;
            report.seconds.torques = Some(torques.seconds.torques);
            report.torque_certificate = Some(TorqueAccount::TwoLink(*torques));
        }
        report
    }

    /// The report of an arm's plan for the problem's `start` and `goal`, with the trajectory when
    /// `with_trajectory`.
    pub fn from_arm(planned: &ArmPlanned, start: &[f64], goal: &[f64], with_trajectory: bool) -> Self {
        let v = planned.verification();
        let n = planned.arm.joints();
        let rows = &planned.trajectory;
        let margins = two_link_margins(&planned.arm, rows);
        let torques = planned.torques.as_ref();
        let optimal = planned.stats().copied();
        let ecsa = planned.ecsa().cloned();
        Self {
            method: planned.method,
            transform: None,
            joints: n,
            robot: planned.arm.clone(),
            mount: [planned.arm.mount.a, planned.arm.mount.b],
            time: planned.plan.horizon(),
            samples: rows.len(),
            start: start.to_vec(),
            goal: goal.to_vec(),
            z0: None,
            zd: None,
            final_error: v.final_error,
            tolerance: v.tolerance,
            certified: planned.certified().is_ok(),
            reached: v.reached.clone(),
            verification: v.clone(),
            max_path_deviation: v.max_path_deviation,
            clearance: v.clearance,
            max_abs_u: planned.peak_rates.clone(),
            min_abs_sigma: margins.map(|m| m.0),
            min_abs_p: margins.map(|m| m.1),
            max_abs_torque: torques.map(|t| t.max_abs_torque.clone()),
            torque_final_error: torques.map(|t| t.certificate.final_error),
            torque_certificate: torques.map(|t| {
                TorqueAccount::Arm(ArmTorqueAccount {
                    max_abs_torque: t.max_abs_torque.clone(),
                    max_abs_base_residual: t.max_abs_base_residual,
                    certificate: t.certificate.clone(),
                })
            }),
            seconds: ReportSeconds { plan: planned.seconds, torques: torques.map(|t| t.seconds), verify: None },
            iterations: optimal.map(|o| o.iterations).or(ecsa.as_ref().map(|e| e.iteration.iterations)),
            steering: None,
            band: None,
            joint_travel: travel(rows),
            effort: planned.effort(),
            verify_steps: v.stats.accepted,
            controls_at_ends: controls_at_ends(rows.iter().map(|p| p.rate.as_slice())),
            ecsa: ecsa.map(EcsaAccount::Arm),
            optimal: optimal.map(OptimalAccount::Arm),
            closed_loop: None,
            notes: Vec::new(),
            to_ee: None,
            limits: (!planned.limits.uses.is_empty()).then(|| planned.limits.clone()),
            trajectory: with_trajectory.then(|| TrajectoryAccount::Arm(trajectory(planned))),
        }
    }

    /// Sets the use of the robot's limits along a 2-link plan checked against them (`None`:
    /// none declared); `certified` holds only inside them, as an arm's report does (issue 20
    /// item 5).
    pub fn set_limits(&mut self, limits: Option<LimitReport>) {
        self.certified &= limits.as_ref().is_none_or(|l| l.check().is_ok());
        self.limits = limits;
    }

    /// This report with the closed-loop certificate (it does not change `certified`, which
    /// holds the open-loop levels).
    pub fn with_closed_loop(mut self, certificate: ClosedLoopCertificate) -> Self {
        self.closed_loop = Some(certificate);
        self
    }
}

/// `[u(0), u(T)]` of the joint velocities of a sampled motion (empty when it is).
fn controls_at_ends<'a>(mut rates: impl DoubleEndedIterator<Item = &'a [f64]>) -> [Vec<f64>; 2] {
    let first = rates.next().map(<[f64]>::to_vec).unwrap_or_default();
    let last = rates.next_back().map_or_else(|| first.clone(), <[f64]>::to_vec);
    [first, last]
}

/// Total variation of `(phi, theta_1..theta_n)` along the samples \[rad\].
fn travel(rows: &[ChainPoint]) -> Vec<f64> {
    let q = |p: &ChainPoint| std::iter::once(p.phi).chain(p.theta.iter().copied()).collect::<Vec<_>>();
    let mut total = rows.first().map_or_else(Vec::new, |p| vec![0.0; p.theta.len() + 1]);
    for pair in rows.windows(2) {
        for (t, (a, b)) in total.iter_mut().zip(q(&pair[0]).into_iter().zip(q(&pair[1]))) {
            *t += (b - a).abs();
        }
    }
    total
}

/// `(min |sigma|, min |P|)` along the samples of a 2-link arm's plan (Eqs. 9, 13, with the arm's
/// lumped constants); `None` for another number of links.
fn two_link_margins(arm: &Arm, rows: &[ChainPoint]) -> Option<(f64, f64)> {
    let k = arm.as_src()?.lumped();
    Some(rows.iter().fold((f64::INFINITY, f64::INFINITY), |(s, p), row| {
        let sh = crate::model::system::shape(&k, row.theta[0], row.theta[1]);
        (s.min(sh.sigma.abs()), p.min(sh.P.abs()))
    }))
}

/// The 2-link ECSA's part of the report (`"ecsa"` key of `plan --method ecsa --format json`).
#[derive(Debug, Clone, Serialize)]
pub struct EcsaReport {
    /// Harmonics `H` of the controls.
    pub harmonics: usize,
    /// `none` (the paper's plain series) or `sin2`.
    pub window: crate::planners::ecsa::Window,
    /// `c = (c_10, ..., c_1,2H, c_20, ..., c_2,2H)` \[rad/s\].
    pub coefficients: Vec<f64>,
    /// Final residual of the iteration \[rad\].
    pub residual: f64,
    /// Its tolerance \[rad\].
    pub residual_tolerance: f64,
    /// Residual before each update and after the last \[rad\].
    pub residual_history: Vec<f64>,
    /// Why the iteration stopped.
    pub termination: crate::planners::ecsa::Termination,
}

impl EcsaReport {
    /// The account of the 2-link ECSA's `solution`.
    pub fn new(solution: &crate::planners::ecsa::EcsaSolution) -> Self {
        let s = &solution.stats;
        Self {
            harmonics: solution.basis.harmonics(),
            window: solution.basis.window(),
            coefficients: solution.coefficients.clone(),
            residual: s.residual,
            residual_tolerance: s.tolerance,
            residual_history: s.residual_history.clone(),
            termination: s.termination,
        }
    }

    /// The termination reason in words.
    pub fn termination_name(&self) -> String {
        self.termination.to_string()
    }
}
