//! The control laws, all on a model of the robot (the nominal one, or the identified one): the
//! planned torques alone, and computed torque with PD feedback on the joint angles, for an arm of
//! any number of joints.

use serde::{Deserialize, Serialize};

use super::motion::JointPoint;
use super::plant::State;
use crate::dynamics::arm::{ArmDynamics, inverse_dynamics};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::arm::lumped::SIZE;

/// The controller of a closed-loop run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Controller {
    /// Open loop: the planned torques (inverse dynamics of the plan on the model, Eq. 6).
    Open,
    /// Computed torque with PD feedback on the joint angles around the plan
    /// ([`computed_torque`]).
    Ct,
    /// [`Controller::Ct`] plus receding-horizon re-planning on the nominal model from the measured
    /// state to the goal in the remaining time.
    Replan,
    /// [`Controller::Replan`] on a model whose momentum map is identified on line (default).
    #[default]
    Adaptive,
}

impl Controller {
    /// All controllers, weakest first.
    pub const ALL: [Controller; 4] = [Controller::Open, Controller::Ct, Controller::Replan, Controller::Adaptive];

    /// `open`, `ct`, `replan` or `adaptive`, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Controller::Open => "open",
            Controller::Ct => "ct",
            Controller::Replan => "replan",
            Controller::Adaptive => "adaptive",
        }
    }

    /// The controller named `name` ([`Controller::name`]).
    pub fn from_name(name: &str) -> Option<Controller> {
        Controller::ALL.into_iter().find(|c| c.name() == name)
    }

    /// True for the controllers that re-plan.
    pub fn replans(self) -> bool {
        matches!(self, Controller::Replan | Controller::Adaptive)
    }
}

/// PD gains of the joint loop: `theta''_cmd = theta''_ref + kd e' + kp e`, `e = theta_ref -
/// theta`. The defaults ([`Gains::for_rate`]) make each joint's error a critically damped
/// second-order system with natural frequency `min(200, rate / 5)` rad/s: `kp = 40000 1/s^2`,
/// `kd = 400 1/s` at the default 1 kHz.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gains {
    /// Proportional gain [1/s^2].
    pub kp: f64,
    /// Derivative gain [1/s].
    pub kd: f64,
}

impl Default for Gains {
    /// [`Gains::for_rate`] at the default control rate, 1 kHz.
    fn default() -> Self {
        Self::for_rate(1000.0)
    }
}

/// Highest natural frequency of the default joint loop \[rad/s\] ([`Gains::for_rate`]).
pub const DEFAULT_BANDWIDTH: f64 = 200.0;

impl Gains {
    /// The default gains at a control rate \[Hz\]: critically damped (`kd = 2 w`, `kp = w^2`)
    /// at the natural frequency `w = min(200, rate / 5)` rad/s, so that `kd dt <= 0.4` and
    /// `kp dt <= kd / 10` ([`Gains::validate_sampled`]) at every rate.
    ///
    /// The joint error under a white relative torque noise of standard deviation `s` has the
    /// variance `(s tau / m)^2 dt / (2 kp kd) = (s tau / m)^2 dt / (4 w^3)` (`m` the inertia the
    /// noise drives), so a stiffer loop is the remedy where a plan brakes hard at its end: on the
    /// hard set of issue 22 (`examples/hard_set.rs`, 1 % torque noise), `w = 50` ended 6 of 20
    /// problems below 95 % of trials within 1e-3 rad; `w = 200` ended none.
    pub fn for_rate(rate: f64) -> Self {
        let w = (rate / 5.0).min(DEFAULT_BANDWIDTH);
        Self { kp: w * w, kd: 2.0 * w }
    }

    /// Checks the gains: finite, `kp >= 0`, `kd >= 0`.
    pub fn validate(&self) -> Result<(), Error> {
        for (name, value) in [("kp", self.kp), ("kd", self.kd)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(
                    InputError::InvalidParameter { name: name.into(), value, expected: "a finite gain >= 0" }.into()
                );
            }
        }
        Ok(())
    }
}

/// Largest gains accepted: `kp` \[1/s^2\] and `kd` \[1/s\] (with the sampled-loop bounds of
/// [`Gains::validate_sampled`]).
pub const MAX_GAINS: (f64, f64) = (1e10, 1e6);

impl Gains {
    /// Checks the gains against the control rate \[Hz\] so that the sampled loop stays finite.
    /// The joint error under a held PD law at tick `dt = 1 / rate` is stable on the model when
    /// `kd dt < 2` and `kp dt < 2 kd` (Jury's test on the zero-order-held double integrator);
    /// freefloat asks for half of each margin, `kd dt <= 1` and `kp dt <= kd`, and
    /// `kp <= 1e10`, `kd <= 1e6` (docs/spec.md §3). Defaults at 1 kHz: `kd dt = 0.4`, `kp dt = 40`.
    pub fn validate_sampled(&self, rate: f64) -> Result<(), Error> {
        let dt = 1.0 / rate;
        let bad = |name: &str, value: f64, expected: &'static str| -> Result<(), Error> {
            Err(InputError::InvalidParameter { name: name.into(), value, expected }.into())
        };
        if self.kp > MAX_GAINS.0 {
            return bad("kp", self.kp, "a gain of at most 1e10 1/s^2");
        }
        if self.kd > MAX_GAINS.1 {
            return bad("kd", self.kd, "a gain of at most 1e6 1/s");
        }
        if self.kd * dt > 1.0 {
            return bad("kd", self.kd, "kd / rate <= 1 for a stable sampled loop: a lower kd or a higher control rate");
        }
        if self.kp * dt > self.kd {
            return bad(
                "kp",
                self.kp,
                "kp / rate <= kd for a stable sampled loop: a lower kp, a higher kd or a higher control rate",
            );
        }
        Ok(())
    }
}

/// Computed torque on the model `arm` with PD feedback on the joint angles, for a torque held
/// over a control tick.
///
/// The joints get the acceleration `a = theta''_ref + kd (theta'_ref - theta') + kp (theta_ref -
/// theta)`; the base, unactuated, takes the acceleration that conserves the angular momentum
/// (the first row of `M q'' + c = (0, tau)`: `phi'' = -(G . a + c_phi)/F`), and the torques are
/// the last `n` rows of `M q'' + c` (Eqs. 3, 6 for `n` links). On the model, with exact
/// measurements and a continuous loop, the joint errors obey `e'' + kd e' + kp e = 0`.
///
/// The law is evaluated at the centre of the tick, `half_tick` \[s\] after the measurement
/// `from`: the state there is predicted from the measurement by the planned acceleration, and
/// `centre` is the plan at that time. The held torque is then the midpoint value of the
/// continuous law, so that the hold costs `O(dt^3)` per tick instead of `O(dt^2)`.
///
/// The base angle is not fed back: no joint loop can correct it (only the holonomy of the joint
/// path moves it), which re-planning does.
pub fn computed_torque(arm: &Arm, from: &State, centre: &JointPoint, half_tick: f64, gains: &Gains) -> Vec<f64> {
    let n = arm.joints();
    let dynamics = ArmDynamics::new(arm);
    // The prediction uses the planned acceleration alone: feedback against a plan half a tick
    // ahead would bias it by `kp u dt / 2`.
    let model = dynamics.model_terms(from.theta(), &from.dq);
    let mut planned = [0.0; SIZE];
    model.accelerations(&centre.acceleration, &mut planned);
    let h = half_tick;
    let (mut mid_q, mut mid_dq) = ([0.0; SIZE], [0.0; SIZE]);
    for i in 0..=n {
        mid_q[i] = from.q[i] + h * from.dq[i] + 0.5 * h * h * planned[i];
        mid_dq[i] = from.dq[i] + h * planned[i];
    }
    let mut a = [0.0; SIZE];
    for (i, a) in a.iter_mut().enumerate().take(n) {
        *a = centre.acceleration[i]
            + gains.kd * (centre.rate[i] - mid_dq[i + 1])
            + gains.kp * (centre.theta[i] - mid_q[i + 1]);
    }
    let model = dynamics.model_terms(&mid_q[1..=n], &mid_dq[..=n]);
    let mut ddq = [0.0; SIZE];
    model.accelerations(&a[..n], &mut ddq);
    let mut forces = [0.0; SIZE];
    model.forces(&ddq, &mut forces);
    forces[1..=n].to_vec()
}

/// The planned torques held over a tick: the inverse dynamics on the model `arm` (Eq. 6 for `n`
/// links, the base at zero momentum) at `centre`, the plan at the centre of the tick (open loop).
pub fn feedforward(arm: &Arm, centre: &JointPoint) -> Vec<f64> {
    inverse_dynamics(arm, &centre.theta, &centre.rate, &centre.acceleration).tau.iter().copied().collect()
}
