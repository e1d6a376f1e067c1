//! The velocity-level certificate (docs/spec.md, Sec. 2), one routine for every arm and method:
//! the original system, `phi' = -(G . u)/F`, `theta' = u` (Eq. 7 with the arm's momentum
//! coefficients, [`Arm::momentum_coefficients`]; at `n = 2` the paper's `F, G, H` of Eq. 8),
//! integrated from the start with the planned controls `u(t)` one piece between breakpoints at a
//! time, compared with the goal.
//!
//! Any plan that is a [`JointMotion`] is certified by [`verify_chain`]; a 2-link [`Motion`]
//! through its view [`MotionView`] ([`verify`], which fills the 2-link [`Verification`]). The
//! torque level ([`super::torques`]) integrates the full dynamics by the same piecewise scheme.

use std::cell::RefCell;

use nalgebra::SVector;
use serde::Serialize;

use super::clearance::{ClearanceMonitor, ClearanceReport};
use super::limit_use::{LimitMonitor, LimitReport};
use super::motion::{Motion, MotionPoint};
use super::problem::PlanningProblem;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::lumped::ArmLumped;
use crate::model::{Configuration, InputError, wrap_angle};
use crate::numerics::ode::{OdeOptions, OdeStats, integrate};

/// A planned joint motion of an `n`-joint arm, exact at any time.
pub trait JointMotion {
    /// The number `n` of joints.
    fn joints(&self) -> usize;
    /// Times \[s\] where the controls may lose smoothness, `0` first and `T` last.
    fn breakpoints(&self) -> &[f64];
    /// The joint angles \[rad\] and velocities `u = theta'` \[rad/s\] at `t` into the buffers.
    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]);
    /// The plan's own base rate `phi'(t)` \[rad/s\] (for the momentum check).
    fn phi_rate(&self, t: f64) -> f64;
    /// The joint accelerations \[rad/s^2\] at `t` into `out` (for the torques).
    fn joint_acceleration(&self, t: f64, out: &mut [f64]);
    /// The joint velocities `u(t)` \[rad/s\] alone into `rate` (`n` values), the control signal
    /// of the velocity-level certificate; by default from [`JointMotion::joint_state`]. Motions
    /// whose angles cost more than their velocities override it.
    fn joint_rate(&self, t: f64, rate: &mut [f64]) {
        let mut theta = [0.0; MAX_CERTIFIED_JOINTS];
        let n = rate.len().min(MAX_CERTIFIED_JOINTS);
        self.joint_state(t, &mut theta[..n], rate);
    }
    /// The planned configuration `(phi, theta_1..n)` \[rad\] at `t` into `q` (`n + 1` values), if
    /// the motion knows it: the certificates then report the largest deviation of the integrated
    /// path from it. Default: unknown (`false`, `q` untouched).
    fn planned_configuration(&self, _t: f64, _q: &mut [f64]) -> bool {
        false
    }
    /// An error the motion met while evaluated (the methods above cannot fail): the certificates
    /// stop with it. Default: none.
    fn check(&self) -> Result<(), Error> {
        Ok(())
    }
}

/// The certificate of an `n`-joint plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainVerification {
    /// `max_i |wrap(q_i(T) - qd_i)|` over `q = (phi, theta_1..n)` \[rad\].
    pub final_error: f64,
    /// `q(T)` reached by the integration \[rad\].
    pub reached: Vec<f64>,
    /// Largest `|F phi'_plan + G . u|` over the integrator's accepted steps, with the model's
    /// `F, G` at the integrated joint angles and the plan's base rate \[kg m^2/s\].
    pub max_abs_momentum: f64,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's accepted steps \[rad\], when
    /// the motion knows its configuration ([`JointMotion::planned_configuration`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_path_deviation: Option<f64>,
    /// Tolerance of the final error \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance` (and finite).
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
    /// The least clearance of the integrated motion, its pair and time, when the arm has shapes
    /// ([`super::clearance`]; `None` without); [`ChainVerification::collision`] judges it. Not
    /// serialised here: the reports carry it as their top-level `clearance`.
    #[serde(skip)]
    pub clearance: Option<ClearanceReport>,
    /// The use of every declared limit along the same integrated motion, when the arm declares
    /// limits ([`super::limit_use`]; `None` without); [`LimitReport::check`] judges it. Not
    /// serialised here: the reports carry it as their top-level `limits`.
    #[serde(skip)]
    pub limits: Option<LimitReport>,
}

impl ChainVerification {
    /// [`Error::Collision`] when the integrated motion comes closer than the clearance asked for
    /// (issue 21): such a plan is never certified, whatever its final error.
    pub fn collision(&self) -> Result<(), Error> {
        collision(self.clearance.as_ref())
    }

    /// The certificate of a motion not yet verified: not certified, errors unknown (NaN), to be
    /// replaced by [`verify_chain`]'s before the plan is returned.
    pub fn pending() -> Self {
        Self {
            final_error: f64::NAN,
            reached: Vec::new(),
            max_abs_momentum: f64::NAN,
            max_path_deviation: None,
            tolerance: f64::NAN,
            certified: false,
            stats: OdeStats::default(),
            clearance: None,
            limits: None,
        }
    }
}

/// Checks that `motion`, `start` and `goal` (`n + 1` values each) have the joint count of `arm`.
pub fn check_lengths(arm: &Arm, motion: &dyn JointMotion, start: &[f64], goal: &[f64]) -> Result<(), Error> {
    let n = arm.joints();
    if motion.joints() != n || start.len() != n + 1 || goal.len() != n + 1 {
        return Err(Error::from(InputError::InvalidParameter {
            name: "joints".into(),
            value: motion.joints() as f64,
            expected: "a motion, start and goal of the arm's joint count",
        }));
    }
    Ok(())
}

/// Largest number of joints [`verify_chain`] takes.
pub const MAX_CERTIFIED_JOINTS: usize = 15;

/// The error of a joint count out of `1..=`[`MAX_CERTIFIED_JOINTS`].
pub(crate) fn joints_error(n: usize) -> Error {
    Error::from(InputError::InvalidParameter { name: "joints".into(), value: n as f64, expected: "1 to 15 joints" })
}

/// Calls `$f::<M>(args)` with the static state size `M = $scale (n + 1)` of an `n`-joint arm,
/// `n` in `1..=15` (the one dispatch of both certificates); another `n` is [`joints_error`].
macro_rules! by_joints {
    ($n:expr, $scale:literal, $f:ident ( $($arg:expr),* $(,)? )) => {
        $crate::plan::certificate::by_joints!(@arms $n, $scale, $f, ($($arg),*), 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15)
    };
    (@arms $n:expr, $scale:literal, $f:ident, $args:tt, $($k:literal)*) => {
        match $n {
            $($k => $crate::plan::certificate::by_joints!(@call $f, { $scale * ($k + 1) }, $args),)*
            n => Err($crate::plan::certificate::joints_error(n)),
        }
    };
    (@call $f:ident, $m:block, ($($arg:expr),*)) => { $f::<$m>($($arg),*) };
}
pub(crate) use by_joints;

/// Integrates `y' = rhs(t, y)` from `y` over each span between the `breakpoints` (`0` first,
/// `T` last), calling `observe(t, y)` at every accepted step and `at_breakpoint(t, y)` at every
/// breakpoint; returns `y(T)` and the integrator's work: the piecewise scheme of both
/// certificates (the adaptive steps never straddle a point where the controls lose smoothness).
pub(crate) fn piecewise<const M: usize>(
    breakpoints: &[f64],
    mut y: SVector<f64, M>,
    ode: &OdeOptions,
    mut rhs: impl FnMut(f64, &SVector<f64, M>) -> Result<SVector<f64, M>, Error>,
    mut observe: impl FnMut(f64, &SVector<f64, M>),
    mut at_breakpoint: impl FnMut(f64, &SVector<f64, M>),
) -> Result<(SVector<f64, M>, OdeStats), Error> {
    let mut stats = OdeStats::default();
    if let Some(&t0) = breakpoints.first() {
        at_breakpoint(t0, &y);
    }
    for w in breakpoints.windows(2) {
        if !(w[1] > w[0]) {
            continue;
        }
        let (y1, s) = integrate(&mut rhs, w[0], y, w[1], ode, &mut observe)?;
        y = y1;
        at_breakpoint(w[1], &y);
        stats.accepted += s.accepted;
        stats.rejected += s.rejected;
        stats.evaluations += s.evaluations;
    }
    Ok((y, stats))
}

/// `max_i |wrap(q_i - goal_i)|` \[rad\] over the first `goal.len()` values of `q`.
pub(crate) fn final_error(q: &[f64], goal: &[f64]) -> f64 {
    q.iter().zip(goal).map(|(q, g)| wrap_angle(q - g).abs()).fold(0.0, f64::max)
}

/// Integrates the original system with the controls of `motion` from `start` (`n + 1` values,
/// `(phi, theta)`) and compares with `goal` (angles modulo 2 pi), to `tolerance` \[rad\].
pub fn verify_chain(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainVerification, Error> {
    verify_chain_observed(arm, motion, start, goal, ode, tolerance, &mut |_, _| {})
}

/// [`verify_chain`], calling `at_breakpoint(t, q)` with the integrated `q = (phi, theta)` at
/// every breakpoint of `motion` (`t = 0` first, `T` last): the base's attitude along the motion
/// with the certificate's accuracy (`freefloat check`).
pub fn verify_chain_observed(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
    at_breakpoint: &mut dyn FnMut(f64, &[f64]),
) -> Result<ChainVerification, Error> {
    check_lengths(arm, motion, start, goal)?;
    let mut points: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut record = |t: f64, q: &[f64]| points.push((t, q.to_vec()));
    let mut v = by_joints!(arm.joints(), 1, run(arm, motion, start, goal, ode, tolerance, &mut record))?;
    if let Some(tighter) = recheck(&v, ode) {
        points.clear();
        let mut record = |t: f64, q: &[f64]| points.push((t, q.to_vec()));
        v = by_joints!(arm.joints(), 1, run(arm, motion, start, goal, &tighter, tolerance, &mut record))?;
    }
    for (t, q) in &points {
        at_breakpoint(*t, q);
    }
    Ok(v)
}

/// A final error above this fraction of the tolerance is integrated again, [`RECHECK_FACTOR`]
/// times tighter (docs/spec.md §2).
pub const RECHECK_FRACTION: f64 = 0.1;

/// How much tighter the integrator's `rtol` and `atol` are on the second pass (down to
/// [`RECHECK_FLOOR`]).
pub const RECHECK_FACTOR: f64 = 100.0;

/// The tightest `rtol` / `atol` of a second pass, a few units of rounding on angles of a few
/// turns.
pub const RECHECK_FLOOR: f64 = 1e-15;

/// The integrator's options of a second pass where the first pass's final error is near the
/// tolerance (above [`RECHECK_FRACTION`] of it, finite), and the integrator can be tightened:
/// an adaptive integrator's global error grows with the steps and the angles' magnitude
/// (`rtol |q|` a step), so at `rtol = 1e-12` it reaches the default tolerance of 1e-9 rad on a long
/// motion over several turns (a = -0.77, b = -0.21, T = 18.3 s: 1.03e-9 rad at 1e-12, 7e-13 rad at
/// 1e-13 and 1e-14, 5e-13 at 1e-15 -- the plan was right and the verdict was the integrator's).
/// The verdict near the tolerance is the tighter integration's, whichever way it goes.
fn recheck(v: &ChainVerification, ode: &OdeOptions) -> Option<OdeOptions> {
    let near = v.final_error.is_finite() && v.final_error > RECHECK_FRACTION * v.tolerance;
    let tighter = OdeOptions {
        rtol: (ode.rtol / RECHECK_FACTOR).max(RECHECK_FLOOR),
        atol: (ode.atol / RECHECK_FACTOR).max(RECHECK_FLOOR),
        ..*ode
    };
    (near && (tighter.rtol < ode.rtol || tighter.atol < ode.atol)).then_some(tighter)
}

/// One integration of [`verify_chain`] from `start` at `ode` as given, without the second pass
/// near the tolerance, for callers that use the motion's limits or clearance and not its final
/// error (measured against `start`, with a tolerance of 1e-3 rad).
pub(crate) fn integrate_once(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    ode: &OdeOptions,
) -> Result<ChainVerification, Error> {
    check_lengths(arm, motion, start, start)?;
    by_joints!(arm.joints(), 1, run(arm, motion, start, start, ode, 1e-3, &mut |_, _| {}))
}

/// [`verify_chain`] with the state `(phi, theta)` of static size `M = n + 1`.
fn run<const M: usize>(
    arm: &Arm,
    motion: &dyn JointMotion,
    start: &[f64],
    goal: &[f64],
    ode: &OdeOptions,
    tolerance: f64,
    at_breakpoint: &mut dyn FnMut(f64, &[f64]),
) -> Result<ChainVerification, Error> {
    let n = M - 1;
    let lumped = ArmLumped::new(arm);
    let rhs = |t: f64, y: &SVector<f64, M>| -> Result<SVector<f64, M>, Error> {
        let dy = eq7_rate(&lumped, motion, t, y);
        motion.check()?;
        Ok(dy)
    };
    let mut max_momentum: f64 = 0.0;
    let mut deviation: Option<f64> = None;
    // The clearance at every accepted step (and between steps, by the monitor's Hermite minimum),
    // and the use of every declared limit (between steps, by its monitor's extrema): both fed
    // from this one integration.
    let mut monitor =
        (!arm.geometry.is_empty()).then(|| ClearanceMonitor::new(arm, &arm.geometry, arm.geometry.clearance));
    let mut limits = LimitMonitor::<M>::new(arm, motion, &lumped);
    let (mut theta, mut u, mut planned) = ([0.0; M], [0.0; M], [0.0; M]);
    // The plan's momentum at every accepted step, with the model's F, G at the integrated angles,
    // and the integrated path's distance from the plan's where the motion knows it.
    let observe = |t: f64, state: &SVector<f64, M>| {
        let mut row = [0.0; M];
        lumped.terms_in::<M>(&state.as_slice()[1..]).momentum_row(&mut row);
        motion.joint_state(t, &mut theta[..n], &mut u[..n]);
        let gu: f64 = row[1..].iter().zip(&u[..n]).map(|(g, u)| g * u).sum();
        max_momentum = max_momentum.max((row[0] * motion.phi_rate(t) + gu).abs());
        if let Some(monitor) = monitor.as_mut() {
            let mut dq = [0.0; M];
            dq[1..].copy_from_slice(&u[..n]);
            dq[0] = -gu / row[0];
            monitor.observe(t, state.as_slice(), &dq);
        }
        if let Some(limits) = limits.as_mut() {
            limits.observe(t, state);
        }
        if motion.planned_configuration(t, &mut planned) {
            let d = state.iter().zip(&planned).map(|(y, q)| (y - q).abs()).fold(0.0, f64::max);
            deviation = Some(deviation.map_or(d, |m: f64| m.max(d)));
        }
    };
    let y0 = SVector::<f64, M>::from_column_slice(start);
    let (y, stats) = piecewise(motion.breakpoints(), y0, ode, rhs, observe, |t, y: &SVector<f64, M>| {
        at_breakpoint(t, y.as_slice())
    })?;
    motion.check()?;
    let limits = limits.map(LimitMonitor::finish);
    motion.check()?;
    let final_error = final_error(y.as_slice(), goal);
    Ok(ChainVerification {
        final_error,
        reached: y.iter().copied().collect(),
        max_abs_momentum: max_momentum,
        max_path_deviation: deviation,
        tolerance,
        certified: final_error.is_finite() && final_error <= tolerance,
        stats,
        clearance: monitor.and_then(ClearanceMonitor::finish),
        limits,
    })
}

/// The right-hand side of Eq. 7 at `(t, y)`, `y = (phi, theta)`: `theta' = u(t)` from the
/// motion, `phi' = -(G . u)/F` with the arm's momentum row from its lumped constants (on the
/// stack, no allocation): the one right-hand side of the velocity certificate and of the limit
/// monitor's rates between its steps.
pub(crate) fn eq7_rate<const M: usize>(
    lumped: &ArmLumped,
    motion: &dyn JointMotion,
    t: f64,
    y: &SVector<f64, M>,
) -> SVector<f64, M> {
    let n = M - 1;
    let (mut rate, mut row) = ([0.0; M], [0.0; M]);
    motion.joint_rate(t, &mut rate[..n]);
    lumped.terms_in::<M>(&y.as_slice()[1..]).momentum_row(&mut row);
    let mut dy = SVector::<f64, M>::zeros();
    let mut s = 0.0;
    for j in 0..n {
        s += row[j + 1] * rate[j];
        dy[j + 1] = rate[j];
    }
    dy[0] = -s / row[0];
    dy
}

/// [`Error::Collision`] when `clearance` is below what it requires.
pub fn collision(clearance: Option<&ClearanceReport>) -> Result<(), Error> {
    match clearance {
        Some(c) if !c.holds() => Err(Error::Collision {
            a: c.a.to_string(),
            b: c.b.to_string(),
            time: c.time,
            clearance: c.min,
            required: c.required,
        }),
        _ => Ok(()),
    }
}

/// A 2-link [`Motion`] as a [`JointMotion`] of its robot's [`Arm`] ([`Arm::from_params`]), so
/// that the one certificate routine serves the NFA, the ECSA and the optimal 2-link plans alike.
///
/// Breakpoints: `0`, the motion's [`Motion::breakpoints`] inside `(0, T)`, `T`. The joint
/// velocities are [`Motion::controls`]; the angles, the base rate (Eq. 7) and the accelerations
/// come from [`Motion::at`] (the last point is kept, since the certificates ask for it several
/// times at each step). The first error a [`Motion`] method returns is kept and reported by
/// [`JointMotion::check`] (the values are then NaN).
pub struct MotionView<'a> {
    motion: &'a dyn Motion,
    arm: Arm,
    breakpoints: Vec<f64>,
    last: RefCell<Option<(f64, MotionPoint)>>,
    error: RefCell<Option<Error>>,
}

impl<'a> MotionView<'a> {
    /// The view of `motion` planned for `problem`'s robot over its horizon.
    pub fn new(motion: &'a dyn Motion, problem: &PlanningProblem) -> Self {
        let horizon = problem.horizon;
        let mut breakpoints = vec![0.0];
        breakpoints.extend(motion.breakpoints().into_iter().filter(|&t| t > 0.0 && t < horizon));
        breakpoints.push(horizon);
        Self {
            motion,
            arm: Arm::from_params(&problem.robot),
            breakpoints,
            last: RefCell::new(None),
            error: RefCell::new(None),
        }
    }

    /// The robot as an arm.
    pub fn arm(&self) -> &Arm {
        &self.arm
    }

    fn keep<T>(&self, value: Result<T, Error>, fallback: T) -> T {
        value.unwrap_or_else(|e| {
            self.error.borrow_mut().get_or_insert(e);
            fallback
        })
    }

    fn point(&self, t: f64) -> MotionPoint {
        if let Some((s, p)) = *self.last.borrow()
            && s.to_bits() == t.to_bits()
        {
            return p;
        }
        let nan =
            MotionPoint { q: Configuration::new(f64::NAN, f64::NAN, f64::NAN), u: [f64::NAN; 2], du: [f64::NAN; 2] };
        let p = self.keep(self.motion.at(t), nan);
        *self.last.borrow_mut() = Some((t, p));
        p
    }
}

impl JointMotion for MotionView<'_> {
    fn joints(&self) -> usize {
        2
    }

    fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        let p = self.point(t);
        theta.copy_from_slice(&[p.q.theta1, p.q.theta2]);
        rate.copy_from_slice(&p.u);
    }

    fn phi_rate(&self, t: f64) -> f64 {
        let p = self.point(t);
        self.arm.base_rate(&[p.q.theta1, p.q.theta2], &p.u)
    }

    fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
        out.copy_from_slice(&self.point(t).du);
    }

    fn joint_rate(&self, t: f64, rate: &mut [f64]) {
        rate.copy_from_slice(&self.keep(self.motion.controls(t), [f64::NAN; 2]));
    }

    fn planned_configuration(&self, t: f64, q: &mut [f64]) -> bool {
        q[..3].copy_from_slice(&self.point(t).q.to_array());
        true
    }

    fn check(&self) -> Result<(), Error> {
        match self.error.borrow_mut().take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// The certificate of a 2-link plan: system (7) integrated from `q0` with the planned controls.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Verification {
    /// `max_i |wrap(q_i(T) - qd_i)|` \[rad\] (docs/spec.md §2).
    pub final_error: f64,
    /// `q(T)` reached by the integration \[rad\].
    pub reached: Configuration,
    /// Largest `|F phi'_plan + G . u|` over the integrator's accepted steps \[kg m^2/s\]
    /// ([`ChainVerification::max_abs_momentum`]).
    pub max_abs_momentum: f64,
    /// Largest `max_i |q_i(t) - q_plan_i(t)|` over the integrator's steps \[rad\].
    pub max_path_deviation: f64,
    /// Tolerance the final error is held to \[rad\].
    pub tolerance: f64,
    /// `final_error <= tolerance`.
    pub certified: bool,
    /// Integrator work.
    pub stats: OdeStats,
    /// The least clearance of the integrated motion (issue 21), when the robot has shapes:
    /// filled by [`super::clearance::motion_clearance`] (the 2-link robot's parameters carry no
    /// geometry). Not serialised here: the reports carry it as their top-level `clearance`.
    #[serde(skip)]
    pub clearance: Option<ClearanceReport>,
}

/// The velocity-level certificate of a 2-link plan: [`verify_chain`] of the [`MotionView`] of
/// `motion` on the problem's robot, `u(t)` evaluated exactly at every stage time, the final error
/// against the goal and the deviation from the planned path.
pub fn verify(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<Verification, Error> {
    let view = MotionView::new(motion, problem);
    let v = verify_view(&view, view.arm(), problem, ode, tolerance)?;
    Ok(Verification {
        final_error: v.final_error,
        reached: Configuration::new(v.reached[0], v.reached[1], v.reached[2]),
        max_abs_momentum: v.max_abs_momentum,
        max_path_deviation: v.max_path_deviation.unwrap_or(f64::NAN),
        tolerance,
        certified: v.certified,
        stats: v.stats,
        clearance: v.clearance,
    })
}

/// The certificate of a 2-link `motion` planned for `problem`, integrated on `arm`: the
/// problem's robot as an [`Arm`] ([`Arm::from_params`] or the robot file's 2-link arm) with the
/// shapes and limits that the 2-link robot's parameters do not carry, so that one pass gives the
/// final error, the clearance and the use of every limit.
pub fn verify_on_arm(
    motion: &dyn Motion,
    problem: &PlanningProblem,
    arm: &Arm,
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainVerification, Error> {
    verify_view(&MotionView::new(motion, problem), arm, problem, ode, tolerance)
}

fn verify_view(
    view: &MotionView<'_>,
    arm: &Arm,
    problem: &PlanningProblem,
    ode: &OdeOptions,
    tolerance: f64,
) -> Result<ChainVerification, Error> {
    let (start, goal) = (problem.start.to_array(), problem.goal.to_array());
    verify_chain(arm, view, &start, &goal, ode, tolerance)
}
