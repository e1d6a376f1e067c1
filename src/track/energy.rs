//! The common factor of the identified parameters, from the energy balance of the joint
//! torques (issue 22).
//!
//! Zero angular momentum sees the inertial parameters `x` of [`super::identify`] only up to a
//! common factor: the momentum map `phi' = -(G . theta')/F` (Eq. 7) is a ratio of two forms
//! linear in `x`. The planner needs no more, but the computed torque does: a model whose
//! parameters are `x / s` asks for torques `1/s` of those the robot needs, and the joint loop
//! then lags by the difference over its gain. Where the plan brakes hard at its end, that lag
//! is the final error.
//!
//! The kinetic energy is linear in the same parameters. With `P_jj'` of [`super::identify`],
//! `T = (1/2) sum_jj' P_jj' gamma_j' gamma_j'' cos(gamma_j - gamma_j') + (1/2) I_0 phi'^2 +
//! (1/2) sum_k I_k psi_k'^2`, so `T = x . e(q, q')` with the energy regressor ([`regressor`])
//!
//! ```text
//! link i:        e = psi_i'^2 / 2
//! links i < j:   e = psi_i' psi_j' cos(Theta_j - Theta_i)
//! mount a, i:    e = phi' psi_i' cos(Theta_i)
//! mount b, i:    e = phi' psi_i' sin(Theta_i)
//! base:          e = phi'^2 / 2
//! ```
//!
//! (the momentum regressor is its derivative in `phi'`, Eq. 5 as `dT/dphi'`). In zero gravity
//! with no external torque the joint torques' work is the change of `T`; under a torque held
//! over a tick it is exactly `tau . (theta(t + dt) - theta(t))`. Over windows `k` of the run,
//! `s x . (e(end_k) - e(start_k)) = W_k`, and least squares with exponential forgetting gives
//! the factor `s` of an estimate `x` ([`EnergyBalance::factor`]).
//!
//! ## Reference
//! W. Khalil, E. Dombre, *Modeling, Identification and Control of Robots*, Hermes Penton 2002,
//! Sec. 12.5 (identification from the energy model), ISBN 978-1-903996-66-9.

use nalgebra::{DMatrix, DVector};

use super::identify::{parameter_count, relative_angles};
use super::plant::State;

/// The energy regressor `e` of the module docs at a state: `x . e = T`, the kinetic energy
/// \[J\], for the parameters `x` of [`super::identify::parameters`].
pub fn regressor(state: &State) -> Vec<f64> {
    let n = state.q.len() - 1;
    let w = state.dq[0];
    let (theta, psi_rate) = relative_angles(state);
    let mut e: Vec<f64> = psi_rate.iter().map(|r| 0.5 * r * r).collect();
    for i in 0..n {
        for j in i + 1..n {
            e.push(psi_rate[i] * psi_rate[j] * (theta[j] - theta[i]).cos());
        }
    }
    for i in 0..n {
        let (s, c) = theta[i].sin_cos();
        e.push(w * psi_rate[i] * c);
        e.push(w * psi_rate[i] * s);
    }
    e.push(0.5 * w * w);
    e
}

/// The length of one window of the balance \[s\]: long enough that the change of the energy
/// stands out of the sensors' noise, short against the forgetting time.
pub const WINDOW: f64 = 0.1;

/// The factor is taken only inside `[1 / FACTOR_RANGE, FACTOR_RANGE]`; outside (a torque bias
/// the model does not know, too little motion) the estimate keeps its own scale.
pub const FACTOR_RANGE: f64 = 4.0;

/// The recursive least squares of the energy balance (module docs), in information form:
/// `A = sum_k lambda_k de_k de_k^T`, `b = sum_k lambda_k de_k W_k`.
#[derive(Debug, Clone)]
pub struct EnergyBalance {
    information: DMatrix<f64>,
    moment: DVector<f64>,
    forgetting_time: f64,
    /// The window being filled: its start's regressor, its work so far \[J\], its length \[s\].
    start: Option<Vec<f64>>,
    work: f64,
    elapsed: f64,
    /// The last measured joint angles and the torque held since \[N m\].
    last: Option<(Vec<f64>, Vec<f64>)>,
}

impl EnergyBalance {
    /// An empty balance for an arm of `n` joints, forgetting windows `forgetting_time` \[s\]
    /// old by `1/e`.
    pub fn new(n: usize, forgetting_time: f64) -> Self {
        let m = parameter_count(n);
        Self {
            information: DMatrix::zeros(m, m),
            moment: DVector::zeros(m),
            forgetting_time,
            start: None,
            work: 0.0,
            elapsed: 0.0,
            last: None,
        }
    }

    /// Adds the measurement `state` at the start of a tick of `dt` \[s\] over which the torque
    /// `tau` [N m] is held (as the actuators take it: after the known saturation). The work of
    /// the previous tick is `tau_prev . (theta - theta_prev)`; a window ends every
    /// [`WINDOW`] seconds.
    pub fn update(&mut self, state: &State, tau: &[f64], dt: f64) {
        if !state.q.iter().chain(&state.dq).chain(tau).all(|x| x.is_finite()) {
            self.start = None;
            self.last = None;
            return;
        }
        let theta = state.theta();
        if let Some((previous, held)) = self.last.as_ref() {
            self.work += held.iter().zip(theta.iter().zip(previous)).map(|(t, (a, b))| t * (a - b)).sum::<f64>();
            self.elapsed += dt;
        }
        self.last = Some((theta.to_vec(), tau.to_vec()));
        let e = regressor(state);
        match self.start.take() {
            Some(start) if self.elapsed >= WINDOW - 0.5 * dt => {
                let de = DVector::from_iterator(e.len(), e.iter().zip(&start).map(|(a, b)| a - b));
                let lambda = (-self.elapsed / self.forgetting_time).exp();
                self.information *= lambda;
                self.moment *= lambda;
                self.information.ger(1.0, &de, &de, 1.0);
                self.moment.axpy(self.work, &de, 1.0);
                (self.work, self.elapsed) = (0.0, 0.0);
                self.start = Some(e);
            }
            Some(start) => self.start = Some(start),
            None => {
                (self.work, self.elapsed) = (0.0, 0.0);
                self.start = Some(e);
            }
        }
    }

    /// The factor `s` that makes `s x` fit the energy balance best (module docs): `x . b / x^T
    /// A x`; 1 when the windows so far do not see `x` (no motion yet), or when the fit falls
    /// outside [`FACTOR_RANGE`].
    pub fn factor(&self, x: &[f64]) -> f64 {
        if x.len() != self.moment.len() {
            return 1.0;
        }
        let x = DVector::from_column_slice(x);
        let seen = x.dot(&(&self.information * &x));
        let s = x.dot(&self.moment) / seen;
        if seen > 0.0 && s.is_finite() && (1.0 / FACTOR_RANGE..=FACTOR_RANGE).contains(&s) { s } else { 1.0 }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::DVector;

    use super::*;
    use crate::dynamics::arm::kinetic_energy;
    use crate::model::RobotParams;
    use crate::model::arm::Arm;
    use crate::track::identify::{parameters, regressor as momentum_regressor};

    fn three_link() -> Arm {
        let mut arm = Arm::from_params(&RobotParams::src());
        let mut third = arm.links[1];
        third.length = 0.4;
        third.com = 0.15;
        third.mass = 0.8;
        third.inertia = 0.01;
        arm.links.push(third);
        arm.mount.a = 0.7;
        arm.mount.b = -0.4;
        arm
    }

    /// `x . e` is the kinetic energy of the dynamics (`(1/2) q'^T M q'`, an independent
    /// formula) at arbitrary states, not only at zero momentum.
    #[test]
    fn the_energy_regressor_gives_the_kinetic_energy() {
        for arm in [Arm::from_params(&RobotParams::src()), three_link()] {
            let n = arm.joints();
            let x = parameters(&arm);
            for k in 0..20 {
                let f = |i: usize| ((k * 7 + i * 3) as f64 * 0.731).sin() * 2.0;
                let q: Vec<f64> = (0..=n).map(|i| f(i) * 2.0).collect();
                let dq: Vec<f64> = (0..=n).map(|i| f(i + 11)).collect();
                let state = State { q: q.clone(), dq: dq.clone() };
                let t: f64 = regressor(&state).iter().zip(&x).map(|(e, x)| e * x).sum();
                let reference = kinetic_energy(&arm, &q[1..], &DVector::from_vec(dq));
                assert!((t - reference).abs() <= 1e-12 * reference.abs().max(1.0), "{t} vs {reference}");
            }
        }
    }

    /// The momentum regressor is the energy regressor's derivative in `phi'` (Eq. 5: the
    /// momentum is `dT/dphi'`), by central differences, exact for a quadratic.
    #[test]
    fn the_momentum_regressor_is_the_derivative_in_the_base_rate() {
        let state = State { q: vec![0.3, -1.1, 2.0, 0.4], dq: vec![0.2, -0.7, 1.3, 0.5] };
        let h = 1e-3;
        let shifted = |d: f64| {
            let mut s = state.clone();
            s.dq[0] += d;
            regressor(&s)
        };
        let (up, down) = (shifted(h), shifted(-h));
        for (i, r) in momentum_regressor(&state).iter().enumerate() {
            let derivative = (up[i] - down[i]) / (2.0 * h);
            assert!((derivative - r).abs() < 1e-10, "{i}: {derivative} vs {r}");
        }
    }

    /// On exact windows of a motion whose energy changes, the factor between an estimate `x / s`
    /// and the balance is `s`; without motion it is 1.
    #[test]
    fn the_factor_of_a_scaled_estimate_is_recovered() {
        let arm = three_link();
        let x = parameters(&arm);
        let mut balance = EnergyBalance::new(3, 5.0);
        assert!((balance.factor(&x) - 1.0).abs() < f64::EPSILON, "no windows: no factor");
        // Windows from rest to states of known energy; the work is the energy's change.
        let mut previous = State { q: vec![0.0; 4], dq: vec![0.0; 4] };
        for k in 1..30 {
            let f = |i: usize| ((k * 5 + i) as f64 * 0.37).sin();
            let next = State { q: (0..4).map(f).collect(), dq: (0..4).map(|i| f(i + 9)).collect() };
            let de: Vec<f64> = regressor(&next).iter().zip(regressor(&previous)).map(|(a, b)| a - b).collect();
            let work: f64 = de.iter().zip(&x).map(|(d, x)| d * x).sum();
            balance.information.ger(1.0, &DVector::from_column_slice(&de), &DVector::from_column_slice(&de), 1.0);
            balance.moment.axpy(work, &DVector::from_column_slice(&de), 1.0);
            previous = next;
        }
        let s = 1.07;
        let estimate: Vec<f64> = x.iter().map(|v| v / s).collect();
        assert!((balance.factor(&estimate) - s).abs() < 1e-12);
    }
}
