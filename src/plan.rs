//! Planning problems, planners and plans with their certificates (Secs. 2, 5 and 6).
//!
//! A [`Planner`] turns a [`PlanningProblem`] into a [`Plan`]: a sampled [`Trajectory`] plus a
//! [`Verification`], obtained by integrating the original system (7) with the planned controls,
//! evaluated exactly at any time through the plan's [`Motion`].

use std::time::Instant;

use num_dual::Dual64;
use serde::Serialize;

use crate::error::Error;
use crate::model::{Configuration, RobotParams};
use crate::normal_form::{NewtonOptions, NormalForm, Transform};
use crate::ode::{OdeOptions, OdeStats, integrate};
use crate::steering::{BandChoice, BandOptions, BandSteering, PolynomialSteering, Steering};
use crate::system::{velocity, velocity_acceleration};

/// Drive the robot from `start` to `goal` in time `horizon`, joint velocities zero at both
/// ends, zero angular momentum (SPEC §2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlanningProblem {
    /// The robot, with its mounting point.
    pub robot: RobotParams,
    /// `q0` \[rad\].
    pub start: Configuration,
    /// `qd` \[rad\], taken literally (not reduced modulo 2 pi).
    pub goal: Configuration,
    /// `T` \[s\].
    pub horizon: f64,
}

impl PlanningProblem {
    /// A validated problem: robot valid, angles finite, `T` finite and positive.
    pub fn new(robot: RobotParams, start: Configuration, goal: Configuration, horizon: f64) -> Result<Self, Error> {
        robot.validate()?;
        for (name, q) in [("start", start), ("goal", goal)] {
            for (axis, x) in ["phi", "theta1", "theta2"].iter().zip(q.to_array()) {
                if !x.is_finite() {
                    return Err(Error::InvalidParameter {
                        name: format!("{name}.{axis}"),
                        value: x,
                        expected: "a finite angle",
                    });
                }
            }
        }
        if !(horizon.is_finite() && horizon > 0.0) {
            return Err(Error::InvalidParameter {
                name: "time".into(),
                value: horizon,
                expected: "a positive, finite horizon [s]",
            });
        }
        Ok(Self { robot, start, goal, horizon })
    }

    /// The paper's problem (Sec. 5) for `robot`: `q0 = (45, 120, 80)` deg,
    /// `qd = (0, 180, 140)` deg, `T = 10` s.
    pub fn paper(robot: RobotParams) -> Self {
        let (start, goal, horizon) = crate::model::paper_problem();
        Self { robot, start, goal, horizon }
    }
}

/// A planned motion, evaluated exactly at any time `t` in `[0, T]`.
pub trait Motion {
    /// The horizon `T` \[s\].
    fn horizon(&self) -> f64;
    /// The planned configuration, joint velocities `u` and their derivatives `du` at `t`.
    fn at(&self, t: f64) -> Result<MotionPoint, Error>;
    /// The joint velocities `u(t)` \[rad/s\] alone (the velocity-level control signal).
    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        Ok(self.at(t)?.u)
    }
    /// The motion at each of `times` \[s\]; by default [`Motion::at`] at each. Planners that keep
    /// samples override it to reuse what they computed there (same values, less work).
    fn points(&self, times: &[f64]) -> Result<Vec<MotionPoint>, Error> {
        times.iter().map(|&t| self.at(t)).collect()
    }
    /// Times in `(0, T)` \[s\] where the controls are less smooth (spline knots), ascending; the
    /// verification integrates one piece at a time between them. Default: none.
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// A point of a [`Motion`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPoint {
    /// Planned configuration \[rad\].
    pub q: Configuration,
    /// Joint velocities `(theta1', theta2')` \[rad/s\]: the controls of system (7).
    pub u: [f64; 2],
    /// Their time derivatives \[rad/s^2\].
    pub du: [f64; 2],
}

/// A sampled trajectory, one entry per sample in every column (SI units, radians).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Trajectory {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Configurations `(phi, theta1, theta2)` \[rad\].
    pub q: Vec<[f64; 3]>,
    /// Velocities `q'` \[rad/s\]; `(dq[1], dq[2])` are the controls `u`.
    pub dq: Vec<[f64; 3]>,
    /// Accelerations `q''` \[rad/s^2\], when computed.
    pub ddq: Option<Vec<[f64; 3]>>,
    /// Chained-form state `z` (NFA only).
    pub z: Option<Vec<[f64; 3]>>,
    /// Joint torques `(tau1, tau2)` \[N m\], when computed.
    pub tau: Option<Vec<[f64; 2]>>,
}

/// The certificate of a plan: system (7) integrated from `q0` with the planned controls.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Verification {
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\] (SPEC §2).
    pub final_error: f64,
    /// `q(T)` reached by the integration \[rad\].
    pub reached: Configuration,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's steps \[rad\].
    pub max_path_deviation: f64,
    /// Tolerance the final error is held to \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
}

/// Wall time of each stage \[s\].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Seconds {
    /// Planning (the velocity-level plan, sampled).
    pub plan: f64,
    /// Inverse dynamics, when torques were asked for.
    pub torques: Option<f64>,
    /// Verification (integration of system (7)).
    pub verify: f64,
}

/// The planning method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Normal Form Approach.
    Nfa,
    /// Endogenous Configuration Space Approach.
    Ecsa,
    /// Minimum-effort (or minimum-energy) trajectory optimisation.
    Optimal,
}

/// A plan with its certificate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// The method used.
    pub method: Method,
    /// The feedback transformation (NFA only).
    pub transform: Option<Transform>,
    /// The problem solved.
    pub problem: PlanningProblem,
    /// Chained-form start `z0 = h(q0)` (NFA only).
    pub z0: Option<[f64; 3]>,
    /// Chained-form goal `zd = h(qd)` (NFA only).
    pub zd: Option<[f64; 3]>,
    /// The sampled trajectory.
    pub trajectory: Trajectory,
    /// `[max |u1|, max |u2|]` over the samples \[rad/s\].
    pub max_abs_u: [f64; 2],
    /// Smallest `|sigma|` along the samples (domain margin).
    pub min_abs_sigma: f64,
    /// Smallest `|P|` along the samples (domain margin).
    pub min_abs_p: f64,
    /// Iterations (ECSA only).
    pub iterations: Option<usize>,
    /// The band steering's choice, when the global normal form needed it (NFA only).
    pub band: Option<BandChoice>,
    /// Total variation of `(phi, theta1, theta2)` along the samples \[rad\].
    pub joint_travel: [f64; 3],
    /// The velocity-level certificate.
    pub verification: Verification,
    /// Wall time per stage.
    pub seconds: Seconds,
}

impl Plan {
    /// Verifies `motion` (see [`verify`]) and assembles its plan from the sampled `trajectory`,
    /// the domain `margins` `(min |sigma|, min |P|)` and the planning time \[s\]: the fields every
    /// planner fills alike. The method's own fields (`transform`, `z0`, `zd`, `band`,
    /// `iterations`) start empty.
    #[allow(clippy::too_many_arguments)]
    pub fn verified(
        method: Method,
        problem: &PlanningProblem,
        motion: &dyn Motion,
        trajectory: Trajectory,
        margins: (f64, f64),
        plan_seconds: f64,
        ode: &OdeOptions,
        tolerance: f64,
    ) -> Result<Plan, Error> {
        let clock = Instant::now();
        let verification = verify(motion, problem, ode, tolerance)?;
        let verify_seconds = clock.elapsed().as_secs_f64();
        Ok(Plan {
            method,
            transform: None,
            problem: *problem,
            z0: None,
            zd: None,
            band: None,
            joint_travel: travel(&trajectory),
            max_abs_u: max_abs_controls(&trajectory),
            trajectory,
            min_abs_sigma: margins.0,
            min_abs_p: margins.1,
            iterations: None,
            verification,
            seconds: Seconds { plan: plan_seconds, torques: None, verify: verify_seconds },
        })
    }

    /// The plan if its velocity-level certificate holds, else [`Error::NotCertified`].
    pub fn certified(&self) -> Result<&Plan, Error> {
        let v = &self.verification;
        if v.certified {
            Ok(self)
        } else {
            Err(Error::NotCertified { final_error: v.final_error, tolerance: v.tolerance, level: "velocity" })
        }
    }
}

/// A motion planner (SPEC §2): NFA or ECSA.
pub trait Planner {
    /// Short name (`nfa`, `ecsa`).
    fn name(&self) -> &'static str;
    /// Plans and verifies. A plan is returned even when its certificate fails (see
    /// [`Plan::certified`]); errors mean there is no plan at all.
    fn plan(&self, problem: &PlanningProblem) -> Result<Plan, Error>;
}

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
    /// Tolerance of the verified final error \[rad\]; default 1e-9 (SPEC §2).
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
    /// Checks the options (at least two samples, a positive tolerance).
    pub fn validate(&self) -> Result<(), Error> {
        if self.samples < 2 {
            return Err(Error::InvalidParameter {
                name: "samples".into(),
                value: self.samples as f64,
                expected: "at least 2",
            });
        }
        if !(self.tolerance > 0.0) {
            return Err(Error::InvalidParameter {
                name: "tolerance".into(),
                value: self.tolerance,
                expected: "a positive number [rad]",
            });
        }
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
    /// With the transformation `None` (SPEC's `auto`), the paper's Eq. (12) or (14) is tried
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
        let polynomial = PolynomialSteering::new(z0, zd, problem.horizon).map(Steering::Polynomial);
        let attempt = polynomial.and_then(|steering| {
            let mut motion = NfaMotion::new(nf.clone(), steering);
            motion.sample(problem, self.options.samples)?;
            Ok(motion)
        });
        let motion = match attempt {
            Err(Error::LeavesBand { .. } | Error::DegenerateSteering { .. }) if transform == Transform::Global => {
                let band = BandSteering::new(&nf, &problem.start, z0, zd, problem.horizon, &self.options.band)?;
                let mut motion = NfaMotion::new(nf, Steering::Band(band));
                motion.sample(problem, self.options.samples)?;
                motion
            }
            result => result?,
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
    fn name(&self) -> &'static str {
        "nfa"
    }

    fn plan(&self, problem: &PlanningProblem) -> Result<Plan, Error> {
        Ok(self.plan_with_motion(problem)?.0)
    }
}

impl NormalFormPlanner {
    /// [`Planner::plan`], also returning the exact motion (e.g. for the torque level,
    /// [`crate::dynamics::torque_plan`]).
    pub fn plan_with_motion(&self, problem: &PlanningProblem) -> Result<(Plan, NfaMotion), Error> {
        let clock = Instant::now();
        let motion = self.motion(problem)?;
        let trajectory = motion.trajectory(problem, self.options.accelerations)?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let (ode, tolerance) = (&self.options.ode, self.options.tolerance);
        let mut plan =
            Plan::verified(Method::Nfa, problem, &motion, trajectory, motion.margins(), plan_seconds, ode, tolerance)?;
        plan.transform = Some(motion.nf.transform());
        (plan.z0, plan.zd) = (Some(motion.steering.ends().0), Some(motion.steering.ends().1));
        plan.band = motion.steering.band_choice();
        Ok((plan, motion))
    }
}

/// Total variation of each coordinate of `q` over a trajectory's samples \[rad\].
pub fn travel(trajectory: &Trajectory) -> [f64; 3] {
    let mut out = [0.0; 3];
    for w in trajectory.q.windows(2) {
        for (o, (a, b)) in out.iter_mut().zip(w[0].iter().zip(&w[1])) {
            *o += (b - a).abs();
        }
    }
    out
}

/// `[max |u1|, max |u2|]` over a trajectory's samples.
pub fn max_abs_controls(trajectory: &Trajectory) -> [f64; 2] {
    trajectory.dq.iter().fold([0.0, 0.0], |m, dq| [m[0].max(dq[1].abs()), m[1].max(dq[2].abs())])
}

/// The NFA's planned motion: the chained-form path mapped back through the inverse feedback,
/// exact at any time (the samples only warm-start Newton's method).
#[derive(Debug, Clone)]
pub struct NfaMotion {
    /// The feedback transformation on the start's piece of its domain.
    pub nf: NormalForm,
    /// The chained-form path.
    pub steering: Steering,
    t: Vec<f64>,
    z: Vec<[f64; 3]>,
    q: Vec<Configuration>,
    u: Vec<[f64; 2]>,
    /// `(min |sigma|, min |P|)` over the samples.
    margins: (f64, f64),
}

impl NfaMotion {
    fn new(nf: NormalForm, steering: Steering) -> Self {
        Self {
            nf,
            steering,
            t: Vec::new(),
            z: Vec::new(),
            q: Vec::new(),
            u: Vec::new(),
            margins: (f64::INFINITY, f64::INFINITY),
        }
    }

    /// Inverts the path at `samples` equally spaced times, each Newton run warm-started from the
    /// previous sample (first-order prediction), and checks that the path stays in the domain.
    fn sample(&mut self, problem: &PlanningProblem, samples: usize) -> Result<(), Error> {
        let horizon = problem.horizon;
        let dt = horizon / (samples - 1) as f64;
        self.t = Vec::with_capacity(samples);
        self.z = Vec::with_capacity(samples);
        self.q = Vec::with_capacity(samples);
        self.u = Vec::with_capacity(samples);
        let mut guess = problem.start.theta2;
        let mut previous_u2 = 0.0;
        for i in 0..samples {
            let t = if i + 1 == samples { horizon } else { i as f64 * dt };
            let p = self.steering.at(t);
            let q = self.nf.invert(p.z, guess, Some(t))?;
            let m = self.nf.check(&q, "path", Some(t))?;
            self.margins = (self.margins.0.min(m.sigma.abs()), self.margins.1.min(m.p.abs()));
            let u = self.nf.control(q.to_array(), p.v);
            // Two-step Adams–Bashforth prediction of the next theta2 (error O(dt^3)).
            guess = q.theta2 + dt * (1.5 * u[1] - 0.5 * previous_u2);
            previous_u2 = u[1];
            self.t.push(t);
            self.z.push(p.z);
            self.q.push(q);
            self.u.push(u);
        }
        Ok(())
    }

    /// The warm start for Newton at `t`: the nearest sample's theta2, advanced by its u2.
    fn guess(&self, t: f64) -> f64 {
        let n = self.t.len();
        let dt = self.steering.horizon() / (n - 1) as f64;
        let i = ((t / dt).round().max(0.0) as usize).min(n - 1);
        self.q[i].theta2 + self.u[i][1] * (t - self.t[i])
    }

    /// The sampled trajectory (with accelerations when asked).
    pub fn trajectory(&self, problem: &PlanningProblem, accelerations: bool) -> Result<Trajectory, Error> {
        let k = problem.robot.lumped();
        let dq = self.q.iter().zip(&self.u).map(|(q, u)| velocity(&k, q.to_array(), *u)).collect();
        let ddq = if accelerations {
            let mut ddq = Vec::with_capacity(self.t.len());
            for (q, &t) in self.q.iter().zip(&self.t) {
                let m = self.point(*q, t)?;
                ddq.push(velocity_acceleration(&k, &m.q, m.u, m.du).1);
            }
            Some(ddq)
        } else {
            None
        };
        Ok(Trajectory {
            t: self.t.clone(),
            q: self.q.iter().map(|q| q.to_array()).collect(),
            dq,
            ddq,
            z: Some(self.z.clone()),
            tau: None,
        })
    }

    /// `(min |sigma|, min |P|)` along the samples: the domain margins.
    pub fn margins(&self) -> (f64, f64) {
        self.margins
    }

    /// The motion at `t` given the planned configuration there: `u` by the inverse feedback and
    /// `du` exactly, by dual numbers through the polynomial path and the feedback.
    fn point(&self, q: Configuration, t: f64) -> Result<MotionPoint, Error> {
        let p = self.steering.at(t);
        let u = self.nf.control(q.to_array(), p.v);
        Ok(self.point_with_controls(q, u, t))
    }

    /// [`NfaMotion::point`] when `u` at `(q, t)` is already known. Eq. (14) takes the fast path
    /// [`eq14_control_rate`]; the others differentiate the inverse feedback with dual numbers.
    fn point_with_controls(&self, q: Configuration, u: [f64; 2], t: f64) -> MotionPoint {
        if self.nf.transform() == Transform::Eq14 {
            let dv = self.steering.at_dual(t).v;
            let du = eq14_control_rate(self.nf.lumped(), self.nf.branch(), &q, u, [dv[0].eps, dv[1].eps]);
            return MotionPoint { q, u, du };
        }
        self.point_by_dual_numbers(q, u, t)
    }

    /// `du` by dual numbers through the inverse feedback: `u' = d/dt control(q(t), v(t))`.
    fn point_by_dual_numbers(&self, q: Configuration, u: [f64; 2], t: f64) -> MotionPoint {
        let p = self.steering.at_dual(t);
        let dq = velocity(self.nf.lumped(), q.to_array(), u);
        let qa = q.to_array();
        let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(qa[i], dq[i]));
        let ud = self.nf.control(qd, p.v);
        MotionPoint { q, u, du: [ud[0].eps, ud[1].eps] }
    }

    /// The index of the sample taken at exactly `t`, if any.
    fn sample_index(&self, t: f64) -> Option<usize> {
        let n = self.t.len();
        let dt = self.steering.horizon() / (n - 1) as f64;
        let i = ((t / dt).round().max(0.0) as usize).min(n - 1);
        (self.t[i].to_bits() == t.to_bits()).then_some(i)
    }
}

impl Motion for NfaMotion {
    fn horizon(&self) -> f64 {
        self.steering.horizon()
    }

    fn at(&self, t: f64) -> Result<MotionPoint, Error> {
        let z = self.steering.at(t).z;
        let q = self.nf.invert(z, self.guess(t), Some(t))?;
        self.point(q, t)
    }

    /// At the sample times the stored Newton solutions and controls are reused (no Newton run);
    /// elsewhere as [`Motion::at`].
    fn points(&self, times: &[f64]) -> Result<Vec<MotionPoint>, Error> {
        times
            .iter()
            .map(|&t| match self.sample_index(t) {
                Some(i) => Ok(self.point_with_controls(self.q[i], self.u[i], t)),
                None => self.at(t),
            })
            .collect()
    }

    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        if let Steering::Band(band) = &self.steering {
            // The joint velocities need neither z3 (a quadrature) nor phi.
            let ([z1, z2], v) = band.joints(t);
            let theta2 = self.nf.band_theta2(z1, z2, self.guess(t), Some(t))?;
            return Ok(self.nf.control([0.0, z1, theta2], v));
        }
        let p = self.steering.at(t);
        let q = self.nf.invert(p.z, self.guess(t), Some(t))?;
        Ok(self.nf.control(q.to_array(), p.v))
    }
}

/// The time derivative `u' = (u1', u2')` [rad/s^2] of the inverse feedback of Eq. (14) along a
/// motion at `q` with joint velocities `u` and chained-form control rates `dv = v'`.
///
/// `u1 = v1` gives `u1' = v1'`. Differentiating `v2 = a u1 + b u2` (`a = dh3/dtheta1`,
/// `b = dh3/dtheta2 = sign(P) 2 sigma / F^2`, Eq. 25) once more along the motion gives
/// `v2' = a u1' + b u2' + h3_11 u1^2 + 2 h3_12 u1 u2 + h3_22 u2^2`, solved for `u2'`. With
/// `h3 = sign(P) G/F + dR/dtheta1` the pure `theta1` derivatives come from one third-order dual
/// number in `theta1` through `R`, `G/F` and `b`; the last one, `h3_22 = db/dtheta2 =
/// 2 sign(P) (sigma_2 - 4 sigma P / F) / F^2` (`dF/dtheta2 = 2 P`, Eq. 13), by hand with
/// `sigma_2 = dsigma/dtheta2 = -(C D - A E)(a c12 + b s12) + (D E (a^2 + b^2) - C I_P) c2`
/// from Eq. (9). Exact, and without the three nested levels of dual numbers of the generic path.
#[allow(non_snake_case)]
fn eq14_control_rate(k: &crate::model::Lumped, branch: f64, q: &Configuration, u: [f64; 2], dv: [f64; 2]) -> [f64; 2] {
    use crate::system::shape;
    use num_dual::{Dual3_64, DualNum};
    let t1 = Dual3_64::new(q.theta1, 1.0, 0.0, 0.0);
    let t2 = Dual3_64::from_re(q.theta2);
    let s = shape(k, t1, t2);
    // R of Eq. (14) from the same shape, exactly as `general::r_function` (atan2 form); the test
    // `eq14_control_rate_matches_nested_dual_numbers` holds the two together.
    let (abs_p, root_d) = (s.P * branch, s.d.sqrt());
    let first = (s.F - s.U).atan2(abs_p * 2.0);
    let second = (s.F * s.U - s.d).atan2(root_d * abs_p * 2.0);
    let R = -first * 0.5 + s.Z / (root_d * 2.0) * second;
    let G_F = s.G / s.F;
    let a = G_F.v1 * branch + R.v2;
    let a1 = G_F.v2 * branch + R.v3;
    let b = s.sigma * (2.0 * branch) / (s.F * s.F);
    let crate::model::Lumped { A, C, D, E, IP, a: ma, b: mb, .. } = *k;
    let (s2, c2) = q.theta2.sin_cos();
    let (s1, c1) = q.theta1.sin_cos();
    let k12 = ma * (c1 * c2 - s1 * s2) + mb * (s1 * c2 + c1 * s2);
    let (F, P, sigma) = (s.F.re, s.P.re, s.sigma.re);
    let sigma2 = -(C * D - A * E) * k12 + (D * E * (ma * ma + mb * mb) - C * IP) * c2;
    let b2 = 2.0 * branch * (sigma2 - 4.0 * sigma * P / F) / (F * F);
    let [u1, u2] = u;
    let du2 = (dv[1] - a * dv[0] - a1 * u1 * u1 - 2.0 * b.v1 * u1 * u2 - b2 * u2 * u2) / b.re;
    [dv[0], du2]
}

/// The velocity-level certificate: integrates system (7) from `q0` with `u(t)` of `motion`
/// (evaluated exactly at every stage time) and measures the final error against the goal.
pub fn verify(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<Verification, Error> {
    let k = problem.robot.lumped();
    let y0 = nalgebra::Vector3::from(problem.start.to_array());
    let mut deviation: f64 = 0.0;
    let mut observe_error = None;
    // One integration per piece between the motion's breakpoints: the adaptive steps never
    // straddle a point where the controls lose smoothness.
    let mut ends: Vec<f64> = motion.breakpoints().into_iter().filter(|&t| t > 0.0 && t < problem.horizon).collect();
    ends.push(problem.horizon);
    let (mut y, mut t0) = (y0, 0.0);
    let mut stats = OdeStats::default();
    for t1 in ends {
        if !(t1 > t0) {
            continue;
        }
        let (y1, piece) = integrate(
            |t, y: &nalgebra::Vector3<f64>| {
                let u = motion.controls(t)?;
                Ok(nalgebra::Vector3::from(velocity(&k, [y[0], y[1], y[2]], u)))
            },
            t0,
            y,
            t1,
            ode,
            |t, y| match motion.at(t) {
                Ok(p) => {
                    let d = (y - nalgebra::Vector3::from(p.q.to_array())).abs().max();
                    deviation = deviation.max(d);
                }
                Err(e) => observe_error = Some(e),
            },
        )?;
        stats.accepted += piece.accepted;
        stats.rejected += piece.rejected;
        stats.evaluations += piece.evaluations;
        (y, t0) = (y1, t1);
    }
    if let Some(e) = observe_error {
        return Err(e);
    }
    let reached = Configuration::new(y[0], y[1], y[2]);
    let final_error = reached.distance(&problem.goal);
    Ok(Verification {
        final_error,
        reached,
        max_path_deviation: deviation,
        tolerance,
        certified: final_error.is_finite() && final_error <= tolerance,
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mount;

    fn paper_case(a: f64, transform: Transform) -> Plan {
        let robot = RobotParams::src().with_mount(Mount::new(a, a).unwrap()).unwrap();
        let options = NfaOptions { transform: Some(transform), accelerations: true, ..Default::default() };
        NormalFormPlanner::new(options).plan(&PlanningProblem::paper(robot)).unwrap()
    }

    /// The paper's five NFA cases (Figs. 4-8) reach the goal with a verified final error
    /// <= 1e-9 rad, start and end at rest, and the samples hit q0 and qd.
    #[test]
    fn paper_cases_are_certified() {
        for (a, transform) in [
            (0.0, Transform::Eq11),
            (0.0, Transform::Eq12),
            (0.1, Transform::Eq14),
            (0.2, Transform::Eq14),
            (0.3, Transform::Eq14),
        ] {
            let plan = paper_case(a, transform);
            let v = &plan.verification;
            assert!(v.final_error <= 1e-9, "a = b = {a}, {transform:?}: final error {}", v.final_error);
            assert!(v.max_path_deviation <= 1e-9, "deviation {}", v.max_path_deviation);
            let tr = &plan.trajectory;
            let (first, last) = (tr.q[0], tr.q[tr.q.len() - 1]);
            assert!(Configuration::from_array(first).distance(&plan.problem.start) < 1e-12);
            assert!(Configuration::from_array(last).distance(&plan.problem.goal) < 1e-11);
            for dq in [tr.dq[0], tr.dq[tr.dq.len() - 1]] {
                assert!(dq.iter().all(|x| x.abs() < 1e-12), "not at rest: {dq:?}");
            }
        }
    }

    /// The exact `du` of the motion matches a central difference of `u(t)`.
    #[test]
    fn control_derivative_matches_finite_difference() {
        let robot = RobotParams::src().with_mount(Mount::new(0.2, 0.2).unwrap()).unwrap();
        let motion = NormalFormPlanner::default().motion(&PlanningProblem::paper(robot)).unwrap();
        for t in [0.7, 3.3, 5.0, 8.9] {
            let h = 1e-5;
            let (up, um) = (motion.controls(t + h).unwrap(), motion.controls(t - h).unwrap());
            let du = motion.at(t).unwrap().du;
            for i in 0..2 {
                let fd = (up[i] - um[i]) / (2.0 * h);
                assert!((fd - du[i]).abs() < 1e-7 * (1.0 + du[i].abs()), "t = {t}: {fd} vs {}", du[i]);
            }
        }
    }

    /// The fast `du` of Eq. (14) equals the generic one (nested dual numbers through the inverse
    /// feedback) to 1e-12 relative, on the paper's mounts and two others, along the whole path.
    #[test]
    fn eq14_control_rate_matches_nested_dual_numbers() {
        for (a, b) in [(0.1, 0.1), (0.2, 0.2), (0.3, 0.3), (0.2, 0.05), (-0.1, 0.1)] {
            let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
            let motion = NormalFormPlanner::default().motion(&PlanningProblem::paper(robot)).unwrap();
            for i in (0..motion.t.len()).step_by(50) {
                let (q, u, t) = (motion.q[i], motion.u[i], motion.t[i]);
                let fast = motion.point_with_controls(q, u, t).du;
                let reference = motion.point_by_dual_numbers(q, u, t).du;
                for j in 0..2 {
                    let tol = 1e-12 * (1.0 + reference[j].abs());
                    assert!((fast[j] - reference[j]).abs() <= tol, "t = {t}: {fast:?} vs {reference:?}");
                }
            }
        }
    }

    #[test]
    fn path_leaving_the_domain_is_an_error() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        let options = NfaOptions { transform: Some(Transform::Eq14), ..Default::default() };
        let r = NormalFormPlanner::new(options).plan(&PlanningProblem::paper(robot));
        assert!(
            matches!(r, Err(Error::Singular { .. } | Error::NewtonFailed { .. } | Error::DifferentComponents { .. })),
            "{r:?}"
        );
    }

    #[test]
    fn goal_in_the_other_branch_is_an_error() {
        let robot = RobotParams::src();
        let mut problem = PlanningProblem::paper(robot);
        problem.goal.theta2 = -problem.goal.theta2;
        for transform in [Transform::Eq11, Transform::Eq12, Transform::Eq14] {
            let options = NfaOptions { transform: Some(transform), ..Default::default() };
            let r = NormalFormPlanner::new(options).plan(&problem);
            assert!(matches!(r, Err(Error::DifferentComponents { .. })), "{transform:?}: {r:?}");
        }
    }

    /// Beyond the paper: the global normal form plans the paper's problem for the paper's mounts
    /// and for the "impossible" a = 1, b = -1 and other mounts with |a|, |b| <= 1, certified to
    /// 1e-9, never through sigma = 0 (its sign is checked at every sample, and the verified path
    /// stays within 1e-9 of the planned one).
    #[test]
    fn global_normal_form_plans_where_the_paper_cannot() {
        let mounts = [
            (0.0, 0.0),
            (0.1, 0.1),
            (0.2, 0.2),
            (0.3, 0.3),
            (1.0, -1.0),
            (0.5, 0.5),
            (0.7, 0.0),
            (-1.0, 1.0),
            (0.0, -1.0),
            (-0.5, -0.5),
        ];
        for (a, b) in mounts {
            let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
            let problem = PlanningProblem::paper(robot);
            let options = NfaOptions { transform: Some(Transform::Global), ..Default::default() };
            let plan = NormalFormPlanner::new(options).plan(&problem).unwrap_or_else(|e| panic!("({a}, {b}): {e}"));
            let v = &plan.verification;
            assert!(v.final_error <= 1e-9 && v.max_path_deviation <= 1e-9, "({a}, {b}): {v:?}");
            assert!(plan.min_abs_sigma > 1e-3, "({a}, {b}): min |sigma| {}", plan.min_abs_sigma);
            let k = robot.lumped();
            let sign = crate::system::shape(&k, problem.start.theta1, problem.start.theta2).sigma.signum();
            for q in &plan.trajectory.q {
                assert!(crate::system::shape(&k, q[1], q[2]).sigma * sign > 0.0);
            }
        }
    }

    /// The band steering's controls vanish at both ends and its chained-form path meets zd.
    #[test]
    fn band_steering_starts_and_ends_at_rest() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        let problem = PlanningProblem::paper(robot);
        let options = NfaOptions { transform: Some(Transform::Global), ..Default::default() };
        let motion = NormalFormPlanner::new(options).motion(&problem).unwrap();
        assert!(motion.steering.band_choice().is_some());
        let (z0, zd) = motion.steering.ends();
        for (t, z) in [(0.0, z0), (problem.horizon, zd)] {
            let p = motion.steering.at(t);
            for (i, (got, want)) in p.z.iter().zip(z).enumerate() {
                assert!((got - want).abs() < 1e-12, "z{} at t = {t}: {got} vs {want}", i + 1);
            }
            assert!(p.v.iter().all(|v| v.abs() < 1e-12), "{:?}", p.v);
        }
        // z3' = z2 v1 along the path, by a central difference of the quadrature.
        for t in [1.3, 4.4, 7.9] {
            let h = 1e-4;
            let dz3 = (motion.steering.at(t + h).z[2] - motion.steering.at(t - h).z[2]) / (2.0 * h);
            let p = motion.steering.at(t);
            assert!((dz3 - p.z[1] * p.v[0]).abs() < 1e-6 * (1.0 + dz3.abs()), "t = {t}: {dz3} vs {}", p.z[1] * p.v[0]);
        }
    }
}
