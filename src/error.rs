//! The error type of the planners: every variant carries the numbers that explain it. The
//! lower layers have their own errors ([`InputError`] of the model, [`OdeError`] of the
//! integrator), which this one wraps, so that neither imports anything above it.

use crate::model::{Configuration, InputError};
use crate::numerics::format::{error_number, number, rounded};
use crate::numerics::iteration::IterationStats;
use crate::numerics::ode::OdeError;

/// A condition of a feedback transformation's domain of existence (Theorem 1; Figs. 13-14).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Singularity {
    /// `sin theta2 = 0`: the domain condition of Eqs. (11) and (12).
    SinTheta2,
    /// `sigma = 0` (Eq. 9): the robot's posture singularity, where `[g1, g2]` lies in the span
    /// of `g1, g2`.
    Sigma,
    /// `P = 0` (Eq. 13): the boundary between the two branches `sign(P)` of Eq. (14).
    P,
    /// An `arcsin` argument of Eq. (14) outside [-1, 1].
    ArcsinArgument,
    /// `d = U^2 - 4 f^2 <= 0` (Eq. 15).
    DNonPositive,
}

impl std::fmt::Display for Singularity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Singularity::SinTheta2 => "sin(theta2) = 0",
            Singularity::Sigma => "sigma = 0 (Eq. 9)",
            Singularity::P => "P = 0 (Eq. 13)",
            Singularity::ArcsinArgument => "an arcsin argument of Eq. (14) outside [-1, 1]",
            Singularity::DNonPositive => "d = U^2 - 4 f^2 <= 0 (Eq. 15)",
        })
    }
}

fn fmt_q(q: &Option<Configuration>) -> String {
    q.map(|q| {
        format!(
            " (phi, theta1, theta2) = ({}, {}, {}) deg",
            rounded(q.phi.to_degrees(), 4),
            rounded(q.theta1.to_degrees(), 4),
            rounded(q.theta2.to_degrees(), 4)
        )
    })
    .unwrap_or_default()
}

fn fmt_newton(iterations: usize, residual: f64, guess: f64) -> String {
    if residual.is_finite() {
        format!(
            "{iterations} iterations from theta2 = {} deg, residual {}",
            rounded(guess.to_degrees(), 4),
            error_number(residual)
        )
    } else {
        format!("the warm start theta2 = {} deg is already off the branch", rounded(guess.to_degrees(), 4))
    }
}

fn fmt_t(t: &Option<f64>) -> String {
    t.map(|t| format!(" at t = {} s", number(t))).unwrap_or_default()
}

/// Everything that can go wrong in freefloat.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Bad input: a parameter out of range, an unreadable robot file or output path.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A transformation was asked for where it does not apply (e.g. Eq. (11) with a != 0).
    #[error("transformation {transform} is not available here: {reason}")]
    TransformUnavailable {
        /// The transformation's name.
        transform: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// A configuration lies outside the domain of the feedback transformation: at the start,
    /// at the goal, or on the planned path at time `t`.
    #[error(
        "{where_}{} is outside the domain of {transform}: {which}{} (value {}); {hint}",
        fmt_q(q),
        fmt_t(t),
        error_number(*value)
    )]
    Singular {
        /// Which condition fails.
        which: Singularity,
        /// The transformation.
        transform: &'static str,
        /// `start`, `goal` or `path`.
        where_: &'static str,
        /// The configuration, when known.
        q: Option<Configuration>,
        /// Time on the path \[s\], when on the path.
        t: Option<f64>,
        /// The value of the failing function (or, for a crossing, its value on the far side).
        value: f64,
        /// What to do about it.
        hint: &'static str,
    },
    /// Start and goal lie in different connected components of the transformation's domain.
    #[error(
        "start and goal lie in different components of the domain of {transform}: sign of {which} \
         is {start_sign:+} at the start and {goal_sign:+} at the goal; no path of this transformation \
         joins them (try another mounting point, another goal, or `freefloat domain`)"
    )]
    DifferentComponents {
        /// The transformation.
        transform: &'static str,
        /// The function whose sign differs.
        which: Singularity,
        /// Its sign at the start.
        start_sign: f64,
        /// Its sign at the goal.
        goal_sign: f64,
    },
    /// The inverse map's Newton iteration (Sec. 6, item 2) did not converge.
    #[error(
        "Newton's method for theta2 did not converge{}: {}; target z2 = {target:.6}: the path \
         probably leaves the domain of the transformation (see `freefloat domain`)",
        fmt_t(t), fmt_newton(*iterations, *residual, *guess)
    )]
    NewtonFailed {
        /// Iterations made.
        iterations: usize,
        /// Last residual `|h3(theta1, theta2) - z2|` (infinite when the start was off the branch).
        residual: f64,
        /// The value of `z2` sought.
        target: f64,
        /// The warm start \[rad\].
        guess: f64,
        /// Time on the path \[s\].
        t: Option<f64>,
    },
    /// The polynomial steering of Sec. 5 divides by `w2 = zd2 - z02`.
    #[error(
        "the polynomial steering of Sec. 5 needs z2 to change between start and goal, but \
         w2 = zd2 - z02 = {w2:.3e}; choose a slightly different goal"
    )]
    DegenerateSteering {
        /// `zd2 - z02`.
        w2: f64,
    },
    /// The adaptive integrator could not continue.
    #[error(transparent)]
    Integration(#[from] OdeError),
    /// The chained-form path leaves the band of the global normal form: `z2` is outside the
    /// range of `h3` over the band `{sigma != 0}` at `theta1 = z1`.
    #[error(
        "the chained-form path leaves the band of the global normal form{}: z2 = {} is outside \
         ({}, {}), the range of h3 at theta1 = {} deg",
        fmt_t(t), number(*z2), number(*lower), number(*upper), rounded(theta1.to_degrees(), 4)
    )]
    LeavesBand {
        /// Time on the path \[s\].
        t: Option<f64>,
        /// `theta1 = z1` \[rad\].
        theta1: f64,
        /// The `z2` sought.
        z2: f64,
        /// Lower end of the band's `h3` range.
        lower: f64,
        /// Upper end of the band's `h3` range.
        upper: f64,
    },
    /// No band steering within the search limits keeps the path inside the band.
    #[error(
        "no band-steered path found with up to {loops} loops of amplitude up to {amplitude} rad: \
         the goal needs more area in the (z1, z2) plane than these loops enclose inside the band \
         (a mounting point with a wider band, see `freefloat domain`, needs fewer loops)"
    )]
    NoBandSteering {
        /// Largest number of loops tried.
        loops: usize,
        /// Largest amplitude tried \[rad\].
        amplitude: f64,
    },
    /// A plan was computed, but its verification failed the tolerance.
    #[error(
        "the plan is not certified: verified final error {} rad exceeds the tolerance {} rad \
         ({level} level)",
        error_number(*final_error),
        number(*tolerance)
    )]
    NotCertified {
        /// The verified final error \[rad\].
        final_error: f64,
        /// The tolerance \[rad\].
        tolerance: f64,
        /// `velocity` or `torque`.
        level: &'static str,
    },
    /// A checked trajectory (`freefloat check`) does not end at its goal: `element` is the
    /// coordinate farthest off (`base phi` or ``joint `NAME` ``), with its wrapped error.
    #[error(
        "the trajectory misses its goal: {element} ends {} rad ({} deg) from --to, tolerance {} rad",
        error_number(*final_error),
        rounded(final_error.to_degrees(), 6),
        number(*tolerance)
    )]
    GoalMissed {
        /// The coordinate farthest off, e.g. ``joint `joint2` ``.
        element: String,
        /// Its wrapped error at the end \[rad\].
        final_error: f64,
        /// The tolerance \[rad\].
        tolerance: f64,
    },
    /// The ECSA iteration (Jacobian pseudo-inverse) stopped without reaching its residual
    /// tolerance: the iteration limit was hit or the residual became non-finite.
    #[error(
        "ECSA did not converge ({}): {} iterations, residual {:.3e} rad > tolerance {:.1e} rad \
         (residuals: {})",
        stats.termination,
        stats.iterations,
        stats.residual,
        stats.tolerance,
        fmt_history(&stats.residual_history)
    )]
    EcsaFailed {
        /// Iterations, residual history and why the iteration stopped.
        stats: IterationStats,
    },
    /// The forward dynamics under the planned torques could not be integrated to the end: the
    /// open-loop motion leaves the plan so fast that the integrator gives up.
    #[error(
        "the torque certificate's forward-dynamics integration failed at t = {} s: {reason}; the \
         open-loop motion under the planned torques diverges from the plan (it is unstable there and \
         would need feedback to be tracked)",
        number(*t)
    )]
    TorqueDiverges {
        /// Time reached \[s\].
        t: f64,
        /// The integrator's reason.
        reason: &'static str,
    },
    /// The chained-form path, mapped back on the start's piece of the domain, ends at another
    /// configuration with the goal's `z`: the goal lies on another piece.
    #[error(
        "the path of {transform} ends at{} instead of the goal{} ({} rad away): the goal lies \
         on another piece of the domain with the same normal-form coordinates (e.g. theta2 whole turns away, \
         across a singular curve); give the goal's representative on the start's side",
        fmt_q(&Some(*reached)), fmt_q(&Some(*goal)), error_number(*distance)
    )]
    GoalNotReached {
        /// The transformation.
        transform: &'static str,
        /// Where the path ends.
        reached: Configuration,
        /// The goal.
        goal: Configuration,
        /// `max_i |wrap(reached_i - goal_i)|` \[rad\].
        distance: f64,
    },
    /// The optimal planner (trust-region SQP) found no plan meeting its tolerances: every seed
    /// stopped short of convergence; the numbers are those of the best attempt.
    #[error("{}", optimal_failed_message(*iterations, *constraint_residual, *kkt_residual, *effort, *seeds, termination))]
    OptimalFailed {
        /// SQP iterations of the best attempt.
        iterations: usize,
        /// Its constraint residual \[rad\].
        constraint_residual: f64,
        /// Its relative KKT residual.
        kkt_residual: f64,
        /// Its effort \[rad^2/s\].
        effort: f64,
        /// Seeds tried.
        seeds: usize,
        /// Why the best attempt stopped (e.g. `max_iterations`).
        termination: &'static str,
    },
    /// The given horizon is too short for the robot's limits (issue 20 item 4): no plan inside
    /// every limit (and clear, issue 21) was found in it, and a longer horizon has one; the limit
    /// that binds there is named (`joint` from 1, 0 for the base angle).
    #[error("{}", too_short_message(*horizon, *shortest, *searched, binding_limit(*joint, quantity, *limit)))]
    HorizonTooShort {
        /// The given horizon \[s\].
        horizon: f64,
        /// A horizon with a certified plan inside every limit \[s\]: the shortest, within 1 %,
        /// where `searched`; else one proven to fit, an upper bound on the shortest.
        shortest: f64,
        /// Whether `shortest` was searched for (`--time auto`'s search), or is the horizon at which
        /// the plan without the rate limits, time-scaled, was certified (docs/spec.md §2).
        searched: bool,
        /// The binding limit's joint, counted from 1 (0: the base angle).
        joint: usize,
        /// `velocity`, `acceleration`, `torque`, `position` or `base`.
        quantity: &'static str,
        /// The binding limit's value (rad/s, rad/s^2, N m, or the range's bound in rad).
        limit: f64,
    },
    /// The verified motion leaves a declared limit of the robot (issue 20; `plan::limit_use`):
    /// the most-used limit, beyond a relative `1e-9`.
    #[error(
        "not certified: the motion leaves the robot's limits: {} {quantity} reaches {} at t = {time:.4} s, \
         beyond its limit {} by {} (docs/spec.md §3)",
        if *joint == 0 { "the base angle phi's".to_string() } else { format!("joint theta{joint}'s") },
        limit_value(quantity, *value, 9),
        limit_value(quantity, *limit, 6),
        limit_value(quantity, if *quantity == "position" { (value - limit).abs() } else { value.abs() - limit.abs() }, 3)
    )]
    LimitExceeded {
        /// The joint, counted from 1 (0: the base angle).
        joint: usize,
        /// `position`, `velocity`, `acceleration` or `torque`.
        quantity: &'static str,
        /// The value where the limit's use is largest (rad, rad/s, rad/s^2, N m).
        value: f64,
        /// The bound crossed (same unit).
        limit: f64,
        /// When \[s\].
        time: f64,
    },
    /// With one joint the base angle is a function of the joint angle (`a(theta) dtheta` is
    /// exact): the goal's `theta_1` fixes `phi(T)`, and the goal asks for another.
    #[error(
        "with {joints} joint the base angle is fixed by the joint angle: the goal's theta1 = \
         {theta_goal:.6} rad gives phi(T) = {reachable:.9} rad, but the goal asks phi = {goal:.9} rad \
         (gap {gap:.3e} rad modulo 2 pi > tolerance {tolerance:.1e} rad); choose phi = {reachable:.9} rad \
         or another goal"
    )]
    HolonomyFixed {
        /// The number of joints (1).
        joints: usize,
        /// The goal's joint angle (the representative tried nearest the start) \[rad\].
        theta_goal: f64,
        /// The base angle the joint path reaches \[rad\].
        reachable: f64,
        /// The goal's base angle \[rad\].
        goal: f64,
        /// `min |wrap(reachable - goal)|` over the representatives tried \[rad\].
        gap: f64,
        /// The tolerance \[rad\].
        tolerance: f64,
    },
    /// The verified motion comes closer than the clearance asked for (issue 21): bodies `a` and
    /// `b` (`base`, `link 2`, `obstacle 1`) are `clearance` apart at `time` (negative: they
    /// overlap by that depth). Never certified.
    #[error(
        "the plan is not certified: {a} and {b} come {} at t = {} s (least clearance {} m, required {} m)",
        if *clearance < 0.0 { format!("{} m into each other", number(-clearance)) } else { format!("within {} m", number(*clearance)) },
        number(*time),
        number(*clearance),
        number(*required)
    )]
    Collision {
        /// The first body.
        a: String,
        /// The second body or obstacle.
        b: String,
        /// When \[s\].
        time: f64,
        /// Their least signed distance along the verified motion \[m\] (negative: the depth).
        clearance: f64,
        /// The clearance asked for \[m\].
        required: f64,
    },
}

fn fmt_history(history: &[f64]) -> String {
    history.iter().map(|r| format!("{r:.1e}")).collect::<Vec<_>>().join(", ")
}

/// [`Error::OptimalFailed`]'s message: the best attempt's numbers, or where there was no attempt
/// (no goal representative or horizon left to solve, the numbers infinite) that alone.
fn optimal_failed_message(
    iterations: usize,
    constraint_residual: f64,
    kkt_residual: f64,
    effort: f64,
    seeds: usize,
    termination: &str,
) -> String {
    if termination == "warm_start" {
        return format!(
            "the optimal planner's warm start gave no certified plan and no search follows ({termination}): \
             {iterations} SQP iterations, {seeds} seeds"
        );
    }
    if !effort.is_finite() && !constraint_residual.is_finite() {
        return format!(
            "the optimal planner had nothing to solve ({termination}): no goal representative or horizon \
             within the robot's limits, {iterations} SQP iterations, {seeds} seeds"
        );
    }
    format!(
        "the optimal planner did not converge ({termination}): {iterations} SQP iterations, constraint residual \
         |phi(T) - phi_d| = {constraint_residual:.3e} rad, relative KKT residual {kkt_residual:.3e}, effort \
         {effort:.6e} rad^2/s, {seeds} seeds"
    )
}

impl Error {
    /// True when the user's input is at fault (exit code 2); otherwise the problem has no
    /// certified plan with this method (exit code 3).
    pub fn is_bad_input(&self) -> bool {
        matches!(self, Error::Input(_) | Error::TransformUnavailable { .. } | Error::HolonomyFixed { .. })
    }

    /// The numbers of the error by the names of its fields (SI units, radians; `q` as `[phi,
    /// theta_1, ..]`), as one JSON object: the `numbers` of the CLI's JSON error object and of
    /// the Python exceptions (docs/spec.md §3). Never empty for an error that has numbers; a
    /// non-finite number is `null`.
    pub fn numbers(&self) -> serde_json::Value {
        use crate::model::kinematics::Unreachable;
        use Error as E;
        use InputError as I;
        use serde_json::json;
        let name = |s: &Singularity| serde_json::to_value(s).unwrap_or(serde_json::Value::Null);
        match self {
            E::Input(I::InvalidParameter { name, value, expected }) => {
                json!({"name": name, "value": value, "expected": expected})
            }
            E::Input(I::InvalidText { name, text, expected }) => {
                json!({"name": name, "value": crate::model::excerpt(text), "expected": expected})
            }
            E::Input(I::RobotFile { path, reason }) => json!({"path": path.display().to_string(), "reason": reason}),
            E::Input(I::Urdf { path, element, reason }) => {
                json!({"path": path.display().to_string(), "element": element, "reason": reason})
            }
            E::Input(I::Io { path, source }) => {
                json!({"path": path.display().to_string(), "reason": source.to_string()})
            }
            E::Input(I::Unreachable(Unreachable { x, y, psi_deg, distance, min, max })) => json!({
                "x": x, "y": y, "psi": psi_deg.to_radians(), "distance": distance, "min": min, "max": max,
            }),
            E::Input(I::Trajectory { path, element, reason }) => {
                json!({"path": path.display().to_string(), "element": element, "reason": reason})
            }
            E::Input(I::TooMuchWork { what, work, limit, unit, hint }) => {
                json!({"name": what, "work": work, "limit": limit, "unit": unit, "hint": hint})
            }
            E::Input(I::NestedTooDeep { path, line, limit }) => {
                json!({"path": path.display().to_string(), "line": line, "limit": limit})
            }
            E::Input(I::NotAFile { path }) => json!({"path": path.display().to_string()}),
            E::Input(I::TooLarge { path, bytes, limit }) => {
                json!({"path": path.display().to_string(), "bytes": bytes, "limit": limit})
            }
            E::Input(I::TooMuchMemory { what, bytes, limit, .. }) => {
                json!({"name": what, "bytes": *bytes as f64, "limit": *limit as f64})
            }
            E::Input(I::PoseBranch { branch, reaching, tried, residual }) => {
                json!({"name": "branch", "value": branch, "reaching": reaching, "tried": tried, "residual": residual})
            }
            E::Input(I::NothingToCheck { obstacles, clearance }) => {
                json!({"obstacles": obstacles, "clearance": clearance})
            }
            E::Input(I::ShardFile { path, line, reason }) => {
                json!({"path": path.display().to_string(), "line": line, "reason": reason})
            }
            E::TransformUnavailable { transform, reason } => json!({"transform": transform, "reason": reason}),
            E::Singular { which, transform, where_, q, t, value, .. } => json!({
                "which": name(which), "transform": transform, "where": where_,
                "q": q.map(|q| q.to_array()), "t": t, "value": value,
            }),
            E::DifferentComponents { transform, which, start_sign, goal_sign } => json!({
                "transform": transform, "which": name(which), "start_sign": start_sign, "goal_sign": goal_sign,
            }),
            E::NewtonFailed { iterations, residual, target, guess, t } => json!({
                "iterations": iterations, "residual": residual, "target": target, "guess": guess, "t": t,
            }),
            E::DegenerateSteering { w2 } => json!({ "w2": w2 }),
            E::Integration(OdeError { t, reason }) | E::TorqueDiverges { t, reason } => {
                json!({"t": t, "reason": reason})
            }
            E::LeavesBand { t, theta1, z2, lower, upper } => json!({
                "t": t, "theta1": theta1, "z2": z2, "lower": lower, "upper": upper,
            }),
            E::NoBandSteering { loops, amplitude } => json!({"loops": loops, "amplitude": amplitude}),
            E::NotCertified { final_error, tolerance, level } => json!({
                "final_error": final_error, "tolerance": tolerance, "level": level,
            }),
            E::GoalMissed { element, final_error, tolerance } => json!({
                "element": element, "final_error": final_error, "tolerance": tolerance,
            }),
            E::EcsaFailed { stats } => json!({
                "iterations": stats.iterations, "residual": stats.residual, "tolerance": stats.tolerance,
                "residual_history": stats.residual_history, "termination": stats.termination,
            }),
            E::HolonomyFixed { joints, theta_goal, reachable, goal, gap, tolerance } => json!({
                "joints": joints, "theta_goal": theta_goal, "reachable": reachable, "goal": goal, "gap": gap,
                "tolerance": tolerance,
            }),
            E::LimitExceeded { joint, quantity, value, limit, time } => json!({
                "joint": joint, "quantity": quantity, "value": value, "limit": limit, "time": time,
            }),
            E::HorizonTooShort { horizon, shortest, searched, joint, quantity, limit } => json!({
                "horizon": horizon, "shortest": shortest, "searched": searched, "joint": joint, "quantity": quantity,
                "limit": limit,
            }),
            E::OptimalFailed { iterations, constraint_residual, kkt_residual, effort, seeds, termination } => json!({
                "iterations": iterations, "constraint_residual": constraint_residual, "kkt_residual": kkt_residual,
                "effort": effort, "seeds": seeds, "termination": termination,
            }),
            E::Collision { a, b, time, clearance, required } => json!({
                "between": [a, b], "time": time, "clearance": clearance, "required": required,
            }),
            E::GoalNotReached { transform, reached, goal, distance } => json!({
                "transform": transform, "reached": reached.to_array(), "goal": goal.to_array(), "distance": distance,
            }),
        }
    }
}

/// A limited quantity's value (issue 20) to `digits` significant digits in its SI unit, and an
/// angle's in degrees too, as the flags give it: `0.174533 rad/s (10 deg/s)`, `0.01 N m`.
fn limit_value(quantity: &str, x: f64, digits: usize) -> String {
    let shown = |x: f64| crate::numerics::format::significant(x, digits);
    match quantity {
        "position" | "base" => format!("{} rad ({} deg)", shown(x), shown(x.to_degrees())),
        "velocity" => format!("{} rad/s ({} deg/s)", shown(x), shown(x.to_degrees())),
        "acceleration" => format!("{} rad/s^2 ({} deg/s^2)", shown(x), shown(x.to_degrees())),
        _ => format!("{} N m", shown(x)),
    }
}

/// [`Error::HorizonTooShort`]'s message: the shortest horizon found, or a horizon proven to fit.
fn too_short_message(horizon: f64, shortest: f64, searched: bool, binding: String) -> String {
    let found = if searched {
        format!("the shortest feasible horizon found is {shortest:.6} s")
    } else {
        format!(
            "the horizon is too short for them: the plan without the rate limits, time-scaled, is certified \
             inside every limit and clearance at {shortest:.6} s (not searched down to the shortest)"
        )
    };
    format!(
        "no plan inside the robot's limits in T = {horizon} s: {found}, where {binding} binds; give --time \
         {shortest:.6} or longer (or --time auto)"
    )
}

/// The limit that binds at the shortest horizon: `joint 2's velocity limit 0.174533 rad/s
/// (10 deg/s)`, or the base angle's range (`joint` 0).
fn binding_limit(joint: usize, quantity: &str, limit: f64) -> String {
    match joint {
        0 => format!("the base angle phi's range bound {}", limit_value("position", limit, 6)),
        _ => format!("joint {joint}'s {quantity} limit {}", limit_value(quantity, limit, 6)),
    }
}
