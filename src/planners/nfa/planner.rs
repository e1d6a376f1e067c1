//! The NFA planner: options, the planner behind the [`Planner`] trait.

use std::time::Instant;

use super::motion::NfaMotion;
use super::normal_form::{NewtonOptions, NormalForm, Transform};
use super::steering::{BandOptions, BandSteering, PolynomialSteering, Steering, keeps_to_band};
use crate::error::Error;
use crate::numerics::ode::OdeOptions;
use serde::Serialize;

use super::steering::BandChoice;
use crate::plan::{Method, Plan, PlanningProblem};
use crate::planners::{Details, Planned, Planner};

/// Options of the [`NormalFormPlanner`].
#[derive(Debug, Clone, PartialEq)]
pub struct NfaOptions {
    /// The feedback transformation; `None` = `auto`: [`Transform::auto`] (the paper's Eq. (12)
    /// or (14)) when its path exists, else [`Transform::Global`]. Default `None`.
    pub transform: Option<Transform>,
    /// Number of samples of the trajectory, including both ends; default 1001.
    pub samples: usize,
    /// Compute accelerations `q''` at the samples (exact, by dual numbers); default false.
    pub accelerations: bool,
    /// Newton options of the inverse map.
    pub newton: NewtonOptions,
    /// Integrator options of the verification (default rtol = atol = 1e-12).
    pub ode: OdeOptions,
    /// Tolerance of the verified final error \[rad\]; default 1e-9 (docs/spec.md §2).
    pub tolerance: f64,
    /// Search limits of the band steering (global normal form).
    pub band: BandOptions,
}

impl Default for NfaOptions {
    fn default() -> Self {
        Self {
            transform: None,
            samples: 1001,
            accelerations: false,
            newton: NewtonOptions::default(),
            ode: OdeOptions::default(),
            tolerance: 1e-9,
            band: BandOptions::default(),
        }
    }
}

impl NfaOptions {
    /// Checks the options: samples and tolerance within the bounds of every request
    /// ([`crate::plan::limits`]).
    pub fn validate(&self) -> Result<(), Error> {
        crate::plan::limits::check_samples("samples", self.samples as u64)?;
        crate::plan::limits::check_tolerance("tolerance", self.tolerance)?;
        Ok(())
    }
}

/// The Normal Form Approach (Sec. 2, Fig. 1): map `q0, qd` to the chained form, steer it with the
/// polynomial controls of Sec. 5, map the path back (Sec. 6, item 2), verify.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NormalFormPlanner {
    /// Options.
    pub options: NfaOptions,
}

impl NormalFormPlanner {
    /// A planner with these options.
    pub fn new(options: NfaOptions) -> Self {
        Self { options }
    }

    /// The velocity-level plan without verification: the exact [`NfaMotion`] and its samples.
    ///
    /// With the transformation `None` (`auto` of docs/spec.md §2), the paper's Eq. (12) or (14) is tried
    /// first and the global normal form when their path does not exist.
    pub fn motion(&self, problem: &PlanningProblem) -> Result<NfaMotion, Error> {
        self.options.validate()?;
        match self.options.transform {
            Some(transform) => self.motion_with(problem, transform),
            None => match self.motion_with(problem, Transform::auto(&problem.robot)) {
                Err(e) if !e.is_bad_input() => self.motion_with(problem, Transform::Global),
                result => result,
            },
        }
    }

    fn motion_with(&self, problem: &PlanningProblem, transform: Transform) -> Result<NfaMotion, Error> {
        let nf = NormalForm::new(&problem.robot, transform, &problem.start)?.with_newton(self.options.newton);
        nf.check(&problem.goal, "goal", None)?;
        let z0 = nf.h(problem.start.to_array());
        let zd = nf.h(problem.goal.to_array());
        let polynomial = PolynomialSteering::new(z0, zd, problem.horizon);
        let sampled = |steering: Steering| -> Result<NfaMotion, Error> {
            let mut motion = NfaMotion::new(nf.clone(), steering);
            motion.sample(problem, self.options.samples)?;
            Ok(motion)
        };
        let band = |nf: &NormalForm| -> Result<NfaMotion, Error> {
            let band = BandSteering::new(nf, &problem.start, z0, zd, problem.horizon, &self.options.band)?;
            sampled(Steering::Band(band))
        };
        let motion = match polynomial {
            // The global normal form keeps the polynomial path only where it keeps to the band
            // as the band steering would: decided on the path, whatever the number of samples.
            Ok(path)
                if transform == Transform::Global && !keeps_to_band(&nf, &problem.start, &path, &self.options.band) =>
            {
                // When no band steering is found, the polynomial path may still be followed.
                band(&nf).or_else(|e| sampled(Steering::Polynomial(path)).map_err(|_| e))?
            }
            Ok(path) => match sampled(Steering::Polynomial(path)) {
                Err(Error::LeavesBand { .. }) if transform == Transform::Global => band(&nf)?,
                result => result?,
            },
            Err(Error::DegenerateSteering { .. }) if transform == Transform::Global => band(&nf)?,
            Err(e) => return Err(e),
        };
        // The path's last sample inverts zd on the start's piece of the domain: if that is not
        // the goal, the goal lies on another piece with the same z (e.g. theta2 whole turns away
        // across a singular curve), and no continuous path of this transformation reaches it.
        let reached = motion.q.last().copied().unwrap_or(problem.start);
        let distance = reached.distance(&problem.goal);
        if !(distance <= 1e-6) {
            return Err(Error::GoalNotReached { transform: transform.name(), reached, goal: problem.goal, distance });
        }
        Ok(motion)
    }
}

impl Planner for NormalFormPlanner {
    fn method(&self) -> Method {
        Method::Nfa
    }

    fn plan(&self, problem: &PlanningProblem) -> Result<Planned, Error> {
        problem.require_rest("nfa")?;
        let (plan, motion) = self.plan_with_motion(problem)?;
        let (z0, zd) = motion.steering.ends();
        let details = NfaDetails { transform: motion.nf.transform(), z0, zd, band: motion.steering.band_choice() };
        Ok(Planned::new(plan, Box::new(motion), Details::Nfa(details)))
    }
}

/// What only the NFA knows of its plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NfaDetails {
    /// The feedback transformation used.
    pub transform: Transform,
    /// Chained-form start `z0 = h(q0)`.
    pub z0: [f64; 3],
    /// Chained-form goal `zd = h(qd)`.
    pub zd: [f64; 3],
    /// The band steering's choice, when the global normal form needed it.
    pub band: Option<BandChoice>,
}

impl NormalFormPlanner {
    /// [`Planner::plan`], also returning the exact motion (e.g. for the torque level,
    /// [`crate::plan::torque_plan`]).
    pub fn plan_with_motion(&self, problem: &PlanningProblem) -> Result<(Plan, NfaMotion), Error> {
        let clock = Instant::now();
        let motion = self.motion(problem)?;
        let trajectory = motion.trajectory(problem, self.options.accelerations)?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let (ode, tolerance) = (&self.options.ode, self.options.tolerance);
        let plan =
            Plan::verified(Method::Nfa, problem, &motion, trajectory, motion.margins(), plan_seconds, ode, tolerance)?;
        Ok((plan, motion))
    }
}
