//! A planned motion, exact at any time, and its sampled trajectory.

use serde::Serialize;

use crate::error::Error;
use crate::model::RobotParams;
use crate::model::kinematics::task_point;
pub use crate::model::system::MotionPoint;
use crate::numerics::extremum::refined_peak;

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
    /// certificates integrate one piece at a time between them. Default: none.
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
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
    /// Base centre of mass `(xb, yb)` \[m\], inertial frame, the system's centre of mass at the
    /// origin ([`task_point`]).
    pub base: Vec<[f64; 2]>,
    /// End-effector pose `(xe, ye, psie)` \[m, m, rad\].
    pub end_effector: Vec<[f64; 3]>,
    /// End-effector velocity `(xe', ye', psie')` \[m/s, m/s, rad/s\].
    pub end_effector_velocity: Vec<[f64; 3]>,
}

impl Trajectory {
    /// Fills the task-space columns ([`Trajectory::base`], [`Trajectory::end_effector`] and its
    /// velocity) from `q` and `q'` by the robot's kinematics.
    pub fn add_task_space(&mut self, robot: &RobotParams) {
        let points: Vec<_> = self.q.iter().zip(&self.dq).map(|(q, dq)| task_point(robot, *q, *dq)).collect();
        self.base = points.iter().map(|p| p.base).collect();
        self.end_effector = points.iter().map(|p| p.end_effector).collect();
        self.end_effector_velocity = points.iter().map(|p| p.end_effector_velocity).collect();
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

/// `[max |u1|, max |u2|]` \[rad/s\] of `motion` over `[0, T]`, not only at the samples: the
/// samples' largest values of `trajectory`, each component's sampled local maxima near the top
/// refined by golden-section search on the exact [`Motion::controls`] between their neighbouring
/// samples ([`refined_peak`]: those within twice the largest change between two samples of the
/// sampled maximum, to `1e-9 T` in time).
pub fn peak_controls(motion: &dyn Motion, trajectory: &Trajectory) -> Result<[f64; 2], Error> {
    let mut peak = max_abs_controls(trajectory);
    for (k, p) in peak.iter_mut().enumerate() {
        let values: Vec<f64> = trajectory.dq.iter().map(|dq| dq[k + 1].abs()).collect();
        let u = |t: f64| motion.controls(t).map(|u| u[k].abs());
        *p = p.max(refined_peak(u, &trajectory.t, &values)?);
    }
    Ok(peak)
}

/// The control effort `integral_0^T |u(t)|^2 dt` \[rad^2/s\] of a trajectory, from the samples of
/// `u = (dtheta1, dtheta2)` by the composite Simpson rule (Simpson's 3/8 rule on the last three
/// intervals when their number is odd, the trapezoid for one interval): error `O(h^4)` for smooth
/// controls. Planners that know their effort exactly replace it (the optimal planner does).
pub fn effort(trajectory: &Trajectory) -> f64 {
    let (t, dq) = (&trajectory.t, &trajectory.dq);
    let f: Vec<f64> = dq.iter().map(|d| d[1] * d[1] + d[2] * d[2]).collect();
    let n = f.len().saturating_sub(1);
    if n == 0 {
        return 0.0;
    }
    let h = (t[n] - t[0]) / n as f64;
    if n == 1 {
        return h * (f[0] + f[1]) / 2.0;
    }
    let simpson = |f: &[f64]| -> f64 {
        let m = f.len() - 1;
        let inner: f64 = (1..m).map(|i| if i % 2 == 1 { 4.0 * f[i] } else { 2.0 * f[i] }).sum();
        h / 3.0 * (f[0] + inner + f[m])
    };
    if n.is_multiple_of(2) {
        simpson(&f)
    } else {
        let (head, tail) = (&f[..=n - 3], &f[n - 3..]);
        let head = if head.len() > 1 { simpson(head) } else { 0.0 };
        head + 3.0 * h / 8.0 * (tail[0] + 3.0 * tail[1] + 3.0 * tail[2] + tail[3])
    }
}
