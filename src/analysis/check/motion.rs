//! A joint trajectory given by points, interpolated between them as a ROS 2
//! joint_trajectory_controller does (docs/spec.md §3, `check`): a quintic per segment from
//! positions, velocities and accelerations; a cubic (Hermite) from positions and velocities; from
//! positions alone, the C2 cubic spline through them at rest at both ends (a controller's linear
//! interpolation jumps in velocity at every point, which no robot follows).

use serde::Serialize;

use crate::model::arm::Arm;
use crate::plan::certificate::JointMotion;

/// How the points are joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Quintic Hermite per segment: positions, velocities and accelerations met at the points
    /// (C2).
    Quintic,
    /// Cubic Hermite per segment: positions and velocities met at the points (C1).
    Cubic,
    /// The C2 cubic spline through the positions with zero velocity at both ends (positions
    /// only).
    ClampedSpline,
}

impl Interpolation {
    /// `quintic`, `cubic` or `clamped_spline`, as in the JSON report.
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Quintic => "quintic",
            Interpolation::Cubic => "cubic",
            Interpolation::ClampedSpline => "clamped_spline",
        }
    }
}

/// Points of a joint trajectory in the robot's joint order, checked: at least two, times
/// strictly increasing from 0, every value finite, `n` values per given array.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSamples {
    /// Times \[s\], `t_0 = 0 < t_1 < ..`.
    pub t: Vec<f64>,
    /// Joint angles per point \[rad\], `n` values each.
    pub positions: Vec<Vec<f64>>,
    /// Joint velocities per point \[rad/s\], when given.
    pub velocities: Option<Vec<Vec<f64>>>,
    /// Joint accelerations per point \[rad/s^2\], when given (with velocities).
    pub accelerations: Option<Vec<Vec<f64>>>,
}

/// The interpolated motion: per segment and joint, the polynomial's coefficients in
/// `tau = t - t_k` (degree 5; a cubic has zero top coefficients).
#[derive(Debug, Clone)]
pub struct InterpolatedMotion {
    t: Vec<f64>,
    n: usize,
    /// `coefficients[k * n + j]`: segment `k`, joint `j`, `c_0..c_5`.
    coefficients: Vec<[f64; 6]>,
    interpolation: Interpolation,
    arm: Arm,
}

impl InterpolatedMotion {
    /// The motion of `arm`'s joints through `samples` (checked, see [`JointSamples`]; one
    /// value per joint of `arm`).
    pub fn new(arm: &Arm, samples: &JointSamples) -> Self {
        let n = samples.positions.first().map_or(0, Vec::len);
        let segments = samples.t.len().saturating_sub(1);
        let interpolation = match (&samples.velocities, &samples.accelerations) {
            (Some(_), Some(_)) => Interpolation::Quintic,
            (Some(_), None) => Interpolation::Cubic,
            _ => Interpolation::ClampedSpline,
        };
        let spline;
        let velocities = match &samples.velocities {
            Some(v) => v,
            None => {
                spline = clamped_slopes(&samples.t, &samples.positions);
                &spline
            }
        };
        let mut coefficients = Vec::with_capacity(segments * n);
        for k in 0..segments {
            let h = samples.t[k + 1] - samples.t[k];
            for j in 0..n {
                let (p0, p1) = (samples.positions[k][j], samples.positions[k + 1][j]);
                let (v0, v1) = (velocities[k][j], velocities[k + 1][j]);
                coefficients.push(match &samples.accelerations {
                    Some(a) => quintic(h, [p0, v0, a[k][j]], [p1, v1, a[k + 1][j]]),
                    None => cubic(h, [p0, v0], [p1, v1]),
                });
            }
        }
        Self { t: samples.t.clone(), n, coefficients, interpolation, arm: arm.clone() }
    }

    /// How the points are joined.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// The segment of `t`: `k` with `t_k <= t < t_(k+1)`, the last one for `t >= T`.
    fn segment(&self, t: f64) -> usize {
        let last = self.t.len().saturating_sub(2);
        self.t.partition_point(|&x| x <= t).saturating_sub(1).min(last)
    }

    /// Position, velocity and acceleration of joint `j` on segment `k` at `tau = t - t_k`.
    fn eval(&self, k: usize, j: usize, tau: f64) -> [f64; 3] {
        let c = &self.coefficients[k * self.n + j];
        let p = c[0] + tau * (c[1] + tau * (c[2] + tau * (c[3] + tau * (c[4] + tau * c[5]))));
        let v = c[1] + tau * (2.0 * c[2] + tau * (3.0 * c[3] + tau * (4.0 * c[4] + tau * 5.0 * c[5])));
        let a = 2.0 * c[2] + tau * (6.0 * c[3] + tau * (12.0 * c[4] + tau * 20.0 * c[5]));
        [p, v, a]
    }

    /// Positions, velocities and accelerations at `t` on segment `k` (any `t`; used at the
    /// points, where the segment that starts there is taken, the last one at `T`).
    pub fn state_on(&self, k: usize, t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let tau = t - self.t[k];
        let (mut p, mut v, mut a) = (vec![0.0; self.n], vec![0.0; self.n], vec![0.0; self.n]);
        for j in 0..self.n {
            [p[j], v[j], a[j]] = self.eval(k, j, tau);
        }
        (p, v, a)
    }

    /// The segment used for point `i`'s state: the one starting there (the last for the
    /// last point).
    pub fn segment_of_point(&self, i: usize) -> usize {
        i.min(self.t.len().saturating_sub(2))
    }
}

impl JointMotion for InterpolatedMotion {
    fn joints(&self) -> usize {
        self.n
    }

    fn breakpoints(&self) -> &[f64] {
        &self.t
    }

    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        let k = self.segment(t);
        let tau = t - self.t[k];
        for j in 0..self.n {
            let [p, v, _] = self.eval(k, j, tau);
            theta[j] = p;
            rate[j] = v;
        }
    }

    /// The trajectory carries no base: its base rate is the interpolant's at zero momentum
    /// (Eq. 7), so the certificate's momentum check is the integration's consistency (its
    /// `theta` against the interpolant's).
    fn phi_rate(&self, t: f64) -> f64 {
        let (mut theta, mut rate) = (vec![0.0; self.n], vec![0.0; self.n]);
        self.joint_state(t, &mut theta, &mut rate);
        self.arm.base_rate(&theta, &rate)
    }

    fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
        let k = self.segment(t);
        let tau = t - self.t[k];
        for (j, o) in out.iter_mut().enumerate().take(self.n) {
            *o = self.eval(k, j, tau)[2];
        }
    }
}

/// The cubic in `tau` with `p(0), p'(0) = start`, `p(h), p'(h) = end`.
fn cubic(h: f64, start: [f64; 2], end: [f64; 2]) -> [f64; 6] {
    let [p0, v0] = start;
    let [p1, v1] = end;
    let delta = (p1 - p0) / h;
    [p0, v0, (3.0 * delta - 2.0 * v0 - v1) / h, (v0 + v1 - 2.0 * delta) / (h * h), 0.0, 0.0]
}

/// The quintic in `tau` with `p, p', p'' = start` at 0 and `end` at `h`.
fn quintic(h: f64, start: [f64; 3], end: [f64; 3]) -> [f64; 6] {
    let [p0, v0, a0] = start;
    let [p1, v1, a1] = end;
    let d = p1 - p0 - v0 * h - 0.5 * a0 * h * h;
    let e = v1 - v0 - a0 * h;
    let f = a1 - a0;
    let (h2, h3) = (h * h, h * h * h);
    [
        p0,
        v0,
        0.5 * a0,
        (10.0 * d - 4.0 * e * h + 0.5 * f * h2) / h3,
        (-15.0 * d + 7.0 * e * h - f * h2) / (h3 * h),
        (6.0 * d - 3.0 * e * h + 0.5 * f * h2) / (h3 * h2),
    ]
}

/// The slopes of the C2 cubic spline through `(t_k, p_k)` per joint with zero slope at both
/// ends (tridiagonal, strictly diagonally dominant: the Thomas algorithm is stable).
fn clamped_slopes(t: &[f64], p: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let m = t.len();
    let n = p.first().map_or(0, Vec::len);
    let mut slopes = vec![vec![0.0; n]; m];
    if m < 3 {
        return slopes;
    }
    for j in 0..n {
        // Unknowns m_1..m_(m-2): h_i m_(i-1) + 2 (h_(i-1) + h_i) m_i + h_(i-1) m_(i+1)
        // = 3 (h_i d_(i-1) + h_(i-1) d_i), h_i = t_(i+1) - t_i, d_i = (p_(i+1) - p_i) / h_i.
        let inner = m - 2;
        let (mut upper, mut rhs) = (vec![0.0; inner], vec![0.0; inner]);
        let mut previous = (0.0, 0.0);
        for r in 0..inner {
            let i = r + 1;
            let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
            let (d0, d1) = ((p[i][j] - p[i - 1][j]) / h0, (p[i + 1][j] - p[i][j]) / h1);
            let (lower, diagonal, up) = (if r > 0 { h1 } else { 0.0 }, 2.0 * (h0 + h1), h0);
            let value = 3.0 * (h1 * d0 + h0 * d1);
            let pivot = diagonal - lower * previous.0;
            upper[r] = if r + 1 < inner { up / pivot } else { 0.0 };
            rhs[r] = (value - lower * previous.1) / pivot;
            previous = (upper[r], rhs[r]);
        }
        for r in (0..inner).rev() {
            let next = if r + 1 < inner { slopes[r + 2][j] } else { 0.0 };
            slopes[r + 1][j] = rhs[r] - upper[r] * next;
        }
    }
    slopes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(velocities: bool, accelerations: bool) -> JointSamples {
        let t = vec![0.0, 0.3, 1.0, 1.4, 2.5];
        let f = |t: f64| [(1.3 * t).sin(), t * t - 0.5 * t];
        let df = |t: f64| [1.3 * (1.3 * t).cos(), 2.0 * t - 0.5];
        let ddf = |t: f64| [-1.69 * (1.3 * t).sin(), 2.0];
        JointSamples {
            positions: t.iter().map(|&x| f(x).to_vec()).collect(),
            velocities: velocities.then(|| t.iter().map(|&x| df(x).to_vec()).collect()),
            accelerations: accelerations.then(|| t.iter().map(|&x| ddf(x).to_vec()).collect()),
            t,
        }
    }

    /// Each interpolant meets what it was given at every point, from both segments, and the
    /// clamped spline is C2 with zero end velocities.
    #[test]
    fn interpolants_meet_the_points() {
        for (v, a) in [(true, true), (true, false), (false, false)] {
            let s = samples(v, a);
            let motion = InterpolatedMotion::new(&Arm::from_params(&crate::RobotParams::src()), &s);
            for i in 0..s.t.len() {
                for k in [i.saturating_sub(1), motion.segment_of_point(i)] {
                    let (p, dp, ddp) = motion.state_on(k, s.t[i]);
                    for j in 0..2 {
                        assert!((p[j] - s.positions[i][j]).abs() < 1e-12, "{v} {a}: p at {i}");
                        if let Some(vel) = &s.velocities {
                            assert!((dp[j] - vel[i][j]).abs() < 1e-11, "{v} {a}: v at {i}");
                        }
                        if let Some(acc) = &s.accelerations {
                            assert!((ddp[j] - acc[i][j]).abs() < 1e-10, "{v} {a}: a at {i}");
                        }
                    }
                }
                if !v && i > 0 && i + 1 < s.t.len() {
                    let (_, dl, al) = motion.state_on(i - 1, s.t[i]);
                    let (_, dr, ar) = motion.state_on(i, s.t[i]);
                    assert!((dl[0] - dr[0]).abs() < 1e-12 && (al[0] - ar[0]).abs() < 1e-10, "spline C2 at {i}");
                }
            }
            if !v {
                let (_, d0, _) = motion.state_on(0, 0.0);
                let (_, d1, _) = motion.state_on(3, 2.5);
                assert!(d0.iter().chain(&d1).all(|x| x.abs() < 1e-12), "{d0:?} {d1:?}");
            }
        }
    }

    /// A quintic reproduces a polynomial of degree 5 exactly; a cubic one of degree 3.
    #[test]
    fn hermite_reproduces_polynomials() {
        let p5 = |x: f64| [1.0 - 2.0 * x + 0.5 * x.powi(3) + 0.1 * x.powi(5), 0.0];
        let q = quintic(
            0.7,
            [p5(0.0)[0], -2.0, 0.0],
            [p5(0.7)[0], -2.0 + 1.5 * 0.49 + 0.5 * 0.7f64.powi(4), 3.0 * 0.7 + 2.0 * 0.7f64.powi(3)],
        );
        for x in [0.1, 0.35, 0.6] {
            let v = q[0] + x * (q[1] + x * (q[2] + x * (q[3] + x * (q[4] + x * q[5]))));
            assert!((v - p5(x)[0]).abs() < 1e-13, "{x}");
        }
        let c = cubic(2.0, [1.0, 0.0], [1.0 + 4.0 - 8.0, 2.0 * 2.0 - 3.0 * 4.0]);
        for x in [0.5, 1.0, 1.5] {
            let v = c[0] + x * (c[1] + x * (c[2] + x * c[3]));
            assert!((v - (1.0 + x * x - x * x * x)).abs() < 1e-13, "{x}");
        }
    }
}
