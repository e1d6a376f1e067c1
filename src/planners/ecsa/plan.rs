//! The engine's plan (any `n`): the joint motion in closed form from the coefficients, the base
//! angle by the holonomy integral, a [`JointMotion`] for the certificates.

use std::sync::Arc;

use num_dual::Dual64;

use super::{Basis, ChainEcsaStats, rule};
use crate::plan::certificate::{ChainVerification, JointMotion};
use crate::planners::chain::ChainPoint;
use crate::planners::chain::connection::Connection;

/// A certified `n`-joint ECSA plan: the joint motion in closed form, the base angle by the
/// holonomy integral from the nearest breakpoint.
#[derive(Debug, Clone)]
pub struct ChainEcsaPlan {
    connection: Arc<Connection>,
    basis: Basis,
    theta0: Vec<f64>,
    /// The breakpoints of the quadrature's pieces and `phi` there.
    breakpoints: Vec<f64>,
    phi_at_breakpoints: Vec<f64>,
    /// The iteration's account.
    pub stats: ChainEcsaStats,
    /// The velocity-level certificate.
    pub verification: ChainVerification,
}

impl ChainEcsaPlan {
    pub(super) fn new(connection: Arc<Connection>, basis: Basis, start: &[f64], stats: ChainEcsaStats) -> Self {
        let pieces = stats.quadrature_pieces;
        let horizon = basis.horizon();
        let breakpoints: Vec<f64> =
            (0..=pieces).map(|i| if i == pieces { horizon } else { horizon * i as f64 / pieces as f64 }).collect();
        let mut me = Self {
            connection,
            basis,
            theta0: start[1..].to_vec(),
            breakpoints,
            phi_at_breakpoints: vec![start[0]],
            stats,
            verification: ChainVerification::pending(),
        };
        for i in 0..pieces {
            let next = me.phi_at_breakpoints[i] - me.holonomy(me.breakpoints[i], me.breakpoints[i + 1]);
            me.phi_at_breakpoints.push(next);
        }
        me
    }

    /// `integral_a^b a(theta) . u dt` by the [`NODES`]-node rule.
    fn holonomy(&self, a: f64, b: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        rule().integrate(a, b, |t| {
            self.state_into(t, &mut theta, &mut rate);
            self.connection.value(&theta, &rate)
        })
    }

    fn state_into(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        let t = t.clamp(0.0, self.horizon());
        let m = self.basis.terms();
        let (b, anti) = (self.basis.values(t), self.basis.antiderivatives(t));
        let c = &self.stats.coefficients;
        for i in 0..theta.len() {
            let ci = &c[i * m..(i + 1) * m];
            theta[i] = self.theta0[i] + ci.iter().zip(&anti).map(|(c, a)| c * a).sum::<f64>();
            rate[i] = ci.iter().zip(&b).map(|(c, b)| c * b).sum();
        }
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.theta0.len()
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        self.basis.horizon()
    }

    /// The control basis.
    pub fn basis(&self) -> &Basis {
        &self.basis
    }

    /// The base angle at `t` \[rad\].
    pub fn phi(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.horizon());
        let pieces = self.breakpoints.len() - 1;
        let s = ((t / self.horizon() * pieces as f64) as usize).min(pieces - 1);
        let b = self.breakpoints[s];
        if t <= b {
            return self.phi_at_breakpoints[s];
        }
        self.phi_at_breakpoints[s] - self.holonomy(b, t)
    }

    /// `(phi, theta, theta', theta'')` at `t` \[s\] (clamped to `[0, T]`).
    pub fn at(&self, t: f64) -> ChainPoint {
        let t = t.clamp(0.0, self.horizon());
        let n = self.joints();
        let (mut theta, mut rate, mut acceleration) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.state_into(t, &mut theta, &mut rate);
        self.joint_acceleration(t, &mut acceleration);
        ChainPoint { t, phi: self.phi(t), theta, rate, acceleration }
    }

    /// `samples >= 2` equally spaced points from 0 to T, the last exactly at T.
    pub fn sample(&self, samples: usize) -> Vec<ChainPoint> {
        let samples = samples.max(2);
        let horizon = self.horizon();
        (0..samples)
            .map(|i| if i + 1 == samples { horizon } else { horizon * i as f64 / (samples - 1) as f64 })
            .map(|t| self.at(t))
            .collect()
    }
}

impl JointMotion for ChainEcsaPlan {
    fn joints(&self) -> usize {
        self.theta0.len()
    }

    fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        self.state_into(t, theta, rate);
    }

    fn phi_rate(&self, t: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        self.state_into(t, &mut theta, &mut rate);
        -self.connection.value(&theta, &rate)
    }

    fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
        let m = self.basis.terms();
        let d = self.basis.values(Dual64::new(t.clamp(0.0, self.horizon()), 1.0));
        let c = &self.stats.coefficients;
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..m).map(|j| c[i * m + j] * d[j].eps).sum();
        }
    }
}
