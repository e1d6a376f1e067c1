//! The plant: the forward dynamics of the true arm (Eqs. 3 and 6 for `n` links, base
//! unactuated, [`crate::dynamics::arm::ArmDynamics::forward`]) under a torque held constant between
//! control ticks, with the actuators' noise, bias and limits and the sensors' noise.

use serde::Serialize;

use super::noise::Noise;
use crate::dynamics::arm::ArmDynamics;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::lumped::SIZE;
use crate::model::arm::{Arm, Limits};

/// Imperfections of the actuators and sensors. The defaults are ideal: no noise, no bias, no
/// limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Disturbances {
    /// Relative torque noise: each tick the applied torque is `tau (1 + n)`, `n` normal with this
    /// standard deviation; default 0.
    pub torque_noise: f64,
    /// Torque bias added to each joint's torque `(tau_1, .., tau_n)` [N m]; default empty (none).
    /// Empty or one value per joint.
    pub torque_bias: Vec<f64>,
    /// Saturation `|tau_i| <= torque_limit` of the commanded torque [N m]; default infinite.
    pub torque_limit: f64,
    /// Standard deviation of the measurement noise on each angle of `q` \[rad\]; default 0.
    pub q_noise: f64,
    /// Standard deviation of the measurement noise on each component of `q'` [rad/s]; default 0.
    pub dq_noise: f64,
}

impl Default for Disturbances {
    fn default() -> Self {
        Self { torque_noise: 0.0, torque_bias: Vec::new(), torque_limit: f64::INFINITY, q_noise: 0.0, dq_noise: 0.0 }
    }
}

impl Disturbances {
    /// Checks the values: noise levels finite and in `[0, 1]`, bias finite, limit positive.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name: &str, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value, expected }))
        };
        for (name, value) in
            [("torque-noise", self.torque_noise), ("noise-q", self.q_noise), ("noise-dq", self.dq_noise)]
        {
            if !(0.0..=1.0).contains(&value) {
                return bad(name, value, "a standard deviation in [0, 1]");
            }
        }
        for &value in &self.torque_bias {
            if !value.is_finite() {
                return bad("torque-bias", value, "a finite torque [N m]");
            }
        }
        if !(self.torque_limit > 0.0) {
            return bad("torque-limit", self.torque_limit, "a positive torque [N m]");
        }
        Ok(())
    }

    /// Checks the bias against an arm of `n` joints: none, or one torque per joint.
    pub fn check_joints(&self, n: usize) -> Result<(), Error> {
        if self.torque_bias.is_empty() || self.torque_bias.len() == n {
            return Ok(());
        }
        Err(InputError::InvalidParameter {
            name: "torque-bias".into(),
            value: self.torque_bias.len() as f64,
            expected: "one torque bias per joint of the arm (TAU1,..,TAUn in N m)",
        }
        .into())
    }
}

/// A measured (or true) state: configuration and velocity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct State {
    /// `q = (phi, theta_1, .., theta_n)` \[rad\].
    pub q: Vec<f64>,
    /// `q'` [rad/s].
    pub dq: Vec<f64>,
}

impl State {
    /// The joint angles `theta = q[1..]` \[rad\].
    pub fn theta(&self) -> &[f64] {
        &self.q[1..]
    }
}

/// What one tick applied to the robot.
#[derive(Debug, Clone, PartialEq)]
pub struct Applied {
    /// The torque on the joints, after saturation, noise and bias [N m].
    pub tau: Vec<f64>,
    /// The command exceeded the limit on some joint.
    pub saturated: bool,
    /// The first declared limit the true motion broke during the tick, checked after every
    /// integrator step ([`Plant::step`]): `position_limit` (a joint left its range),
    /// `base_limit` (the base angle left its range) or `velocity_limit`; `None` within them
    /// (always for an arm without limits).
    pub broken: Option<&'static str>,
}

/// A callback `(t, q, q')` on the plant's true state \[s, rad, rad/s\] ([`Plant::step_observed`]).
pub type StateObserver<'a> = dyn FnMut(f64, &[f64], &[f64]) + 'a;

/// The true robot in motion.
#[derive(Debug, Clone)]
pub struct Plant {
    arm: Arm,
    dynamics: ArmDynamics,
    /// `(q, q')`, `2 (n + 1)` values.
    state: Vec<f64>,
    disturbances: Disturbances,
    actuator: Noise,
    sensor: Noise,
}

impl Plant {
    /// The arm `arm` at rest at `start` (`n + 1` angles); its noise streams are those of `seed`
    /// (streams 1 and 2 of [`Noise`]).
    pub fn new(arm: &Arm, start: &[f64], disturbances: Disturbances, seed: u64) -> Self {
        let mut state = start.to_vec();
        state.resize(2 * start.len(), 0.0);
        Self {
            arm: arm.clone(),
            dynamics: ArmDynamics::new(arm),
            state,
            disturbances,
            actuator: Noise::new(seed, 1),
            sensor: Noise::new(seed, 2),
        }
    }

    /// The same plant with the joints moving at `velocity` \[rad/s\] (`n` values) and the base at
    /// zero angular momentum (Eq. 7), for a problem with a moving start.
    pub fn moving(mut self, velocity: &[f64]) -> Self {
        let n = self.arm.joints();
        let phi_rate = self.arm.base_rate(&self.state[1..=n], velocity);
        self.state[n + 1] = phi_rate;
        self.state[n + 2..].copy_from_slice(velocity);
        self
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.arm.joints()
    }

    /// The true state.
    pub fn state(&self) -> State {
        let m = self.state.len() / 2;
        State { q: self.state[..m].to_vec(), dq: self.state[m..].to_vec() }
    }

    /// The state as the sensors report it: the true state plus Gaussian noise.
    pub fn measure(&mut self) -> State {
        let (q_noise, dq_noise) = (self.disturbances.q_noise, self.disturbances.dq_noise);
        let m = self.state.len() / 2;
        let mut noisy = |x: f64, sd: f64| if sd > 0.0 { x + sd * self.sensor.normal() } else { x };
        let q = self.state[..m].iter().map(|&x| noisy(x, q_noise)).collect();
        let dq = self.state[m..].iter().map(|&x| noisy(x, dq_noise)).collect();
        State { q, dq }
    }

    /// The torque limit of joint `j` (0-based) [N m]: the smaller of the arm's declared limit
    /// ([`crate::model::arm::JointLimits::torque`]) and the user's cap
    /// [`Disturbances::torque_limit`]; infinite when neither is set.
    pub fn torque_limit(&self, j: usize) -> f64 {
        let declared = self.arm.limits.joint(j).torque.unwrap_or(f64::INFINITY);
        declared.min(self.disturbances.torque_limit)
    }

    /// The torque applied for the command `tau` [N m]: each joint's command clamped to
    /// `[-limit, limit]` ([`Plant::torque_limit`]), times `1 + noise`, plus the bias; and whether
    /// some joint saturated.
    pub fn actuate(&mut self, tau: &[f64]) -> Applied {
        let limits: Vec<f64> = (0..tau.len()).map(|j| self.torque_limit(j)).collect();
        let d = &self.disturbances;
        let saturated = tau.iter().zip(&limits).any(|(t, l)| t.abs() > *l);
        let mut applied = Vec::with_capacity(tau.len());
        for (j, t) in tau.iter().enumerate() {
            let t = t.clamp(-limits[j], limits[j]);
            let noise = if d.torque_noise > 0.0 { d.torque_noise * self.actuator.normal() } else { 0.0 };
            applied.push(t * (1.0 + noise) + d.torque_bias.get(j).copied().unwrap_or(0.0));
        }
        Applied { tau: applied, saturated, broken: None }
    }

    /// Applies the command `tau` [N m] (`n` values; saturated, then with noise and bias, see
    /// [`Plant::actuate`]) for `dt` seconds, held constant (zero-order hold), integrating the
    /// forward dynamics by `substeps` classical Runge–Kutta steps. A diverging motion (or an
    /// inertia matrix that is no longer positive definite) leaves a non-finite state
    /// ([`Plant::is_finite`]), never a panic. After every step the state is held to the arm's
    /// declared position, base and velocity limits ([`Applied::broken`]).
    pub fn step(&mut self, tau: &[f64], dt: f64, substeps: usize) -> Applied {
        self.step_observed(tau, dt, substeps, 0.0, &mut |_, _, _| {})
    }

    /// [`Plant::step`] from the time `t0` \[s\], calling `observe(t, q, q')` with the true state
    /// after every finite integrator step (`t = t0 + (i + 1) dt / substeps`): the clearance of
    /// the true motion is watched there ([`crate::plan::clearance::ClearanceMonitor`]).
    pub fn step_observed(
        &mut self,
        tau: &[f64],
        dt: f64,
        substeps: usize,
        t0: f64,
        observe: &mut StateObserver<'_>,
    ) -> Applied {
        let mut applied = self.actuate(tau);
        let torque = applied.tau.as_slice();
        let limits = &self.arm.limits;
        let mut broken = None;
        let dynamics = &self.dynamics;
        let m = self.state.len() / 2;
        let len = 2 * m;
        // The state's derivative `(q', q'')` into `out`; NaN where the dynamics cannot be
        // evaluated (the state stops being finite).
        let f = |y: &[f64], out: &mut [f64]| {
            out[..m].copy_from_slice(&y[m..len]);
            if dynamics.forward(&y[1..m], &y[m..len], torque, &mut out[m..len]).is_err() {
                out[..len].fill(f64::NAN);
            }
        };
        let h = dt / substeps.max(1) as f64;
        let mut y = [0.0; 2 * SIZE];
        y[..len].copy_from_slice(&self.state);
        let (mut k1, mut k2, mut k3, mut k4, mut stage) =
            ([0.0; 2 * SIZE], [0.0; 2 * SIZE], [0.0; 2 * SIZE], [0.0; 2 * SIZE], [0.0; 2 * SIZE]);
        let axpy = |stage: &mut [f64], y: &[f64], a: f64, k: &[f64]| {
            for i in 0..len {
                stage[i] = y[i] + a * k[i];
            }
        };
        for i in 0..substeps.max(1) {
            if !y[..len].iter().all(|x| x.is_finite()) {
                break;
            }
            f(&y, &mut k1);
            axpy(&mut stage, &y, h / 2.0, &k1);
            f(&stage, &mut k2);
            axpy(&mut stage, &y, h / 2.0, &k2);
            f(&stage, &mut k3);
            axpy(&mut stage, &y, h, &k3);
            f(&stage, &mut k4);
            for i in 0..len {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if broken.is_none() && !limits.is_empty() {
                broken = broken_limit(limits, &y[..m], &y[m..len]);
            }
            if y[..len].iter().all(|x| x.is_finite()) {
                observe(t0 + (i + 1) as f64 * h, &y[..m], &y[m..len]);
            }
        }
        self.state.copy_from_slice(&y[..len]);
        applied.broken = broken;
        applied
    }

    /// The declared limits of the true arm.
    pub fn limits(&self) -> &Limits {
        &self.arm.limits
    }

    /// True while the state is finite (the simulated motion has not diverged).
    pub fn is_finite(&self) -> bool {
        self.state.iter().all(|x| x.is_finite())
    }
}

/// The first limit of `limits` that the state `(q, q')` breaks: a joint angle outside its
/// position range (`position_limit`), the base angle outside its range (`base_limit`), a joint
/// velocity above its limit (`velocity_limit`); `None` within all of them. A non-finite state
/// breaks none (it is the divergence, reported as such).
pub fn broken_limit(limits: &Limits, q: &[f64], dq: &[f64]) -> Option<&'static str> {
    let outside = |x: f64, [lo, hi]: [f64; 2]| x < lo || x > hi;
    if limits.base.is_some_and(|r| outside(q[0], r)) {
        return Some("base_limit");
    }
    for (i, joint) in limits.joints.iter().enumerate() {
        if joint.position.is_some_and(|r| outside(q[i + 1], r)) {
            return Some("position_limit");
        }
        if joint.velocity.is_some_and(|v| dq[i + 1].abs() > v) {
            return Some("velocity_limit");
        }
    }
    None
}
