//! How much of each declared limit a plan uses (issue 20 item 5; docs/spec.md §3): the check of
//! the robot's limits that every certificate adds, for every method.
//!
//! The motion checked is the velocity certificate's (Eq. 7: `phi' = -(G . u)/F`, `theta' = u`
//! integrated from the start with the planned `u(t)`, piecewise between breakpoints): its one
//! integration feeds every accepted step to a [`LimitMonitor`] (and to the clearance's monitor),
//! so that a plan is integrated once for all its checks. Between two accepted steps the state is the
//! cubic Hermite interpolant of the two states and their rates, and each joint velocity the cubic
//! Hermite interpolant of `u` and the planned `theta''`: their extrema inside a step are found in
//! closed form, so that an excursion between steps is caught. A joint's extremum is then polished
//! by Newton on the plan's exact rates (the integrated angle is the plan's plus the integration's
//! drift, interpolated linearly across the step), to the integration's accuracy; the base angle's
//! stays the cubic's (error `O(h^4)` in the steps of a `1e-12` integration). Accelerations are
//! read at the steps' ends and middles; torques are the plan's inverse dynamics (the closed form
//! of the torque level, [`ArmDynamics`]) at the same points and, near the limit, at the vertex of
//! the parabola through them (a torque at 50.00217 N m between those points, 4.3e-5 beyond the
//! limit, was certified without it: SPART's example with +-2 rad, 0.3 rad/s, 50 N m at 13.5 s).
//!
//! The use of a range `[lo, hi]` is `|q - mid| / half` (1 at either bound), of a velocity,
//! acceleration or torque limit `L` it is `|x| / L`. A use beyond `1 + 1e-9` is
//! [`Error::LimitExceeded`].

use nalgebra::SVector;
use serde::Serialize;

use super::certificate::{JointMotion, eq7_rate, integrate_once};
use super::torques::torques_into;
use crate::dynamics::arm::ArmDynamics;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::lumped::ArmLumped;
use crate::numerics::ode::OdeOptions;

/// Relative slack of the check: a use up to `1 + LIMIT_SLACK` is inside.
pub const LIMIT_SLACK: f64 = 1e-9;

/// A torque's extremum between a step's three points is read where the parabola through them
/// puts it within this fraction of the limit.
const NEAR_PEAK: f64 = 1e-3;

/// The quantity a limit bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    /// An angle's range \[rad\] (a joint's, or the base's `phi`).
    Position,
    /// `|theta_k'|` \[rad/s\].
    Velocity,
    /// `|theta_k''|` \[rad/s^2\].
    Acceleration,
    /// `|tau_k|` \[N m\].
    Torque,
}

impl Quantity {
    /// The quantity's name, as in the robot file and `--limit`.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
            Quantity::Torque => "torque",
        }
    }
}

/// The use of one declared limit along the verified motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitUse {
    /// The joint, counted from 1; 0 is the base angle `phi`.
    pub joint: usize,
    /// `theta1`.., or `phi`.
    pub name: String,
    /// The quantity bounded.
    pub quantity: Quantity,
    /// The limit: `[lower, upper]` of a range \[rad\], else `[-L, L]` (SI units).
    pub limit: [f64; 2],
    /// The largest use (module doc): 1 at the limit, above 1 outside.
    #[serde(rename = "use")]
    pub used: f64,
    /// The value where the use is largest (SI units, rad for angles).
    pub value: f64,
    /// When \[s\].
    pub time: f64,
}

impl LimitUse {
    fn new(joint: usize, quantity: Quantity, limit: [f64; 2]) -> Self {
        let name = if joint == 0 { "phi".to_string() } else { format!("theta{joint}") };
        Self { joint, name, quantity, limit, used: f64::NEG_INFINITY, value: f64::NAN, time: f64::NAN }
    }

    /// Takes `value` at `time` into account (a NaN counts as outside).
    fn see(&mut self, value: f64, time: f64) {
        let [lo, hi] = self.limit;
        let used = ((value - 0.5 * (lo + hi)) / (0.5 * (hi - lo))).abs();
        let used = if used.is_nan() { f64::INFINITY } else { used };
        if used > self.used {
            (self.used, self.value, self.time) = (used, value, time);
        }
    }

    /// The bound nearest the value (the one crossed when outside).
    pub fn bound(&self) -> f64 {
        if self.value >= 0.5 * (self.limit[0] + self.limit[1]) { self.limit[1] } else { self.limit[0] }
    }

    /// `true` when the use is within `1 + LIMIT_SLACK`.
    pub fn inside(&self) -> bool {
        self.used <= 1.0 + LIMIT_SLACK
    }
}

/// The use of every limit of an arm along a plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitReport {
    /// One entry per declared limit: the base's range first, then joint by joint.
    pub uses: Vec<LimitUse>,
    /// Every use within `1 + LIMIT_SLACK`.
    pub inside: bool,
}

impl LimitReport {
    /// The most-used limit, if any is declared.
    pub fn most_used(&self) -> Option<&LimitUse> {
        self.uses.iter().max_by(|a, b| a.used.total_cmp(&b.used))
    }

    /// `Ok` inside every limit, else [`Error::LimitExceeded`] for the most-used one.
    pub fn check(&self) -> Result<(), Error> {
        match self.most_used() {
            Some(u) if !u.inside() => Err(Error::LimitExceeded {
                joint: u.joint,
                quantity: u.quantity.name(),
                value: u.value,
                limit: u.bound(),
                time: u.time,
            }),
            _ => Ok(()),
        }
    }
}

/// The extrema candidates of the cubic Hermite interpolant on `[0, h]` of the values `p0, p1`
/// and slopes `m0, m1` at its ends: `(s, p(s))` at both ends and at each critical point inside.
pub fn hermite_candidates(p0: f64, m0: f64, p1: f64, m1: f64, h: f64) -> Vec<(f64, f64)> {
    // p(x) = a x^3 + b x^2 + c x + p0 with x = s / h in [0, 1], slopes scaled by h.
    let (m0, m1) = (m0 * h, m1 * h);
    let a = 2.0 * p0 + m0 - 2.0 * p1 + m1;
    let b = -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1;
    let c = m0;
    let p = |x: f64| ((a * x + b) * x + c) * x + p0;
    let mut out = vec![(0.0, p0), (h, p1)];
    // p'(x) = 3a x^2 + 2b x + c.
    let (qa, qb, qc) = (3.0 * a, 2.0 * b, c);
    let mut roots = Vec::new();
    if qa.abs() > 1e-300 {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let r = disc.sqrt();
            // The numerically stable pair.
            let q = -0.5 * (qb + qb.signum() * r);
            roots.push(q / qa);
            if q.abs() > 1e-300 {
                roots.push(qc / q);
            }
        }
    } else if qb.abs() > 1e-300 {
        roots.push(-qc / qb);
    }
    for x in roots {
        if x > 0.0 && x < 1.0 {
            out.push((x * h, p(x)));
        }
    }
    out
}

/// A zero of `g` near `t` in `[lo, hi]` by Newton (`g_and_slope(t) = (g, g')`, four steps, each
/// kept only if it stays in the interval and is finite): the polish of an extremum's time.
fn polish(mut t: f64, lo: f64, hi: f64, mut g_and_slope: impl FnMut(f64) -> (f64, f64)) -> f64 {
    for _ in 0..4 {
        let (g, slope) = g_and_slope(t);
        let next = t - g / slope;
        if !(next.is_finite() && next >= lo && next <= hi) {
            break;
        }
        t = next;
    }
    t
}

/// The use of every limit of `arm` along `motion` from `start` (`n + 1` angles `(phi,
/// theta)`), integrated with `ode`: the velocity certificate's one pass
/// ([`super::certificate::verify_chain`], whose [`ChainVerification::limits`] this is), for a
/// motion not otherwise certified. An arm without limits gives an empty report (inside).
///
/// [`ChainVerification::limits`]: super::certificate::ChainVerification::limits
pub fn limit_use(arm: &Arm, motion: &dyn JointMotion, start: &[f64], ode: &OdeOptions) -> Result<LimitReport, Error> {
    if arm.limits.is_empty() {
        return Ok(LimitReport::empty());
    }
    let v = integrate_once(arm, motion, start, ode)?;
    Ok(v.limits.unwrap_or_else(LimitReport::empty))
}

impl LimitReport {
    /// The report of an arm without limits: no use, inside.
    pub fn empty() -> Self {
        Self { uses: Vec::new(), inside: true }
    }
}

/// Watches the use of every declared limit of an arm along the certificate's integrated states
/// (`M = n + 1`, module docs): fed each accepted step `(t, q)` in time order, it takes the
/// extrema of the step that ends there; [`LimitMonitor::finish`] gives the report.
pub struct LimitMonitor<'a, const M: usize> {
    /// The closed-form inverse dynamics, for the torques (built only with a torque limit).
    dynamics: Option<ArmDynamics>,
    motion: &'a dyn JointMotion,
    lumped: &'a ArmLumped,
    /// Rates at a step's end are read this far inside the step \[s\].
    nudge: f64,
    last: Option<(f64, SVector<f64, M>)>,
    base: Option<LimitUse>,
    position: Vec<Option<LimitUse>>,
    velocity: Vec<Option<LimitUse>>,
    acceleration: Vec<Option<LimitUse>>,
    torque: Vec<Option<LimitUse>>,
}

impl<'a, const M: usize> LimitMonitor<'a, M> {
    /// A monitor of `arm`'s limits along `motion` (`lumped`: the arm's constants, for the rates
    /// of Eq. 7); `None` when the arm declares no limit.
    pub fn new(arm: &'a Arm, motion: &'a dyn JointMotion, lumped: &'a ArmLumped) -> Option<Self> {
        let limits = &arm.limits;
        if limits.is_empty() {
            return None;
        }
        let n = M - 1;
        let any_torque = limits.joints.iter().any(|j| j.torque.is_some());
        let mut monitor = Self {
            dynamics: any_torque.then(|| ArmDynamics::new(arm)),
            motion,
            lumped,
            // The controls may lose smoothness at a breakpoint, never inside a step.
            nudge: 1e-12 * motion.breakpoints().last().copied().unwrap_or(0.0).max(1.0),
            last: None,
            base: limits.base.map(|r| LimitUse::new(0, Quantity::Position, r)),
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            acceleration: Vec::with_capacity(n),
            torque: Vec::with_capacity(n),
        };
        for k in 0..n {
            let j = limits.joint(k);
            monitor.position.push(j.position.map(|r| LimitUse::new(k + 1, Quantity::Position, r)));
            monitor.velocity.push(j.velocity.map(|v| LimitUse::new(k + 1, Quantity::Velocity, [-v, v])));
            monitor.acceleration.push(j.acceleration.map(|v| LimitUse::new(k + 1, Quantity::Acceleration, [-v, v])));
            monitor.torque.push(j.torque.map(|v| LimitUse::new(k + 1, Quantity::Torque, [-v, v])));
        }
        Some(monitor)
    }

    /// The integrated state `y = (phi, theta)` at `t`: the step from the last state to it is
    /// checked; a time not after the last state's is skipped (a span's first state repeats the
    /// last one's end).
    pub fn observe(&mut self, t: f64, y: &SVector<f64, M>) {
        match self.last {
            Some((last, _)) if t <= last => return,
            Some((ta, ya)) => self.step(ta, &ya, t, y),
            None => {}
        }
        self.last = Some((t, *y));
    }

    /// The report: one entry per declared limit, the base's range first, then joint by joint.
    pub fn finish(mut self) -> LimitReport {
        let mut uses: Vec<LimitUse> = self.base.take().into_iter().collect();
        for k in 0..M - 1 {
            uses.extend(self.position[k].take());
            uses.extend(self.velocity[k].take());
            uses.extend(self.acceleration[k].take());
            uses.extend(self.torque[k].take());
        }
        let inside = uses.iter().all(LimitUse::inside);
        LimitReport { uses, inside }
    }

    /// The extrema of the step from `(ta, ya)` to `(tb, yb)` (module docs).
    fn step(&mut self, ta: f64, ya: &SVector<f64, M>, tb: f64, yb: &SVector<f64, M>) {
        let (n, motion) = (M - 1, self.motion);
        let h = tb - ta;
        let (ea, eb) = (ta + self.nudge.min(0.25 * h), tb - self.nudge.min(0.25 * h));
        let dya = eq7_rate(self.lumped, motion, ea, ya);
        let dyb = eq7_rate(self.lumped, motion, eb, yb);
        let (mut theta, mut u, mut acc) = ([0.0; M], [0.0; M], [0.0; M]);
        motion.joint_state(ea, &mut theta[..n], &mut u[..n]);
        motion.joint_acceleration(ea, &mut acc[..n]);
        let (ua, aa) = (u, acc);
        motion.joint_state(eb, &mut theta[..n], &mut u[..n]);
        motion.joint_acceleration(eb, &mut acc[..n]);
        let (ub, ab) = (u, acc);
        if let Some(b) = self.base.as_mut() {
            for (s, v) in hermite_candidates(ya[0], dya[0], yb[0], dyb[0], h) {
                b.see(v, ta + s);
            }
        }
        // The plan's angles at both ends, for the integration's drift.
        let (mut plan_a, mut plan_b) = ([0.0; M], [0.0; M]);
        if self.position.iter().any(Option::is_some) {
            motion.joint_state(ta, &mut plan_a[..n], &mut u[..n]);
            motion.joint_state(tb, &mut plan_b[..n], &mut u[..n]);
        }
        for k in 0..n {
            if let Some(p) = self.position[k].as_mut() {
                // The integrated angle is the plan's plus the integration's drift (linear across
                // the step): an interior extremum found on the Hermite cubic is polished by
                // Newton on the plan's exact `theta' = u`, `theta'' `.
                let (drift_a, drift_b) = (ya[k + 1] - plan_a[k], yb[k + 1] - plan_b[k]);
                for (s, v) in hermite_candidates(ya[k + 1], dya[k + 1], yb[k + 1], dyb[k + 1], h) {
                    if s > 0.0 && s < h {
                        let (mut th, mut r, mut ac) = ([0.0; M], [0.0; M], [0.0; M]);
                        let t = polish(ta + s, ea, eb, |t| {
                            motion.joint_state(t, &mut th[..n], &mut r[..n]);
                            motion.joint_acceleration(t, &mut ac[..n]);
                            (r[k], ac[k])
                        });
                        motion.joint_state(t, &mut th[..n], &mut r[..n]);
                        let x = (t - ta) / h;
                        p.see(th[k] + drift_a + x * (drift_b - drift_a), t);
                    } else {
                        p.see(v, ta + s);
                    }
                }
            }
            if let Some(v) = self.velocity[k].as_mut() {
                for (s, x) in hermite_candidates(ua[k], aa[k], ub[k], ab[k], h) {
                    if s > 0.0 && s < h {
                        // Newton on the plan's `theta''` (its rate by central differences).
                        let (mut ac, mut th, mut r) = ([0.0; M], [0.0; M], [0.0; M]);
                        let d = 1e-6 * h;
                        let t = polish(ta + s, ea, eb, |t| {
                            motion.joint_acceleration(t + d, &mut ac[..n]);
                            let up = ac[k];
                            motion.joint_acceleration(t - d, &mut ac[..n]);
                            let down = ac[k];
                            motion.joint_acceleration(t, &mut ac[..n]);
                            (ac[k], (up - down) / (2.0 * d))
                        });
                        motion.joint_state(t, &mut th[..n], &mut r[..n]);
                        v.see(r[k], t);
                    } else {
                        v.see(x, ta + s);
                    }
                }
            }
        }
        let mid = ta + 0.5 * h;
        if self.acceleration.iter().any(Option::is_some) || self.dynamics.is_some() {
            motion.joint_acceleration(mid, &mut acc[..n]);
            for (k, a) in self.acceleration.iter_mut().enumerate() {
                if let Some(a) = a.as_mut() {
                    a.see(aa[k], ea);
                    a.see(ab[k], eb);
                    a.see(acc[k], mid);
                }
            }
        }
        if let Some(dynamics) = &self.dynamics {
            let times = [ea, mid, eb];
            let mut tau = [[0.0; M]; 3];
            for (t, tau) in times.iter().zip(tau.iter_mut()) {
                torques_into(dynamics, motion, *t, &mut tau[..n]);
            }
            let mut peak = [0.0; M];
            for (k, limit) in self.torque.iter_mut().enumerate() {
                let Some(limit) = limit.as_mut() else { continue };
                for (t, tau) in times.iter().zip(&tau) {
                    limit.see(tau[k], *t);
                }
                // An extremum between the three points (the torque is smooth inside a step): the
                // vertex of the parabola through them, read where it comes near the limit.
                let [a, b, c] = [tau[0][k], tau[1][k], tau[2][k]];
                let curvature = a - 2.0 * b + c;
                let s = 0.5 * (a - c) / curvature;
                if !(s.abs() < 1.0) {
                    continue;
                }
                let vertex = b - 0.25 * (a - c) * s;
                if vertex.abs() >= (1.0 - NEAR_PEAK) * limit.limit[1] {
                    let t = mid + s * (mid - ea);
                    torques_into(dynamics, motion, t, &mut peak[..n]);
                    limit.see(peak[k], t);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mount;
    use crate::model::arm::{Base, JointLimits, Limits, Link};

    #[test]
    fn hermite_candidates_find_a_peak_between_the_ends() {
        // p(s) = s - s^2 on [0, 1]: equal ends, the peak 0.25 at s = 0.5.
        let c = hermite_candidates(0.0, 1.0, 0.0, -1.0, 1.0);
        let peak = c.iter().copied().fold((0.0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
        assert!((peak.0 - 0.5).abs() < 1e-15 && (peak.1 - 0.25).abs() < 1e-15, "{c:?}");
        // A monotone cubic has its extrema at the ends only.
        assert_eq!(hermite_candidates(0.0, 1.0, 1.0, 1.0, 1.0).len(), 2);
    }

    /// One joint along `theta = A sin(w t)` on `[0, T]`, `w = pi / T`: its peak `A` at `T / 2`
    /// lies between the integrator's steps.
    struct Sine {
        amplitude: f64,
        w: f64,
        breakpoints: Vec<f64>,
    }

    impl JointMotion for Sine {
        fn joints(&self) -> usize {
            1
        }
        fn breakpoints(&self) -> &[f64] {
            &self.breakpoints
        }
        fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
            theta[0] = self.amplitude * (self.w * t).sin();
            rate[0] = self.amplitude * self.w * (self.w * t).cos();
        }
        fn phi_rate(&self, _t: f64) -> f64 {
            0.0
        }
        fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
            out[0] = -self.amplitude * self.w * self.w * (self.w * t).sin();
        }
    }

    fn arm(limits: JointLimits) -> Arm {
        let link = Link { length: 1.0, com: 0.5, mass: 1.0, inertia: 0.1 };
        Arm::new(Base { mass: 10.0, inertia: 1.0 }, Mount::default(), vec![link])
            .unwrap()
            .with_limits(Limits { joints: vec![limits], base: None })
            .unwrap()
    }

    /// A torque's peak between the integrator's steps is read (the vertex of the parabola through
    /// a step's three points): the one joint along `A sin(w t)` with `w = pi / 7` on `[0, 10]`,
    /// whose torque peaks near the acceleration's peak at 3.5 s. A limit at the peak (sampled at
    /// 100001 points) is inside; one 1e-7 below it is refused.
    #[test]
    fn a_torque_peak_between_steps_is_caught_and_refused() {
        let (a, horizon) = (1.2, 10.0);
        let motion = Sine { amplitude: a, w: std::f64::consts::PI / 7.0, breakpoints: vec![0.0, horizon] };
        let (start, ode) = ([0.0, 0.0], OdeOptions::default());
        let limited = |l: f64| arm(JointLimits { torque: Some(l), ..JointLimits::default() });
        let dynamics = ArmDynamics::new(&limited(1.0));
        let mut tau = [0.0];
        let peak = (0..=100_000)
            .map(|i| {
                torques_into(&dynamics, &motion, horizon * i as f64 / 1e5, &mut tau);
                tau[0].abs()
            })
            .fold(0.0, f64::max);
        let r = limit_use(&limited(peak), &motion, &start, &ode).unwrap();
        assert!(r.inside && (r.uses[0].used - 1.0).abs() < 1e-9, "{r:?}");
        let r = limit_use(&limited(peak * (1.0 - 1e-7)), &motion, &start, &ode).unwrap();
        assert!(!r.inside, "{r:?}");
    }

    #[test]
    fn an_excursion_between_steps_is_caught_and_refused() {
        let (a, horizon) = (1.2, 10.0);
        let motion = Sine { amplitude: a, w: std::f64::consts::PI / horizon, breakpoints: vec![0.0, horizon] };
        let start = [0.0, 0.0];
        let ode = OdeOptions::default();
        // The range's upper bound at the peak: the use is 1 at t = T / 2, inside.
        let at_peak = JointLimits { position: Some([-a, a]), velocity: Some(a * motion.w), ..JointLimits::default() };
        let r = limit_use(&arm(at_peak), &motion, &start, &ode).unwrap();
        let p = &r.uses[0];
        assert_eq!((p.joint, p.quantity), (1, Quantity::Position));
        assert!((p.used - 1.0).abs() < 1e-9 && (p.value - a).abs() < 1e-9 * a, "{p:?}");
        assert!((p.time - 0.5 * horizon).abs() < 1e-3, "{p:?}");
        let v = &r.uses[1];
        assert!((v.used - 1.0).abs() < 1e-9, "the velocity peaks at the ends: {v:?}");
        assert!(r.inside && r.check().is_ok(), "{r:?}");
        // 1e-6 below the peak: only the interpolation between steps sees it, and it is refused.
        let below = JointLimits { position: Some([-a, a * (1.0 - 1e-6)]), ..JointLimits::default() };
        let r = limit_use(&arm(below), &motion, &start, &ode).unwrap();
        assert!(!r.inside);
        let Err(Error::LimitExceeded { joint, quantity, value, limit, time }) = r.check() else { panic!("refused") };
        assert_eq!((joint, quantity), (1, "position"));
        assert!((value - a).abs() < 1e-9 && (limit - a * (1.0 - 1e-6)).abs() < 1e-15 && (time - 5.0).abs() < 1e-3);
        // Without limits: nothing to check.
        let free = Arm { limits: Limits::default(), ..arm(below) };
        assert!(limit_use(&free, &motion, &start, &ode).unwrap().uses.is_empty());
    }
}
