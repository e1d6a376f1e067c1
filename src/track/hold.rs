//! The hold correction: the feedforward that makes the sampled computed-torque loop end at the
//! goal on the nominal robot.
//!
//! A digital controller holds each torque over a control tick (zero-order hold). Even with the
//! law evaluated at the tick's centre ([`computed_torque`]), each tick then departs from the
//! continuous motion by `O(dt^3)`, so the run ends `O(dt^2)` off, in proportion to the plan's
//! jerk: 1.2e-6 rad at 1 kHz for the minimum-effort plan at `a = 1, b = -1`, whose end layers turn
//! fast, and the joints still move at 1e-4 rad/s at the end, lagging the layer. The joint loop
//! corrects the joints afterwards; the base angle `phi` keeps the holonomy of the joints' small
//! departures (Eq. 8), during the run and while the joints settle.
//!
//! The correction adds a small joint acceleration `delta a(t)` to the plan's, a polynomial of
//! degree [`DEGREE`] in time per joint, chosen so that the loop on the nominal model ends at the
//! plan's final configuration and joint velocity (`2n + 1` conditions for `n` joints,
//! `n (DEGREE + 1)` unknowns, the least-norm solution). The loop's end state is smooth in the coefficients, and Newton's method
//! with a finite-difference Jacobian of the whole loop (each column one simulated run) converges
//! in two or three steps. On the nominal robot without noise the loop then follows the corrected
//! run tick for tick and ends at the goal, at rest, to round-off. The correction is small: at
//! `a = 1, b = -1` its largest acceleration is 0.63 rad/s^2, under 1 % of the plan's, mostly
//! for the final layer's velocity lag; on any other robot it is a feedforward far below what the feedback corrects.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::control::{Gains, computed_torque};
use super::motion::{ArmMotion, JointPoint};
use super::plant::{Disturbances, Plant, State};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::planners::chain::ChainProblem;

/// Degree of the correction's polynomial per joint.
pub const DEGREE: usize = 2;

/// Finite-difference step of the Jacobian [rad/s^2]: the joints then move by about
/// `step / kp ~ 4e-7 rad` (default gains), where the loop is linear to about 1e-13 and the
/// differences keep eight digits above the round-off of a 10^4-tick run.
const STEP: f64 = 1e-3;

/// The loop's end counts as reached within this \[rad, rad/s\].
const REACHED: f64 = 1e-12;

/// The corrected feedforward of one plan at one control rate, and the nominal loop's states.
#[derive(Debug, Clone)]
pub struct HoldCorrection {
    /// `DEGREE + 1` Legendre coefficients per joint, joint-major.
    coefficients: Vec<f64>,
    horizon: f64,
    states: Vec<State>,
    /// `max |wrap(q_i(T) - qd_i)|` of the nominal loop before the correction \[rad\].
    pub error_before: f64,
    /// The same after the correction \[rad\].
    pub error_after: f64,
    /// The largest `|delta a_i(t)|` [rad/s^2].
    pub peak_acceleration: f64,
}

/// The sampled loop whose end is corrected: the nominal arm, its plan at the ticks' centres.
struct Loop<'a> {
    model: &'a Arm,
    problem: &'a ChainProblem,
    centres: Vec<JointPoint>,
    dt: f64,
    substeps: usize,
    gains: Gains,
    /// `(q(T), theta'(T))` of the plan.
    end: Vec<f64>,
}

impl HoldCorrection {
    /// The correction of `plan` (for `problem`, on its nominal arm `model`) at `rate` \[Hz\] with
    /// `substeps` plant steps per tick and the joint loop `gains`. `None` when the nominal loop
    /// diverges or leaves a declared limit of `model` (issue 20), or Newton's method does not
    /// reduce its final error (the run then uses the plan as it is); a Newton step whose loop
    /// leaves a limit is not taken.
    pub fn new(
        model: &Arm,
        problem: &ChainProblem,
        plan: &dyn ArmMotion,
        rate: f64,
        substeps: usize,
        gains: Gains,
    ) -> Result<Option<HoldCorrection>, Error> {
        let n = model.joints();
        let unknowns = n * (DEGREE + 1);
        let horizon = problem.horizon;
        let ticks = (horizon * rate).round().max(1.0) as usize;
        let dt = horizon / ticks as f64;
        let centres = (0..ticks).map(|i| plan.joints_at(i as f64 * dt + 0.5 * dt)).collect::<Result<Vec<_>, _>>()?;
        let mut end = plan.q(horizon)?;
        end.extend(plan.joints_at(horizon)?.rate);
        let lp = Loop { model, problem, centres, dt, substeps, gains, end };
        let zero = vec![0.0; unknowns];
        let (r0, states0) = lp.run(&zero);
        let error_before = position_error(&r0, n);
        if !error_before.is_finite() {
            return Ok(None);
        }
        let columns: Vec<Vec<f64>> = (0..unknowns)
            .into_par_iter()
            .map(|j| {
                let mut c = zero.clone();
                c[j] = STEP;
                let (r, _) = lp.run(&c);
                r.iter().zip(&r0).map(|(r, r0)| (r - r0) / STEP).collect()
            })
            .collect();
        let jacobian = DMatrix::<f64>::from_fn(2 * n + 1, unknowns, |i, j| columns[j][i]);
        let Ok(inverse) = jacobian.clone().svd(true, true).pseudo_inverse(1e-12 * jacobian.norm()) else {
            return Ok(None);
        };
        let (mut c, mut r, mut states) = (zero, r0, states0);
        for _ in 0..4 {
            if r.iter().all(|x| x.abs() <= REACHED) {
                break;
            }
            let step = &inverse * DVector::from_column_slice(&r);
            let trial: Vec<f64> = c.iter().zip(step.iter()).map(|(c, s)| c - s).collect();
            let (rt, st) = lp.run(&trial);
            if !(norm(&rt) < norm(&r)) {
                break;
            }
            (c, r, states) = (trial, rt, st);
        }
        let error_after = position_error(&r, n);
        if !(error_after < error_before) {
            return Ok(None);
        }
        let mut correction =
            HoldCorrection { coefficients: c, horizon, states, error_before, error_after, peak_acceleration: 0.0 };
        correction.peak_acceleration = (0..=100)
            .flat_map(|i| correction.acceleration(horizon * i as f64 / 100.0))
            .fold(0.0_f64, |m, a| m.max(a.abs()));
        Ok(Some(correction))
    }

    /// `delta a(t)` [rad/s^2] at time `t` of the run \[s\], one value per joint.
    pub fn acceleration(&self, t: f64) -> Vec<f64> {
        let p = legendre(2.0 * t / self.horizon - 1.0);
        self.coefficients.chunks(DEGREE + 1).map(|c| c.iter().zip(&p).map(|(c, p)| c * p).sum()).collect()
    }

    /// The plan's point `centre` with the correction at time `t` added to its acceleration.
    pub fn corrected(&self, mut centre: JointPoint, t: f64) -> JointPoint {
        for (a, d) in centre.acceleration.iter_mut().zip(self.acceleration(t)) {
            *a += d;
        }
        centre
    }

    /// The nominal loop's state at the start of tick `i`, if the run has that tick.
    pub fn nominal(&self, i: usize) -> Option<&State> {
        self.states.get(i)
    }
}

impl Loop<'_> {
    /// Runs the loop with the correction `c`: the end's residual `(phi, theta, theta')` against
    /// the plan's, and the states at every tick's start.
    fn run(&self, c: &[f64]) -> (Vec<f64>, Vec<State>) {
        let p = self.problem;
        let correction = HoldCorrection {
            coefficients: c.to_vec(),
            horizon: p.horizon,
            states: Vec::new(),
            error_before: 0.0,
            error_after: 0.0,
            peak_acceleration: 0.0,
        };
        let mut plant = Plant::new(self.model, &p.start, Disturbances::default(), 0).moving(&p.initial_velocity);
        let mut states = Vec::with_capacity(self.centres.len());
        for (i, centre) in self.centres.iter().enumerate() {
            let measured = plant.measure();
            let centre = correction.corrected(centre.clone(), i as f64 * self.dt + 0.5 * self.dt);
            let command = computed_torque(self.model, &measured, &centre, 0.5 * self.dt, &self.gains);
            states.push(measured);
            // A correction that takes the nominal robot beyond a declared limit is no
            // correction (a plan at a velocity limit with an impulsive start asked for 853
            // rad/s^2 and broke the limit in the first tick): as a diverged loop.
            let broken = plant.step(&command, self.dt, self.substeps).broken.is_some();
            if broken || !plant.is_finite() {
                return (vec![f64::INFINITY; self.end.len()], states);
            }
        }
        let s = plant.state();
        let reached = s.q.iter().chain(&s.dq[1..]);
        (reached.zip(&self.end).map(|(x, e)| x - e).collect(), states)
    }
}

/// Legendre polynomials `P_0..P_DEGREE` at `x` in `[-1, 1]` (Bonnet's recursion).
fn legendre(x: f64) -> [f64; DEGREE + 1] {
    let mut p = [0.0; DEGREE + 1];
    p[0] = 1.0;
    if DEGREE >= 1 {
        p[1] = x;
    }
    for n in 1..DEGREE {
        p[n + 1] = ((2 * n + 1) as f64 * x * p[n] - n as f64 * p[n - 1]) / (n + 1) as f64;
    }
    p
}

/// The largest error of the `n + 1` angles of a residual.
fn position_error(r: &[f64], n: usize) -> f64 {
    r[..=n].iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn norm(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum::<f64>().sqrt()
}
