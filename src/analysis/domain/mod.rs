//! Domains of existence of the feedback transformations on the `(theta1, theta2)` torus (Sec. 6,
//! item 3; Figs. 13-14), and their connected components.
//!
//! A feedback transformation of Theorem 1 exists where its conditions hold: `sin theta2 != 0` for
//! Eqs. (11)-(12), `sigma != 0` (Eq. 9) and `P != 0` (Eq. 13) for Eq. (14), and `sigma != 0`
//! alone for the global normal form of [`crate::planners::nfa::normal_form::global`] (docs/spec.md §6, item 4:
//! `d > 0` and both arcsin arguments in `[-1, 1]` hold everywhere since `F > 0`; they are checked
//! anyway). None of them depends on `phi`, so the domain is a region of the torus
//! `T^2 = [0, 2 pi)^2` of the joint angles. Its zero curves have measure zero: what matters is how
//! they cut the torus into connected pieces. A plan of the Normal Form Approach can only join
//! configurations of the same piece, since its joint path is continuous and every condition keeps
//! its sign along it.
//!
//! # Discretisation: cells, samples and cuts
//! The torus is divided into `N x N` square cells of side `h = 2 pi / N`; cell `(i1, i2)` covers
//! `[i1 h, (i1 + 1) h) x [i2 h, (i2 + 1) h)` and is represented by the sample at its centre
//! `((i1 + 1/2) h, (i2 + 1/2) h)`. Cells and sample points are therefore the same thing, and:
//!
//! * a cell is **defined** when every condition holds at its centre; it then carries the signs
//!   of the conditions' functions there (`sign(sigma)`, and the branch `sign(P)`, or
//!   `sign(sin theta2)` for Eqs. 11-12);
//! * two cells that share a side (wrap-around included: cell `N - 1` neighbours cell `0` on both
//!   axes) are **connected** when both are defined and no function changes sign between their
//!   centres. A zero curve is thus detected on the segment between two samples by the sign
//!   change, never by `|x| < eps`, and it **cuts** that segment instead of removing cells: the
//!   curves have no area, and the areas of the components of a map whose conditions only fail on
//!   curves add up to exactly 1;
//! * a **component** is a connected set of cells (4-neighbours on the torus). Its area is its
//!   number of cells over `N^2`. All its cells have the same signs, so the branch of a component
//!   is well defined.
//!
//! **Slivers.** Where two zero curves cross at a small angle, the sectors between them are
//! wedges thinner than a cell near their apex; the cells of such a wedge that lie there are
//! isolated in the 4-neighbour graph although the wedge is connected. Their number does not
//! grow with `N` and their area tends to 0 (at `a = b = 0.3`, 12 such pieces of 1-4 cells at
//! every `N` from 720 to 2880). A component is therefore counted as *resolved* only when some
//! cell of it has all 8 surrounding cells in it; the others are reported apart as slivers, with
//! their total area, and still take part in [`DomainMap::component_at`].
//!
//! For even `N` no centre lies on `theta2 = 0` or `pi`, so at `a = b = 0` the two halves
//! `sin theta2 > 0` and `< 0` are exactly `N/2` rows each. Features thinner than a cell (two zero
//! crossings between neighbouring samples, a passage narrower than `h`) are below the map's
//! resolution; refine `N` to check that a count has converged.
//!
//! [`CellClass`] classifies each cell for display by the first condition that fails there, in the
//! order `sigma`-crossing, `P`-crossing (or `sin theta2`-crossing), `d <= 0`, arcsin argument; a
//! cell classified as a crossing still belongs to the component of its centre.

use crate::model::InputError;
use serde::Serialize;

use crate::error::{Error, Singularity};
use crate::model::system::{Shape, shape, shape_from_trig};
use crate::model::{Configuration, Lumped, RobotParams};
use crate::planners::nfa::normal_form::Transform;

/// Largest grid size accepted: `N^2` cells must fit in memory comfortably.
pub const MAX_GRID: usize = 8192;

/// Slack allowed on `|arcsin argument| <= 1` for rounding: at `P = 0` the first argument is
/// exactly `+-1` in exact arithmetic (Eq. 21).
const ARCSIN_SLACK: f64 = 1e-12;

/// The signs of the domain's functions on a defined cell or component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Signs {
    /// The branch: `sign(P)` for Eq. (14), `sign(sin theta2)` for Eqs. (11)-(12); `+1` or `-1`.
    pub branch: i8,
    /// `sign(sigma)` for Eq. (14); `None` for Eqs. (11)-(12), whose only condition is
    /// `sin theta2 != 0`.
    pub sigma: Option<i8>,
}

/// What holds at a cell's centre.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellStatus {
    /// Every condition holds; the signs of the functions there.
    Defined(Signs),
    /// The first condition that fails at the centre (an exact zero of `sigma`, `P` or
    /// `sin theta2`, `d <= 0`, an arcsin argument outside `[-1, 1]`, or a non-finite value).
    Undefined(Singularity),
}

/// A cell classified for display by the first condition that fails on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CellClass {
    /// A zero curve (`sigma = 0`, `P = 0` or `sin theta2 = 0`) passes through the centre or
    /// between the centre and a neighbour's centre (a sign change).
    Crossing(Singularity),
    /// `d <= 0` or an arcsin argument outside `[-1, 1]` at the centre (never for a physical robot,
    /// docs/spec.md §6, item 4).
    Undefined(Singularity),
    /// Defined, with the branch `sign(P)` (Eq. 14) or `sign(sin theta2)` (Eqs. 11-12).
    Defined {
        /// `+1` or `-1`.
        branch: i8,
    },
}

/// A connected component of the domain on the torus.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Component {
    /// Number of cells.
    pub cells: usize,
    /// Share of the torus' area, `cells / N^2`.
    pub fraction: f64,
    /// The signs of the domain's functions on the component.
    pub signs: Signs,
    /// The first cell `(i1, i2)` in row-major order (rows of constant `theta2`).
    pub first_cell: (usize, usize),
    /// The component is resolved by the grid: at least one of its cells has all 8 surrounding
    /// cells in it. An unresolved component (a *sliver*) is nowhere 3 cells thick; slivers
    /// appear where two zero curves meet at a small angle, as the isolated cells of a wedge
    /// thinner than a cell, and shrink as `N` grows (see the module docs).
    pub resolved: bool,
}

/// The samples of one function whose zero curve cuts the torus (`sigma`, `P` or `sin theta2`),
/// at the cell centres, row-major (index `i2 * N + i1`).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSamples {
    /// Which condition.
    pub which: Singularity,
    /// The values at the centres.
    pub values: Vec<f64>,
}

/// The domain of existence of one feedback transformation on an `N x N` grid of the
/// `(theta1, theta2)` torus, with its connected components (see the module docs for the
/// discretisation).
///
/// ```
/// use freefloat::{RobotParams, Transform, analysis::domain::DomainMap};
/// let map = DomainMap::new(&RobotParams::src(), Transform::Eq14, 64).unwrap();
/// // a = b = 0: the domain is sin(theta2) != 0, two halves of the torus.
/// assert_eq!(map.components().len(), 2);
/// assert!((map.components()[0].fraction - 0.5).abs() < 1e-12);
/// ```
#[derive(Debug, Clone)]
pub struct DomainMap {
    robot: RobotParams,
    transform: Transform,
    n: usize,
    status: Vec<CellStatus>,
    curves: Vec<CurveSamples>,
    /// Component of each cell (index into `components`), `NONE` when undefined.
    labels: Vec<u32>,
    components: Vec<Component>,
}

const NONE: u32 = u32::MAX;

/// The pointwise conditions of `transform` given the functions at one configuration.
/// `s2 = sin theta2`. Returns the signs, or the first failing condition.
fn classify(transform: Transform, s: &Shape<f64>, s2: f64) -> CellStatus {
    let sign = |x: f64| if x > 0.0 { 1 } else { -1 };
    match transform {
        Transform::Eq11 | Transform::Eq12 => {
            if !(s2.abs() > 0.0) {
                return CellStatus::Undefined(Singularity::SinTheta2);
            }
            CellStatus::Defined(Signs { branch: sign(s2), sigma: None })
        }
        Transform::Global => {
            if !(s.sigma.abs() > 0.0) {
                return CellStatus::Undefined(Singularity::Sigma);
            }
            CellStatus::Defined(Signs { branch: sign(s.sigma), sigma: Some(sign(s.sigma)) })
        }
        Transform::Eq14 => {
            if !(s.sigma.abs() > 0.0) {
                return CellStatus::Undefined(Singularity::Sigma);
            }
            if !(s.P.abs() > 0.0) {
                return CellStatus::Undefined(Singularity::P);
            }
            if !(s.d > 0.0 && s.f > 0.0 && s.F > 0.0) {
                return CellStatus::Undefined(Singularity::DNonPositive);
            }
            // The literal arcsin arguments of Eq. (14), as in `general::arcsin_arguments`.
            let x1 = (s.F - s.U) / (2.0 * s.f);
            let x2 = (s.F * s.U - s.d) / (2.0 * s.f * s.F);
            if !(x1.abs() <= 1.0 + ARCSIN_SLACK && x2.abs() <= 1.0 + ARCSIN_SLACK) {
                return CellStatus::Undefined(Singularity::ArcsinArgument);
            }
            CellStatus::Defined(Signs { branch: sign(s.P), sigma: Some(sign(s.sigma)) })
        }
    }
}

/// The connectivity key of a status: 0 when undefined, else `1 + ` the sign bits, so that two
/// defined cells may be joined exactly when their keys are equal.
fn key(status: CellStatus) -> u8 {
    match status {
        CellStatus::Undefined(_) => 0,
        CellStatus::Defined(s) => 1 + u8::from(s.branch > 0) + 2 * u8::from(s.sigma.is_some_and(|x| x > 0)),
    }
}

/// Connected components of the cells with equal non-zero `keys` on the `n x n` torus
/// (4-neighbours, wrap-around on both axes), by flood fill in row-major order.
///
/// Returns the label of each cell (`NONE` where the key is 0) and, per component, its number of
/// cells and first cell index; components are numbered by decreasing area, ties by first cell.
fn label_components(n: usize, keys: &[u8]) -> (Vec<u32>, Vec<(usize, usize)>) {
    let mut labels = vec![NONE; n * n];
    let mut found: Vec<(usize, usize)> = Vec::new(); // (cells, first index)
    let mut stack: Vec<usize> = Vec::new();
    for start in 0..n * n {
        if keys[start] == 0 || labels[start] != NONE {
            continue;
        }
        let label = found.len() as u32;
        let k = keys[start];
        labels[start] = label;
        stack.push(start);
        let mut cells = 0;
        while let Some(c) = stack.pop() {
            cells += 1;
            let (i1, i2) = (c % n, c / n);
            let row = i2 * n;
            let neighbours = [
                row + if i1 + 1 == n { 0 } else { i1 + 1 },
                row + if i1 == 0 { n - 1 } else { i1 - 1 },
                if i2 + 1 == n { i1 } else { c + n },
                if i2 == 0 { (n - 1) * n + i1 } else { c - n },
            ];
            for nb in neighbours {
                if keys[nb] == k && labels[nb] == NONE {
                    labels[nb] = label;
                    stack.push(nb);
                }
            }
        }
        found.push((cells, start));
    }
    // Renumber by decreasing area (stable: ties keep row-major order of first cells).
    let mut order: Vec<usize> = (0..found.len()).collect();
    order.sort_by(|&x, &y| found[y].0.cmp(&found[x].0));
    let mut rank = vec![0u32; found.len()];
    for (new, &old) in order.iter().enumerate() {
        rank[old] = new as u32;
    }
    for l in labels.iter_mut().filter(|l| **l != NONE) {
        *l = rank[*l as usize];
    }
    (labels, order.into_iter().map(|old| found[old]).collect())
}

/// `sin` and `cos` of `(k + offset) h` for `k` in `0..n`, `h = 2 pi / n`.
fn trig_table(n: usize, offset: f64) -> Vec<(f64, f64)> {
    let h = std::f64::consts::TAU / n as f64;
    (0..n).map(|k| ((k as f64 + offset) * h).sin_cos()).collect()
}

impl DomainMap {
    /// The domain of `transform` for `robot` on a `grid x grid` map of the torus.
    ///
    /// Errors: [`InputError::InvalidParameter`] for a grid outside `3..=`[`MAX_GRID`] or an invalid
    /// robot; [`Error::TransformUnavailable`] for Eqs. (11)-(12) with `a, b != 0`.
    pub fn new(robot: &RobotParams, transform: Transform, grid: usize) -> Result<Self, Error> {
        robot.validate()?;
        if !(3..=MAX_GRID).contains(&grid) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "grid".into(),
                value: grid as f64,
                expected: "a grid size between 3 and 8192",
            }));
        }
        if matches!(transform, Transform::Eq11 | Transform::Eq12) && !robot.mount.is_centred() {
            return Err(Error::TransformUnavailable {
                transform: transform.name(),
                reason: "Eqs. (11) and (12) hold only for a = b = 0; use eq14 (or auto)",
            });
        }
        let n = grid;
        let k: Lumped = robot.lumped();
        // Centres (i + 1/2) h; theta1 + theta2 = (i1 + i2 + 1) h.
        let centre = trig_table(n, 0.5);
        let sum = trig_table(n, 0.0);
        let mut status = Vec::with_capacity(n * n);
        let with_p = transform == Transform::Eq14;
        let mut first = Vec::with_capacity(n * n);
        let mut second = Vec::with_capacity(if with_p { n * n } else { 0 });
        for i2 in 0..n {
            let t2 = centre[i2];
            for (i1, &t1) in centre.iter().enumerate() {
                let j = i1 + i2 + 1;
                let t12 = sum[if j >= n { j - n } else { j }];
                let s = shape_from_trig(&k, t1, t2, t12);
                status.push(classify(transform, &s, t2.0));
                if with_p {
                    first.push(s.sigma);
                    second.push(s.P);
                } else if transform == Transform::Global {
                    first.push(s.sigma);
                } else {
                    first.push(t2.0);
                }
            }
        }
        let curves = if with_p {
            vec![
                CurveSamples { which: Singularity::Sigma, values: first },
                CurveSamples { which: Singularity::P, values: second },
            ]
        } else if transform == Transform::Global {
            vec![CurveSamples { which: Singularity::Sigma, values: first }]
        } else {
            vec![CurveSamples { which: Singularity::SinTheta2, values: first }]
        };
        let keys: Vec<u8> = status.iter().map(|&s| key(s)).collect();
        let (labels, found) = label_components(n, &keys);
        let total = (n * n) as f64;
        let components = found
            .into_iter()
            .map(|(cells, first)| Component {
                cells,
                fraction: cells as f64 / total,
                signs: match status[first] {
                    CellStatus::Defined(s) => s,
                    // Invariant: components are made of defined cells only.
                    CellStatus::Undefined(_) => Signs { branch: 0, sigma: None },
                },
                first_cell: (first % n, first / n),
                resolved: false,
            })
            .collect::<Vec<_>>();
        let mut components = components;
        for (c, &l) in labels.iter().enumerate() {
            if l == NONE || components[l as usize].resolved {
                continue;
            }
            let (i1, i2) = (c % n, c / n);
            let (l1, r1, d2, u2) = ((i1 + n - 1) % n, (i1 + 1) % n, (i2 + n - 1) % n, (i2 + 1) % n);
            let around = [(l1, d2), (i1, d2), (r1, d2), (l1, i2), (r1, i2), (l1, u2), (i1, u2), (r1, u2)];
            if around.iter().all(|&(j1, j2)| labels[j2 * n + j1] == l) {
                components[l as usize].resolved = true;
            }
        }
        Ok(Self { robot: *robot, transform, n, status, curves, labels, components })
    }

    /// The grid size `N`.
    pub fn grid(&self) -> usize {
        self.n
    }

    /// The transformation whose domain this is.
    pub fn transform(&self) -> Transform {
        self.transform
    }

    /// The robot (with its mounting point).
    pub fn robot(&self) -> &RobotParams {
        &self.robot
    }

    /// The side of a cell, `h = 2 pi / N` \[rad\].
    pub fn cell_size(&self) -> f64 {
        std::f64::consts::TAU / self.n as f64
    }

    /// The centre `(theta1, theta2)` of cell `(i1, i2)`, in `[0, 2 pi)` \[rad\].
    pub fn centre(&self, i1: usize, i2: usize) -> (f64, f64) {
        let h = self.cell_size();
        ((i1 as f64 + 0.5) * h, (i2 as f64 + 0.5) * h)
    }

    /// The cell that holds `(theta1, theta2)` \[rad\], any representative of the angles.
    pub fn cell_of(&self, theta1: f64, theta2: f64) -> (usize, usize) {
        let index = |x: f64| {
            let u = x.rem_euclid(std::f64::consts::TAU) / self.cell_size();
            (u.floor() as usize).min(self.n - 1)
        };
        (index(theta1), index(theta2))
    }

    fn idx(&self, i1: usize, i2: usize) -> usize {
        (i2 % self.n) * self.n + (i1 % self.n)
    }

    /// What holds at the centre of cell `(i1, i2)` (indices taken modulo `N`).
    pub fn status(&self, i1: usize, i2: usize) -> CellStatus {
        self.status[self.idx(i1, i2)]
    }

    /// The component of cell `(i1, i2)` (indices modulo `N`), `None` when it is undefined.
    pub fn component(&self, i1: usize, i2: usize) -> Option<usize> {
        let l = self.labels[self.idx(i1, i2)];
        (l != NONE).then_some(l as usize)
    }

    /// The components, by decreasing area.
    pub fn components(&self) -> &[Component] {
        &self.components
    }

    /// The functions whose zero curves cut the torus, sampled at the cell centres: `sigma` and
    /// `P` for Eq. (14), `sin theta2` for Eqs. (11)-(12).
    pub fn curves(&self) -> &[CurveSamples] {
        &self.curves
    }

    /// Number of resolved components (see [`Component::resolved`]): the count of docs/spec.md §3.
    pub fn resolved_count(&self) -> usize {
        self.components.iter().filter(|c| c.resolved).count()
    }

    /// Share of the torus where the transformation is defined (the sum of the components'
    /// fractions).
    pub fn defined_fraction(&self) -> f64 {
        self.components.iter().map(|c| c.cells).sum::<usize>() as f64 / (self.n * self.n) as f64
    }

    /// The cell's class for display: the first failing condition, crossings first (see
    /// [`CellClass`]).
    pub fn class(&self, i1: usize, i2: usize) -> CellClass {
        let n = self.n;
        let (i1, i2) = (i1 % n, i2 % n);
        let here = self.idx(i1, i2);
        let neighbours =
            [self.idx(i1 + 1, i2), self.idx(i1 + n - 1, i2), self.idx(i1, i2 + 1), self.idx(i1, i2 + n - 1)];
        let sign = |x: f64| {
            if x > 0.0 {
                1
            } else if x < 0.0 {
                -1
            } else {
                0
            }
        };
        for curve in &self.curves {
            let s = sign(curve.values[here]);
            if s == 0 || neighbours.iter().any(|&nb| sign(curve.values[nb]) != s) {
                return CellClass::Crossing(curve.which);
            }
        }
        match self.status[here] {
            CellStatus::Defined(signs) => CellClass::Defined { branch: signs.branch },
            CellStatus::Undefined(which) => CellClass::Undefined(which),
        }
    }

    /// The component that holds the configuration `q` (its `phi` does not matter), or `None` when
    /// `q` is outside the domain.
    ///
    /// The conditions are evaluated at `q` itself. When `q` lies so close to a zero curve that
    /// the centre of its own cell is across the curve, the nearest of the 8 surrounding cells on
    /// `q`'s side is taken; `None` if there is none (the map is too coarse there).
    pub fn component_at(&self, q: &Configuration) -> Option<usize> {
        let k = self.robot.lumped();
        let s = shape(&k, q.theta1, q.theta2);
        let target = key(classify(self.transform, &s, q.theta2.sin()));
        if target == 0 {
            return None;
        }
        let (c1, c2) = self.cell_of(q.theta1, q.theta2);
        let here = self.idx(c1, c2);
        if key(self.status[here]) == target {
            return self.component(c1, c2);
        }
        let h = self.cell_size();
        let torus = |x: f64| {
            let r = x.rem_euclid(std::f64::consts::TAU);
            r.min(std::f64::consts::TAU - r)
        };
        let n = self.n;
        let mut best: Option<(f64, usize)> = None;
        for d2 in [n - 1, 0, 1] {
            for d1 in [n - 1, 0, 1] {
                let (j1, j2) = ((c1 + d1) % n, (c2 + d2) % n);
                if key(self.status[self.idx(j1, j2)]) != target {
                    continue;
                }
                let (x1, x2) = ((j1 as f64 + 0.5) * h, (j2 as f64 + 0.5) * h);
                let dist = torus(x1 - q.theta1).hypot(torus(x2 - q.theta2));
                if best.is_none_or(|(b, _)| dist < b) {
                    best = Some((dist, self.idx(j1, j2)));
                }
            }
        }
        best.and_then(|(_, i)| (self.labels[i] != NONE).then_some(self.labels[i] as usize))
    }

    /// The summary of docs/spec.md §3 (`freefloat domain --format json`) for the start `q0` and goal `qd`.
    pub fn summary(&self, start: &Configuration, goal: &Configuration) -> DomainSummary {
        let start_component = self.component_at(start);
        let goal_component = self.component_at(goal);
        DomainSummary {
            mount: [self.robot.mount.a, self.robot.mount.b],
            grid: self.n,
            transform: self.transform,
            components: self.resolved_count(),
            component_fractions: self.components.iter().filter(|c| c.resolved).map(|c| c.fraction).collect(),
            slivers: self.components.len() - self.resolved_count(),
            sliver_fraction: self.components.iter().filter(|c| !c.resolved).map(|c| c.fraction).sum(),
            defined_fraction: self.defined_fraction(),
            start: start.to_array(),
            goal: goal.to_array(),
            start_component,
            goal_component,
            start_component_fraction: start_component.map_or(0.0, |c| self.components[c].fraction),
            start_goal_connected: start_component.is_some() && start_component == goal_component,
        }
    }
}

/// The report of `freefloat domain` (docs/spec.md §3), radians inside.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DomainSummary {
    /// `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Grid size `N` (the map has `N x N` cells).
    pub grid: usize,
    /// The transformation.
    pub transform: Transform,
    /// Number of connected components of the domain on the torus (resolved by the grid).
    pub components: usize,
    /// Area share of each resolved component, decreasing.
    pub component_fractions: Vec<f64>,
    /// Number of unresolved components (slivers, see [`Component::resolved`]).
    pub slivers: usize,
    /// Their total area share.
    pub sliver_fraction: f64,
    /// Area share of the whole domain.
    pub defined_fraction: f64,
    /// `q0 = [phi, theta1, theta2]` \[rad\].
    pub start: [f64; 3],
    /// `qd` \[rad\].
    pub goal: [f64; 3],
    /// Index of `q0`'s component (into `component_fractions`, slivers after the resolved
    /// ones when they are smaller), null outside the domain.
    pub start_component: Option<usize>,
    /// Index of `qd`'s component, null outside the domain.
    pub goal_component: Option<usize>,
    /// Area share of `q0`'s component: where a plan from `q0` may go; 0 outside the domain.
    pub start_component_fraction: f64,
    /// `q0` and `qd` lie in the same component.
    pub start_goal_connected: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Mount, paper_problem};

    fn robot(a: f64, b: f64) -> RobotParams {
        RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap()
    }

    /// a = b = 0: the domain of Eq. (14) is sin(theta2) != 0 (sigma = -C I_P s2, P = -C s2): two
    /// components, exactly the two halves of the grid, the same as Eqs. (11)-(12).
    #[test]
    fn centred_mount_has_two_halves() {
        for n in [16, 64, 720] {
            for transform in [Transform::Eq14, Transform::Eq11, Transform::Eq12] {
                let map = DomainMap::new(&robot(0.0, 0.0), transform, n).unwrap();
                let c = map.components();
                assert_eq!(c.len(), 2, "{transform:?}, N = {n}");
                // The grid's own count of the cells with sin(theta2) > 0.
                let upper = (0..n).filter(|&i2| map.centre(0, i2).1.sin() > 0.0).count() * n;
                assert_eq!(upper, n * n / 2);
                for comp in c {
                    assert_eq!(comp.cells, upper);
                    assert!((comp.fraction - 0.5).abs() < 1e-15);
                }
                assert!((map.defined_fraction() - 1.0).abs() < 1e-15);
                assert_ne!(c[0].signs.branch, c[1].signs.branch);
            }
        }
    }

    /// The grid's cell count, labels and component records agree, and every component has one
    /// sign pattern, equal to the pointwise signs of each of its cells.
    #[test]
    fn labels_are_consistent() {
        let map = DomainMap::new(&robot(0.3, 0.3), Transform::Eq14, 128).unwrap();
        let n = map.grid();
        let mut counts = vec![0; map.components().len()];
        for i2 in 0..n {
            for i1 in 0..n {
                match (map.status(i1, i2), map.component(i1, i2)) {
                    (CellStatus::Defined(s), Some(c)) => {
                        counts[c] += 1;
                        assert_eq!(s, map.components()[c].signs);
                        // A neighbour in the same component has the same signs: no cut inside.
                        if map.component(i1 + 1, i2) == Some(c) {
                            assert_eq!(map.status(i1 + 1, i2), CellStatus::Defined(s));
                        }
                    }
                    (CellStatus::Undefined(_), None) => {}
                    other => panic!("inconsistent cell ({i1}, {i2}): {other:?}"),
                }
            }
        }
        let listed: Vec<usize> = map.components().iter().map(|c| c.cells).collect();
        assert_eq!(counts, listed);
        assert!(listed.windows(2).all(|w| w[0] >= w[1]), "not sorted: {listed:?}");
    }

    /// Off-centre mounting points split the torus into more pieces (Figs. 13-14), and the pieces
    /// still cover the torus: the conditions fail only on curves.
    #[test]
    fn off_centre_mounts_have_more_components() {
        for a in [0.1, 0.2, 0.3] {
            let coarse = DomainMap::new(&robot(a, a), Transform::Eq14, 360).unwrap();
            let fine = DomainMap::new(&robot(a, a), Transform::Eq14, 720).unwrap();
            assert!(coarse.resolved_count() > 2, "a = b = {a}: {} components", coarse.resolved_count());
            // The resolved count has converged; the slivers' area shrinks with the cells.
            assert_eq!(coarse.resolved_count(), fine.resolved_count());
            let slivers =
                |m: &DomainMap| m.components().iter().filter(|c| !c.resolved).map(|c| c.fraction).sum::<f64>();
            assert!(slivers(&fine) < 1e-4 && slivers(&fine) <= slivers(&coarse));
            assert!((coarse.defined_fraction() - 1.0).abs() < 1e-12);
        }
    }

    /// The paper's q0 and qd lie in one component of the domain of Eq. (14) for a = b = 0.1,
    /// 0.2, 0.3, where the paper's NFA succeeds (Figs. 6-8), and of Eqs. (11)-(12) at a = b = 0.
    #[test]
    fn paper_start_and_goal_are_connected() {
        let (q0, qd, _) = paper_problem();
        for (a, transform) in
            [(0.0, Transform::Eq12), (0.1, Transform::Eq14), (0.2, Transform::Eq14), (0.3, Transform::Eq14)]
        {
            let map = DomainMap::new(&robot(a, a), transform, 720).unwrap();
            let s = map.summary(&q0, &qd);
            assert!(s.start_goal_connected, "a = b = {a}: {s:?}");
            assert!(s.start_component_fraction > 0.0 && s.start_component_fraction <= 1.0);
        }
    }

    /// Component labelling on the torus: a band that leaves the grid on one side and comes back
    /// on the other is one component; the same band without wrap-around would be several.
    #[test]
    fn wrapping_bands_are_one_component() {
        let n = 12;
        // A diagonal band two cells wide: (i, i) and (i + 1, i), wrapping on both axes.
        let mut keys = vec![0u8; n * n];
        for i in 0..n {
            keys[i * n + i] = 1;
            keys[i * n + (i + 1) % n] = 1;
        }
        let (labels, comps) = label_components(n, &keys);
        assert_eq!(comps, vec![(2 * n, 0)]);
        assert_eq!(labels.iter().filter(|&&l| l == 0).count(), 2 * n);
        // A horizontal band across the seam theta2 = 0 (rows n-1 and 0), a vertical one across
        // theta1 = 0, and a separate blob with another key.
        let mut keys = vec![0u8; n * n];
        for i in 0..n {
            keys[i] = 1;
            keys[(n - 1) * n + i] = 1;
        }
        for i2 in 3..6 {
            keys[i2 * n] = 2;
            keys[i2 * n + n - 1] = 2;
        }
        keys[8 * n + 5] = 3;
        let (labels, comps) = label_components(n, &keys);
        assert_eq!(comps.iter().map(|c| c.0).collect::<Vec<_>>(), vec![2 * n, 6, 1]);
        assert_eq!(labels[0], labels[(n - 1) * n + 3]);
        assert_eq!(labels[3 * n], labels[5 * n + n - 1]);
        assert_eq!(labels[8 * n + 4], NONE);
        // Equal keys that only touch diagonally are not connected.
        let mut keys = vec![0u8; n * n];
        keys[0] = 1;
        keys[n + 1] = 1;
        assert_eq!(label_components(n, &keys).1.len(), 2);
    }

    /// The table-driven map evaluates the same functions as `shape` at the centres.
    #[test]
    fn samples_match_shape() {
        let r = robot(0.2, -0.1);
        let map = DomainMap::new(&r, Transform::Eq14, 37).unwrap();
        let k = r.lumped();
        for (i1, i2) in [(0, 0), (5, 30), (36, 36), (18, 2)] {
            let (t1, t2) = map.centre(i1, i2);
            let s = shape(&k, t1, t2);
            let idx = i2 * 37 + i1;
            assert!((map.curves()[0].values[idx] - s.sigma).abs() < 1e-13);
            assert!((map.curves()[1].values[idx] - s.P).abs() < 1e-13);
            assert_eq!(map.cell_of(t1, t2), (i1, i2));
            assert_eq!(map.cell_of(t1 - 4.0 * std::f64::consts::PI, t2 + std::f64::consts::TAU), (i1, i2));
        }
    }

    /// A point just across a zero curve from its cell's centre is put in the component on its
    /// own side; a point on no side (on sin theta2 = 0) is outside.
    #[test]
    fn component_at_respects_sides() {
        let map = DomainMap::new(&robot(0.0, 0.0), Transform::Eq12, 8).unwrap();
        let above = map.component_at(&Configuration::new(0.0, 1.0, 1e-9)).unwrap();
        let below = map.component_at(&Configuration::new(0.0, 1.0, -1e-9)).unwrap();
        assert_ne!(above, below);
        assert_eq!(map.components()[above].signs.branch, 1);
        assert_eq!(map.component_at(&Configuration::new(0.0, 1.0, 0.0)), None);
        // Cell centres at (k + 1/2) 45 deg: theta2 = 1 deg is in cell 0, whose centre is above.
        assert_eq!(map.component_at(&Configuration::new(0.0, 1.0, 1f64.to_radians())), Some(above));
    }

    #[test]
    fn bad_inputs_are_errors() {
        assert!(matches!(
            DomainMap::new(&RobotParams::src(), Transform::Eq14, 2),
            Err(Error::Input(InputError::InvalidParameter { .. }))
        ));
        assert!(matches!(
            DomainMap::new(&robot(0.1, 0.0), Transform::Eq11, 16),
            Err(Error::TransformUnavailable { .. })
        ));
    }

    /// Classes: at a = b = 0 the rows next to theta2 = 0 and pi are crossings, all others
    /// defined with the branch sign(s2).
    #[test]
    fn classes_mark_crossings() {
        let n = 8;
        let map = DomainMap::new(&robot(0.0, 0.0), Transform::Eq11, n).unwrap();
        for i2 in 0..n {
            let expected = if [0, n / 2 - 1, n / 2, n - 1].contains(&i2) {
                CellClass::Crossing(Singularity::SinTheta2)
            } else {
                CellClass::Defined { branch: if i2 < n / 2 { 1 } else { -1 } }
            };
            assert_eq!(map.class(3, i2), expected, "row {i2}");
        }
    }

    /// The global normal form's domain `{sigma != 0}` has two components, each about half the
    /// torus, for every mounting point tested (up to |a|, |b| = 1), and the paper's q0 and qd
    /// share one (beyond the paper: where Eq. (14) leaves q0 and qd apart, e.g. a = 1, b = -1).
    #[test]
    fn global_domain_is_two_halves() {
        let (q0, qd, _) = crate::model::paper_problem();
        for (a, b) in
            [(0.0, 0.0), (0.1, 0.1), (0.3, 0.3), (1.0, -1.0), (0.5, 0.5), (-1.0, 1.0), (0.7, 0.0), (0.0, -1.0)]
        {
            let map = DomainMap::new(&robot(a, b), Transform::Global, 256).unwrap();
            let summary = map.summary(&q0, &qd);
            assert_eq!(summary.components, 2, "({a}, {b})");
            for f in &summary.component_fractions {
                assert!((f - 0.5).abs() < 0.05, "({a}, {b}): {f}");
            }
            assert!(summary.start_goal_connected, "({a}, {b})");
        }
    }
}
