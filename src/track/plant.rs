//! The plant: the 6-state forward dynamics of the true robot (Sec. 3.1, Eqs. 3 and 6, base
//! unactuated) under a torque held constant between control ticks, with the actuators' noise,
//! bias and limits and the sensors' noise.

use serde::Serialize;

use super::noise::Noise;
use crate::dynamics::forward_dynamics;
use crate::error::Error;
use crate::model::{Configuration, InputError, Lumped, RobotParams};

/// Imperfections of the actuators and sensors. The defaults are ideal: no noise, no bias, no
/// limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Disturbances {
    /// Relative torque noise: each tick the applied torque is `tau (1 + n)`, `n` normal with this
    /// standard deviation; default 0.
    pub torque_noise: f64,
    /// Torque bias added to each joint's torque `(tau1, tau2)` [N m]; default 0.
    pub torque_bias: [f64; 2],
    /// Saturation `|tau_i| <= torque_limit` of the commanded torque [N m]; default infinite.
    pub torque_limit: f64,
    /// Standard deviation of the measurement noise on each angle of `q` \[rad\]; default 0.
    pub q_noise: f64,
    /// Standard deviation of the measurement noise on each component of `q'` [rad/s]; default 0.
    pub dq_noise: f64,
}

impl Default for Disturbances {
    fn default() -> Self {
        Self { torque_noise: 0.0, torque_bias: [0.0; 2], torque_limit: f64::INFINITY, q_noise: 0.0, dq_noise: 0.0 }
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
        for value in self.torque_bias {
            if !value.is_finite() {
                return bad("torque-bias", value, "a finite torque [N m]");
            }
        }
        if !(self.torque_limit > 0.0) {
            return bad("torque-limit", self.torque_limit, "a positive torque [N m]");
        }
        Ok(())
    }
}

/// A measured (or true) state: configuration and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct State {
    /// `q = (phi, theta1, theta2)` \[rad\].
    pub q: Configuration,
    /// `q'` [rad/s].
    pub dq: [f64; 3],
}

/// What one tick applied to the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Applied {
    /// The torque on the joints, after saturation, noise and bias [N m].
    pub tau: [f64; 2],
    /// The command exceeded the limit on some joint.
    pub saturated: bool,
}

/// The true robot in motion.
#[derive(Debug, Clone)]
pub struct Plant {
    k: Lumped,
    state: [f64; 6],
    disturbances: Disturbances,
    actuator: Noise,
    sensor: Noise,
}

impl Plant {
    /// The robot `robot` at rest at `start`; its noise streams are those of `seed` (streams 1
    /// and 2 of [`Noise`]).
    pub fn new(robot: &RobotParams, start: Configuration, disturbances: Disturbances, seed: u64) -> Self {
        let q = start.to_array();
        Self {
            k: robot.lumped(),
            state: [q[0], q[1], q[2], 0.0, 0.0, 0.0],
            disturbances,
            actuator: Noise::new(seed, 1),
            sensor: Noise::new(seed, 2),
        }
    }

    /// The same plant with the joints moving at `velocity` \[rad/s\] and the base at zero angular
    /// momentum (Eq. 7), for a problem with a moving start.
    pub fn moving(mut self, velocity: [f64; 2]) -> Self {
        let q = [self.state[0], self.state[1], self.state[2]];
        let dq = crate::model::system::velocity(&self.k, q, velocity);
        self.state[3..].copy_from_slice(&dq);
        self
    }

    /// The true state.
    pub fn state(&self) -> State {
        let s = self.state;
        State { q: Configuration::new(s[0], s[1], s[2]), dq: [s[3], s[4], s[5]] }
    }

    /// The state as the sensors report it: the true state plus Gaussian noise.
    pub fn measure(&mut self) -> State {
        let d = self.disturbances;
        let s = self.state;
        let mut noisy = |x: f64, sd: f64| if sd > 0.0 { x + sd * self.sensor.normal() } else { x };
        State {
            q: Configuration::new(noisy(s[0], d.q_noise), noisy(s[1], d.q_noise), noisy(s[2], d.q_noise)),
            dq: [noisy(s[3], d.dq_noise), noisy(s[4], d.dq_noise), noisy(s[5], d.dq_noise)],
        }
    }

    /// Applies the command `tau` [N m] (saturated, then with noise and bias) for `dt` seconds,
    /// held constant (zero-order hold), integrating the forward dynamics by `substeps` classical
    /// Runge–Kutta steps. A diverging motion leaves a non-finite state ([`Plant::is_finite`]),
    /// never a panic.
    pub fn step(&mut self, tau: [f64; 2], dt: f64, substeps: usize) -> Applied {
        let d = self.disturbances;
        let saturated = tau.iter().any(|t| t.abs() > d.torque_limit);
        let mut applied = [0.0; 2];
        for (out, t) in applied.iter_mut().zip(tau) {
            let t = t.clamp(-d.torque_limit, d.torque_limit);
            let noise = if d.torque_noise > 0.0 { d.torque_noise * self.actuator.normal() } else { 0.0 };
            *out = t * (1.0 + noise);
        }
        applied = [applied[0] + d.torque_bias[0], applied[1] + d.torque_bias[1]];
        let k = self.k;
        let f = |y: &[f64; 6]| -> [f64; 6] {
            let q = Configuration::new(y[0], y[1], y[2]);
            let ddq = forward_dynamics(&k, &q, [y[3], y[4], y[5]], [0.0, applied[0], applied[1]]);
            [y[3], y[4], y[5], ddq[0], ddq[1], ddq[2]]
        };
        let h = dt / substeps.max(1) as f64;
        let axpy = |y: &[f64; 6], a: f64, k: &[f64; 6]| -> [f64; 6] { std::array::from_fn(|i| y[i] + a * k[i]) };
        for _ in 0..substeps.max(1) {
            let y = self.state;
            let k1 = f(&y);
            let k2 = f(&axpy(&y, h / 2.0, &k1));
            let k3 = f(&axpy(&y, h / 2.0, &k2));
            let k4 = f(&axpy(&y, h, &k3));
            self.state = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        }
        Applied { tau: applied, saturated }
    }

    /// True while the state is finite (the simulated motion has not diverged).
    pub fn is_finite(&self) -> bool {
        self.state.iter().all(|x| x.is_finite())
    }
}
