//! A planned motion, exact at any time, and its sampled trajectory.

use serde::Serialize;

use crate::error::Error;
pub use crate::model::system::MotionPoint;

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
