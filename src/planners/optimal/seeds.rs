//! Warm starts of the SQP: the straight joint line, loops superimposed on it (their enclosed
//! signed area sets the net base rotation) and the NFA's joint path.
//!
//! By Green's theorem and Eq. (25), a closed joint loop turns the base by
//! `Delta phi = -oint (G/F dtheta1 + H/F dtheta2) = iint 2 sigma / F^2 dtheta1 dtheta2`
//! (counter-clockwise loops count positive area), so a loop of radius `R` centred where the
//! curvature `kappa = 2 sigma / F^2` (Eq. 9) is roughly constant turns it by `pi R^2 kappa`.

use std::f64::consts::{PI, TAU};

use serde::Serialize;

use crate::model::Lumped;
use crate::model::system::shape;

/// Where a seed came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SeedKind {
    /// The straight joint line, smooth-step timing.
    Line,
    /// The line with one closed loop of radius `radius` \[rad\] centred `side` (+1 left, -1 right,
    /// 0 on the line's midpoint) of it, counter-clockwise when `orientation = +1`.
    Loop {
        /// Side of the line.
        side: i8,
        /// `+1` counter-clockwise, `-1` clockwise in the `(theta1, theta2)` plane.
        orientation: i8,
        /// Radius \[rad\].
        radius: f64,
        /// Number of turns around the loop.
        turns: usize,
    },
    /// A coil: from the start straight to a circle of radius `radius` \[rad\] around `centre`,
    /// `turns` times around it counter-clockwise, and straight on to the end, at one smooth-step
    /// timing of the whole length. Centred where the curvature has the sign of the rotation
    /// needed and is largest, it turns the base far where a loop on the line cannot.
    Coil {
        /// Centre `(theta1, theta2)` \[rad\].
        centre: [f64; 2],
        /// Radius \[rad\].
        radius: f64,
        /// Number of turns.
        turns: usize,
    },
    /// The line with `turns` closed loops of radius `radius` \[rad\] through the moving line
    /// point, centred `radius` along joint `axis` (0: `theta1`, 1: `theta2`) of it,
    /// counter-clockwise when `orientation = +1`: the n-joint planner's loop in the plane of two
    /// joints. It reaches basins the loops beside the line miss where the line is oblique.
    AxisLoop {
        /// The joint along which the centre lies (0 or 1).
        axis: u8,
        /// `+1` counter-clockwise, `-1` clockwise in the `(theta1, theta2)` plane.
        orientation: i8,
        /// Radius \[rad\].
        radius: f64,
        /// Number of turns around the loop.
        turns: usize,
    },
    /// The NFA's joint path.
    Nfa,
}

impl SeedKind {
    /// The same seed with another radius (loops and coils; others unchanged).
    pub fn with_radius(self, r: f64) -> Self {
        match self {
            SeedKind::Loop { side, orientation, turns, .. } => SeedKind::Loop { side, orientation, radius: r, turns },
            SeedKind::Coil { centre, turns, .. } => SeedKind::Coil { centre, radius: r, turns },
            SeedKind::AxisLoop { axis, orientation, turns, .. } => {
                SeedKind::AxisLoop { axis, orientation, radius: r, turns }
            }
            other => other,
        }
    }

    fn radius(self) -> Option<f64> {
        match self {
            SeedKind::Loop { radius, .. } | SeedKind::Coil { radius, .. } | SeedKind::AxisLoop { radius, .. } => {
                Some(radius)
            }
            _ => None,
        }
    }
}

/// Largest number of turns of a coil seed.
pub const MAX_TURNS: usize = 64;

/// The ends and timing shared by the seeds.
#[derive(Debug, Clone, Copy)]
pub struct Line {
    /// `theta(0)` \[rad\].
    pub start: [f64; 2],
    /// `theta(T)` \[rad\].
    pub end: [f64; 2],
    /// `theta'(0)` \[rad/s\].
    pub initial_velocity: [f64; 2],
    /// `T` \[s\].
    pub horizon: f64,
}

/// Cubic smooth step `3 s^2 - 2 s^3` on `[0, 1]` (zero slope at both ends).
fn smooth_step(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// From 0 to 1 on `[0, 1]` at constant speed but for ramps of duration `ramp` at both ends,
/// where the speed follows the smooth step: zero slope at both ends, nearly the least effort.
pub(crate) fn ramped(s: f64, ramp: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    // Speed v = 1 / (1 - ramp) between the ramps; a ramp covers v ramp / 2
    // (the integral of the smooth step, x^3 - x^4 / 2).
    let v = 1.0 / (1.0 - ramp);
    if s < ramp {
        let x = s / ramp;
        v * ramp * (x * x * x - 0.5 * x * x * x * x)
    } else if s > 1.0 - ramp {
        1.0 - ramped(1.0 - s, ramp)
    } else {
        v * (ramp / 2.0 + (s - ramp))
    }
}

impl Line {
    /// The straight line at `t` \[s\], with the initial velocity added by the Hermite function
    /// `t (1 - t/T)^2` (zero at both ends, slope 1 at 0, 0 at T).
    pub fn at(&self, t: f64) -> [f64; 2] {
        let s = smooth_step(t / self.horizon);
        let h = t * (1.0 - t / self.horizon).powi(2);
        std::array::from_fn(|j| self.start[j] + (self.end[j] - self.start[j]) * s + self.initial_velocity[j] * h)
    }

    /// Unit vector normal to the line (left of it), `(0, 1)` for a degenerate line.
    fn normal(&self) -> [f64; 2] {
        let d = [self.end[0] - self.start[0], self.end[1] - self.start[1]];
        let n = d[0].hypot(d[1]);
        if n < 1e-9 { [0.0, 1.0] } else { [-d[1] / n, d[0] / n] }
    }

    /// A loop seed that should turn the base by about `needed` \[rad\] more than the line:
    /// centred `side` of the line's midpoint (0: on it), radius from the curvature at the centre,
    /// clamped to `[0.1, max_radius]` rad; with `orientation = 0` the orientation follows the
    /// curvature's sign, else it is forced.
    pub fn loop_seed(&self, k: &Lumped, needed: f64, side: i8, orientation: i8, max_radius: f64) -> SeedKind {
        let mid = self.at(self.horizon / 2.0);
        let n = self.normal();
        let mut radius: f64 = 0.5;
        let mut orient = if orientation == 0 { 1 } else { orientation };
        let mut turns = 1;
        for _ in 0..3 {
            let c = [mid[0] + side as f64 * radius * n[0], mid[1] + side as f64 * radius * n[1]];
            let s = shape(k, c[0], c[1]);
            let kappa = 2.0 * s.sigma / (s.F * s.F);
            let area = needed / kappa;
            if orientation == 0 {
                orient = if area >= 0.0 { 1 } else { -1 };
            }
            let wanted = if area * orient as f64 > 0.0 { area.abs() / PI } else { 0.25 };
            turns = ((wanted / (max_radius * max_radius)).ceil() as usize).clamp(1, 6);
            radius = (wanted / turns as f64).sqrt().clamp(0.1, max_radius);
        }
        SeedKind::Loop { side, orientation: orient, radius, turns }
    }

    /// An [`SeedKind::AxisLoop`] along joint `axis` that should turn the base by about `needed`
    /// \[rad\] more than the line: the radius from the curvature at its centre,
    /// `pi R^2 |kappa| = |needed|` (several turns above `max_radius`), clamped to
    /// `[0.05, max_radius]`, the orientation from the signs.
    pub fn axis_loop_seed(&self, k: &Lumped, needed: f64, axis: u8, max_radius: f64) -> SeedKind {
        let mid = self.at(self.horizon / 2.0);
        let (mut radius, mut orientation, mut turns): (f64, i8, usize) = (0.5, 1, 1);
        for _ in 0..3 {
            let mut c = mid;
            c[usize::from(axis.min(1))] += radius;
            let s = shape(k, c[0], c[1]);
            let kappa = 2.0 * s.sigma / (s.F * s.F);
            let area = if kappa.abs() > 1e-12 { (needed / kappa).abs().max(0.01) } else { 0.25 };
            orientation = if needed * kappa >= 0.0 { 1 } else { -1 };
            turns = ((area / (PI * max_radius * max_radius)).ceil() as usize).clamp(1, MAX_TURNS);
            radius = (area / (PI * turns as f64)).sqrt().clamp(0.05, max_radius);
        }
        SeedKind::AxisLoop { axis, orientation, radius, turns }
    }

    /// The loop seed `kind` with its radius re-fitted (secant iteration, at most 8 evaluations of
    /// `residual`) so that the residual of the holonomy constraint vanishes; the radius stays in
    /// `[0.05, max_radius]` and the best one seen is returned.
    pub fn fit_radius(&self, kind: SeedKind, max_radius: f64, mut residual: impl FnMut(SeedKind) -> f64) -> SeedKind {
        let Some(radius) = kind.radius() else { return kind };
        let with = |r: f64| kind.with_radius(r);
        let (mut r0, mut r1) = (radius, (radius * 1.2).min(max_radius));
        if (r1 - r0).abs() < 1e-9 {
            r1 = 0.8 * r0;
        }
        let (mut c0, mut c1) = (residual(with(r0)), residual(with(r1)));
        let mut best = if c0.abs() < c1.abs() { (r0, c0) } else { (r1, c1) };
        for _ in 0..6 {
            if !(c1 - c0).is_finite() || (c1 - c0).abs() < 1e-300 || best.1.abs() < 1e-6 {
                break;
            }
            let r2 = (r1 - c1 * (r1 - r0) / (c1 - c0)).clamp(0.05, max_radius);
            let c2 = residual(with(r2));
            if c2.abs() < best.1.abs() {
                best = (r2, c2);
            }
            (r0, c0, r1, c1) = (r1, c1, r2, c2);
        }
        with(best.0)
    }

    /// A coil seed for the extra rotation `needed` \[rad\] about `site` (of the sign of
    /// `needed`, see [`coil_sites`]), centred at the site's copy nearest the line's midpoint, with
    /// as many turns as the area needs (at most [`MAX_TURNS`]) and the radius shrunk toward it.
    pub fn coil(&self, site: &CoilSite, needed: f64, max_radius: f64) -> SeedKind {
        let mid = self.at(self.horizon / 2.0);
        let centre: [f64; 2] = std::array::from_fn(|j| {
            let c = site.centre[j];
            c + TAU * ((mid[j] - c) / TAU).round()
        });
        let (radius, area) = (site.radius, site.area);
        let turns = if area > 0.0 { ((needed.abs() / area).ceil() as usize).clamp(1, MAX_TURNS) } else { 1 };
        // Shrink the radius toward the area needed (about quadratically in the radius).
        let radius = if area > 0.0 {
            (radius * (needed.abs() / (area * turns as f64)).sqrt()).clamp(0.05, max_radius)
        } else {
            radius
        };
        SeedKind::Coil { centre, radius, turns }
    }

    /// The effort `L^2 / T` of the seed's path run at constant speed, with its length `L`
    /// estimated as the line's length plus the loop's circumference times its turns.
    pub fn effort_estimate(&self, kind: SeedKind) -> f64 {
        let d = (self.end[0] - self.start[0]).hypot(self.end[1] - self.start[1]);
        let length = match kind {
            SeedKind::Loop { radius, turns, .. } | SeedKind::AxisLoop { radius, turns, .. } => {
                d + TAU * radius * turns as f64
            }
            SeedKind::Coil { .. } => self.coil_legs(kind).map_or(d, |(_, _, l1, l2, l3)| l1 + l2 + l3),
            _ => d,
        };
        length.powi(2) / self.horizon
    }

    /// The seed's joint path at `t` \[s\] (not for [`SeedKind::Nfa`], which is sampled instead).
    pub fn path(&self, kind: SeedKind, t: f64) -> [f64; 2] {
        if let Some((e, u, l1, l2, l3)) = self.coil_legs(kind) {
            let SeedKind::Coil { centre, radius, .. } = kind else { return self.at(t) };
            let h = t * (1.0 - t / self.horizon).powi(2);
            let s = (l1 + l2 + l3) * ramped(t / self.horizon, 0.05);
            let p: [f64; 2] = if s < l1 {
                std::array::from_fn(|j| self.start[j] + (e[j] - self.start[j]) * s / l1.max(1e-300))
            } else if s < l1 + l2 {
                let (sp, cp) = ((s - l1) / radius).sin_cos();
                let v = [u[0] * cp - u[1] * sp, u[0] * sp + u[1] * cp];
                std::array::from_fn(|j| centre[j] + radius * v[j])
            } else {
                std::array::from_fn(|j| e[j] + (self.end[j] - e[j]) * ((s - l1 - l2) / l3.max(1e-300)).min(1.0))
            };
            return std::array::from_fn(|j| p[j] + self.initial_velocity[j] * h);
        }
        let base = self.at(t);
        let (a, orientation, radius, turns) = match kind {
            SeedKind::Loop { side, orientation, radius, turns } => {
                let n = self.normal();
                // Centre `side` of the midpoint; on the line (side 0) the loop starts toward the normal.
                (if side == 0 { n } else { [side as f64 * n[0], side as f64 * n[1]] }, orientation, radius, turns)
            }
            SeedKind::AxisLoop { axis, orientation, radius, turns } => {
                (if axis == 0 { [1.0, 0.0] } else { [0.0, 1.0] }, orientation, radius, turns)
            }
            _ => return base,
        };
        let b = [-a[1], a[0]];
        let psi = TAU * turns as f64 * smooth_step(t / self.horizon);
        let (sp, cp) = psi.sin_cos();
        // Circle through the line point, centre at radius * a: counter-clockwise for +1.
        let o = orientation as f64;
        std::array::from_fn(|j| base[j] + radius * ((1.0 - cp) * a[j] - o * sp * b[j]))
    }
}

/// Entry point, unit vector from the centre to it, and the three legs' lengths of a coil.
type CoilLegs = ([f64; 2], [f64; 2], f64, f64, f64);

impl Line {
    /// A coil's entry point on its circle (nearest the line's midpoint), the unit vector from the
    /// centre to it, and the lengths of its three legs (in, around, out) \[rad\].
    fn coil_legs(&self, kind: SeedKind) -> Option<CoilLegs> {
        let SeedKind::Coil { centre, radius, turns } = kind else { return None };
        let mid = self.at(self.horizon / 2.0);
        let d = [mid[0] - centre[0], mid[1] - centre[1]];
        let norm = d[0].hypot(d[1]);
        let u = if norm < 1e-9 { [1.0, 0.0] } else { [d[0] / norm, d[1] / norm] };
        let e = [centre[0] + radius * u[0], centre[1] + radius * u[1]];
        let l1 = (e[0] - self.start[0]).hypot(e[1] - self.start[1]);
        let l3 = (self.end[0] - e[0]).hypot(self.end[1] - e[1]);
        Some((e, u, l1, TAU * radius * turns as f64, l3))
    }
}

/// Where a coil turns the base fastest for one sign of rotation: the grid point where
/// `sign kappa` is largest, the radius (at most the largest loop radius) of most rotation per
/// length of circle, and the rotation of one turn there \[rad\].
#[derive(Debug, Clone, Copy)]
pub struct CoilSite {
    /// Centre `(theta1, theta2)` \[rad\] (any copy modulo 2 pi).
    pub centre: [f64; 2],
    /// Radius \[rad\].
    pub radius: f64,
    /// `sign iint kappa` over the disc \[rad\].
    pub area: f64,
}

/// Points per angle of the curvature grid of [`curvature_grid`].
const GRID: usize = 32;

/// The curvature `kappa = 2 sigma / F^2` (Eqs. 9, 25) on the `32 x 32` grid
/// `(2 pi i / 32, 2 pi j / 32)`, row `i` first: the table of [`coil_sites_on`] and
/// [`curvature_bound_on`].
pub fn curvature_grid(k: &Lumped) -> Vec<f64> {
    let mut grid = Vec::with_capacity(GRID * GRID);
    for i in 0..GRID {
        for j in 0..GRID {
            let s = shape(k, TAU * i as f64 / GRID as f64, TAU * j as f64 / GRID as f64);
            grid.push(2.0 * s.sigma / (s.F * s.F));
        }
    }
    grid
}

/// The coil sites of positive and negative rotation (in that order).
pub fn coil_sites(k: &Lumped, max_radius: f64) -> [CoilSite; 2] {
    coil_sites_on(k, max_radius, &curvature_grid(k))
}

/// [`coil_sites`] from the [`curvature_grid`] `grid`.
pub fn coil_sites_on(k: &Lumped, max_radius: f64, grid: &[f64]) -> [CoilSite; 2] {
    [1.0, -1.0].map(|sign| {
        let kappa = |t1: f64, t2: f64| {
            let s = shape(k, t1, t2);
            sign * 2.0 * s.sigma / (s.F * s.F)
        };
        let mut best = (f64::NEG_INFINITY, [0.0; 2]);
        for i in 0..GRID {
            for j in 0..GRID {
                let v = sign * grid[i * GRID + j];
                if v > best.0 {
                    best = (v, [TAU * i as f64 / GRID as f64, TAU * j as f64 / GRID as f64]);
                }
            }
        }
        let centre = best.1;
        // Cumulative signed area over discs of growing radius (rings, midpoint rule).
        let (rings, angles) = (20, 24);
        let dr = max_radius / rings as f64;
        let (mut area, mut chosen) = (0.0, (f64::NEG_INFINITY, dr, 0.0));
        for i in 0..rings {
            let r = (i as f64 + 0.5) * dr;
            let mean = (0..angles)
                .map(|m| {
                    let (s, c) = (TAU * m as f64 / angles as f64).sin_cos();
                    kappa(centre[0] + r * c, centre[1] + r * s)
                })
                .sum::<f64>()
                / angles as f64;
            area += mean * TAU * r * dr;
            let outer = (i + 1) as f64 * dr;
            if area / outer > chosen.0 {
                chosen = (area / outer, outer, area);
            }
        }
        CoilSite { centre, radius: chosen.1, area: chosen.2 }
    })
}

/// Cubic Hermite interpolation of sampled `(t, theta, theta')`.
#[derive(Debug, Clone, PartialEq)]
pub struct Sampled {
    /// Equally spaced times \[s\].
    pub t: Vec<f64>,
    /// Joint angles \[rad\].
    pub theta: Vec<[f64; 2]>,
    /// Joint velocities \[rad/s\].
    pub rate: Vec<[f64; 2]>,
}

impl Sampled {
    /// The interpolated joint path at `t` \[s\].
    pub fn at(&self, t: f64) -> [f64; 2] {
        let n = self.t.len();
        let dt = self.t[n - 1] / (n - 1) as f64;
        let i = ((t / dt).floor().max(0.0) as usize).min(n - 2);
        let h = self.t[i + 1] - self.t[i];
        let s = ((t - self.t[i]) / h).clamp(0.0, 1.0);
        let (h00, h10, h01, h11) = (
            2.0 * s * s * s - 3.0 * s * s + 1.0,
            s * s * s - 2.0 * s * s + s,
            -2.0 * s * s * s + 3.0 * s * s,
            s * s * s - s * s,
        );
        std::array::from_fn(|j| {
            h00 * self.theta[i][j]
                + h10 * h * self.rate[i][j]
                + h01 * self.theta[i + 1][j]
                + h11 * h * self.rate[i + 1][j]
        })
    }
}

/// An upper bound of the curvature `|2 sigma / F^2|` (Eqs. 9, 25) over the torus: its largest
/// value on a 32 x 32 grid, times 1.5 (the function is a smooth ratio of low-order trigonometric
/// polynomials, so the grid misses its maximum by far less).
pub fn curvature_bound(k: &Lumped) -> f64 {
    curvature_bound_on(&curvature_grid(k))
}

/// [`curvature_bound`] from the [`curvature_grid`] `grid`.
pub fn curvature_bound_on(grid: &[f64]) -> f64 {
    1.5 * grid.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// A lower bound of the effort of any joint path between the line's ends whose holonomy differs
/// from the line's by `needed` \[rad\]: closed by the line, the path encloses (with multiplicity)
/// an area of at least `|needed| / kappa_max`, so by the Banchoff–Pohl isoperimetric inequality
/// its length is at least `L = sqrt(4 pi |needed| / kappa_max) - d` (`d` the line's length), and
/// at least `d`; by Cauchy–Schwarz the effort is at least `L^2 / T`.
pub fn effort_lower_bound(line: &Line, needed: f64, kappa_max: f64) -> f64 {
    let d = (line.end[0] - line.start[0]).hypot(line.end[1] - line.start[1]);
    let loop_length = (4.0 * PI * needed.abs() / kappa_max).sqrt() - d;
    let length = d.max(loop_length);
    length * length / line.horizon
}
