//! The robot's declared limits ([`crate::model::arm::Limits`], issue 20 item 3) as constraints of
//! the minimum-effort planner: `g(x) <= 0` rows of the SQP ([`Inequalities`]), each scaled to
//! its limit.
//!
//! - **Position** `lo <= theta_j(t) <= hi` on the whole continuous path: a clamped B-spline lies
//!   in the convex hull of its control points, so `lo <= c_k <= hi` for every coefficient of
//!   joint `j` is sufficient (linear rows). It is conservative: the control polygon stands off
//!   the curve by at most `O(h^2 max |theta''|)` on spans of width `h` (about
//!   `h^2 max |theta''| / 8` at a peak of a cubic on uniform knots), so a path may be kept up to
//!   that far inside its range; doubling the spans quarters the gap.
//! - **Velocity** and **acceleration**: the same argument on the derivative splines, whose control
//!   points `p (c_{k+1} - c_k) / (t_{k+p+1} - t_{k+1})` (and their differences) are linear in the
//!   coefficients.
//! - **Torque** `|tau_j| <= tau_max` with the exact inverse dynamics at zero momentum
//!   ([`ArmDynamics::inverse`], Eq. 6) at every breakpoint and at two interior points of every span
//!   (a dense set, not a bound between the points); the derivatives in `theta''` exactly (the
//!   torque is affine in it), in `theta` and `theta'` by central differences.
//! - **Base range** `lo <= phi(t) <= hi` at every breakpoint, `phi(t) = phi(0) - integral_0^t g`
//!   by 8-node Gauss–Legendre quadrature per span, with the connection's exact gradient.
//!
//! The torque and base-range rows hold at their points only: a refined plan that leaves either
//! limit between them is solved again with the rows of the spans concerned tightened ([`hold`]).
//!
//! Every limit is tightened by a relative `1e-9` of itself so that a solution within the SQP's
//! tolerance is inside the declared one.

mod clearance;
pub(crate) use clearance::obstacles_within_reach;
mod curvature;
mod ends;
mod hold;
mod phi_path;
mod ranges;
mod restore;
use phi_path::PathPoint;

pub(crate) use clearance::PIECES as CLEARANCE_PIECES;
pub(crate) use hold::Margins;
pub(crate) use ranges::{inside_ranges, least_time, within_reach};
pub(crate) use restore::onto_holonomy;

use nalgebra::DVector;

use super::ChainPlanner;
use super::connection::Connection;
use super::discrete::Discretisation;
use crate::dynamics::arm::ArmDynamics;
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::arm::lumped::SIZE;
use crate::planners::optimal::band::BandCholesky;
use crate::planners::optimal::discrete::Evaluation;
use crate::planners::optimal::spline::SplineBasis;
use crate::planners::optimal::sqp::{self, Discretised, Inequalities, SqpOptions, SqpResult, Termination};

/// Relative margin by which every limit is tightened.
const MARGIN: f64 = 1e-9;

/// Points per knot span at which the torque is bounded (the span's start and interior points;
/// the horizon's end is added).
const TORQUE_POINTS: usize = 3;

/// The times of the torque rows on `basis`: [`TORQUE_POINTS`] per knot span (its start and
/// interior points), and the horizon's end.
fn torque_times(basis: &SplineBasis) -> Vec<f64> {
    let mut times = Vec::new();
    for w in basis.breakpoints().windows(2) {
        times.extend((0..TORQUE_POINTS).map(|k| w[0] + (w[1] - w[0]) * k as f64 / TORQUE_POINTS as f64));
    }
    times.push(basis.horizon());
    times
}

/// A linear row `sum_k a_k c_k + constant` in all coefficients of one joint.
#[derive(Debug, Clone)]
struct Linear {
    joint: usize,
    terms: Vec<(usize, f64)>,
    scale: f64,
    offset: f64,
}

/// A discretisation with the arm's limits as inequalities.
pub(crate) struct Limited<'a> {
    disc: &'a Discretisation,
    arm: &'a Arm,
    connection: &'a Connection,
    linear: Vec<Linear>,
    /// `(joint, 1 / tau_max)` of the torque-limited joints.
    torque: Vec<(usize, f64)>,
    base: Option<[f64; 2]>,
    /// The clearance rows of an arm with shapes (issue 21).
    clearance: Option<clearance::Clearance>,
    /// Free index of coefficient `i` of joint `j`: `free[i]` times `n` plus `j`.
    free: Vec<Option<usize>>,
    /// The margins of the torque and base-range rows by span, where a plan left those limits
    /// between the rows' points ([`hold`]; none at first).
    held: Option<std::sync::Arc<Margins>>,
    /// The basis' values at [`Limited::phi_path_each`]'s quadrature nodes, by parts per span
    /// (found at its first call).
    nodes: std::cell::RefCell<Vec<(usize, std::rc::Rc<[phi_path::Values]>)>>,
    /// The basis' values and rates at [`Limited::phi_path_each`]'s points, by parts per span
    /// ([`Limited::end_values`]).
    ends: std::cell::RefCell<Vec<(usize, std::rc::Rc<[phi_path::Values]>)>>,
    /// The obstacles' rows that carry a gradient at the last evaluation with gradients, as
    /// `(row, point, d g / d phi)`: the row's index, its point's among the path's, and its
    /// slope in the base angle there (their curvature through `phi(t)`,
    /// [`Limited::obstacle_curvature`]).
    phi_slopes: std::cell::RefCell<Vec<(usize, usize, f64)>>,
    /// The last [`Limited::obstacle_curvature`], keyed by the bits of its iterate and of its
    /// nodes' weights (asked again after a rejected step).
    obstacle_hessian: std::cell::RefCell<Option<(Vec<u64>, nalgebra::DMatrix<f64>)>>,
    /// The links' sines and cosines at the path's quadrature nodes, by parts per span
    /// ([`Limited::node_sines`]).
    sines: std::cell::RefCell<Vec<phi_path::Sines>>,
}

/// The derivative spline's control-point rows: row `k` of the `m`-th derivative as
/// `(coefficient, factor)` pairs, for `len` coefficients on `knots` (degree `p`).
fn derivative_rows(knots: &[f64], p: usize, len: usize, order: usize) -> Vec<Vec<(usize, f64)>> {
    let mut rows: Vec<Vec<(usize, f64)>> = (0..len).map(|k| vec![(k, 1.0)]).collect();
    for m in 1..=order {
        let deg = (p - m + 1) as f64;
        let mut next = Vec::new();
        for k in 0..rows.len().saturating_sub(1) {
            let width = knots[k + p + 1] - knots[k + m];
            if !(width > 0.0) {
                next.push(Vec::new());
                continue;
            }
            let f = deg / width;
            let mut row: Vec<(usize, f64)> = rows[k + 1].iter().map(|&(i, a)| (i, a * f)).collect();
            for &(i, a) in &rows[k] {
                match row.iter_mut().find(|(j, _)| *j == i) {
                    Some(e) => e.1 -= a * f,
                    None => row.push((i, -a * f)),
                }
            }
            next.push(row);
        }
        rows = next;
    }
    rows
}

impl<'a> Limited<'a> {
    /// The constraints of `arm`'s limits on `disc`; `None` when the basis' knots are not the
    /// clamped simple ones this module assumes (never for the planner's bases).
    pub(super) fn new(planner: &'a ChainPlanner, disc: &'a Discretisation) -> Option<Self> {
        let (arm, connection) = (&*planner.arm, &*planner.connection);
        let basis = disc.basis();
        let (p, len) = (basis.degree(), basis.len());
        let b = basis.breakpoints();
        if len + 1 != b.len() + p {
            return None;
        }
        let mut knots = vec![0.0; p];
        knots.extend_from_slice(b);
        knots.extend(std::iter::repeat_n(basis.horizon(), p));
        let n = arm.joints();
        let nf = disc.dim() / n;
        let fixed = (len - nf) / 2;
        let free = (0..len).map(|i| (fixed..len - fixed).contains(&i).then(|| i - fixed)).collect();
        let mut linear = Vec::new();
        let mut torque = Vec::new();
        for j in 0..n {
            let l = arm.limits.joint(j);
            if let Some([lo, hi]) = l.position {
                let pad = MARGIN * (hi - lo);
                for k in 0..len {
                    linear.push(Linear { joint: j, terms: vec![(k, 1.0)], scale: 1.0, offset: -(hi - pad) });
                    linear.push(Linear { joint: j, terms: vec![(k, -1.0)], scale: 1.0, offset: lo + pad });
                }
            }
            for (order, limit) in [(1, l.velocity), (2, l.acceleration)] {
                let Some(v) = limit else { continue };
                let v = v * (1.0 - MARGIN);
                for row in derivative_rows(&knots, p, len, order) {
                    let neg = row.iter().map(|&(i, a)| (i, -a)).collect();
                    linear.push(Linear { joint: j, terms: row, scale: 1.0 / v, offset: -1.0 });
                    linear.push(Linear { joint: j, terms: neg, scale: 1.0 / v, offset: -1.0 });
                }
            }
            if let Some(t) = l.torque {
                torque.push((j, 1.0 / (t * (1.0 - MARGIN))));
            }
        }
        let base = arm.limits.base.map(|[lo, hi]| [lo + MARGIN * (hi - lo), hi - MARGIN * (hi - lo)]);
        let clearance = planner
            .clearance_rows
            .then(|| {
                let o = &planner.options;
                clearance::Clearance::new(arm, planner.obstacle_rows, o.clearance_reserve, o.clearance_rise)
                    .map(|c| c.at(planner.clearance_pieces, planner.clearance_dense.clone()))
            })
            .flatten();
        let held = planner.held.clone().filter(|m| m.fits(b.len() - 1));
        Some(Self {
            disc,
            arm,
            connection,
            linear,
            torque,
            base,
            clearance,
            free,
            held,
            nodes: Default::default(),
            ends: Default::default(),
            phi_slopes: Default::default(),
            obstacle_hessian: Default::default(),
            sines: Default::default(),
        })
    }

    /// `x` with every position-limited joint's free coefficients clipped into its range (a seed
    /// that starts inside).
    fn clip(&self, mut x: DVector<f64>) -> DVector<f64> {
        let n = self.arm.joints();
        for j in 0..n {
            if let Some([lo, hi]) = self.arm.limits.joint(j).position {
                let pad = 2.0 * MARGIN * (hi - lo);
                for k in (j..x.len()).step_by(n) {
                    x[k] = x[k].clamp(lo + pad, hi - pad);
                }
            }
        }
        x
    }

    /// The free index of coefficient `i` of joint `j`.
    fn index(&self, i: usize, j: usize) -> Option<usize> {
        self.free[i].map(|f| f * self.arm.joints() + j)
    }

    /// The torque rows (two per joint and point) into `out`.
    // The indices are the formula's: joints `j`, `k` and the basis functions `l` of the span.
    #[allow(clippy::needless_range_loop)]
    fn torques(&self, c: &[Vec<f64>], order: usize, out: &mut Inequalities) {
        if self.torque.is_empty() {
            return;
        }
        let basis = self.disc.basis();
        let (p, n) = (basis.degree(), self.arm.joints());
        let times = torque_times(basis);
        let (mut th, mut w, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        // The arm's constants once for every point (as `inverse_dynamics` builds them per call).
        let dynamics = ArmDynamics::new(self.arm);
        // Work arrays of the inverse dynamics (no allocation per call).
        let mut tau = [0.0; SIZE];
        let mut spare = ([0.0; SIZE], [0.0; SIZE]);
        // Sensitivities d tau_j / d (theta_k, theta'_k, theta''_k): `sens[which][j][k]`.
        let mut sens = [[[0.0; SIZE]; SIZE]; 3];
        let mut row = Vec::new();
        for (i, &t) in times.iter().enumerate() {
            let span = basis.span_of_interval(basis.interval(t));
            let d = basis.ders(span, t);
            let first = span - p;
            for j in 0..n {
                let cj = &c[j][first..=first + p];
                th[j] = (0..=p).map(|l| d[0][l] * cj[l]).sum();
                w[j] = (0..=p).map(|l| d[1][l] * cj[l]).sum();
                a[j] = (0..=p).map(|l| d[2][l] * cj[l]).sum();
            }
            // The angles' terms once for the torque, its differences in theta' and its
            // derivative in theta'' (the same values as the inverse dynamics at `th`).
            let at = dynamics.at_angles(&th);
            at.inverse_into(&w, &a, &mut tau[..n], &mut spare.0[..=n], &mut spare.1[..=n]);
            if order >= 1 {
                // In theta and theta' in closed form ([`InverseAt::sensitivities`]); in theta''
                // the reduced inertia `M_jk - M_j0 M_0k / M_00` (the torque is affine in it, the
                // base's `phi''` eliminated by the momentum row).
                let [angles, rates, accelerations] = &mut sens;
                at.sensitivities(&w, &a, angles, rates);
                for jj in 0..n {
                    for k in 0..n {
                        accelerations[jj][k] =
                            at.inertia(jj + 1, k + 1) - at.inertia(jj + 1, 0) * at.inertia(0, k + 1) / at.inertia(0, 0);
                    }
                }
            }
            for &(j, inv) in &self.torque {
                // A held row at `1 - margin` of the limit ([`hold`]; the horizon's end, point 0 of
                // span `spans`, the last span's).
                let inv = match &self.held {
                    Some(m) => inv / (1.0 - m.at_point(hold::Held::Torque(j), i / TORQUE_POINTS, i % TORQUE_POINTS)),
                    None => inv,
                };
                out.values.push(tau[j] * inv - 1.0);
                out.values.push(-tau[j] * inv - 1.0);
                if order >= 1 {
                    row.clear();
                    for l in 0..=p {
                        for k in 0..n {
                            if let Some(idx) = self.index(first + l, k) {
                                let v = sens[0][j][k] * d[0][l] + sens[1][j][k] * d[1][l] + sens[2][j][k] * d[2][l];
                                row.push((idx, v * inv));
                            }
                        }
                    }
                    out.rows.push(row.clone());
                    out.rows.push(row.iter().map(|&(i, v)| (i, -v)).collect());
                }
            }
        }
    }

    /// The base-range rows (two per breakpoint after `t = 0`) into `out`, each side tightened by
    /// its margin ([`hold`]) but never past the start's or the goal's base angle.
    fn base(&self, c: &[Vec<f64>], order: usize, out: &mut Inequalities) {
        let Some(range) = self.base else { return };
        for (i, point) in self.phi_path(c, 1, order).into_iter().enumerate() {
            let [lo, hi] = self.held_base(range, i + 1);
            out.values.push(point.phi - hi);
            out.values.push(lo - point.phi);
            if order >= 1 {
                let row: Vec<(usize, f64)> =
                    point.grad.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, v)| (i, *v)).collect();
                out.rows.push(row.clone());
                out.rows.push(row.into_iter().map(|(i, v)| (i, -v)).collect());
            }
        }
    }
}

impl Limited<'_> {
    /// The base range `range` of the rows at breakpoint `i`, each side tightened by its margin
    /// ([`hold`]; in units of the declared range's width) but never past the start's or the
    /// goal's base angle.
    fn held_base(&self, [lo, hi]: [f64; 2], i: usize) -> [f64; 2] {
        let (Some(m), Some([dlo, dhi])) = (&self.held, self.arm.limits.base) else { return [lo, hi] };
        let targets = self.disc.targets();
        let ends = [targets.phi_start, targets.phi_end];
        let (above, below) = (m.at_breakpoint(hold::Held::BaseAbove, i), m.at_breakpoint(hold::Held::BaseBelow, i));
        let hi = if above > 0.0 { (hi - above * (dhi - dlo)).max(ends[0].max(ends[1])) } else { hi };
        let lo = if below > 0.0 { (lo + below * (dhi - dlo)).min(ends[0].min(ends[1])) } else { lo };
        [lo, hi]
    }
}

impl Discretised for Limited<'_> {
    fn dim(&self) -> usize {
        self.disc.dim()
    }
    fn half_bandwidth(&self) -> usize {
        self.disc.half_bandwidth()
    }
    fn effort_hessian(&self) -> &nalgebra::DMatrix<f64> {
        self.disc.effort_hessian()
    }
    fn effort_cholesky(&self) -> Option<&BandCholesky> {
        self.disc.effort_cholesky()
    }
    fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        self.disc.evaluate(x, order)
    }
    fn inequalities(&self, x: &DVector<f64>, order: usize) -> Option<Inequalities> {
        let c = self.disc.coefficients(x);
        let mut out = Inequalities::default();
        for row in &self.linear {
            let value: f64 = row.terms.iter().map(|&(i, a)| a * c[row.joint][i]).sum();
            out.values.push(row.scale * value + row.offset);
            if order >= 1 {
                let terms = row.terms.iter().filter_map(|&(i, a)| self.index(i, row.joint).map(|k| (k, a * row.scale)));
                out.rows.push(terms.collect());
            }
        }
        self.torques(&c, order, &mut out);
        self.base(&c, order, &mut out);
        self.clearance(&c, order, &mut out);
        Some(out)
    }
    fn curvature(&self, x: &DVector<f64>, z: &[f64]) -> Option<nalgebra::DMatrix<f64>> {
        let base = self.base_curvature(x, z);
        match (base, self.obstacle_curvature(x, z)) {
            (Some(a), Some(b)) => Some(a + b),
            (a, b) => a.or(b),
        }
    }
    fn curved_rows(&self) -> std::ops::Range<usize> {
        self.base_rows()
    }
}

/// SQP iterations of a rate-limited line's first coarse solve (see `ChainPlanner::solve_seed`).
pub(crate) const CAPPED_LINE: usize = 8;

/// The stall iterations of a deciding search's solves (`ChainPlanner::deciding`), the probes'
/// (`horizon.rs`).
const DECIDING_STALL: usize = 3;

/// The least fraction by which a deciding search's infeasible solve must reduce its
/// infeasibility in twice [`DECIDING_STALL`] iterations ([`SqpOptions::feasibility_progress`];
/// 1 % elsewhere). The search asks only whether a plan fits: a solve that falls by less than
/// 30 % in 6 iterations would need about 300 iterations at that rate to reach the coarse
/// tolerance from 1e-2, against its 40. On issue 20's `--time auto` bench (3-link, velocity
/// limits) the failing full search at 9.87 s crawled from 5.7e-3 to its plateau at 4.92e-3 rad
/// off the holonomy for 15 iterations in one solve and 31 in another: with this, the bench's
/// QPs 486 -> 390 (Clarabel iterations 5980 -> 4595), the same horizon (9.9329 s) and plan
/// (effort 18.0891287310).
const DECIDING_PROGRESS: f64 = 0.3;

/// Restarts of a constrained solve that stalled short of its KKT tolerance ([`solve`]).
const STALL_RESTARTS: usize = 4;

/// Solves `disc` from `x0` inside `arm`'s limits (the seed clipped into the position ranges):
/// [`sqp::solve`] with the limits' inequalities, or exactly [`sqp::solve`] for an arm without
/// limits.
pub(crate) fn solve(
    planner: &ChainPlanner,
    disc: &Discretisation,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
) -> Result<SqpResult, Error> {
    solve_watched(planner, disc, x0, options, guess, &mut |_, _, _| false)
}

/// [`solve`] with `abandon(iterations, f, c)` asked at every iterate
/// ([`sqp::solve_watched`]): where it answers `true` the solve stops there as
/// [`Termination::Abandoned`].
pub(crate) fn solve_watched(
    planner: &ChainPlanner,
    disc: &Discretisation,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
    abandon: &mut dyn FnMut(usize, f64, f64) -> bool,
) -> Result<SqpResult, Error> {
    if !constrained(planner) {
        return sqp::solve_watched(disc, x0, options, guess, abandon);
    }
    let deciding = SqpOptions {
        stall_iterations: options.stall_iterations.min(DECIDING_STALL),
        feasibility_progress: DECIDING_PROGRESS,
        ..*options
    };
    let options = if planner.deciding { &deciding } else { options };
    match Limited::new(planner, disc) {
        Some(limited) => {
            let x0 = limited.clip(x0);
            sqp::solve_watched(&limited, x0, options, guess, abandon)
        }
        None => Err(Error::from(InputError::InvalidParameter {
            name: "spans".into(),
            value: disc.basis().len() as f64,
            expected: "a clamped spline basis with simple interior knots",
        })),
    }
}

/// The first phase of a clearance search ([`super::augmented`]): the augmented Lagrangian of
/// `disc` with `planner`'s limits and rows from `x0` (clipped into the position ranges), every
/// constraint soft at first; the point and the holonomy's multiplier, the SQP's start. `None`
/// where `planner` has no rows.
pub(crate) fn soft_start(
    planner: &ChainPlanner,
    disc: &Discretisation,
    x0: DVector<f64>,
    tolerance: f64,
) -> Option<(DVector<f64>, f64)> {
    if !constrained(planner) {
        return None;
    }
    let limited = Limited::new(planner, disc)?;
    let x0 = limited.clip(x0);
    Some(super::augmented::augmented_lagrangian(&limited, x0, tolerance))
}

/// [`solve`] at the refinement's accuracy, restarted where it stalls short of its KKT
/// tolerance: a stall is often the trust region's and the multipliers' history, not the
/// problem's. On binding position ranges (issue 20's oracle cases 7 and 15) the iteration
/// stopped at KKT residuals of 0.08 and 4e-4 at points from which the independent oracle
/// descends; restarted from there (a fresh radius, the holonomy multiplier kept) both converged
/// (case 7 to 0.2 % of the oracle). Up to [`STALL_RESTARTS`] times, while the KKT residual at
/// least halves at no loss of feasibility. Not for the coarse solves: restarting those changed
/// which candidates the search refines, and lost case 19's minimum. Nor in a deciding search
/// (`ChainPlanner::deciding`) off the constraint: it asks whether a plan fits, not its minimum.
pub(crate) fn solve_restarting(
    planner: &ChainPlanner,
    disc: &Discretisation,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
) -> Result<SqpResult, Error> {
    let mut result = solve(planner, disc, x0, options, guess)?;
    if !constrained(planner) || (planner.deciding && result.c.abs() > options.constraint_tolerance) {
        return Ok(result);
    }
    for _ in 0..STALL_RESTARTS {
        if result.converged() || result.termination != Termination::Stalled {
            break;
        }
        let again = solve(planner, disc, result.x.clone(), options, Some(result.lambda))?;
        let feasible = again.c.abs() <= options.constraint_tolerance.max(result.c.abs());
        if !(feasible && again.kkt < 0.5 * result.kkt) {
            break;
        }
        // Off the constraint and no nearer it (to 0.1 %): kept, not restarted again (issue 20's
        // `--time auto` bench: four restarts at the failing horizon's residual 5.9e-3, 91 QPs).
        let stuck = result.c.abs() > options.constraint_tolerance && again.c.abs() >= 0.999 * result.c.abs();
        result = SqpResult { iterations: result.iterations + again.iterations, ..again };
        if stuck {
            break;
        }
    }
    Ok(result)
}

/// Whether `planner`'s solves carry inequality rows: declared limits or a clearance to keep.
pub(super) fn constrained(planner: &ChainPlanner) -> bool {
    !planner.arm.limits.is_empty() || keeps_clearance(planner)
}

/// True when `planner` solves with clearance rows: its arm has a pair of bodies (or a body and
/// an obstacle, with obstacle rows on) that is checked, and the rows are on.
pub(crate) fn keeps_clearance(planner: &ChainPlanner) -> bool {
    planner.clearance_rows
        && clearance::Clearance::new(&planner.arm, planner.obstacle_rows, 0.0, Default::default()).is_some()
}
