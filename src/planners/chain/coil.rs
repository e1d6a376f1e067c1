//! Coil seeds: where one loop beside the line cannot turn the base far enough, the seed leaves
//! the line for the place of a joint plane where the curvature turns the base fastest, winds
//! round it, and comes back (the two-joint planner's coil, in the plane `(theta_i, theta_j)` of
//! an `n`-joint arm with the other joints at the line's midpoint).
//!
//! By Green's theorem a closed loop in the plane turns the base by the curvature
//! `kappa_ij = -(da_j/dtheta_i - da_i/dtheta_j)` integrated over the area it encloses (with
//! multiplicity), so `turns` windings round a disc of signed curvature integral `A` add about
//! `turns A`.

use std::f64::consts::TAU;
use std::sync::{Arc, Mutex, PoisonError};

use rayon::prelude::*;

use super::connection::{Angles, Connection};
use super::seeds::{Line, Seed};
use crate::planners::optimal::seeds::ramped;

/// Points per angle of the curvature grid of a plane.
const GRID: usize = 32;

/// Largest number of turns of a coil seed.
pub const MAX_TURNS: usize = 64;

/// Where a coil in a joint plane turns the base fastest for one sign of rotation: the grid point
/// of largest signed curvature, and the disc about it whose curvature integral per radius is
/// largest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoilSite {
    /// Centre `(theta_i, theta_j)` \[rad\] (any copy modulo 2 pi, except a coordinate inside a
    /// position range, see `literal`).
    pub centre: [f64; 2],
    /// Which coordinates lie inside a joint's position range: taken literally, never moved by
    /// whole turns (a limited joint does not wrap).
    pub literal: [bool; 2],
    /// Radius \[rad\].
    pub radius: f64,
    /// The signed curvature integral over the disc, of the site's sign \[rad\] (positive).
    pub area: f64,
}

/// The coil sites of a planner's calls, by plane, whether inside the joints' position ranges
/// (and their bits), the largest radius and the angles of the other joints: found once per
/// planner (at two joints a site depends on the arm alone; on the paper's problem at
/// a = b = 0.1 its grids were 4 % of a plan's instructions). Shared by the planner's clones,
/// which keep its connection; a clone with other ranges or radius has other keys.
#[derive(Debug, Default, Clone)]
pub struct Sites {
    /// Each joint's position range \[rad\] (none: unlimited; an empty list: no joint limited).
    ranges: Vec<Option<[f64; 2]>>,
    found: Arc<Mutex<Vec<FoundSite>>>,
}

/// Every planner's sites compare equal (a cache of what its connection determines).
impl PartialEq for Sites {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// A plane `(i, j)`, the bits of its ranges where the sites are inside them, the bits of the
/// largest radius and of the other joints' angles.
type SiteKey = (usize, usize, Vec<u64>, Vec<u64>);

/// A plane's sites with their key.
type FoundSite = (SiteKey, [CoilSite; 2]);

/// Sites kept per planner before the list is emptied (keys of other joints' angles grow with
/// the problems planned at three joints or more).
const KEPT_SITES: usize = 256;

impl Sites {
    /// No sites yet, to be found inside the joints' position `ranges` \[rad\] (one per joint,
    /// none where a joint is unlimited).
    pub fn within(ranges: Vec<Option<[f64; 2]>>) -> Self {
        Self { ranges, found: Arc::default() }
    }

    /// The same sites found so far, to be found inside `ranges`.
    pub fn with_ranges(&self, ranges: Vec<Option<[f64; 2]>>) -> Self {
        Self { ranges, found: self.found.clone() }
    }

    /// Whether a coil `seed`, clipped into the position ranges of its plane's joints (as the
    /// solve clips every seed), still winds round its centre: the centre inside the ranges (a
    /// circle cut by a range's bound is flattened there but still closed round it; one centred
    /// beyond the bound is flattened onto it and winds round nothing). True for another seed.
    pub fn winds(&self, seed: Seed) -> bool {
        let Seed::Coil { i, j, centre, .. } = seed else { return true };
        [(i, centre[0]), (j, centre[1])]
            .iter()
            .all(|&(k, c)| self.ranges.get(k).copied().flatten().is_none_or(|[lo, hi]| (lo..=hi).contains(&c)))
    }

    /// The [`sites`] of the plane `(i, j)` through `base`, inside the ranges when `ranged` (else
    /// as if the joints were unlimited), computed once.
    pub fn get(
        &mut self,
        connection: &Connection,
        base: &[f64],
        i: usize,
        j: usize,
        max_radius: f64,
        ranged: bool,
    ) -> [CoilSite; 2] {
        let range = |k: usize| self.ranges.get(k).copied().flatten().filter(|_| ranged);
        let ranges = [range(i), range(j)];
        let others = base.iter().enumerate().filter(|(k, _)| *k != i && *k != j).map(|(_, v)| v.to_bits());
        let bounds =
            ranges.iter().map(|r| r.map_or([f64::NAN; 2], |r| r)).flat_map(|[lo, hi]| [lo.to_bits(), hi.to_bits()]);
        let key = (i, j, bounds.collect(), std::iter::once(max_radius.to_bits()).chain(others).collect());
        let found = |f: &Vec<FoundSite>| f.iter().find(|(k, _)| *k == key).map(|(_, s)| *s);
        if let Some(s) = found(&self.found.lock().unwrap_or_else(PoisonError::into_inner)) {
            return s;
        }
        let s = sites(connection, base, i, j, max_radius, ranges);
        let mut kept = self.found.lock().unwrap_or_else(PoisonError::into_inner);
        if found(&kept).is_none() {
            if kept.len() >= KEPT_SITES {
                kept.clear();
            }
            kept.push((key, s));
        }
        s
    }
}

/// The rotation of the base per counter-clockwise area of the `(theta_i, theta_j)` plane at
/// `theta` \[rad / rad^2\].
pub fn curvature(connection: &Connection, theta: &[f64], i: usize, j: usize) -> f64 {
    connection.curvature(theta, i, j)
}

/// The coil sites of the plane `(i, j)` through `base` (the other joints held there) for a
/// positive and a negative rotation, in that order. A coordinate with a position range
/// (`ranges`, of `theta_i` and `theta_j`) is searched inside it, literally, and the disc kept
/// inside it (a limited joint cannot wind past its range: on issue 20's oracle case 15 the
/// unlimited plane's site lies 0.16 rad beyond the range, its coil clipped by the solve never
/// winds, and the oracle's minimum winds inside the range): the centre is the grid point of
/// largest `sign kappa room^2` (the curvature times the largest disc about it inside the
/// ranges, of radius `room <= max_radius`), which without ranges is the point of largest
/// curvature.
pub fn sites(
    connection: &Connection,
    base: &[f64],
    i: usize,
    j: usize,
    max_radius: f64,
    ranges: [Option<[f64; 2]>; 2],
) -> [CoilSite; 2] {
    // The curvature at `(theta_i, theta_j)` with the other joints at `base`, of a fresh copy
    // of the angles (the angles of the segments before both joints are the base's at every
    // point, computed once per copy).
    let kappa_from = || {
        let (mut theta, mut fixed) = (base.to_vec(), Angles::default());
        connection.angles_from(&theta, 0, &mut fixed);
        move |ti: f64, tj: f64| {
            theta[i] = ti;
            theta[j] = tj;
            connection.angles_from(&theta, i.min(j), &mut fixed);
            connection.curvature_at(&fixed, i, j)
        }
    };
    // The grid's coordinate `a` of axis `c`: a turn, or the cell centres of the range.
    let axis = |c: usize, a: usize| match ranges[c] {
        Some([lo, hi]) => lo + (hi - lo).min(TAU) * (a as f64 + 0.5) / GRID as f64,
        None => TAU * a as f64 / GRID as f64,
    };
    // The largest disc about `centre` inside the ranges.
    let room = |centre: [f64; 2]| {
        (0..2).fold(max_radius, |r, c| match ranges[c] {
            Some([lo, hi]) => r.min(centre[c] - lo).min(hi - centre[c]),
            None => r,
        })
    };
    // The grid's rows hold `theta_i`: the angles of the segments before joint `j` are taken
    // once per row (bit for bit those of `kappa`). The rows are independent, computed in
    // parallel and gathered in their order (a planning call's coil sites are a fifth of its
    // time on issue 19's 3-link and 7-link benches, all on the search's thread).
    let rows: Vec<Vec<([f64; 2], f64)>> = (0..GRID)
        .into_par_iter()
        .map(|a| {
            let (mut row, mut angles) = (base.to_vec(), Angles::default());
            row[i] = axis(0, a);
            connection.angles_from(&row, 0, &mut angles);
            (0..GRID)
                .map(|b| {
                    row[j] = axis(1, b);
                    connection.angles_from(&row, j, &mut angles);
                    ([row[i], row[j]], connection.curvature_at(&angles, i, j))
                })
                .collect()
        })
        .collect();
    let grid: Vec<([f64; 2], f64)> = rows.into_iter().flatten().collect();
    let literal = ranges.map(|r| r.is_some());
    // Cumulative signed area over discs of growing radius (rings, midpoint rule), at the same
    // angles on every ring (their sines and cosines taken once).
    let (rings, angles) = (20, 24);
    let directions: Vec<(f64, f64)> = (0..angles).map(|m| (TAU * m as f64 / angles as f64).sin_cos()).collect();
    // The site of one sign: the two signs' rings are independent, computed in parallel.
    let site = |sign: f64| {
        let mut kappa = kappa_from();
        let (mut top, mut centre) = (f64::NEG_INFINITY, [0.0; 2]);
        for &(point, v) in &grid {
            let score = sign * v * room(point).powi(2);
            if score > top {
                (top, centre) = (score, point);
            }
        }
        let dr = room(centre) / rings as f64;
        let (mut area, mut chosen) = (0.0, (f64::NEG_INFINITY, dr, 0.0));
        for ring in 0..rings {
            let r = (ring as f64 + 0.5) * dr;
            let mean = directions.iter().map(|&(s, c)| sign * kappa(centre[0] + r * c, centre[1] + r * s)).sum::<f64>()
                / angles as f64;
            area += mean * TAU * r * dr;
            let outer = (ring + 1) as f64 * dr;
            if area / outer > chosen.0 {
                chosen = (area / outer, outer, area);
            }
        }
        CoilSite { centre, literal, radius: chosen.1, area: chosen.2 }
    };
    let (positive, negative) = rayon::join(|| site(1.0), || site(-1.0));
    [positive, negative]
}

/// Entry point in the plane, unit vector from the centre to it, and the three legs' lengths
/// (in, around, out) \[rad\] of a coil.
type Legs = ([f64; 2], [f64; 2], f64, f64, f64);

impl Line {
    /// The coil in the plane `(i, j)` that should add the rotation `needed` \[rad\] at `site`
    /// (of `needed`'s sign): the copy of its centre nearest the line's midpoint, as many turns as
    /// the site's disc needs, the radius shrunk toward the area needed.
    pub fn coil(&self, i: usize, j: usize, site: &CoilSite, needed: f64, max_radius: f64) -> Seed {
        let mid = self.midpoint();
        let centre = [(i, 0), (j, 1)].map(|(k, c)| {
            let v = site.centre[c];
            if site.literal[c] { v } else { v + TAU * ((mid[k] - v) / TAU).round() }
        });
        let (radius, area) = (site.radius, site.area);
        let turns = if area > 0.0 { ((needed.abs() / area).ceil() as usize).clamp(1, MAX_TURNS) } else { 1 };
        let radius = if area > 0.0 {
            (radius * (needed.abs() / (area * turns as f64)).sqrt()).clamp(0.05, max_radius)
        } else {
            radius
        };
        Seed::Coil { i, j, centre, radius, turns }
    }

    /// The line's point at half the horizon \[rad\].
    pub fn midpoint(&self) -> Vec<f64> {
        let mut mid = vec![0.0; self.start.len()];
        self.at(self.horizon / 2.0, &mut mid);
        mid
    }

    /// The coil's legs (see [`Legs`]); `None` for another seed.
    fn legs(&self, seed: Seed) -> Option<Legs> {
        let Seed::Coil { i, j, centre, radius, turns } = seed else { return None };
        let mid = self.midpoint();
        let d = [mid[i] - centre[0], mid[j] - centre[1]];
        let norm = d[0].hypot(d[1]);
        let u = if norm < 1e-9 { [1.0, 0.0] } else { [d[0] / norm, d[1] / norm] };
        let e = [centre[0] + radius * u[0], centre[1] + radius * u[1]];
        let entry = self.entry(&mid, i, j, e);
        let distance = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt();
        Some((e, u, distance(&self.start, &entry), TAU * radius * turns as f64, distance(&entry, &self.end)))
    }

    /// The midpoint with its `(i, j)` coordinates moved to `e`.
    fn entry(&self, mid: &[f64], i: usize, j: usize, e: [f64; 2]) -> Vec<f64> {
        let mut entry = mid.to_vec();
        (entry[i], entry[j]) = (e[0], e[1]);
        entry
    }

    /// The length of a coil's path \[rad\] (`None` for another seed).
    pub fn coil_length(&self, seed: Seed) -> Option<f64> {
        self.legs(seed).map(|(.., l1, l2, l3)| l1 + l2 + l3)
    }

    /// A coil's joint path at `t` \[s\] into `out`: straight from the start to the entry point,
    /// `turns` counter-clockwise windings at constant speed, straight to the end, the speed
    /// ramped at both ends; the initial velocity added as on the line. False for another seed.
    pub fn coil_path(&self, seed: Seed, t: f64, out: &mut [f64]) -> bool {
        self.coil_path_of(seed).is_some_and(|c| c.at(self, t, out))
    }

    /// What [`Self::coil_path`] computes once per coil (its legs, entry point), for many `t`
    /// (a projection evaluates the path at every quadrature node); `None` for another seed.
    pub fn coil_path_of(&self, seed: Seed) -> Option<CoilPath> {
        let (Seed::Coil { i, j, centre, radius, .. }, Some((e, u, l1, l2, l3))) = (seed, self.legs(seed)) else {
            return None;
        };
        let mid = self.midpoint();
        let entry = self.entry(&mid, i, j, e);
        Some(CoilPath { i, j, centre, radius, u, l1, l2, l3, entry })
    }
}

/// A coil's path with its legs computed ([`Line::coil_path_of`]).
#[derive(Debug, Clone)]
pub struct CoilPath {
    i: usize,
    j: usize,
    centre: [f64; 2],
    radius: f64,
    u: [f64; 2],
    l1: f64,
    l2: f64,
    l3: f64,
    entry: Vec<f64>,
}

impl CoilPath {
    /// [`Line::coil_path`] at `t` on `line` (the line it was made of); always true.
    pub fn at(&self, line: &Line, t: f64, out: &mut [f64]) -> bool {
        let CoilPath { i, j, centre, radius, u, l1, l2, l3, ref entry } = *self;
        let s = (l1 + l2 + l3) * ramped(t / line.horizon, 0.05);
        if s < l1 {
            let f = s / l1.max(1e-300);
            for (k, o) in out.iter_mut().enumerate() {
                *o = line.start[k] + (entry[k] - line.start[k]) * f;
            }
        } else if s < l1 + l2 {
            out.copy_from_slice(entry);
            let (sp, cp) = ((s - l1) / radius).sin_cos();
            out[i] = centre[0] + radius * (u[0] * cp - u[1] * sp);
            out[j] = centre[1] + radius * (u[0] * sp + u[1] * cp);
        } else {
            let f = ((s - l1 - l2) / l3.max(1e-300)).min(1.0);
            for (k, o) in out.iter_mut().enumerate() {
                *o = entry[k] + (line.end[k] - entry[k]) * f;
            }
        }
        let h = t * (1.0 - t / line.horizon).powi(2);
        for (o, u0) in out.iter_mut().zip(&line.initial_velocity) {
            *o += u0 * h;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RobotParams;
    use crate::model::arm::Arm;

    /// A coil's path starts and ends at the line's ends and winds `turns` times about its
    /// centre (the winding number of its middle leg, counted by the change of angle).
    #[test]
    fn a_coil_joins_the_ends_and_winds_its_turns() {
        let arm = Arm::from_params(&RobotParams::src());
        let connection = Connection::new(&arm);
        let line =
            Line { start: vec![0.3, -0.4], end: vec![1.2, 0.9], initial_velocity: vec![0.0, 0.0], horizon: 10.0 };
        let site = sites(&connection, &line.midpoint(), 0, 1, 2.0, [None; 2])[0];
        let seed = Seed::Coil { i: 0, j: 1, centre: site.centre, radius: 0.7, turns: 3 };
        let Seed::Coil { centre, .. } = line.coil(0, 1, &site, 3.0 * site.area, 2.0) else { panic!("a coil") };
        let mut p = [0.0; 2];
        assert!(line.coil_path(seed, 0.0, &mut p));
        assert!((p[0] - 0.3).abs() < 1e-12 && (p[1] + 0.4).abs() < 1e-12);
        line.coil_path(seed, 10.0, &mut p);
        assert!((p[0] - 1.2).abs() < 1e-12 && (p[1] - 0.9).abs() < 1e-12);
        let (mut total, mut last) = (0.0, None::<f64>);
        for k in 0..=20000 {
            line.coil_path(seed, 10.0 * k as f64 / 20000.0, &mut p);
            let r = (p[0] - site.centre[0]).hypot(p[1] - site.centre[1]);
            if (r - 0.7).abs() < 1e-9 {
                let angle = (p[1] - site.centre[1]).atan2(p[0] - site.centre[0]);
                if let Some(l) = last {
                    total += (angle - l + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI;
                }
                last = Some(angle);
            }
        }
        assert!((total / TAU - 3.0).abs() < 1e-3, "windings {}", total / TAU);
        // The coil's centre is the site's copy nearest the line's midpoint.
        let mid = line.midpoint();
        assert!(
            (centre[0] - mid[0]).abs() <= std::f64::consts::PI && (centre[1] - mid[1]).abs() <= std::f64::consts::PI
        );
    }

    /// Inside a position range of `theta_1` the sites' discs lie within it, and a coil keeps the
    /// site's centre there (not a copy a turn away) and stays inside the range all along.
    #[test]
    fn a_site_inside_a_range_keeps_its_coil_inside() {
        let arm = Arm::from_params(&RobotParams::src());
        let connection = Connection::new(&arm);
        let (lo, hi) = (0.2, 1.4);
        let line =
            Line { start: vec![0.3, -0.4], end: vec![1.2, 0.9], initial_velocity: vec![0.0, 0.0], horizon: 10.0 };
        for (sign, site) in
            [1.0, -1.0].into_iter().zip(sites(&connection, &line.midpoint(), 0, 1, 2.0, [Some([lo, hi]), None]))
        {
            assert_eq!(site.literal, [true, false]);
            assert!(
                site.centre[0] - site.radius >= lo - 1e-12 && site.centre[0] + site.radius <= hi + 1e-12,
                "{site:?}"
            );
            assert!(site.area > 0.0, "{site:?}");
            let seed = line.coil(0, 1, &site, sign * 3.0 * site.area, 2.0);
            let Seed::Coil { centre, turns, .. } = seed else { panic!("a coil") };
            assert!((centre[0] - site.centre[0]).abs() <= 1e-12 && turns >= 3, "{seed:?}");
            let mut p = [0.0; 2];
            for k in 0..=2000 {
                line.coil_path(seed, 10.0 * k as f64 / 2000.0, &mut p);
                assert!((lo - 1e-12..=hi + 1e-12).contains(&p[0]), "{p:?} at sample {k}");
            }
        }
    }

    /// A coil clipped into a range still winds round a centre inside it, not round one beyond
    /// it; without ranges every coil winds.
    #[test]
    fn a_coil_centred_beyond_a_range_does_not_wind() {
        let coil = |c: f64| Seed::Coil { i: 0, j: 1, centre: [c, 0.0], radius: 0.5, turns: 2 };
        let limited = Sites::within(vec![Some([0.0, 1.0]), None]);
        assert!(limited.winds(coil(0.9)) && !limited.winds(coil(1.1)) && !limited.winds(coil(-0.1)));
        assert!(Sites::within(Vec::new()).winds(coil(7.0)));
    }

    /// The site's disc integral is the curvature integrated over the disc: against a fine polar
    /// sum, and of the site's sign at its centre.
    #[test]
    fn a_site_holds_curvature_of_its_sign() {
        let arm = Arm::from_params(&RobotParams::src().with_mount(crate::model::Mount { a: 1.0, b: -1.0 }).unwrap());
        let connection = Connection::new(&arm);
        for (sign, site) in [1.0, -1.0].into_iter().zip(sites(&connection, &[0.0, 0.0], 0, 1, 2.0, [None; 2])) {
            assert!(sign * curvature(&connection, &site.centre, 0, 1) > 0.0);
            let (rings, angles) = (200, 240);
            let dr = site.radius / rings as f64;
            let mut sum = 0.0;
            for r in 0..rings {
                let rr = (r as f64 + 0.5) * dr;
                for m in 0..angles {
                    let (s, c) = (TAU * m as f64 / angles as f64).sin_cos();
                    let th = [site.centre[0] + rr * c, site.centre[1] + rr * s];
                    sum += sign * curvature(&connection, &th, 0, 1) * rr * dr * TAU / angles as f64;
                }
            }
            assert!(site.area > 0.0 && (sum - site.area).abs() <= 0.02 * sum.abs(), "{sum} vs {}", site.area);
        }
    }
}
