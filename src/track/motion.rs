//! The motion a closed loop follows, for an arm of any number of joints: the plan's joint
//! angles, velocities and accelerations at any time (what the joint loop needs every tick) and
//! its base angle (what the re-planner compares with the measurement).

use crate::error::Error;
use crate::model::arm::Arm;
use crate::plan::{Motion, PlanningProblem};
use crate::planners::arm::ArmPlan;
use crate::planners::chain::{ChainPlan, ChainProblem};
use crate::planners::ecsa::ChainEcsaPlan;

/// The joints of a motion at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct JointPoint {
    /// Joint angles `theta` \[rad\] (`n` values).
    pub theta: Vec<f64>,
    /// Joint velocities `theta'` [rad/s].
    pub rate: Vec<f64>,
    /// Joint accelerations `theta''` [rad/s^2].
    pub acceleration: Vec<f64>,
}

/// A planned motion of an `n`-joint arm, exact at any time, as the closed loop reads it.
pub trait ArmMotion: Sync {
    /// The number `n` of joints.
    fn joints(&self) -> usize;
    /// The horizon `T` \[s\].
    fn horizon(&self) -> f64;
    /// The joints at `t` \[s\] (clamped to `[0, T]`).
    fn joints_at(&self, t: f64) -> Result<JointPoint, Error>;
    /// The base angle `phi` at `t` \[s\] (clamped to `[0, T]`) \[rad\].
    fn phi(&self, t: f64) -> Result<f64, Error>;
    /// The breakpoints `0 = b_0 < .. < b_N = T` of the motion's spline basis \[s\], where it is
    /// a spline (the minimum-effort planner's): a re-plan keeps them ([`super::replan`]).
    fn breakpoints(&self) -> Option<Vec<f64>> {
        None
    }
    /// `q = (phi, theta)` at `t` \[s\] \[rad\].
    fn q(&self, t: f64) -> Result<Vec<f64>, Error> {
        let mut q = vec![self.phi(t)?];
        q.extend(self.joints_at(t)?.theta);
        Ok(q)
    }
}

impl ArmMotion for ChainPlan {
    fn joints(&self) -> usize {
        self.coefficients().len()
    }

    fn horizon(&self) -> f64 {
        ChainPlan::horizon(self)
    }

    fn joints_at(&self, t: f64) -> Result<JointPoint, Error> {
        let t = t.clamp(0.0, ChainPlan::horizon(self));
        let mut p = JointPoint { theta: Vec::new(), rate: Vec::new(), acceleration: Vec::new() };
        for c in self.coefficients() {
            let [v, d, a] = self.basis().evaluate(c, t);
            p.theta.push(v);
            p.rate.push(d);
            p.acceleration.push(a);
        }
        Ok(p)
    }

    fn phi(&self, t: f64) -> Result<f64, Error> {
        Ok(ChainPlan::phi(self, t))
    }

    fn breakpoints(&self) -> Option<Vec<f64>> {
        Some(self.basis().breakpoints().to_vec())
    }
}

impl ArmMotion for ChainEcsaPlan {
    fn joints(&self) -> usize {
        ChainEcsaPlan::joints(self)
    }

    fn horizon(&self) -> f64 {
        ChainEcsaPlan::horizon(self)
    }

    fn joints_at(&self, t: f64) -> Result<JointPoint, Error> {
        let p = self.at(t);
        Ok(JointPoint { theta: p.theta, rate: p.rate, acceleration: p.acceleration })
    }

    fn phi(&self, t: f64) -> Result<f64, Error> {
        Ok(ChainEcsaPlan::phi(self, t))
    }
}

impl ArmMotion for ArmPlan {
    fn joints(&self) -> usize {
        self.motion().joints()
    }

    fn horizon(&self) -> f64 {
        ArmPlan::horizon(self)
    }

    fn joints_at(&self, t: f64) -> Result<JointPoint, Error> {
        match self {
            ArmPlan::Optimal(p) => p.joints_at(t),
            ArmPlan::Ecsa(p) => p.joints_at(t),
        }
    }

    fn phi(&self, t: f64) -> Result<f64, Error> {
        match self {
            ArmPlan::Optimal(p) => ArmMotion::phi(p, t),
            ArmPlan::Ecsa(p) => ArmMotion::phi(p, t),
        }
    }

    fn breakpoints(&self) -> Option<Vec<f64>> {
        match self {
            ArmPlan::Optimal(p) => ArmMotion::breakpoints(p),
            ArmPlan::Ecsa(_) => None,
        }
    }
}

/// A 2-link plan ([`Motion`]: the NFA's, the 2-joint ECSA's or minimum-effort planner's) read
/// as the motion of the 2-link [`Arm`] ([`Arm::from_params`]); with [`two_link`], the closed
/// loop tracks it as any arm's.
pub struct TwoLinkMotion<'a>(pub &'a (dyn Motion + Sync));

impl ArmMotion for TwoLinkMotion<'_> {
    fn joints(&self) -> usize {
        2
    }

    fn horizon(&self) -> f64 {
        self.0.horizon()
    }

    fn joints_at(&self, t: f64) -> Result<JointPoint, Error> {
        let p = self.0.at(t.clamp(0.0, self.0.horizon()))?;
        Ok(JointPoint { theta: vec![p.q.theta1, p.q.theta2], rate: p.u.to_vec(), acceleration: p.du.to_vec() })
    }

    fn phi(&self, t: f64) -> Result<f64, Error> {
        Ok(self.0.at(t.clamp(0.0, self.0.horizon()))?.q.phi)
    }
}

/// The arm and the problem of a 2-link planning problem: [`Arm::from_params`] of its robot, its
/// start, goal, horizon and start velocity (the goal's angles modulo 2 pi).
pub fn two_link(problem: &PlanningProblem) -> (Arm, ChainProblem) {
    let arm = Arm::from_params(&problem.robot);
    let chain = ChainProblem {
        start: problem.start.to_array().to_vec(),
        goal: problem.goal.to_array().to_vec(),
        horizon: problem.horizon,
        initial_velocity: problem.start_velocity.to_vec(),
        wrap: true,
    };
    (arm, chain)
}
