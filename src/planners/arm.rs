//! Planning for any planar serial arm (docs/spec.md §1–2): the one entry point that the command
//! line, the report and Python use for an arm that is not the paper's 2-link robot.
//!
//! The methods are the minimum-effort planner for `n` joints ([`super::chain`], the default) and
//! the ECSA for `n` joints ([`super::ecsa`]): the holonomy constraint `phi(T) = phid` is
//! one scalar for any `n` (Eq. 7 with `G = (G_1..G_n)`). The NFA's chained form (Eq. 10) is the
//! 2-link robot's; for other arms it is refused with the reason. Every plan is certified at the velocity level (the
//! system integrated with the planned joint velocities), and with `torques` at the torque level
//! (the full dynamics, base unactuated, integrated with the planned torques, Eq. 6).

use std::time::Instant;

use serde::Serialize;

use super::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainPoint, ChainProblem, ChainStats};
use super::ecsa::{ChainEcsaPlan, ChainEcsaPlanner, ChainEcsaStats, ChainSolver, EcsaOptions, Window};
use super::optimal::Cost;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::numerics::extremum::refined_peak;
use crate::numerics::ode::OdeOptions;
use crate::plan::certificate::{ChainVerification, JointMotion};
use crate::plan::limit_use::LimitReport;
use crate::plan::torques::{ChainTorqueCertificate, certify_joint_torques, chain_torques_at};
use crate::plan::{Method, TorqueOptions};

/// What to plan for an arm, and how.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmRequest {
    /// The problem: `n + 1` start and goal angles \[rad\], the horizon, the start velocity.
    pub problem: ChainProblem,
    /// Samples of the reported trajectory, both ends included (at least 2).
    pub samples: usize,
    /// Tolerance of the velocity-level certificate \[rad\] (default 1e-9).
    pub tolerance: f64,
    /// Add the torque level: torques at the samples and their certificate.
    pub torques: bool,
    /// The ECSA's harmonics and window (its tolerance is `tolerance`), for [`Method::Ecsa`].
    pub ecsa: EcsaOptions,
    /// The cost the minimum-effort planner minimises, for [`Method::Optimal`] (default effort).
    pub cost: Cost,
    /// Quintic ends (`theta'' = 0` at both ends, torques from and to zero), for
    /// [`Method::Optimal`] (default false).
    pub smooth_ends: bool,
    /// The shortest horizon (`--time auto`, issue 20 item 4), for [`Method::Optimal`] and an
    /// arm with a velocity, acceleration or torque limit: the least horizon, to 1 %, in which a
    /// certified plan fits every limit ([`ChainPlanner::shortest_horizon`], the problem's horizon
    /// its first probe), and the minimum-effort plan at it. Default false: the problem's horizon,
    /// and when it is too short for the limits an [`Error::HorizonTooShort`] naming the limit
    /// that binds and the shortest horizon found ([`ChainPlanner::plan_within_limits`]).
    pub shortest_horizon: bool,
}

impl ArmRequest {
    /// A request with the defaults: 1001 samples, tolerance 1e-9, no torques, the ECSA's and the
    /// minimum-effort planner's default options.
    pub fn new(problem: ChainProblem) -> Self {
        Self {
            problem,
            samples: 1001,
            tolerance: 1e-9,
            torques: false,
            ecsa: EcsaOptions::default(),
            cost: Cost::Effort,
            smooth_ends: false,
            shortest_horizon: false,
        }
    }

    /// Checks the request against the bounds of every request ([`crate::plan::limits`]):
    /// samples, tolerance, and the ECSA's options (harmonics, window). The problem itself is
    /// checked against the arm by the planner ([`ChainProblem::validate`]).
    pub fn validate(&self) -> Result<(), Error> {
        crate::plan::limits::check_samples("samples", self.samples as u64)?;
        crate::plan::limits::check_tolerance("tolerance", self.tolerance)?;
        EcsaOptions { tolerance: self.tolerance, samples: self.samples, ..self.ecsa }.validate()
    }
}

/// The torque level of an arm's plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArmTorques {
    /// Joint torques at the samples [N m], one row per sample.
    pub tau: Vec<Vec<f64>>,
    /// Largest `|tau_k|` over the samples, per joint [N m].
    pub max_abs_torque: Vec<f64>,
    /// Largest `|base row of (6)|` over the samples [N m]: zero for a motion at zero momentum.
    pub max_abs_base_residual: f64,
    /// The forward-dynamics certificate.
    pub certificate: ChainTorqueCertificate,
    /// Wall time of the torques and their certificate \[s\].
    pub seconds: f64,
}

/// The planned motion of an arm, exact at any time: the method's plan.
#[derive(Debug, Clone)]
pub enum ArmPlan {
    /// The minimum-effort planner's.
    Optimal(ChainPlan),
    /// The ECSA's.
    Ecsa(ChainEcsaPlan),
}

impl ArmPlan {
    /// The motion, for the certificates and the torques.
    pub fn motion(&self) -> &dyn JointMotion {
        match self {
            ArmPlan::Optimal(p) => p,
            ArmPlan::Ecsa(p) => p,
        }
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        match self {
            ArmPlan::Optimal(p) => p.horizon(),
            ArmPlan::Ecsa(p) => p.horizon(),
        }
    }

    /// The velocity-level certificate.
    pub fn verification(&self) -> &ChainVerification {
        match self {
            ArmPlan::Optimal(p) => &p.verification,
            ArmPlan::Ecsa(p) => &p.verification,
        }
    }

    /// The effort `integral_0^T |theta'|^2 dt` \[rad^2/s\].
    pub fn effort(&self) -> f64 {
        match self {
            ArmPlan::Optimal(p) => p.effort(),
            ArmPlan::Ecsa(p) => p.stats.effort,
        }
    }

    /// `samples >= 2` equally spaced points from 0 to T, the last exactly at T.
    pub fn sample(&self, samples: usize) -> Vec<ChainPoint> {
        match self {
            ArmPlan::Optimal(p) => p.sample(samples),
            ArmPlan::Ecsa(p) => p.sample(samples),
        }
    }
}

/// A plan for an arm with its certificates: certified unless [`ArmPlanned::certified`] says
/// otherwise (a plan below the default tolerance that misses it is returned for its report).
#[derive(Debug, Clone)]
pub struct ArmPlanned {
    /// The arm.
    pub arm: Arm,
    /// The method (optimal or ECSA).
    pub method: Method,
    /// The planned motion, exact at any time.
    pub plan: ArmPlan,
    /// The trajectory at `samples` equally spaced times.
    pub trajectory: Vec<ChainPoint>,
    /// The torque level, when asked for.
    pub torques: Option<ArmTorques>,
    /// Wall time of the plan and its velocity certificate \[s\].
    pub seconds: f64,
    /// The use of every declared limit along the verified motion (issue 20): empty without limits.
    pub limits: LimitReport,
    /// `max |theta_k'|` over `[0, T]` per joint \[rad/s\], not only at the samples
    /// ([`peak_rates`]), as the 2-link plan's `max_abs_u` (issue 11, item 5.4).
    pub peak_rates: Vec<f64>,
}

impl ArmPlanned {
    /// The velocity-level certificate.
    pub fn verification(&self) -> &ChainVerification {
        self.plan.verification()
    }

    /// The minimum-effort planner's statistics (effort, peak velocity, iterations,
    /// optimality); `None` for the ECSA.
    pub fn stats(&self) -> Option<&ChainStats> {
        match &self.plan {
            ArmPlan::Optimal(p) => Some(&p.stats),
            ArmPlan::Ecsa(_) => None,
        }
    }

    /// The ECSA's account (coefficients, iterations, residual, quadrature); `None` for the
    /// optimal planner.
    pub fn ecsa(&self) -> Option<&ChainEcsaStats> {
        match &self.plan {
            ArmPlan::Ecsa(p) => Some(&p.stats),
            ArmPlan::Optimal(_) => None,
        }
    }

    /// The effort `integral_0^T |theta'|^2 dt` \[rad^2/s\].
    pub fn effort(&self) -> f64 {
        self.plan.effort()
    }

    /// `Ok` when every certificate computed holds, else [`Error::NotCertified`] naming the level;
    /// then every declared limit, else [`Error::LimitExceeded`].
    pub fn certified(&self) -> Result<(), Error> {
        let v = self.verification();
        if !v.certified {
            return Err(Error::NotCertified { final_error: v.final_error, tolerance: v.tolerance, level: "velocity" });
        }
        v.collision()?;
        match &self.torques {
            Some(t) if !t.certificate.certified => Err(Error::NotCertified {
                final_error: t.certificate.final_error,
                tolerance: t.certificate.tolerance,
                level: "torque",
            }),
            _ => self.limits.check(),
        }
    }
}

/// Plans `request` for `arm` with `method` ([`Method::Optimal`] or [`Method::Ecsa`] with its
/// default options; [`Method::Nfa`] is bad input naming the reason), certifies it, and adds the
/// torque level when asked. The ECSA plans from rest (a moving start is bad input).
pub fn plan_arm(arm: &Arm, method: Method, request: &ArmRequest) -> Result<ArmPlanned, Error> {
    let refuse = |expected: &'static str| {
        Err(Error::from(InputError::InvalidText { name: "--method".into(), text: "nfa".into(), expected }))
    };
    if method == Method::Nfa {
        return refuse(if arm.joints() == 2 {
            "the optimal or ecsa method for an arm planned by this pipeline: the NFA plans the paper's 2-link \
             model (`plan --method nfa`, which checks its plan against the arm's limits and shapes)"
        } else {
            "the optimal or ecsa method for this arm: the NFA's chained form (Eq. 10) is the 2-link robot's, \
             and this arm has another number of links"
        });
    }
    request.validate()?;
    if method != Method::Ecsa && (request.ecsa.harmonics != 1 || request.ecsa.window != Window::None) {
        return Err(Error::from(InputError::InvalidParameter {
            name: "harmonics/window".into(),
            value: request.ecsa.harmonics as f64,
            expected: "the defaults (1 harmonic, no window) for another method than the ECSA: they shape the ECSA's controls only",
        }));
    }
    if method == Method::Ecsa && (request.cost != Cost::Effort || request.smooth_ends) {
        return Err(Error::from(InputError::InvalidText {
            name: "option".into(),
            text: if request.smooth_ends { "smooth_ends".into() } else { "cost".into() },
            expected: "the optimal method for the energy cost or smooth ends: the ECSA's controls are its \
                       harmonic basis, with neither",
        }));
    }
    if request.shortest_horizon && (method != Method::Optimal || !arm.limits.rate_limited()) {
        return Err(Error::from(InputError::InvalidText {
            name: "horizon".into(),
            text: "--time auto".into(),
            expected: "the optimal method and an arm with a velocity, acceleration or torque limit: the shortest \
                       horizon is the one in which the motion fits them",
        }));
    }
    let clock = Instant::now();
    let mut problem = request.problem.clone();
    let plan = if method == Method::Ecsa {
        let options = EcsaOptions { tolerance: request.tolerance, ..request.ecsa };
        // Two joints: the paper's damped pseudo-inverse iteration (its reproduction, Figs. 9-12,
        // for the paper's robot through any pipeline); more: the least-norm solution.
        let solver = if arm.joints() == 2 { ChainSolver::PseudoInverse } else { ChainSolver::default() };
        ArmPlan::Ecsa(ChainEcsaPlanner::new(arm.clone(), options).with_solver(solver).plan(&request.problem)?)
    } else {
        let options = ChainOptions {
            tolerance: request.tolerance,
            cost: request.cost,
            smooth_ends: request.smooth_ends,
            ..ChainOptions::default()
        };
        let planner = ChainPlanner::new(arm.clone(), options);
        if request.shortest_horizon {
            let shortest = planner.shortest_horizon(&problem)?;
            problem.horizon = shortest.horizon;
            ArmPlan::Optimal(shortest.plan)
        } else {
            ArmPlan::Optimal(match planner.plan_within_limits(&problem) {
                Err(Error::NotCertified { .. }) if request.tolerance < super::optimal::DEFAULT_TOLERANCE => {
                    // No plan holds the tolerance asked for: the plan at the default one, its
                    // certificate judged at the tolerance asked for, for the report to say by how
                    // much it misses (exit 3 with the numbers), as for the 2-link robot.
                    let options =
                        ChainOptions { tolerance: super::optimal::DEFAULT_TOLERANCE, ..planner.options.clone() };
                    let mut plan = ChainPlanner::new(arm.clone(), options).plan_within_limits(&problem)?;
                    let v = &mut plan.verification;
                    v.tolerance = request.tolerance;
                    v.certified = v.final_error <= v.tolerance;
                    plan
                }
                result => result?,
            })
        }
    };
    let trajectory = plan.sample(request.samples);
    let peak_rates = peak_rates(plan.motion(), &trajectory);
    let seconds = clock.elapsed().as_secs_f64();
    let torques = request.torques.then(|| arm_torques(arm, &plan, &trajectory, &problem)).transpose()?;
    // The certificate's own pass checked the limits too (one integration for every check).
    let limits = plan.verification().limits.clone().unwrap_or_else(LimitReport::empty);
    Ok(ArmPlanned { arm: arm.clone(), method, plan, trajectory, torques, seconds, limits, peak_rates })
}

/// `max |theta_k'|` of `motion` over `[0, T]` per joint \[rad/s\], not only at the `samples`
/// ([`refined_peak`]: the sampled maxima near the top refined on the exact rates), as
/// [`crate::plan::motion::peak_controls`] for a 2-link plan.
pub fn peak_rates(motion: &dyn JointMotion, samples: &[ChainPoint]) -> Vec<f64> {
    let times: Vec<f64> = samples.iter().map(|p| p.t).collect();
    let mut rate = vec![0.0; motion.joints()];
    (0..rate.len())
        .map(|k| {
            let values: Vec<f64> = samples.iter().map(|p| p.rate[k].abs()).collect();
            let f = |t: f64| -> Result<f64, std::convert::Infallible> {
                motion.joint_rate(t, &mut rate);
                Ok(rate[k].abs())
            };
            match refined_peak(f, &times, &values) {
                Ok(peak) => peak,
                Err(never) => match never {},
            }
        })
        .collect()
}

/// The torques at the samples and the forward-dynamics certificate (tolerance and integrator
/// of the 2-link torque level, docs/spec.md §2).
fn arm_torques(arm: &Arm, plan: &ArmPlan, samples: &[ChainPoint], problem: &ChainProblem) -> Result<ArmTorques, Error> {
    let clock = Instant::now();
    let defaults = TorqueOptions::default();
    let plan = plan.motion();
    let n = arm.joints();
    let mut tau = Vec::with_capacity(samples.len());
    let (mut peak, mut residual) = (vec![0.0_f64; n], 0.0_f64);
    for p in samples {
        let id = chain_torques_at(arm, plan, p.t);
        for (m, t) in peak.iter_mut().zip(id.tau.iter()) {
            *m = m.max(t.abs());
        }
        residual = residual.max(id.base_residual.abs());
        tau.push(id.tau.iter().copied().collect());
    }
    let ode: OdeOptions = defaults.ode;
    // From the problem's start state (at rest by default), not the plan's own velocities at
    // t = 0: a plan whose velocities jump there (the ECSA's plain series) cannot be followed, and
    // the certificate shows it (docs/spec.md §2), as the 2-link robot's does.
    let start_rate = Some(problem.initial_velocity.as_slice());
    let certificate =
        certify_joint_torques(arm, plan, &problem.start, start_rate, &problem.goal, &ode, defaults.tolerance)?;
    Ok(ArmTorques {
        tau,
        max_abs_torque: peak,
        max_abs_base_residual: residual,
        certificate,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Mount, RobotParams};
    use crate::plan::PlanningProblem;
    use crate::planners::{Planner, optimal::OptimalPlanner};

    /// An arm's peak joint rates are the motion's, not the samples': from every 10th of 2001
    /// samples they are those of all 2001 (to 1e-9 relative) and at least the samples' largest;
    /// on the paper's robot they are the 2-link plan's `max_abs_u` (its own motion, the paper's
    /// closed-form connection) at a = 1, b = -1, where the peak lies between samples.
    #[test]
    fn peak_rates_do_not_depend_on_the_samples() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        let paper = PlanningProblem::paper(robot);
        let two_link = OptimalPlanner::default().plan(&paper).unwrap();
        let arm = Arm::from_params(&robot);
        let problem = ChainProblem {
            start: paper.start.to_array().to_vec(),
            goal: paper.goal.to_array().to_vec(),
            horizon: paper.horizon,
            initial_velocity: vec![0.0; 2],
            wrap: true,
        };
        let three =
            Arm::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml")))
                .unwrap();
        let three_problem = ChainProblem {
            start: [0.0, 0.0, 30.0, 30.0].map(f64::to_radians).to_vec(),
            goal: [20.0, 90.0, 30.0, -30.0].map(f64::to_radians).to_vec(),
            horizon: 10.0,
            initial_velocity: vec![0.0; 3],
            wrap: true,
        };
        for (arm, problem) in [(arm, problem), (three, three_problem)] {
            let planned =
                plan_arm(&arm, Method::Optimal, &ArmRequest { samples: 2001, ..ArmRequest::new(problem) }).unwrap();
            let coarse: Vec<ChainPoint> = planned.trajectory.iter().step_by(10).cloned().collect();
            let from_coarse = peak_rates(planned.plan.motion(), &coarse);
            for (k, (c, f)) in from_coarse.iter().zip(&planned.peak_rates).enumerate() {
                let sampled = planned.trajectory.iter().fold(0.0_f64, |m, p| m.max(p.rate[k].abs()));
                assert!(*f >= sampled, "joint {}: {f} < sampled {sampled}", k + 1);
                assert!((c - f).abs() <= 1e-9 * f, "joint {}: {c} vs {f}", k + 1);
            }
            if arm.joints() == 2 {
                for (k, (a, b)) in planned.peak_rates.iter().zip(two_link.plan.max_abs_u).enumerate() {
                    assert!((a - b).abs() <= 1e-9 * b, "u{}: arm {a} vs 2-link {b}", k + 1);
                }
            }
        }
    }
}
