//! Feedback transformations of the driftless system (7) to the chained form (10),
//! `z1' = v1, z2' = v2, z3' = z2 v1` (Sec. 4, Theorem 1), with their domains of existence and
//! inverse maps (Sec. 6, item 2).
//!
//! A [`NormalForm`] is one transformation on one connected piece of its domain: the branch
//! (`sign(s2)` for Eqs. 11-12, `sign(P)` for Eq. 14) is fixed by the start configuration.

pub mod centred;
pub mod general;
pub mod global;

use crate::model::InputError;
use serde::Serialize;

use crate::Scalar;
use crate::error::{Error, Singularity};
use crate::model::system::shape;
use crate::model::{Configuration, Lumped, RobotParams};

/// The feedback transformations of Theorem 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Transform {
    /// Eq. (11), `a = b = 0` only: `z1 = phi + theta1`, `z2 = -2 C c2`, `z3` linear in the
    /// angles; domain `sin theta2 != 0`.
    Eq11,
    /// Eq. (12), `a = b = 0` only (Eq. (14) at `a = b = 0`): `z1 = theta1`,
    /// `z2 = -sign(s2) G/F`; domain `sin theta2 != 0`.
    Eq12,
    /// Eq. (14), any mounting point: domain `sigma != 0` and `P != 0`, one branch `sign(P)`.
    Eq14,
    /// Beyond the paper: the global normal form of [`global`], any mounting point, domain
    /// `sigma != 0` only.
    Global,
}

impl Transform {
    /// The name used on the command line and in reports (`eq11`, `eq12`, `eq14`).
    pub fn name(&self) -> &'static str {
        match self {
            Transform::Eq11 => "eq11",
            Transform::Eq12 => "eq12",
            Transform::Eq14 => "eq14",
            Transform::Global => "global",
        }
    }

    /// docs/spec.md §2's `auto`: Eq. (12) when `a = b = 0`, else Eq. (14). (The planner with no
    /// transformation chosen tries this one first and falls back to [`Transform::Global`].)
    pub fn auto(robot: &RobotParams) -> Self {
        if robot.mount.is_centred() { Transform::Eq12 } else { Transform::Eq14 }
    }
}

/// Options of the inverse map's Newton iteration on `z2 = h3(theta1, theta2)` (Eq. 14 only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Largest number of iterations; default 50.
    pub max_iterations: usize,
    /// Newton correction `|delta theta2| / (1 + |theta2|)` at which the iteration has
    /// converged (the next one is below rounding); default 1e-10.
    pub step_tolerance: f64,
    /// Residual `|h3 - z2|` still accepted when no step can reduce it further (rounding);
    /// default 1e-11.
    pub residual_tolerance: f64,
    /// Largest Newton step in theta2 \[rad\]; default 0.5.
    pub max_step: f64,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self { max_iterations: 50, step_tolerance: 1e-10, residual_tolerance: 1e-11, max_step: 0.5 }
    }
}

/// Values of the domain conditions at one configuration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Margins {
    /// `sigma` of Eq. (9).
    pub sigma: f64,
    /// `P` of Eq. (13).
    pub p: f64,
}

/// A feedback transformation on one piece of its domain, ready to map `q -> z`, `u -> v` and
/// back.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalForm {
    lumped: Lumped,
    transform: Transform,
    /// `sign(s2)` (Eqs. 11-12) or `sign(P)` (Eq. 14) on this piece of the domain.
    branch: f64,
    /// `n` with `theta2` in `(n pi, (n+1) pi)` (Eqs. 11-12).
    interval: i64,
    /// `sign(sigma)` on this piece of the domain.
    sigma_sign: f64,
    /// Scale below which `|sigma|` counts as zero.
    sigma_eps: f64,
    /// Scale below which `|P|` counts as zero.
    p_eps: f64,
    newton: NewtonOptions,
}

/// `n` with `theta2` in `[n pi, (n+1) pi)`.
fn theta2_interval(theta2: f64) -> i64 {
    (theta2 / std::f64::consts::PI).floor() as i64
}

/// Relative size below which a domain function counts as zero.
const ZERO: f64 = 1e-10;

impl NormalForm {
    /// The transformation `transform` on the piece of its domain that holds `start`.
    ///
    /// Errors: [`Error::TransformUnavailable`] for Eqs. (11)-(12) with `a, b != 0`;
    /// [`Error::Singular`] when `start` is outside the domain.
    pub fn new(robot: &RobotParams, transform: Transform, start: &Configuration) -> Result<Self, Error> {
        robot.validate()?;
        if matches!(transform, Transform::Eq11 | Transform::Eq12) && !robot.mount.is_centred() {
            return Err(Error::TransformUnavailable {
                transform: transform.name(),
                reason: "Eqs. (11) and (12) hold only for a = b = 0; use eq14 (or auto)",
            });
        }
        if !start.is_finite() {
            return Err(Error::from(InputError::InvalidParameter {
                name: "start".into(),
                value: f64::NAN,
                expected: "finite angles",
            }));
        }
        let k = robot.lumped();
        let ab = robot.mount.a.hypot(robot.mount.b);
        let sigma_scale = ((k.B * k.D - k.C * k.E).abs() + (k.C * k.D - k.A * k.E).abs()) * ab
            + (k.D * k.E * ab * ab - k.C * k.IP).abs();
        let p_scale = k.C + k.E * ab;
        let s = shape(&k, start.theta1, start.theta2);
        let mut nf = Self {
            lumped: k,
            transform,
            branch: 1.0,
            interval: theta2_interval(start.theta2),
            sigma_sign: s.sigma.signum(),
            sigma_eps: ZERO * sigma_scale,
            p_eps: ZERO * p_scale,
            newton: NewtonOptions::default(),
        };
        nf.branch = match transform {
            Transform::Eq11 | Transform::Eq12 => start.theta2.sin().signum(),
            Transform::Eq14 => s.P.signum(),
            Transform::Global => s.sigma.signum(),
        };
        nf.check(start, "start", None)?;
        Ok(nf)
    }

    /// The same transformation with other Newton options.
    pub fn with_newton(self, newton: NewtonOptions) -> Self {
        Self { newton, ..self }
    }

    /// The transformation.
    pub fn transform(&self) -> Transform {
        self.transform
    }

    /// The branch sign fixed by the start: `sign(s2)` (Eqs. 11-12) or `sign(P)` (Eq. 14).
    pub fn branch(&self) -> f64 {
        self.branch
    }

    /// The lumped constants of the robot.
    pub fn lumped(&self) -> &Lumped {
        &self.lumped
    }

    /// Checks that `q` lies in this piece of the domain and returns the margins there.
    /// `where_` (`start`, `goal`, `path`) and `t` only label the error.
    pub fn check(&self, q: &Configuration, where_: &'static str, t: Option<f64>) -> Result<Margins, Error> {
        let s = shape(&self.lumped, q.theta1, q.theta2);
        let margins = Margins { sigma: s.sigma, p: s.P };
        let singular = |which, value, hint| Error::Singular {
            which,
            transform: self.transform.name(),
            where_,
            q: Some(*q),
            t,
            value,
            hint,
        };
        match self.transform {
            Transform::Eq11 | Transform::Eq12 => {
                let s2 = q.theta2.sin();
                if s2.abs() <= ZERO {
                    return Err(singular(Singularity::SinTheta2, s2, "move theta2 away from 0 and 180 deg"));
                }
                if theta2_interval(q.theta2) != self.interval {
                    return Err(match where_ {
                        "goal" => Error::DifferentComponents {
                            transform: self.transform.name(),
                            which: Singularity::SinTheta2,
                            start_sign: self.branch,
                            goal_sign: s2.signum(),
                        },
                        _ => singular(Singularity::SinTheta2, s2, "the path crosses sin(theta2) = 0"),
                    });
                }
            }
            Transform::Global => {
                if s.sigma.abs() <= self.sigma_eps {
                    return Err(singular(
                        Singularity::Sigma,
                        s.sigma,
                        "a posture singularity: choose another configuration",
                    ));
                }
                if s.sigma * self.sigma_sign <= 0.0 {
                    return Err(match where_ {
                        "goal" => Error::DifferentComponents {
                            transform: self.transform.name(),
                            which: Singularity::Sigma,
                            start_sign: self.sigma_sign,
                            goal_sign: s.sigma.signum(),
                        },
                        _ => singular(Singularity::Sigma, s.sigma, "the path crosses sigma = 0"),
                    });
                }
            }
            Transform::Eq14 => {
                if s.sigma.abs() <= self.sigma_eps {
                    return Err(singular(
                        Singularity::Sigma,
                        s.sigma,
                        "a posture singularity: choose another configuration",
                    ));
                }
                if s.P.abs() <= self.p_eps {
                    return Err(singular(
                        Singularity::P,
                        s.P,
                        "P = 0 separates the branches of Eq. (14): choose another configuration or mounting point",
                    ));
                }
                if !(s.d > 0.0) || !(s.f > 0.0) {
                    return Err(singular(Singularity::DNonPositive, s.d, "this mounting point admits no Eq. (14)"));
                }
                let (x1, x2) = general::arcsin_arguments(&s);
                if !(x1.abs() <= 1.0 + 1e-12 && x2.abs() <= 1.0 + 1e-12) {
                    return Err(singular(
                        Singularity::ArcsinArgument,
                        if x1.abs() > 1.0 { x1 } else { x2 },
                        "check the robot parameters",
                    ));
                }
                for (which, value, sign) in
                    [(Singularity::P, s.P, self.branch), (Singularity::Sigma, s.sigma, self.sigma_sign)]
                {
                    if value * sign <= 0.0 {
                        return Err(match where_ {
                            "goal" => Error::DifferentComponents {
                                transform: self.transform.name(),
                                which,
                                start_sign: sign,
                                goal_sign: value.signum(),
                            },
                            _ => singular(
                                which,
                                value,
                                "the path crosses this curve: the goal is not reachable with this transformation",
                            ),
                        });
                    }
                }
            }
        }
        Ok(margins)
    }

    /// The chained-form coordinates `z = h(q)`; generic so that AD can differentiate it.
    pub fn h<D: Scalar>(&self, q: [D; 3]) -> [D; 3] {
        match self.transform {
            Transform::Eq11 => centred::eq11_h(&self.lumped, q),
            Transform::Eq12 => centred::eq12_h(&self.lumped, self.branch, q),
            Transform::Eq14 => general::eq14_h(&self.lumped, self.branch, q),
            Transform::Global => global::global_h(&self.lumped, q),
        }
    }

    /// The feedback `v = alpha(q) + beta(q) u`: chained-form controls from joint velocities.
    pub fn feedback<D: Scalar>(&self, q: [D; 3], u: [D; 2]) -> [D; 2] {
        match self.transform {
            Transform::Eq11 => centred::eq11_feedback(&self.lumped, q, u),
            Transform::Eq12 => centred::eq12_feedback(&self.lumped, self.branch, q, u),
            Transform::Eq14 => general::eq14_feedback(&self.lumped, self.branch, q, u),
            Transform::Global => global::global_feedback(&self.lumped, q, u),
        }
    }

    /// The inverse feedback `u = beta(q)^-1 (v - alpha(q))`: joint velocities \[rad/s\] from
    /// chained-form controls. With dual `q, v` (carrying `q'` and `v'`) it also gives `u'`.
    pub fn control<D: Scalar>(&self, q: [D; 3], v: [D; 2]) -> [D; 2] {
        match self.transform {
            Transform::Eq11 => centred::eq11_control(&self.lumped, q, v),
            Transform::Eq12 => centred::eq12_control(&self.lumped, self.branch, q, v),
            Transform::Eq14 => general::eq14_control(&self.lumped, self.branch, q, v),
            Transform::Global => global::global_control(&self.lumped, q, v),
        }
    }

    /// The inverse map `q = h^-1(z)` on this piece of the domain (Sec. 6, item 2).
    ///
    /// Eqs. (11)-(12) invert in closed form. Eq. (14): `theta1 = z1`; Newton's method on
    /// `z2 = h3(theta1, theta2)` from `theta2_guess`, damped so that it never leaves the branch,
    /// with at most [`NewtonOptions::max_iterations`] iterations; then `phi` analytically from
    /// `z3 = h2`. `t` only labels errors.
    pub fn invert(&self, z: [f64; 3], theta2_guess: f64, t: Option<f64>) -> Result<Configuration, Error> {
        let k = &self.lumped;
        let closed = |q: Option<[f64; 3]>| {
            q.map(Configuration::from_array).ok_or(Error::Singular {
                which: Singularity::SinTheta2,
                transform: self.transform.name(),
                where_: "path",
                q: None,
                t,
                value: z[1],
                hint: "z2 leaves the range of Eq. (11)/(12): the path reaches sin(theta2) = 0",
            })
        };
        let q = match self.transform {
            Transform::Eq11 => closed(centred::eq11_invert(k, z, self.interval))?,
            Transform::Eq12 => closed(centred::eq12_invert(k, self.branch, z, self.interval))?,
            Transform::Eq14 => {
                let theta1 = z[0];
                let theta2 = self.newton_theta2(theta1, z[1], theta2_guess, t)?;
                Configuration::new(general::eq14_phi(k, self.branch, z[2], theta1, theta2), theta1, theta2)
            }
            Transform::Global => {
                let theta1 = z[0];
                let theta2 = self.band_theta2(theta1, z[1], theta2_guess, t)?;
                Configuration::new(z[2] - global::psi(k, theta1, theta2), theta1, theta2)
            }
        };
        Ok(q)
    }

    /// The band `{sign(sigma) = start's}` at `theta1` that holds (or is nearest to) `theta2_ref`;
    /// when sigma has no zero at this `theta1`, a bracket of the root around `theta2_ref`.
    pub fn band(&self, theta1: f64, theta2_ref: f64) -> (f64, f64) {
        global::band(&self.lumped, self.sigma_sign, theta1, theta2_ref)
            .unwrap_or((theta2_ref - std::f64::consts::PI, theta2_ref + std::f64::consts::PI))
    }

    /// The band `{sign(sigma) = start's}` at `theta1` that holds (or is nearest to) `theta2_ref`,
    /// `None` when sigma has no zero at this `theta1` (the band has no edges there).
    pub fn band_edges(&self, theta1: f64, theta2_ref: f64) -> Option<(f64, f64)> {
        global::band(&self.lumped, self.sigma_sign, theta1, theta2_ref)
    }

    /// `theta2` with `h3(theta1, theta2) = z2` inside the band near `guess` (global form): the
    /// joint part of [`NormalForm::invert`], without `phi`.
    pub fn band_theta2(&self, theta1: f64, z2: f64, guess: f64, t: Option<f64>) -> Result<f64, Error> {
        let k = &self.lumped;
        let mut bracket = self.band(theta1, guess);
        let bounded = global::band(k, self.sigma_sign, theta1, guess).is_some();
        for _ in 0..8 {
            match global::solve_in_band(k, theta1, z2, bracket, guess) {
                Ok(theta2) => return Ok(theta2),
                Err((lower, upper)) if bounded => {
                    return Err(Error::LeavesBand { t, theta1, z2, lower: lower.min(upper), upper: lower.max(upper) });
                }
                // Unbounded band (sigma without zeros at this theta1): widen the bracket.
                Err(_) => bracket = (bracket.0 - std::f64::consts::TAU, bracket.1 + std::f64::consts::TAU),
            }
        }
        Err(Error::NewtonFailed { iterations: 0, residual: f64::INFINITY, target: z2, guess, t })
    }

    /// True when `(theta1, theta2)` is on this branch of Eq. (14) with the start's sign of sigma.
    #[cfg(test)]
    fn on_branch(&self, theta1: f64, theta2: f64) -> bool {
        let s = shape(&self.lumped, theta1, theta2);
        self.on_branch_values(s.P, s.sigma)
    }

    /// [`Self::on_branch`] from the values of `P` and `sigma`.
    fn on_branch_values(&self, p: f64, sigma: f64) -> bool {
        p * self.branch > self.p_eps && sigma * self.sigma_sign > self.sigma_eps
    }

    fn newton_theta2(&self, theta1: f64, z2: f64, guess: f64, t: Option<f64>) -> Result<f64, Error> {
        let k = &self.lumped;
        let opts = &self.newton;
        let fail = |iterations, residual: f64| Error::NewtonFailed {
            iterations,
            residual: residual.abs(),
            target: z2,
            guess,
            t,
        };
        let mut theta2 = guess;
        let mut point = general::newton_point(k, self.branch, theta1, theta2);
        if !self.on_branch_values(point.p, point.sigma) {
            return Err(fail(0, f64::INFINITY));
        }
        let mut r = point.h3 - z2;
        for iteration in 1..=opts.max_iterations {
            let full = -r / point.slope;
            if full.abs() <= opts.step_tolerance * (1.0 + theta2.abs()) {
                // Quadratic convergence: the next correction is below rounding.
                return Ok(theta2 + full);
            }
            // Damping: halve the step until it stays on the branch and reduces the residual.
            let mut step = full.clamp(-opts.max_step, opts.max_step);
            let mut accepted = false;
            for _ in 0..60 {
                let trial = theta2 + step;
                let p = general::newton_point(k, self.branch, theta1, trial);
                if self.on_branch_values(p.p, p.sigma) && (p.h3 - z2).abs() < r.abs() {
                    theta2 = trial;
                    point = p;
                    r = p.h3 - z2;
                    accepted = true;
                    break;
                }
                step *= 0.5;
            }
            if !accepted {
                // No step reduces the residual: either at rounding level, or stuck at the
                // branch's edge (z2 outside the range of h3 on the branch).
                if r.abs() <= opts.residual_tolerance {
                    return Ok(theta2);
                }
                return Err(fail(iteration, r));
            }
        }
        Err(fail(opts.max_iterations, r))
    }
}

#[cfg(test)]
mod tests;
