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

mod components;
mod summary;
#[cfg(test)]
mod tests;

use components::{label_components, trig_table};
pub use summary::DomainSummary;

/// Largest grid size accepted: `N^2` cells must fit in memory comfortably (see also
/// [`BYTES_PER_CELL`]: the memory budget refuses grids above 6192).
pub const MAX_GRID: usize = 8192;

/// Memory of one cell of a map while it is built and summarised \[bytes\] (measured: 17.5 for
/// `domain`, 25.5 per map of a sweep; counted generously): a map of `N^2` cells needs
/// `N^2 * BYTES_PER_CELL`, within [`crate::plan::limits::MEMORY_LIMIT`] (`N <= 6192`).
pub const BYTES_PER_CELL: u128 = 28;

/// The memory of one `grid x grid` map within the budget ([`BYTES_PER_CELL`]), else
/// [`InputError::TooMuchMemory`] with the estimate.
pub fn check_map_memory(grid: usize) -> Result<(), Error> {
    let limit = crate::plan::limits::MEMORY_LIMIT;
    let largest = ((limit / BYTES_PER_CELL) as f64).sqrt().floor();
    crate::plan::limits::check_memory(
        &format!("a domain map of grid {grid} ({} cells)", grid as u128 * grid as u128),
        grid as u128 * grid as u128 * BYTES_PER_CELL,
        &format!("a grid of at most {largest}"),
    )
}

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

impl DomainMap {
    /// The domain of `transform` for `robot` on a `grid x grid` map of the torus.
    ///
    /// Errors: [`InputError::InvalidParameter`] for a grid outside `3..=`[`MAX_GRID`] or an invalid
    /// robot; [`InputError::TooMuchMemory`] for a map beyond the memory budget ([`check_map_memory`]); [`Error::TransformUnavailable`] for Eqs. (11)-(12) with `a, b != 0`.
    pub fn new(robot: &RobotParams, transform: Transform, grid: usize) -> Result<Self, Error> {
        robot.validate()?;
        if !(3..=MAX_GRID).contains(&grid) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "grid".into(),
                value: grid as f64,
                expected: "a grid size between 3 and 8192",
            }));
        }
        check_map_memory(grid)?;
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
}
