//! On-line identification of the momentum map (Eqs. 5, 8): the angular momentum
//! `F phi' + G theta1' + H theta2' = 0` is linear in the lumped constants of Sec. 3.1, so the
//! measured motion determines them (up to one common factor) by least squares.
//!
//! With `k1 = a c1 + b s1` and `k12 = a c12 + b s12`, the products `D k1` and `E k12` are linear
//! in `D a, D b, E a, E b`; the unknowns are therefore
//! `x = (A, B, C, D a, D b, E a, E b, I_P)`, which also absorbs an error of the mounting point,
//! and each measurement `(phi', theta', theta)` gives one linear equation `r^T x = 0` with
//!
//! ```text
//! r = ( w + u1,  w + u1 + u2,  c2 (2w + 2u1 + u2),  c1 (2w + u1),  s1 (2w + u1),
//!       c12 (2w + u1 + u2),  s12 (2w + u1 + u2),  w ),      w = phi', u = theta'.
//! ```
//!
//! The estimate minimises the exponentially forgotten sum of squares plus a small pull toward
//! the nominal constants, `sum_k lambda^(n-k) (r_k^T x)^2 + rho |x - x_nom|^2` (in units of the
//! nominal constants): recursive least squares with forgetting in information form. The pull
//! fixes the common factor, which zero momentum cannot see (it then sits at the nominal
//! projection), and keeps unexcited directions at their nominal values. The constants are
//! mapped back to a robot ([`fit_robot`]) so that the planner and the computed torque both use
//! them.
//!
//! ## Reference
//! L. Ljung, T. Söderström, *Theory and Practice of Recursive Identification*, MIT Press 1983,
//! Sec. 2.6 (least squares with exponential forgetting), ISBN 978-0-262-12095-5.

use nalgebra::{SMatrix, SVector};
use serde::Serialize;

use super::plant::State;
use crate::error::Error;
use crate::model::system::shape;
use crate::model::{InputError, Lumped, Mount, RobotParams};

/// The identified parameter vector `(A, B, C, D a, D b, E a, E b, I_P)` [kg m^2].
pub type Constants = [f64; 8];

/// The constants `(A, B, C, D a, D b, E a, E b, I_P)` of a model.
pub fn constants(k: &Lumped) -> Constants {
    [k.A, k.B, k.C, k.D * k.a, k.D * k.b, k.E * k.a, k.E * k.b, k.IP]
}

/// The regressor `r` of the module docs at a state: `r^T x = F phi' + G theta1' + H theta2'`.
pub fn regressor(state: &State) -> [f64; 8] {
    let q = &state.q;
    let [w, u1, u2] = state.dq;
    let (s1, c1) = q.theta1.sin_cos();
    let c2 = q.theta2.cos();
    let (s12, c12) = (q.theta1 + q.theta2).sin_cos();
    let (d, e) = (2.0 * w + u1, 2.0 * w + u1 + u2);
    [w + u1, w + u1 + u2, c2 * (2.0 * w + 2.0 * u1 + u2), c1 * d, s1 * d, c12 * e, s12 * e, w]
}

/// Options of the identification.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IdentifyOptions {
    /// Time constant of the exponential forgetting \[s\]: data `tau` seconds old weigh `1/e`;
    /// default 5 s.
    pub forgetting_time: f64,
    /// Weight `rho` of the pull toward the nominal constants, in units of the data's weight
    /// (squared regressor times seconds, constants in nominal units); default 1e-6 (a second of
    /// the paper's motion weighs about 1e-2).
    pub prior_weight: f64,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        Self { forgetting_time: 5.0, prior_weight: 1e-6 }
    }
}

impl IdentifyOptions {
    /// Checks the options: both positive and finite.
    pub fn validate(&self) -> Result<(), Error> {
        for (name, value) in [("forgetting", self.forgetting_time), ("prior-weight", self.prior_weight)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(
                    InputError::InvalidParameter { name: name.into(), value, expected: "a positive number" }.into()
                );
            }
        }
        Ok(())
    }
}

/// The recursive estimator of the constants (see the module docs).
#[derive(Debug, Clone)]
pub struct Identifier {
    scale: [f64; 8],
    nominal: SVector<f64, 8>,
    information: SMatrix<f64, 8, 8>,
    options: IdentifyOptions,
}

impl Identifier {
    /// An estimator starting at the constants of `nominal`.
    pub fn new(nominal: &RobotParams, options: IdentifyOptions) -> Self {
        let k = nominal.lumped();
        let r = k.a.hypot(k.b).max(0.05);
        let scale = [k.A, k.B, k.C, k.D * r, k.D * r, k.E * r, k.E * r, k.IP];
        let c = constants(&k);
        let nominal = SVector::from_fn(|i, _| c[i] / scale[i]);
        Self { scale, nominal, information: SMatrix::zeros(), options }
    }

    /// Adds the measurement `state`, weighted by the time `dt` \[s\] it stands for, and forgets
    /// the older ones by `exp(-dt / forgetting_time)`.
    pub fn update(&mut self, state: &State, dt: f64) {
        let r = regressor(state);
        let v = SVector::<f64, 8>::from_fn(|i, _| r[i] * self.scale[i]);
        if v.iter().all(|x| x.is_finite()) {
            let lambda = (-dt / self.options.forgetting_time).exp();
            self.information = self.information * lambda + v * v.transpose() * dt;
        }
    }

    /// The current estimate: `x = (R + rho I)^-1 rho x_nom` in nominal units.
    pub fn estimate(&self) -> Constants {
        let rho = self.options.prior_weight;
        let a = self.information + SMatrix::<f64, 8, 8>::identity() * rho;
        let x = a.cholesky().map(|c| c.solve(&(self.nominal * rho))).unwrap_or(self.nominal);
        std::array::from_fn(|i| x[i] * self.scale[i])
    }
}

/// The unknowns of [`fit_robot`]: logarithms of `M, I, m1, m2, l1, d1, d2`, then `a, b`.
fn unknowns(robot: &RobotParams) -> [f64; 9] {
    let r = robot;
    [r.base_mass.ln(), r.base_inertia.ln(), r.m1.ln(), r.m2.ln(), r.l1.ln(), r.d1.ln(), r.d2.ln(), r.mount.a, r.mount.b]
}

fn robot_of(p: &[f64; 9], like: &RobotParams) -> RobotParams {
    RobotParams {
        base_mass: p[0].exp(),
        base_inertia: p[1].exp(),
        m1: p[2].exp(),
        m2: p[3].exp(),
        l1: p[4].exp(),
        d1: p[5].exp(),
        d2: p[6].exp(),
        mount: Mount { a: p[7], b: p[8] },
        ..*like
    }
}

/// A robot whose constants ([`constants`]) match `target`, found by damped Gauss–Newton
/// (Levenberg–Marquardt) from `start` in the logarithms of its masses, inertia and lengths and
/// its mounting point. The map has more unknowns than equations: the damping keeps the robot
/// near `start`. `l2`, which the momentum map does not see, is `start`'s. Returns the robot
/// and the final residual in units of the nominal constants; a robot that fails
/// [`RobotParams::validate`] (a centre of mass past its link) is an error.
pub fn fit_robot(target: &Constants, start: &RobotParams) -> Result<(RobotParams, f64), Error> {
    let k0 = start.lumped();
    let r0 = k0.a.hypot(k0.b).max(0.05);
    let scale = [k0.A, k0.B, k0.C, k0.D * r0, k0.D * r0, k0.E * r0, k0.E * r0, k0.IP];
    let residual = |p: &[f64; 9]| -> SVector<f64, 8> {
        let c = constants(&robot_of(p, start).lumped());
        SVector::from_fn(|i, _| (c[i] - target[i]) / scale[i])
    };
    let mut p = unknowns(start);
    let mut r = residual(&p);
    let mut mu = 1e-6;
    for _ in 0..40 {
        if r.norm() < 1e-13 {
            break;
        }
        let mut j = SMatrix::<f64, 8, 9>::zeros();
        for col in 0..9 {
            let mut pp = p;
            let h = 1e-7 * (1.0 + p[col].abs());
            pp[col] += h;
            j.set_column(col, &((residual(&pp) - r) / h));
        }
        // Minimum-change step: (J^T J + mu I) dp = -J^T r.
        let a = j.transpose() * j + SMatrix::<f64, 9, 9>::identity() * mu;
        let Some(chol) = a.cholesky() else { break };
        let dp = chol.solve(&(-(j.transpose() * r)));
        let trial: [f64; 9] = std::array::from_fn(|i| p[i] + dp[i]);
        let rt = residual(&trial);
        if rt.norm() < r.norm() {
            (p, r) = (trial, rt);
            mu = (mu * 0.3).max(1e-12);
        } else {
            mu *= 10.0;
            if mu > 1e3 {
                break;
            }
        }
    }
    let robot = RobotParams::new(robot_of(&p, start))?;
    Ok((robot, r.norm()))
}

/// The largest difference between the momentum maps `(G/F, H/F)` (Eq. 7: `phi' = -(G theta1' +
/// H theta2')/F`) of two models over a 36 x 36 grid of the joint torus: what the planner sees
/// of a model error, free of the common factor of the constants.
pub fn momentum_map_error(a: &Lumped, b: &Lumped) -> f64 {
    let n = 36;
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (t1, t2) = (std::f64::consts::TAU * i as f64 / n as f64, std::f64::consts::TAU * j as f64 / n as f64);
            let (sa, sb) = (shape(a, t1, t2), shape(b, t1, t2));
            worst = worst.max((sa.G / sa.F - sb.G / sb.F).abs()).max((sa.H / sa.F - sb.H / sb.F).abs());
        }
    }
    worst
}
