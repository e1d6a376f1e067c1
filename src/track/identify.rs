//! On-line identification of the momentum map (Eqs. 5, 8 for `n` links): the angular momentum
//! `F(theta) phi' + G(theta) . theta'` (the first row of the inertia matrix times `q'`) is linear
//! in a vector of inertial parameters of the arm ([`parameters`]), so the measured motion at zero
//! momentum determines them (up to one common factor) by least squares.
//!
//! Relative to the base's centre of mass, link `k`'s centre of mass is
//! `p_k = a e(phi) + b e(phi + pi/2) + sum_{i<k} l_i e(psi_i) + d_k e(psi_k)`, a combination
//! `sum_j C_kj v_j` of unit vectors `v_j = e(gamma_j)` turning with `gamma_j` (`phi`,
//! `phi + pi/2`, `psi_1 .. psi_n`; `psi_i = phi + theta_1 + .. + theta_i`). With the system's
//! centre of mass at rest at the origin the momentum is
//! `sum_{k,l} W_kl p_k x p_l' + I_0 phi' + sum_k I_k psi_k'`, `W = diag(m) - m m^T / m_total`, and
//! `v_j x (d/dt) v_l = gamma_l' cos(gamma_l - gamma_j)`; so with `P_jj' = sum_k m_k C_kj C_kj' - S_j
//! S_j' / m_total`, `S_j = sum_k m_k C_kj`, the unknowns and their regressors are
//!
//! ```text
//! link i:        x = P_ii + I_i                 r = psi_i'
//! links i < j:   x = P_ij                       r = (psi_i' + psi_j') cos(Theta_j - Theta_i)
//! mount a, i:    x = P_ai                       r = (phi' + psi_i') cos(Theta_i)
//! mount b, i:    x = P_bi                       r = (phi' + psi_i') sin(Theta_i)
//! base:          x = P_aa + P_bb + I_0          r = phi'
//! ```
//!
//! (`Theta_i = theta_1 + .. + theta_i`; `v_a x v_b'` vanishes), `n + n (n - 1)/2 + 2 n + 1`
//! in all ([`parameter_count`]); for the SRC robot (`n = 2`) they are the paper's lumped constants
//! `(A, B, C, D a, D b, E a, E b, I_P)` of Sec. 3.1 with their regressors, in that order, and the
//! mount terms absorb an error of the mounting point. Each measurement gives one linear
//! equation `r^T x = 0`.
//!
//! The estimate minimises the exponentially forgotten sum of squares plus a small pull toward
//! the nominal parameters, `sum_k lambda^(n-k) (r_k^T x)^2 + rho |x - x_nom|^2` (in units of the
//! nominal parameters): recursive least squares with forgetting in information form. The pull
//! fixes the common factor, which zero momentum cannot see (it then sits at the nominal
//! projection), and keeps unexcited directions at their nominal values. The parameters are
//! mapped back to an arm ([`fit_arm`]) so that the planner and the computed torque both use
//! them.
//!
//! ## Reference
//! L. Ljung, T. Söderström, *Theory and Practice of Recursive Identification*, MIT Press 1983,
//! Sec. 2.6 (least squares with exponential forgetting), ISBN 978-0-262-12095-5.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::plant::State;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::{InputError, Mount};

/// The identified parameter vector of the module docs [kg m^2], in the order of
/// [`parameter_names`].
pub type Constants = Vec<f64>;

/// The number of parameters of an arm of `n` joints: `n` links, `n (n - 1) / 2` pairs, `2 n`
/// mount terms and the base.
pub fn parameter_count(n: usize) -> usize {
    n + n * (n.saturating_sub(1)) / 2 + 2 * n + 1
}

/// The names of the parameters of an arm of `n` joints, in order: `link1`.., `link1.link2`..,
/// `a.link1`, `b.link1`.., `base`; for `n = 2` the paper's `A, B, C, D a, D b, E a, E b, I_P`
/// follow in parentheses.
pub fn parameter_names(n: usize) -> Vec<String> {
    let mut names: Vec<String> = (1..=n).map(|i| format!("link{i}")).collect();
    for i in 1..=n {
        for j in i + 1..=n {
            names.push(format!("link{i}.link{j}"));
        }
    }
    for i in 1..=n {
        names.push(format!("a.link{i}"));
        names.push(format!("b.link{i}"));
    }
    names.push("base".into());
    if n == 2 {
        let paper = ["A", "B", "C", "D a", "D b", "E a", "E b", "I_P"];
        names = names.iter().zip(paper).map(|(n, p)| format!("{n} ({p})")).collect();
    }
    names
}

/// The parameters of `arm` (module docs), in the order of [`parameter_names`].
pub fn parameters(arm: &Arm) -> Constants {
    let n = arm.joints();
    let total = arm.total_mass();
    // C_kj, basis vectors j = (a, b, e_1 .. e_n), bodies k = links 1..n.
    let coefficients: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let mut c = vec![arm.mount.a, arm.mount.b];
            c.extend((0..n).map(|i| match i.cmp(&k) {
                std::cmp::Ordering::Less => arm.links[i].length,
                std::cmp::Ordering::Equal => arm.links[k].com,
                std::cmp::Ordering::Greater => 0.0,
            }));
            c
        })
        .collect();
    let s: Vec<f64> =
        (0..n + 2).map(|j| arm.links.iter().zip(&coefficients).map(|(l, c)| l.mass * c[j]).sum()).collect();
    let p = |j: usize, jj: usize| -> f64 {
        arm.links.iter().zip(&coefficients).map(|(l, c)| l.mass * c[j] * c[jj]).sum::<f64>() - s[j] * s[jj] / total
    };
    let mut x: Vec<f64> = (0..n).map(|i| p(i + 2, i + 2) + arm.links[i].inertia).collect();
    for i in 0..n {
        for j in i + 1..n {
            x.push(p(i + 2, j + 2));
        }
    }
    for i in 0..n {
        x.push(p(0, i + 2));
        x.push(p(1, i + 2));
    }
    x.push(p(0, 0) + p(1, 1) + arm.base.inertia);
    x
}

/// The sums `Theta_i = theta_1 + .. + theta_i` \[rad\] and the links' absolute rates `psi_i' =
/// phi' + theta_1' + .. + theta_i'` [rad/s] at a state (module docs): what the momentum and the
/// energy regressors ([`super::energy::regressor`]) are made of.
pub fn relative_angles(state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.q.len() - 1;
    let (mut theta, mut psi_rate) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut sum, mut rate) = (0.0, state.dq[0]);
    for i in 0..n {
        sum += state.q[i + 1];
        rate += state.dq[i + 1];
        theta.push(sum);
        psi_rate.push(rate);
    }
    (theta, psi_rate)
}

/// The regressor `r` of the module docs at a state: `r . x = F phi' + G . theta'`, for
/// [`parameters`] `x`.
pub fn regressor(state: &State) -> Vec<f64> {
    let n = state.q.len() - 1;
    let w = state.dq[0];
    let (theta, psi_rate) = relative_angles(state);
    let mut r = psi_rate.clone();
    for i in 0..n {
        for j in i + 1..n {
            r.push((psi_rate[i] + psi_rate[j]) * (theta[j] - theta[i]).cos());
        }
    }
    for i in 0..n {
        let (s, c) = theta[i].sin_cos();
        r.push((w + psi_rate[i]) * c);
        r.push((w + psi_rate[i]) * s);
    }
    r.push(w);
    r
}

/// The units of the parameters of `arm`: their nominal magnitudes, the mount terms' at a mount
/// of length `max(|(a, b)|, 0.05 m)` (so that a mount at the origin keeps a unit), every unit at
/// least 1e-9 of the largest.
fn units(arm: &Arm) -> Vec<f64> {
    let n = arm.joints();
    let reach = arm.mount.a.hypot(arm.mount.b).max(0.05);
    let along = Arm { mount: Mount { a: reach, b: 0.0 }, ..arm.clone() };
    let (x, xa) = (parameters(arm), parameters(&along));
    let mounts = n + n * n.saturating_sub(1) / 2;
    let mut u: Vec<f64> = x.iter().map(|v| v.abs()).collect();
    for i in 0..n {
        let unit = xa[mounts + 2 * i].abs();
        u[mounts + 2 * i] = unit;
        u[mounts + 2 * i + 1] = unit;
    }
    let largest = u.iter().fold(0.0_f64, |m, v| m.max(*v));
    u.iter().map(|v| v.max(1e-9 * largest)).collect()
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

/// The recursive estimator of the parameters (see the module docs).
#[derive(Debug, Clone)]
pub struct Identifier {
    scale: Vec<f64>,
    nominal: DVector<f64>,
    information: DMatrix<f64>,
    options: IdentifyOptions,
}

impl Identifier {
    /// An estimator starting at the parameters of `nominal`.
    pub fn new(nominal: &Arm, options: IdentifyOptions) -> Self {
        let scale = units(nominal);
        let c = parameters(nominal);
        let m = c.len();
        let nominal = DVector::from_iterator(m, c.iter().zip(&scale).map(|(c, s)| c / s));
        Self { scale, nominal, information: DMatrix::zeros(m, m), options }
    }

    /// Adds the measurement `state`, weighted by the time `dt` \[s\] it stands for, and forgets
    /// the older ones by `exp(-dt / forgetting_time)`.
    pub fn update(&mut self, state: &State, dt: f64) {
        let r = regressor(state);
        let v = DVector::from_iterator(r.len(), r.iter().zip(&self.scale).map(|(r, s)| r * s));
        if v.len() == self.scale.len() && v.iter().all(|x| x.is_finite()) {
            let lambda = (-dt / self.options.forgetting_time).exp();
            self.information *= lambda;
            self.information.ger(dt, &v, &v, 1.0);
        }
    }

    /// The current estimate: `x = (R + rho I)^-1 rho x_nom` in nominal units.
    pub fn estimate(&self) -> Constants {
        let rho = self.options.prior_weight;
        let m = self.scale.len();
        let a = &self.information + DMatrix::<f64>::identity(m, m) * rho;
        let x = a.cholesky().map(|c| c.solve(&(&self.nominal * rho))).unwrap_or_else(|| self.nominal.clone());
        x.iter().zip(&self.scale).map(|(x, s)| x * s).collect()
    }
}

/// What [`fit_arm`] changes: the logarithms of the base's mass and inertia, of every link's
/// mass, of every length but the last (which the momentum map does not see), of every positive
/// centre-of-mass distance and link inertia; then the mount `a, b` (zero distances and
/// inertias stay zero).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Unknown {
    BaseMass,
    BaseInertia,
    Mass(usize),
    Length(usize),
    Com(usize),
    Inertia(usize),
    MountA,
    MountB,
}

fn unknowns(arm: &Arm) -> Vec<Unknown> {
    let n = arm.joints();
    let mut u = vec![Unknown::BaseMass, Unknown::BaseInertia];
    u.extend((0..n).map(Unknown::Mass));
    u.extend((0..n - 1).map(Unknown::Length));
    u.extend((0..n).filter(|&k| arm.links[k].com > 0.0).map(Unknown::Com));
    u.extend((0..n).filter(|&k| arm.links[k].inertia > 0.0).map(Unknown::Inertia));
    u.extend([Unknown::MountA, Unknown::MountB]);
    u
}

fn values(arm: &Arm, unknowns: &[Unknown]) -> Vec<f64> {
    unknowns
        .iter()
        .map(|u| match *u {
            Unknown::BaseMass => arm.base.mass.ln(),
            Unknown::BaseInertia => arm.base.inertia.ln(),
            Unknown::Mass(k) => arm.links[k].mass.ln(),
            Unknown::Length(k) => arm.links[k].length.ln(),
            Unknown::Com(k) => arm.links[k].com.ln(),
            Unknown::Inertia(k) => arm.links[k].inertia.ln(),
            Unknown::MountA => arm.mount.a,
            Unknown::MountB => arm.mount.b,
        })
        .collect()
}

fn arm_of(p: &[f64], unknowns: &[Unknown], like: &Arm) -> Arm {
    let mut arm = like.clone();
    for (u, &v) in unknowns.iter().zip(p) {
        match *u {
            Unknown::BaseMass => arm.base.mass = v.exp(),
            Unknown::BaseInertia => arm.base.inertia = v.exp(),
            Unknown::Mass(k) => arm.links[k].mass = v.exp(),
            Unknown::Length(k) => arm.links[k].length = v.exp(),
            Unknown::Com(k) => arm.links[k].com = v.exp(),
            Unknown::Inertia(k) => arm.links[k].inertia = v.exp(),
            Unknown::MountA => arm.mount.a = v,
            Unknown::MountB => arm.mount.b = v,
        }
    }
    arm
}

/// An arm whose parameters ([`parameters`]) match `target`, found by damped Gauss–Newton
/// (Levenberg–Marquardt) from `start` in the logarithms of its masses, inertias and lengths and
/// its mounting point (see the private `Unknown`s: the last link's length, which the momentum
/// map does not see, is `start`'s). The map may have more unknowns than equations: the damping
/// keeps the arm near `start`. Returns the arm and the final residual in units of the nominal
/// parameters; an arm that fails [`Arm::validate`] (a centre of mass past its link) is an error.
pub fn fit_arm(target: &[f64], start: &Arm) -> Result<(Arm, f64), Error> {
    let scale = units(start);
    if target.len() != scale.len() {
        return Err(InputError::InvalidParameter {
            name: "identified parameters".into(),
            value: target.len() as f64,
            expected: "one value per parameter of the arm (parameter_count)",
        }
        .into());
    }
    let unknowns = unknowns(start);
    let residual = |p: &[f64]| -> DVector<f64> {
        let c = parameters(&arm_of(p, &unknowns, start));
        DVector::from_iterator(c.len(), c.iter().zip(target).zip(&scale).map(|((c, t), s)| (c - t) / s))
    };
    let m = unknowns.len();
    let mut p = values(start, &unknowns);
    let mut r = residual(&p);
    let mut mu = 1e-6;
    for _ in 0..40 {
        if r.norm() < 1e-13 {
            break;
        }
        let mut j = DMatrix::<f64>::zeros(r.len(), m);
        for col in 0..m {
            let mut pp = p.clone();
            let h = 1e-7 * (1.0 + p[col].abs());
            pp[col] += h;
            j.set_column(col, &((residual(&pp) - &r) / h));
        }
        // Minimum-change step: (J^T J + mu I) dp = -J^T r.
        let a = j.transpose() * &j + DMatrix::<f64>::identity(m, m) * mu;
        let Some(chol) = a.cholesky() else { break };
        let dp = chol.solve(&(-(j.transpose() * &r)));
        let trial: Vec<f64> = p.iter().zip(dp.iter()).map(|(p, d)| p + d).collect();
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
    let arm = arm_of(&p, &unknowns, start);
    arm.validate()?;
    Ok((arm, r.norm()))
}

/// The largest difference between the momentum maps `G_j / F` (Eq. 7: `phi' = -(G . theta')/F`)
/// of two arms of the same joint count over a grid of the joint torus (`k` points per joint,
/// `k = max(2, floor(1296^(1/n)))`: 36 x 36 for two joints): what the planner sees of a model
/// error, free of the common factor of the parameters.
pub fn momentum_map_error(a: &Arm, b: &Arm) -> f64 {
    let n = a.joints();
    let k = ((1296f64.powf(1.0 / n as f64) + 1e-9).floor() as usize).max(2);
    let total = k.pow(n as u32);
    let mut worst: f64 = 0.0;
    let mut theta = vec![0.0; n];
    for index in 0..total {
        let mut rest = index;
        for t in theta.iter_mut() {
            *t = std::f64::consts::TAU * (rest % k) as f64 / k as f64;
            rest /= k;
        }
        let ((fa, ga), (fb, gb)) = (a.momentum_coefficients(&theta), b.momentum_coefficients(&theta));
        for (x, y) in ga.iter().zip(&gb) {
            worst = worst.max((x / fa - y / fb).abs());
        }
    }
    worst
}
