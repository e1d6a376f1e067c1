//! The clearance of a verified motion (issue 21 item 5; docs/spec.md §2): the least signed
//! distance between the robot's bodies and to the obstacles along the integrated motion, the
//! pair and the time where it occurs.
//!
//! A [`ClearanceMonitor`] is fed the integrated state `(t, q, q')` at every accepted step of the
//! certificate's integrator. At each state it evaluates every pair's signed distance and its
//! rate (one forward-mode pass along `q'`, [`Geometry::clearances`]); between two states it takes
//! the least value of each pair's cubic Hermite interpolant of those values and rates, so a
//! dip between steps is seen (the interpolant errs by `O(h^4)` on the integrator's step `h`
//! where the distance is smooth; where a pair's nearest features change the rate is one-sided
//! and the least of the two ends is kept as well).

use num_dual::Dual64;
use serde::Serialize;

use super::certificate::verify_on_arm;
use super::motion::Motion;
use super::problem::PlanningProblem;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::collision::{Body, Geometry};
use crate::numerics::ode::OdeOptions;

/// The least clearance of a motion; in JSON `{min, between: [a, b], time, required}` (bodies as
/// `base`, `link 2`, `obstacle 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceReport {
    /// The least signed distance \[m\] (negative: the bodies overlap by that much).
    pub min: f64,
    /// The first body of the pair.
    pub a: Body,
    /// The second body (or obstacle) of the pair.
    pub b: Body,
    /// When \[s\].
    pub time: f64,
    /// The clearance asked for \[m\] (`--clearance`, 0 by default).
    pub required: f64,
}

impl Serialize for ClearanceReport {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut s = serializer.serialize_struct("ClearanceReport", 5)?;
        s.serialize_field("min", &self.min)?;
        s.serialize_field("between", &[self.a.to_string(), self.b.to_string()])?;
        s.serialize_field("time", &self.time)?;
        s.serialize_field("required", &self.required)?;
        s.serialize_field("holds", &self.holds())?;
        s.end()
    }
}

/// The clearance of a 2-link `motion` planned for `problem`, on the robot with `geometry`: the
/// velocity certificate's integration ([`verify_on_arm`], the integrator `ode`) run again on the
/// arm with the shapes, the monitor fed at every accepted step. `None` when the geometry has no
/// pair to check. (The 2-link robot's parameters carry no geometry, so its planners'
/// certificates cannot see it; the command line's `plan` checks shapes and limits in one such
/// pass.)
pub fn motion_clearance(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    geometry: &Geometry,
    ode: &OdeOptions,
) -> Result<Option<ClearanceReport>, Error> {
    if geometry.is_empty() {
        return Ok(None);
    }
    let arm = Arm::from_params(&problem.robot).with_geometry(geometry.clone())?;
    // The tolerance only sets the returned `certified`, which is not used here.
    Ok(verify_on_arm(motion, problem, &arm, ode, 1.0)?.clearance)
}

impl ClearanceReport {
    /// True when the motion keeps the clearance asked for.
    pub fn holds(&self) -> bool {
        self.min >= self.required
    }
}

/// Watches the clearance of a motion along its integrated states (module docs).
pub struct ClearanceMonitor<'a> {
    arm: &'a Arm,
    geometry: &'a Geometry,
    required: f64,
    /// The last state's time and each pair's distance and rate.
    last: Option<(f64, Vec<(f64, f64)>)>,
    best: Option<ClearanceReport>,
}

impl<'a> ClearanceMonitor<'a> {
    /// A monitor of `geometry` on `arm`, against the clearance `required` \[m\].
    pub fn new(arm: &'a Arm, geometry: &'a Geometry, required: f64) -> Self {
        Self { arm, geometry, required, last: None, best: None }
    }

    /// The state at time `t`: `q = (phi, theta)` and its rate `q'` (`n + 1` values each).
    pub fn observe(&mut self, t: f64, q: &[f64], dq: &[f64]) {
        let qd: Vec<Dual64> = q.iter().zip(dq).map(|(x, v)| Dual64::new(*x, *v)).collect();
        let now = self.geometry.clearances(self.arm, &qd);
        let values: Vec<(f64, f64)> = now.iter().map(|c| (c.distance.re, c.distance.eps)).collect();
        for (k, c) in now.iter().enumerate() {
            let (d, rate) = values[k];
            let mut candidates = vec![(d, t)];
            if let Some((t0, previous)) = &self.last {
                candidates.push(hermite_min(*t0, previous[k], t, (d, rate)));
            }
            for (value, time) in candidates {
                if self.best.is_none_or(|b| value < b.min) {
                    self.best = Some(ClearanceReport { min: value, a: c.a, b: c.b, time, required: self.required });
                }
            }
        }
        self.last = Some((t, values));
    }

    /// The least clearance seen so far; `None` before the first state, or when the geometry has
    /// no pair to check.
    pub fn least(&self) -> Option<&ClearanceReport> {
        self.best.as_ref()
    }

    /// The least clearance seen; `None` when the geometry has no pair to check.
    pub fn finish(self) -> Option<ClearanceReport> {
        self.best
    }
}

/// The least value on `[t0, t1]` of the cubic Hermite interpolant of `(value, rate)` at both
/// ends, and where it is.
fn hermite_min(t0: f64, (y0, r0): (f64, f64), t1: f64, (y1, r1): (f64, f64)) -> (f64, f64) {
    let h = t1 - t0;
    let mut best = if y0 <= y1 { (y0, t0) } else { (y1, t1) };
    if !(h > 0.0) {
        return best;
    }
    // p(s) = y0 H00 + h r0 H10 + y1 H01 + h r1 H11 on s in [0, 1]; p'(s) = a s^2 + b s + c.
    let (m0, m1) = (h * r0, h * r1);
    let a = 6.0 * y0 + 3.0 * m0 - 6.0 * y1 + 3.0 * m1;
    let b = -6.0 * y0 - 4.0 * m0 + 6.0 * y1 - 2.0 * m1;
    let c = m0;
    let p = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        y0 * (2.0 * s3 - 3.0 * s2 + 1.0) + m0 * (s3 - 2.0 * s2 + s) + y1 * (-2.0 * s3 + 3.0 * s2) + m1 * (s3 - s2)
    };
    let mut roots = Vec::with_capacity(2);
    if a.abs() > 1e-300 {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let sq = disc.sqrt();
            roots.extend([(-b - sq) / (2.0 * a), (-b + sq) / (2.0 * a)]);
        }
    } else if b.abs() > 1e-300 {
        roots.push(-c / b);
    }
    for s in roots.into_iter().filter(|s| (0.0..=1.0).contains(s)) {
        let v = p(s);
        if v < best.0 {
            best = (v, t0 + s * h);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mount;
    use crate::model::arm::{Base, Link};
    use crate::model::geometry::Shape;

    #[test]
    fn hermite_min_finds_a_dip_between_the_ends() {
        // y = (t - 0.3)^2 on [0, 1]: exact for a cubic interpolant, least value 0 at 0.3.
        let (v, t) = hermite_min(0.0, (0.09, -0.6), 1.0, (0.49, 1.4));
        assert!(v.abs() < 1e-15 && (t - 0.3).abs() < 1e-12, "{v} at {t}");
        // Monotone: the smaller end.
        assert_eq!(hermite_min(0.0, (1.0, -1.0), 1.0, (0.0, -1.0)), (0.0, 1.0));
    }

    /// A link swinging past an obstacle between two coarse observations: the monitor's least
    /// clearance matches a dense sweep, though neither observed state is near the dip.
    #[test]
    fn a_dip_between_steps_is_seen() {
        let link = Link { length: 1.0, com: 0.5, mass: 1.0, inertia: 0.1 };
        let arm = Arm::new(Base { mass: 50.0, inertia: 5.0 }, Mount::new(0.3, 0.0).unwrap(), vec![link]).unwrap();
        let geometry = Geometry {
            links: vec![vec![Shape::capsule([0.0, 0.0], [1.0, 0.0], 0.05).unwrap()]],
            // Beyond the tip's arc near theta = 0.8 rad, about 0.1 m from it.
            obstacles: vec![Shape::circle([0.3 + 1.25 * 0.8f64.cos(), 1.25 * 0.8f64.sin()], 0.1).unwrap()],
            ..Default::default()
        };
        // theta(t) = t on [0, 1.5] rad, phi from the momentum constraint (Eq. 7): phi' = -G/F theta'.
        let state = |t: f64| -> ([f64; 2], [f64; 2]) {
            // With one link, phi(theta) is found by a fine quadrature of -G/F.
            let (mut phi, steps) = (0.0, 2000);
            for i in 0..steps {
                let s = t * (i as f64 + 0.5) / steps as f64;
                let (f, g) = arm.momentum_coefficients(&[s]);
                phi -= g[0] / f * t / steps as f64;
            }
            let (f, g) = arm.momentum_coefficients(&[t]);
            ([phi, t], [-g[0] / f, 1.0])
        };
        // The dense sweep's least clearance and its time; the observations straddle it 0.05 s away
        // (the certificate's integrator steps are finer still).
        let (dense, t_min) = (0..=1500)
            .map(|i| {
                let t = i as f64 * 1e-3;
                (geometry.min_clearance(&arm, &state(t).0).map_or(f64::INFINITY, |c| c.distance), t)
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
        let coarse_times = [t_min - 0.15, t_min - 0.05, t_min + 0.05, t_min + 0.15];
        let mut monitor = ClearanceMonitor::new(&arm, &geometry, 0.0);
        for t in coarse_times {
            let (q, dq) = state(t);
            monitor.observe(t, &q, &dq);
        }
        let report = monitor.finish().unwrap();
        let coarse = coarse_times
            .iter()
            .map(|&t| geometry.min_clearance(&arm, &state(t).0).map_or(f64::INFINITY, |c| c.distance))
            .fold(f64::INFINITY, f64::min);
        assert!(coarse - dense > 1e-3, "the samples alone miss the dip: {coarse} against {dense}");
        assert!(
            dense > 0.0 && (report.min - dense).abs() < (coarse - dense) / 10.0,
            "{} against the dense sweep's {dense}",
            report.min
        );
        assert_eq!((report.a, report.b), (Body::Link(1), Body::Obstacle(1)));
    }
}
