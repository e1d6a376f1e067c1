//! The ECSA's planned motion (Sec. 5, Figs. 9-12): the analytic controls and the configurations
//! from a dense integration of system (7).

use num_dual::Dual64;

use super::{Basis, Flow};
use crate::error::Error;
use crate::model::system::{shape, velocity_acceleration};
use crate::model::{Configuration, Lumped};
use crate::numerics::ode::{OdeError, OdeOptions};
use crate::plan::{Motion, MotionPoint, Trajectory};

/// The ECSA's planned motion: analytic controls, configurations from the stored samples of a
/// dense integration of (7), advanced from the nearest earlier sample (cheap).
#[derive(Debug, Clone)]
pub struct EcsaMotion {
    pub(super) k: Lumped,
    pub(super) basis: Basis,
    pub(super) coefficients: Vec<f64>,
    pub(super) ode: OdeOptions,
    pub(super) t: Vec<f64>,
    pub(super) q: Vec<[f64; 3]>,
}

impl EcsaMotion {
    /// The coefficients of the controls \[rad/s\].
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    fn flow(&self) -> Flow<'_> {
        Flow { k: self.k, basis: self.basis, coefficients: &self.coefficients, ode: self.ode }
    }

    /// The controls and their exact time derivatives at `t`.
    fn controls_and_rates(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        let u = self.basis.controls(&self.coefficients, Dual64::new(t, 1.0));
        ([u[0].re, u[1].re], [u[0].eps, u[1].eps])
    }

    /// The sampled trajectory: `q` from the integration, `dq = g(q) u`, `ddq` exact (dual
    /// numbers through (7) with the analytic `du/dt`); `z` is `None`.
    pub fn trajectory(&self) -> Result<Trajectory, Error> {
        let n = self.t.len();
        let mut dq = Vec::with_capacity(n);
        let mut ddq = Vec::with_capacity(n);
        for (q, &t) in self.q.iter().zip(&self.t) {
            let (u, du) = self.controls_and_rates(t);
            let (v, a) = velocity_acceleration(&self.k, &Configuration::from_array(*q), u, du);
            dq.push(v);
            ddq.push(a);
        }
        Ok(Trajectory { t: self.t.clone(), q: self.q.clone(), dq, ddq: Some(ddq), ..Default::default() })
    }

    /// `(min |sigma|, min |P|)` over the samples (Eqs. 9 and 13): how close the ECSA's path
    /// comes to the singular curves of the NFA's transformation (14), which ECSA itself does
    /// not need to avoid.
    pub fn margins(&self) -> (f64, f64) {
        self.q.iter().fold((f64::INFINITY, f64::INFINITY), |(s, p), q| {
            let sh = shape(&self.k, q[1], q[2]);
            (s.min(sh.sigma.abs()), p.min(sh.P.abs()))
        })
    }
}

impl Motion for EcsaMotion {
    fn horizon(&self) -> f64 {
        self.basis.horizon()
    }

    fn at(&self, t: f64) -> Result<MotionPoint, Error> {
        let n = self.t.len();
        let horizon = self.basis.horizon();
        if !(t >= 0.0 && t <= horizon * (1.0 + 1e-14)) {
            return Err(OdeError { t, reason: "time outside [0, T] of the plan" }.into());
        }
        let dt = horizon / (n - 1) as f64;
        let mut i = ((t / dt).floor() as usize).min(n - 1);
        while i > 0 && self.t[i] > t {
            i -= 1;
        }
        let q = self.flow().advance(self.t[i], self.q[i], t)?;
        let (u, du) = self.controls_and_rates(t);
        Ok(MotionPoint { q: Configuration::from_array(q), u, du })
    }

    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        Ok(self.basis.controls(&self.coefficients, t))
    }
}
