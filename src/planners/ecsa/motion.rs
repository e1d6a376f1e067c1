//! The ECSA's planned motion for the 2-link robot (Sec. 5, Figs. 9-12): the engine's plan
//! ([`ChainEcsaPlan`], analytic controls and joint angles, the base angle by the holonomy
//! integral) as a 2-link [`Motion`], with its samples.

use num_dual::Dual64;

use super::ChainEcsaPlan;
use crate::error::Error;
use crate::model::system::{shape, velocity_acceleration};
use crate::model::{Configuration, Lumped};
use crate::numerics::ode::OdeError;
use crate::plan::{Motion, MotionPoint, Trajectory};

/// The ECSA's planned motion of the 2-link robot: the engine's plan, exact at any time, and
/// its configurations at equally spaced samples.
#[derive(Debug, Clone)]
pub struct EcsaMotion {
    plan: ChainEcsaPlan,
    k: Lumped,
    t: Vec<f64>,
    q: Vec<[f64; 3]>,
}

impl EcsaMotion {
    /// The motion of `plan` (2 joints) of the robot of lumped constants `k`, sampled at
    /// `samples >= 2` equally spaced times, the last exactly at `T`.
    pub(super) fn new(plan: ChainEcsaPlan, k: Lumped, samples: usize) -> Self {
        let points = plan.sample(samples);
        let t = points.iter().map(|p| p.t).collect();
        let q = points.iter().map(|p| [p.phi, p.theta[0], p.theta[1]]).collect();
        Self { plan, k, t, q }
    }

    /// The coefficients of the controls \[rad/s\].
    pub fn coefficients(&self) -> &[f64] {
        &self.plan.stats.coefficients
    }

    /// The engine's plan.
    pub fn plan(&self) -> &ChainEcsaPlan {
        &self.plan
    }

    /// The sampled trajectory: `q` from the plan, `dq = g(q) u`, `ddq` exact (dual numbers
    /// through (7) with the analytic `du/dt`); `z` is `None`.
    pub fn trajectory(&self) -> Result<Trajectory, Error> {
        let n = self.t.len();
        let mut dq = Vec::with_capacity(n);
        let mut ddq = Vec::with_capacity(n);
        for (q, &t) in self.q.iter().zip(&self.t) {
            // The analytic controls and their exact rates (the angles are the samples').
            let w = self.plan.basis().controls(self.coefficients(), Dual64::new(t, 1.0));
            let (u, du) = ([w[0].re, w[1].re], [w[0].eps, w[1].eps]);
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
        self.plan.horizon()
    }

    fn at(&self, t: f64) -> Result<MotionPoint, Error> {
        let horizon = self.plan.horizon();
        if !(t >= 0.0 && t <= horizon * (1.0 + 1e-14)) {
            return Err(OdeError { t, reason: "time outside [0, T] of the plan" }.into());
        }
        let p = self.plan.at(t);
        Ok(MotionPoint {
            q: Configuration::new(p.phi, p.theta[0], p.theta[1]),
            u: [p.rate[0], p.rate[1]],
            du: [p.acceleration[0], p.acceleration[1]],
        })
    }

    fn controls(&self, t: f64) -> Result<[f64; 2], Error> {
        Ok(self.plan.basis().controls(self.coefficients(), t))
    }
}
