//! Warm starts for an `n`-joint arm: the straight joint line, and the line with a closed loop in
//! the plane of two joints, which turns the base by about `pi R^2 kappa_ij` (Green's theorem with
//! the curvature `kappa_ij = da_i/dtheta_j - da_j/dtheta_i` of the connection `a = G/F`).

use std::f64::consts::{PI, TAU};

use super::coil::{MAX_TURNS, Sites, curvature};
use super::connection::{Connection, Local};

/// Which seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Seed {
    /// The straight joint line, smooth-step timing.
    Line,
    /// The line with `turns` closed loops of radius `radius` \[rad\] in the `(theta_i, theta_j)`
    /// plane through the line's point, centred `radius` from it at the angle `direction` in the
    /// plane (0: along `theta_i`), counter-clockwise when `orientation = +1`.
    Loop {
        /// First joint of the plane (0-based).
        i: usize,
        /// Second joint of the plane (0-based).
        j: usize,
        /// The angle of the centre from the line's point in the plane \[rad\].
        direction: f64,
        /// `+1` counter-clockwise, `-1` clockwise.
        orientation: f64,
        /// Radius \[rad\].
        radius: f64,
        /// Turns.
        turns: usize,
    },
    /// A [coil](super::coil): in to a site of the `(theta_i, theta_j)` plane, `turns`
    /// counter-clockwise windings of radius `radius` about `centre`, out to the end.
    Coil {
        /// First joint of the plane (0-based).
        i: usize,
        /// Second joint of the plane (0-based).
        j: usize,
        /// Centre `(theta_i, theta_j)` \[rad\].
        centre: [f64; 2],
        /// Radius \[rad\].
        radius: f64,
        /// Turns.
        turns: usize,
    },
}

impl Seed {
    /// The same seed with radius `r` (a line unchanged).
    pub fn with_radius(self, r: f64) -> Self {
        match self {
            Seed::Loop { i, j, direction, orientation, turns, .. } => {
                Seed::Loop { i, j, direction, orientation, radius: r, turns }
            }
            Seed::Coil { i, j, centre, turns, .. } => Seed::Coil { i, j, centre, radius: r, turns },
            Seed::Line => Seed::Line,
        }
    }
}

/// Cubic smooth step `3 s^2 - 2 s^3` on `[0, 1]`.
fn smooth_step(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// The ends and timing shared by the seeds.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// `theta(0)` \[rad\].
    pub start: Vec<f64>,
    /// `theta(T)` \[rad\].
    pub end: Vec<f64>,
    /// `theta'(0)` \[rad/s\].
    pub initial_velocity: Vec<f64>,
    /// `T` \[s\].
    pub horizon: f64,
}

impl Line {
    /// The straight line at `t`, with the initial velocity added by `t (1 - t/T)^2`.
    pub fn at(&self, t: f64, out: &mut [f64]) {
        let s = smooth_step(t / self.horizon);
        let h = t * (1.0 - t / self.horizon).powi(2);
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.start[j] + (self.end[j] - self.start[j]) * s + self.initial_velocity[j] * h;
        }
    }

    /// The seed's joint path at `t`.
    pub fn path(&self, seed: Seed, t: f64, out: &mut [f64]) {
        if self.coil_path(seed, t, out) {
            return;
        }
        self.other_path(seed, t, out);
    }

    /// [`Self::path`] as a function of `t`, with what a coil's computes once per coil
    /// computed once (for the many `t` of a projection).
    pub fn path_of(&self, seed: Seed) -> impl Fn(f64, &mut [f64]) + '_ {
        let coil = self.coil_path_of(seed);
        move |t, out| match &coil {
            Some(c) => {
                c.at(self, t, out);
            }
            None => self.other_path(seed, t, out),
        }
    }

    /// [`Self::path`] of a seed that is not a coil.
    fn other_path(&self, seed: Seed, t: f64, out: &mut [f64]) {
        self.at(t, out);
        if let Seed::Loop { i, j, direction, orientation, radius, turns } = seed {
            let psi = TAU * turns as f64 * smooth_step(t / self.horizon);
            let (sp, cp) = psi.sin_cos();
            // The circle through the line's point with its centre `radius` along `a`.
            let (sa, ca) = direction.sin_cos();
            let (a, b) = ([ca, sa], [-sa, ca]);
            out[i] += radius * ((1.0 - cp) * a[0] - orientation * sp * b[0]);
            out[j] += radius * ((1.0 - cp) * a[1] - orientation * sp * b[1]);
        }
    }

    /// The holonomy integral `integral g dt` along the straight line from start to end (any
    /// timing gives the same) \[rad\], by a composite 16-point Gauss–Legendre rule.
    pub fn holonomy(&self, connection: &Connection) -> f64 {
        let rule = crate::numerics::quadrature::GaussLegendre::new(16);
        let delta: Vec<f64> = self.start.iter().zip(&self.end).map(|(a, b)| b - a).collect();
        let length = delta.iter().map(|d| d * d).sum::<f64>().sqrt();
        let pieces = ((length / 0.5).ceil() as usize).clamp(1, 64);
        let mut theta = vec![0.0; delta.len()];
        rule.integrate_composite(0.0, 1.0, pieces, |s| {
            for (k, th) in theta.iter_mut().enumerate() {
                *th = self.start[k] + s * delta[k];
            }
            connection.value(&theta, &delta)
        })
    }

    /// The length of the line \[rad\].
    pub fn length(&self) -> f64 {
        self.start.iter().zip(&self.end).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt()
    }

    /// The seeds beside the line that should add the base rotation `needed` \[rad\], in the
    /// `count` joint planes of largest `|kappa_ij|` at the line's midpoint (the two-joint
    /// planner's, in each plane): where one loop cannot add it (a [coil](super::coil) at the
    /// plane's site needs two turns or more), the coil alone; else a loop on either side of the
    /// line and one along `theta_i`, each radius from the curvature at its centre. A two-joint
    /// arm also tries the one-turn coil and the loop toward the normal with its radius from the
    /// curvature at the line's midpoint (the two-joint planner's centred loop): on 50 random
    /// mounts of the paper's problem they hold the least effort on 4 where the others miss it
    /// (by up to 2.2 times; `optimal::comparison`). Where that coil is centred beyond a joint's
    /// position range (`sites` knows the ranges), also the coil at the site inside the range
    /// ([`super::coil::sites`]).
    pub fn loops(
        &self,
        connection: &Connection,
        needed: f64,
        count: usize,
        max_radius: f64,
        sites: &mut Sites,
    ) -> Vec<Seed> {
        let n = self.start.len();
        if n < 2 {
            return Vec::new();
        }
        let mid = self.midpoint();
        let mut planes = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                planes.push((i, j, curvature(connection, &mid, i, j)));
            }
        }
        planes.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
        let mut out = Vec::new();
        for (i, j, kappa) in planes.into_iter().take(count) {
            if kappa.abs() <= 1e-12 {
                continue;
            }
            let kappa_at = |centre: [f64; 2]| {
                let mut theta = mid.clone();
                (theta[i], theta[j]) = (centre[0], centre[1]);
                curvature(connection, &theta, i, j)
            };
            // Along theta_i: pi R^2 |kappa| = |needed|, several turns above `max_radius`.
            let (mut axis, mut turns) = (Seed::Line, 1);
            let mut radius: f64 = 0.5;
            for _ in 0..3 {
                let kappa = kappa_at([mid[i] + radius, mid[j]]);
                let area = if kappa.abs() > 1e-12 { (needed / kappa).abs().max(0.01) } else { 0.25 };
                let orientation = if needed * kappa >= 0.0 { 1.0 } else { -1.0 };
                turns = ((area / (PI * max_radius * max_radius)).ceil() as usize).clamp(1, MAX_TURNS);
                radius = (area / (PI * turns as f64)).sqrt().clamp(0.05, max_radius);
                axis = Seed::Loop { i, j, direction: 0.0, orientation, radius, turns };
            }
            if n == 2 || turns >= 2 {
                let sign = usize::from(needed < 0.0);
                let site = sites.get(connection, &mid, i, j, max_radius, false)[sign];
                let coil = self.coil(i, j, &site, needed, max_radius);
                // Where the coil above (at the unlimited plane's site) is centred beyond a
                // position range, the solve clips it onto the range's bound, which it rides (as
                // the oracle's minima of issue 20's cases 11 and 19 do for half the horizon) but
                // never winds round anything; then also the coil at the site inside the range,
                // which winds there as case 15's minimum does, where the range holds curvature of
                // the rotation's sign (the site's disc integral is positive) enough for it in at
                // most `MAX_TURNS` turns (else the coil would leave the range: its radius grows
                // past the disc's).
                let ranged = sites.get(connection, &mid, i, j, max_radius, true)[sign];
                let fits = ranged.area > 0.0 && needed.abs() <= ranged.area * MAX_TURNS as f64;
                let inside = (!sites.winds(coil) && fits).then(|| self.coil(i, j, &ranged, needed, max_radius));
                if matches!(coil, Seed::Coil { turns, .. } if turns >= 2) {
                    out.push(coil);
                    out.extend(inside);
                    continue;
                }
                if n == 2 {
                    // One turn at the site beside the loops: on the 50 mounts of the reference
                    // comparison it holds the least effort where the loops on the line miss it.
                    out.push(coil);
                }
                out.extend(inside);
            }
            let d = [self.end[i] - self.start[i], self.end[j] - self.start[j]];
            let normal = if d[0].hypot(d[1]) < 1e-9 { [0.0, 1.0] } else { [-d[1], d[0]] };
            for side in [1.0, -1.0] {
                let (mut radius, mut orientation, mut turns): (f64, f64, usize) = (0.5, 1.0, 1);
                let direction = (side * normal[1]).atan2(side * normal[0]);
                for _ in 0..3 {
                    let (s, c) = direction.sin_cos();
                    let area = needed / kappa_at([mid[i] + radius * c, mid[j] + radius * s]);
                    orientation = if area >= 0.0 { 1.0 } else { -1.0 };
                    let wanted = if area.is_finite() && area != 0.0 { area.abs() / PI } else { 0.25 };
                    turns = ((wanted / (max_radius * max_radius)).ceil() as usize).clamp(1, 6);
                    radius = (wanted / turns as f64).sqrt().clamp(0.1, max_radius);
                }
                out.push(Seed::Loop { i, j, direction, orientation, radius, turns });
            }
            if n == 2 {
                // The two-joint planner's centred loop: toward the normal, its radius from the
                // curvature at the line's midpoint rather than at its centre.
                let area = needed / kappa_at([mid[i], mid[j]]);
                let orientation = if area >= 0.0 { 1.0 } else { -1.0 };
                let wanted = if area.is_finite() && area != 0.0 { area.abs() / PI } else { 0.25 };
                let turns = ((wanted / (max_radius * max_radius)).ceil() as usize).clamp(1, 6);
                let radius = (wanted / turns as f64).sqrt().clamp(0.1, max_radius);
                let direction = normal[1].atan2(normal[0]);
                let centred = Seed::Loop { i, j, direction, orientation, radius, turns };
                // Not where it is the loop toward the normal already (radii within 10 %).
                let same = |s: &Seed| match *s {
                    Seed::Loop { direction: d, orientation: o, radius: r, turns: t, .. } => {
                        (d - direction).abs() < 1e-12
                            && o * orientation > 0.0
                            && t == turns
                            && (r / radius - 1.0).abs() < 0.1
                    }
                    _ => false,
                };
                if !out.iter().any(same) {
                    out.push(centred);
                }
            }
            out.push(axis);
        }
        out
    }

    /// A rough effort of the seed run at constant speed, `1.2 (L + 2 pi R turns)^2 / T`, for
    /// ranking goal representatives.
    pub fn effort_estimate(&self, seed: Seed) -> f64 {
        let extra = match seed {
            Seed::Loop { radius, turns, .. } => TAU * radius * turns as f64,
            Seed::Line => 0.0,
            Seed::Coil { .. } => return 1.2 * self.coil_length(seed).unwrap_or(0.0).powi(2) / self.horizon,
        };
        1.2 * (self.length() + extra).powi(2) / self.horizon
    }

    /// The loop seed with its radius re-fitted (secant, at most 8 evaluations of `residual`)
    /// so that the holonomy residual vanishes; the best radius seen is kept.
    pub fn fit_radius(&self, seed: Seed, max_radius: f64, mut residual: impl FnMut(Seed) -> f64) -> Seed {
        let (Seed::Loop { radius, .. } | Seed::Coil { radius, .. }) = seed else { return seed };
        let (mut r0, mut r1) = (radius, (radius * 1.2).min(max_radius));
        if (r1 - r0).abs() < 1e-9 {
            r1 = 0.8 * r0;
        }
        let (mut c0, mut c1) = (residual(seed.with_radius(r0)), residual(seed.with_radius(r1)));
        let mut best = if c0.abs() < c1.abs() { (r0, c0) } else { (r1, c1) };
        for _ in 0..6 {
            if !(c1 - c0).is_finite() || (c1 - c0).abs() < 1e-300 || best.1.abs() < 1e-6 {
                break;
            }
            let r2 = (r1 - c1 * (r1 - r0) / (c1 - c0)).clamp(0.05_f64.min(max_radius), max_radius);
            let c2 = residual(seed.with_radius(r2));
            if c2.abs() < best.1.abs() {
                best = (r2, c2);
            }
            (r0, c0, r1, c1) = (r1, c1, r2, c2);
        }
        seed.with_radius(best.0)
    }
}

/// A bound (sampled, with a safety factor 1.5) of the curvature's comass over the joint space:
/// `1.5 max_k sqrt(sum_{i<j} kappa_ij(theta_k)^2)` over 64 points of a Kronecker sequence on
/// the torus; 0 for one joint (no curvature).
pub fn curvature_bound(connection: &Connection) -> f64 {
    let n = connection.joints();
    if n < 2 {
        return 0.0;
    }
    let mut local = Local::new(n);
    let zero = vec![0.0; n];
    let mut theta = vec![0.0; n];
    let mut peak: f64 = 0.0;
    for k in 1..=64 {
        for (i, t) in theta.iter_mut().enumerate() {
            // sqrt of the (i + 1)-th prime's fractional multiples: equidistributed on the torus.
            let alpha = [2.0f64, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0, 31.0, 37.0, 41.0, 43.0, 47.0]
                [i % 15]
                .sqrt();
            *t = TAU * (k as f64 * alpha).fract();
        }
        connection.local(&theta, &zero, &mut local);
        let mut sum = 0.0;
        for i in 0..n {
            for j in i + 1..n {
                let kappa = local.mixed[i * n + j] - local.mixed[j * n + i];
                sum += kappa * kappa;
            }
        }
        peak = peak.max(sum.sqrt());
    }
    1.5 * peak
}

/// A lower bound of the effort of any joint path between the line's ends whose holonomy differs
/// from the line's by `needed` \[rad\] (as the two-joint planner's, with the comass bound
/// `kappa_max`): closed by the line, the path bounds a surface on which the curvature integrates
/// to `needed`, of area at least `|needed| / kappa_max`, so by the isoperimetric inequality its
/// length is at least `sqrt(4 pi |needed| / kappa_max) - d` (`d` the line's length), and at least
/// `d`; by Cauchy–Schwarz the effort is at least `length^2 / T`.
pub fn effort_lower_bound(line: &Line, needed: f64, kappa_max: f64) -> f64 {
    let d = line.length();
    let loop_length = if kappa_max > 0.0 { (4.0 * PI * needed.abs() / kappa_max).sqrt() - d } else { 0.0 };
    let length = d.max(loop_length);
    length * length / line.horizon
}
