//! The NFA's planned motion: the chained-form path mapped back through the inverse feedback.

use num_dual::Dual64;

use super::normal_form::{NormalForm, Transform};
use super::steering::Steering;
use crate::error::Error;
use crate::model::Configuration;
use crate::model::system::{velocity, velocity_acceleration};
use crate::plan::{Motion, MotionPoint, PlanningProblem, Trajectory};

/// The NFA's planned motion: the chained-form path mapped back through the inverse feedback,
/// exact at any time (the samples only warm-start Newton's method).
#[derive(Debug, Clone)]
pub struct NfaMotion {
    /// The feedback transformation on the start's piece of its domain.
    pub nf: NormalForm,
    /// The chained-form path.
    pub steering: Steering,
    pub(super) t: Vec<f64>,
    pub(super) z: Vec<[f64; 3]>,
    pub(super) q: Vec<Configuration>,
    pub(super) u: Vec<[f64; 2]>,
    /// `(min |sigma|, min |P|)` over the samples.
    pub(super) margins: (f64, f64),
    /// Every `stride`-th stored sample is a reported one; the others only carry the
    /// continuation of Newton's method through a band path's loops.
    stride: usize,
}

/// Newton's continuation along a band path takes at least this many steps per loop (and per
/// path without loops), whatever the number of reported samples: a step of a fifth of a loop
/// or more can warm-start Newton on the wrong side of the band.
const STEPS_PER_LOOP: usize = 100;

impl NfaMotion {
    pub(super) fn new(nf: NormalForm, steering: Steering) -> Self {
        Self {
            nf,
            steering,
            t: Vec::new(),
            z: Vec::new(),
            q: Vec::new(),
            u: Vec::new(),
            margins: (f64::INFINITY, f64::INFINITY),
            stride: 1,
        }
    }

    /// Inverts the path at `samples` equally spaced times, each Newton run warm-started from the
    /// previous sample (first-order prediction), and checks that the path stays in the domain.
    /// A band path is inverted at [`STEPS_PER_LOOP`] times per loop at least, of which the
    /// reported samples are every `stride`-th.
    pub(super) fn sample(&mut self, problem: &PlanningProblem, samples: usize) -> Result<(), Error> {
        let horizon = problem.horizon;
        let needed = self.steering.band_choice().map_or(1, |c| STEPS_PER_LOOP * (c.loops + 1));
        self.stride = needed.div_ceil(samples - 1).max(1);
        let samples = (samples - 1) * self.stride + 1;
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
    pub(super) fn guess(&self, t: f64) -> f64 {
        let n = self.t.len();
        let dt = self.steering.horizon() / (n - 1) as f64;
        let i = ((t / dt).round().max(0.0) as usize).min(n - 1);
        self.q[i].theta2 + self.u[i][1] * (t - self.t[i])
    }

    /// The sampled trajectory (with accelerations when asked) at the reported samples.
    pub fn trajectory(&self, problem: &PlanningProblem, accelerations: bool) -> Result<Trajectory, Error> {
        let k = problem.robot.lumped();
        let every = |n: usize| (0..n).step_by(self.stride);
        let reported: Vec<usize> = every(self.t.len()).collect();
        let dq = reported.iter().map(|&i| velocity(&k, self.q[i].to_array(), self.u[i])).collect();
        let ddq = if accelerations {
            let mut ddq = Vec::with_capacity(reported.len());
            for &i in &reported {
                let m = self.point_with_controls(self.q[i], self.u[i], self.t[i]);
                ddq.push(velocity_acceleration(&k, &m.q, m.u, m.du).1);
            }
            Some(ddq)
        } else {
            None
        };
        Ok(Trajectory {
            t: reported.iter().map(|&i| self.t[i]).collect(),
            q: reported.iter().map(|&i| self.q[i].to_array()).collect(),
            dq,
            ddq,
            z: Some(reported.iter().map(|&i| self.z[i]).collect()),
            ..Default::default()
        })
    }

    /// `(min |sigma|, min |P|)` along the samples: the domain margins.
    pub fn margins(&self) -> (f64, f64) {
        self.margins
    }

    /// The motion at `t` given the planned configuration there: `u` by the inverse feedback and
    /// `du` exactly, by dual numbers through the polynomial path and the feedback.
    pub(super) fn point(&self, q: Configuration, t: f64) -> Result<MotionPoint, Error> {
        let p = self.steering.at(t);
        let u = self.nf.control(q.to_array(), p.v);
        Ok(self.point_with_controls(q, u, t))
    }

    /// [`NfaMotion::point`] when `u` at `(q, t)` is already known. Eq. (14) takes the fast path
    /// [`eq14_control_rate`]; the others differentiate the inverse feedback with dual numbers.
    pub(super) fn point_with_controls(&self, q: Configuration, u: [f64; 2], t: f64) -> MotionPoint {
        if self.nf.transform() == Transform::Eq14 {
            let dv = self.steering.at_dual(t).v;
            let du = eq14_control_rate(self.nf.lumped(), self.nf.branch(), &q, u, [dv[0].eps, dv[1].eps]);
            return MotionPoint { q, u, du };
        }
        self.point_by_dual_numbers(q, u, t)
    }

    /// `du` by dual numbers through the inverse feedback: `u' = d/dt control(q(t), v(t))`.
    pub(super) fn point_by_dual_numbers(&self, q: Configuration, u: [f64; 2], t: f64) -> MotionPoint {
        let p = self.steering.at_dual(t);
        let dq = velocity(self.nf.lumped(), q.to_array(), u);
        let qa = q.to_array();
        let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(qa[i], dq[i]));
        let ud = self.nf.control(qd, p.v);
        MotionPoint { q, u, du: [ud[0].eps, ud[1].eps] }
    }

    /// The index of the sample taken at exactly `t`, if any.
    pub(super) fn sample_index(&self, t: f64) -> Option<usize> {
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
    use crate::model::system::shape;
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
