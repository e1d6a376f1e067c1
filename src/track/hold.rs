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
//! plan's final configuration and joint velocity (5 conditions, `2 (DEGREE + 1)` unknowns, the
//! least-norm solution). The loop's end state is smooth in the coefficients, and Newton's method
//! with a finite-difference Jacobian of the whole loop (each column one simulated run) converges
//! in two or three steps. On the nominal robot without noise the loop then follows the corrected
//! run tick for tick and ends at the goal, at rest, to round-off. The correction is small: at
//! `a = 1, b = -1` its largest acceleration is 0.63 rad/s^2, under 1 % of the plan's, mostly
//! for the final layer's velocity lag; on any other robot it is a feedforward far below what the feedback corrects.

use rayon::prelude::*;

use super::control::{Gains, computed_torque};
use super::plant::{Disturbances, Plant, State};
use crate::error::Error;
use crate::plan::{Motion, MotionPoint, PlanningProblem};

/// Degree of the correction's polynomial per joint.
pub const DEGREE: usize = 2;

/// Unknowns of the correction: `DEGREE + 1` Legendre coefficients per joint.
const UNKNOWNS: usize = 2 * (DEGREE + 1);

/// Finite-difference step of the Jacobian [rad/s^2]: the joints then move by about
/// `step / kp ~ 4e-7 rad` (default gains), where the loop is linear to about 1e-13 and the
/// differences keep eight digits above the round-off of a 10^4-tick run.
const STEP: f64 = 1e-3;

/// The loop's end counts as reached within this \[rad, rad/s\].
const REACHED: f64 = 1e-12;

/// The corrected feedforward of one plan at one control rate, and the nominal loop's states.
#[derive(Debug, Clone)]
pub struct HoldCorrection {
    coefficients: [f64; UNKNOWNS],
    horizon: f64,
    states: Vec<State>,
    /// `max |wrap(q_i(T) - qd_i)|` of the nominal loop before the correction \[rad\].
    pub error_before: f64,
    /// The same after the correction \[rad\].
    pub error_after: f64,
    /// The largest `|delta a_i(t)|` [rad/s^2].
    pub peak_acceleration: f64,
}

/// The sampled loop whose end is corrected: the nominal robot, its plan at the ticks' centres.
struct Loop<'a> {
    problem: &'a PlanningProblem,
    centres: Vec<MotionPoint>,
    dt: f64,
    substeps: usize,
    gains: Gains,
    end: MotionPoint,
}

impl HoldCorrection {
    /// The correction of `plan` (for `problem`, on its nominal robot) at `rate` \[Hz\] with
    /// `substeps` plant steps per tick and the joint loop `gains`. `None` when the nominal loop
    /// diverges or Newton's method does not reduce its final error (the run then uses the plan
    /// as it is).
    pub fn new(
        problem: &PlanningProblem,
        plan: &(dyn Motion + Sync),
        rate: f64,
        substeps: usize,
        gains: Gains,
    ) -> Result<Option<HoldCorrection>, Error> {
        let horizon = problem.horizon;
        let ticks = (horizon * rate).round().max(1.0) as usize;
        let dt = horizon / ticks as f64;
        let centres = (0..ticks).map(|i| plan.at(i as f64 * dt + 0.5 * dt)).collect::<Result<Vec<_>, _>>()?;
        let lp = Loop { problem, centres, dt, substeps, gains, end: plan.at(horizon)? };
        let zero = [0.0; UNKNOWNS];
        let (r0, states0) = lp.run(&zero);
        let error_before = position_error(&r0);
        if !error_before.is_finite() {
            return Ok(None);
        }
        let columns: Vec<[f64; 5]> = (0..UNKNOWNS)
            .into_par_iter()
            .map(|j| {
                let mut c = zero;
                c[j] = STEP;
                let (r, _) = lp.run(&c);
                std::array::from_fn(|i| (r[i] - r0[i]) / STEP)
            })
            .collect();
        let jacobian = nalgebra::SMatrix::<f64, 5, UNKNOWNS>::from_fn(|i, j| columns[j][i]);
        let Ok(inverse) = jacobian.svd(true, true).pseudo_inverse(1e-12 * jacobian.norm()) else { return Ok(None) };
        let (mut c, mut r, mut states) = (zero, r0, states0);
        for _ in 0..4 {
            if r.iter().all(|x| x.abs() <= REACHED) {
                break;
            }
            let step = inverse * nalgebra::SVector::<f64, 5>::from(r);
            let trial: [f64; UNKNOWNS] = std::array::from_fn(|j| c[j] - step[j]);
            let (rt, st) = lp.run(&trial);
            if !(norm(&rt) < norm(&r)) {
                break;
            }
            (c, r, states) = (trial, rt, st);
        }
        let error_after = position_error(&r);
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

    /// `delta a(t)` [rad/s^2] at time `t` of the run \[s\].
    pub fn acceleration(&self, t: f64) -> [f64; 2] {
        let p = legendre(2.0 * t / self.horizon - 1.0);
        std::array::from_fn(|j| (0..=DEGREE).map(|m| self.coefficients[j * (DEGREE + 1) + m] * p[m]).sum())
    }

    /// The plan's point `centre` with the correction at time `t` added to its acceleration.
    pub fn corrected(&self, mut centre: MotionPoint, t: f64) -> MotionPoint {
        let a = self.acceleration(t);
        centre.du = [centre.du[0] + a[0], centre.du[1] + a[1]];
        centre
    }

    /// The nominal loop's state at the start of tick `i`, if the run has that tick.
    pub fn nominal(&self, i: usize) -> Option<&State> {
        self.states.get(i)
    }
}

impl Loop<'_> {
    /// Runs the loop with the correction `c`: the end's residual `(phi, theta1, theta2,
    /// theta1', theta2')` against the plan's, and the states at every tick's start.
    fn run(&self, c: &[f64; UNKNOWNS]) -> ([f64; 5], Vec<State>) {
        let p = self.problem;
        let correction = HoldCorrection {
            coefficients: *c,
            horizon: p.horizon,
            states: Vec::new(),
            error_before: 0.0,
            error_after: 0.0,
            peak_acceleration: 0.0,
        };
        let k = p.robot.lumped();
        let mut plant = Plant::new(&p.robot, p.start, Disturbances::default(), 0).moving(p.start_velocity);
        let mut states = Vec::with_capacity(self.centres.len());
        for (i, centre) in self.centres.iter().enumerate() {
            let measured = plant.measure();
            states.push(measured);
            let centre = correction.corrected(*centre, i as f64 * self.dt + 0.5 * self.dt);
            let command = computed_torque(&k, &measured, &centre, 0.5 * self.dt, &self.gains);
            plant.step(command, self.dt, self.substeps);
            if !plant.is_finite() {
                return ([f64::INFINITY; 5], states);
            }
        }
        let s = plant.state();
        let (q, qd) = (s.q.to_array(), self.end.q.to_array());
        ([q[0] - qd[0], q[1] - qd[1], q[2] - qd[2], s.dq[1] - self.end.u[0], s.dq[2] - self.end.u[1]], states)
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

fn position_error(r: &[f64; 5]) -> f64 {
    r[..3].iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn norm(r: &[f64; 5]) -> f64 {
    r.iter().map(|x| x * x).sum::<f64>().sqrt()
}
