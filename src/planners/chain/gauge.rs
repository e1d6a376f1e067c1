//! A lower bound of a two-joint representative's effort from its holonomy requirement alone, in
//! a gauge where the connection is nearly constant (issue 19, speed: it drops representatives
//! before any solve where [`super::seeds::effort_lower_bound`] cannot).
//!
//! Along any joint path from `theta_0` to `theta_1` the base turns by `phi(0) - phi(T) =
//! integral a(theta) . theta' dt` (Eq. 7 with zero momentum, `a = G/F`). For any smooth periodic
//! `psi` and `a' = a - grad psi`, that integral is `H' + psi(theta_1) - psi(theta_0)` with
//! `H' = integral a' . theta' dt`, and for any constant vector `nu`, by Cauchy–Schwarz,
//! `|H' + nu . (theta_1 - theta_0)| = |integral (a' + nu) . theta' dt|
//! <= sqrt(T) max_theta |a' + nu| sqrt(effort)`, so
//! `effort >= (H' + nu . d)^2 / (T max_theta |a' + nu|^2)`. With `psi = 0` the bound is weak
//! (`a` itself varies as much as its mean); with `psi` the gradient part of `a`'s Helmholtz
//! decomposition on the torus (a Fourier solve of `laplacian psi = div a`), `a'` is the constant
//! mean plus the divergence-free part that carries the curvature, and the bound sees how little
//! rotation a path can pick up beyond the mean's. On the paper's problem at a = 1, b = -1,
//! `max |a| = 0.33` rad/rad and `max |a'| = 0.076`.
//!
//! The bound holds for every `psi` and `nu`: `psi` is the truncated series used consistently (its
//! value for `Delta psi`, its gradient for `a'`), `nu` found by a compass search. The maximum over
//! the torus is taken at a grid of samples plus a Lipschitz margin: the half-diagonal of a cell
//! times a bound of `|D a'|`: 1.5 times its sampled largest Frobenius norm (the safety factor of
//! [`super::seeds::curvature_bound`]).

use std::f64::consts::{PI, TAU};
use std::sync::{Arc, OnceLock};

use super::connection::{Connection, Local};

/// Fourier grid of the gauge's solve (per joint).
const FOURIER: usize = 32;

/// Sample grid of the maximum (per joint).
const SAMPLES: usize = 48;

/// A planner's gauge, made on its first use and shared by the planner's clones (it depends on
/// the connection alone, which the clones share): on the paper's problem at a = 1, b = -1 it
/// took 13 M of the plan's 300 M instructions (2304 samples of the connection), for every plan
/// of the criterion bench's kept planner.
#[derive(Clone, Default)]
pub(super) struct KeptGauge(Arc<OnceLock<Option<Gauge>>>);

/// Every planner's gauge compares equal (a cache of what the connection determines).
impl PartialEq for KeptGauge {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for KeptGauge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.get().is_some() { "KeptGauge(made)" } else { "KeptGauge(not made)" })
    }
}

impl KeptGauge {
    /// The gauge of `connection` (the planner's own), made on the first call.
    pub(super) fn get(&self, connection: &Connection) -> Option<&Gauge> {
        self.0.get_or_init(|| Gauge::new(connection)).as_ref()
    }
}

/// The gauge of a two-joint arm's connection and the samples of `a'` (see the module docs).
pub(super) struct Gauge {
    /// `Psi` at frequencies `(freq(p), freq(q))` at `p * FOURIER + q`, as `(re, im)` (zero at
    /// `(0, 0)` and the Nyquist frequency).
    coefficients: Vec<(f64, f64)>,
    /// The convex hull of the sampled `a'` (the maximum over `theta` of `|a' + nu|` is at one).
    hull: Vec<[f64; 2]>,
    /// Added to the sampled maximum of `|a' + nu|` for the points between the samples.
    margin: f64,
}

impl Gauge {
    /// The gauge of a two-joint arm's `connection`; `None` for other joint counts.
    pub(super) fn new(connection: &Connection) -> Option<Self> {
        if connection.joints() != 2 {
            return None;
        }
        let g = FOURIER;
        let mut local = Local::new(2);
        let zero = [0.0; 2];
        let twiddle: Vec<(f64, f64)> = (0..g).map(|k| (-TAU * k as f64 / g as f64).sin_cos()).collect();
        // Row transforms of both components: rows[i][q] = sum_j a(i, j) e^{-2 pi i q j / g}.
        let mut rows = vec![[(0.0, 0.0); 2]; g * g];
        for i in 0..g {
            let mut values = vec![[0.0; 2]; g];
            for (j, v) in values.iter_mut().enumerate() {
                connection.local(&[TAU * i as f64 / g as f64, TAU * j as f64 / g as f64], &zero, &mut local);
                *v = [local.a[0], local.a[1]];
            }
            for q in 0..g {
                let mut acc = [(0.0, 0.0); 2];
                for (j, v) in values.iter().enumerate() {
                    let (s, c) = twiddle[(q * j) % g];
                    for m in 0..2 {
                        acc[m].0 += v[m] * c;
                        acc[m].1 += v[m] * s;
                    }
                }
                rows[i * g + q] = acc;
            }
        }
        let mut coefficients = vec![(0.0, 0.0); g * g];
        for p in (0..g).filter(|&p| p != g / 2) {
            for q in (0..g).filter(|&q| q != g / 2 && (p, q) != (0, 0)) {
                let mut a = [(0.0, 0.0); 2];
                for i in 0..g {
                    let (s, c) = twiddle[(p * i) % g];
                    for (m, am) in a.iter_mut().enumerate() {
                        let (re, im) = rows[i * g + q][m];
                        am.0 += re * c - im * s;
                        am.1 += re * s + im * c;
                    }
                }
                // Psi = -i (p A1 + q A2) / (p^2 + q^2), normalised by the g^2 points.
                let k = [freq(p), freq(q)];
                let (re, im) = (k[0] * a[0].0 + k[1] * a[1].0, k[0] * a[0].1 + k[1] * a[1].1);
                let scale = (k[0] * k[0] + k[1] * k[1]) * (g * g) as f64;
                coefficients[p * g + q] = (im / scale, -re / scale);
            }
        }
        let mut gauge = Self { coefficients, hull: Vec::new(), margin: 0.0 };
        let (mut points, mut slope) = (Vec::with_capacity(SAMPLES * SAMPLES), 0.0_f64);
        let at = |i: usize| TAU * (i as f64 + 0.5) / SAMPLES as f64;
        let columns: Vec<Vec<(f64, f64)>> = (0..SAMPLES).map(|j| phases(at(j))).collect();
        for i in 0..SAMPLES {
            // Sums over p first: rows[q] = sum_p Psi_pq e^{i p theta_1}, and with the factor p.
            let (e1, mut rows) = (phases(at(i)), vec![[(0.0, 0.0); 3]; g]);
            for (p, &(c, s)) in e1.iter().enumerate() {
                for (q, row) in rows.iter_mut().enumerate() {
                    let (re, im) = gauge.coefficients[p * g + q];
                    let (er, ei) = (re * c - im * s, re * s + im * c);
                    for (m, r) in row.iter_mut().enumerate() {
                        let w = freq(p).powi(m as i32);
                        *r = (r.0 + w * er, r.1 + w * ei);
                    }
                }
            }
            for (j, e2) in columns.iter().enumerate() {
                connection.local(&[at(i), at(j)], &zero, &mut local);
                // grad psi = Re(i k Z) = -Im(k Z) and its Hessian -Re(k k^T Z), Z = Psi e^{i k . theta}.
                let (mut grad, mut hess) = ([0.0; 2], [0.0; 3]);
                for (q, &(c, s)) in e2.iter().enumerate() {
                    let [r0, r1, r2] = rows[q].map(|(re, im)| (re * c - im * s, re * s + im * c));
                    let k = freq(q);
                    grad[0] -= r1.1;
                    grad[1] -= k * r0.1;
                    hess[0] -= r2.0;
                    hess[1] -= k * r1.0;
                    hess[2] -= k * k * r0.0;
                }
                let m = &local.mixed;
                let da = [m[0] - hess[0], m[1] - hess[1], m[2] - hess[1], m[3] - hess[2]];
                slope = slope.max(da.iter().map(|v| v * v).sum::<f64>().sqrt());
                points.push([local.a[0] - grad[0], local.a[1] - grad[1]]);
            }
        }
        let half_diagonal = PI / SAMPLES as f64 * 2f64.sqrt();
        gauge.margin = 1.5 * slope * half_diagonal;
        gauge.hull = hull(points);
        Some(gauge)
    }

    /// `psi(theta) = Re sum Psi_k e^{i k . theta}`.
    fn psi(&self, theta: [f64; 2]) -> f64 {
        let (e1, e2) = (phases(theta[0]), phases(theta[1]));
        let mut value = 0.0;
        for (p, &(c1, s1)) in e1.iter().enumerate() {
            for (q, &(c2, s2)) in e2.iter().enumerate() {
                let (re, im) = self.coefficients[p * FOURIER + q];
                let (c, s) = (c1 * c2 - s1 * s2, s1 * c2 + c1 * s2);
                value += re * c - im * s;
            }
        }
        value
    }

    /// A lower bound of the effort \[rad^2/s\] of any joint path from `start` to `end` in
    /// `horizon` \[s\] along which `integral a . theta' dt = holonomy` \[rad\] (module docs): the
    /// search's best, or the first above `enough` (the caller asks whether it exceeds that; on
    /// the paper's problem at a = 1, b = -1, 49 of its 65 bounds do, most by 20 times: 13 M
    /// instructions a plan for all 40 steps of every search).
    pub(super) fn effort_bound(&self, start: &[f64], end: &[f64], holonomy: f64, horizon: f64, enough: f64) -> f64 {
        let h = holonomy - (self.psi([end[0], end[1]]) - self.psi([start[0], start[1]]));
        let d = [end[0] - start[0], end[1] - start[1]];
        let length = d[0].hypot(d[1]);
        let bound = |nu: [f64; 2]| {
            let top = self.hull.iter().map(|a| (a[0] + nu[0]).powi(2) + (a[1] + nu[1]).powi(2)).fold(0.0, f64::max);
            let num = h + nu[0] * d[0] + nu[1] * d[1];
            num * num / ((top.sqrt() + self.margin).powi(2) * horizon)
        };
        let count = self.hull.len().max(1) as f64;
        let centre = self.hull.iter().fold([0.0; 2], |c, a| [c[0] - a[0] / count, c[1] - a[1] / count]);
        let radius = self.hull.iter().map(|a| (a[0] + centre[0]).hypot(a[1] + centre[1])).fold(0.0, f64::max);
        let axes = if length > 1e-12 {
            [[d[0] / length, d[1] / length], [-d[1] / length, d[0] / length]]
        } else {
            [[1.0, 0.0], [0.0, 1.0]]
        };
        // A compass search from the hull's centre: any `nu` gives a valid bound.
        let (mut nu, mut best) = (centre, bound(centre));
        let mut step = radius + self.margin + 1e-3;
        for _ in 0..40 {
            if best > enough {
                break;
            }
            let moves =
                axes.iter().flat_map(|e| [1.0, -1.0].map(|s| [nu[0] + s * step * e[0], nu[1] + s * step * e[1]]));
            match moves.map(|m| (bound(m), m)).max_by(|a, b| a.0.total_cmp(&b.0)) {
                Some((value, m)) if value > best => (best, nu) = (value, m),
                _ => step *= 0.5,
            }
        }
        best
    }
}

/// The frequency of Fourier index `k` (`-FOURIER/2 <= freq < FOURIER/2`).
fn freq(k: usize) -> f64 {
    if k < FOURIER / 2 { k as f64 } else { k as f64 - FOURIER as f64 }
}

/// `(cos, sin)` of `freq(k) x` for every index `k`.
fn phases(x: f64) -> Vec<(f64, f64)> {
    (0..FOURIER).map(|k| (freq(k) * x).sin_cos()).map(|(s, c)| (c, s)).collect()
}

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise.
fn hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut out: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let floor = out.len();
        let ordered: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in ordered {
            while out.len() >= floor + 2 && cross(out[out.len() - 2], out[out.len() - 1], p) <= 0.0 {
                out.pop();
            }
            out.push(p);
        }
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::arm::Arm;
    use crate::model::geometry::tests::rng;
    use crate::{Mount, RobotParams};

    /// The bound holds for joint paths of every kind: on the paper's robot at four mounts, 50
    /// random paths each (a straight line of up to two turns per joint plus up to four harmonics
    /// of up to 1.5 rad, some of them winding loops), their effort and holonomy by a midpoint
    /// rule of 20000 steps (relative error about 1e-7, hence the 1e-4 allowance).
    #[test]
    fn the_bound_is_below_the_effort_of_random_paths() {
        let mut next = rng(0x6A06E);
        for (a, b) in [(1.0, -1.0), (0.1, 0.1), (0.0, -1.0), (-1.4, 1.2)] {
            let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
            let connection = Connection::new(&Arm::from_params(&robot));
            let gauge = Gauge::new(&connection).expect("two joints");
            let mut tightest: f64 = 0.0;
            for _ in 0..50 {
                let start = [TAU * next(), TAU * next()];
                let end = [start[0] + 4.0 * PI * (next() - 0.5), start[1] + 4.0 * PI * (next() - 0.5)];
                let harmonics: Vec<(f64, [f64; 2], f64)> =
                    (0..4).map(|k| ((k + 1) as f64, [3.0 * next() - 1.5, 3.0 * next() - 1.5], TAU * next())).collect();
                let horizon = 10.0;
                let path = |t: f64| {
                    let s = t / horizon;
                    let (mut theta, mut rate) = ([0.0; 2], [0.0; 2]);
                    for j in 0..2 {
                        theta[j] = start[j] + (end[j] - start[j]) * s;
                        rate[j] = (end[j] - start[j]) / horizon;
                    }
                    for &(k, amplitude, shift) in &harmonics {
                        // Zero at both ends: sin(pi k s) on the first joint, on the second a
                        // shifted sine less its line between the ends' values.
                        let w = PI * k / horizon;
                        theta[0] += amplitude[0] * (w * t).sin();
                        rate[0] += amplitude[0] * w * (w * t).cos();
                        theta[1] += amplitude[1] * (w * t + shift).sin()
                            - amplitude[1] * shift.sin() * (1.0 - s)
                            - amplitude[1] * (PI * k + shift).sin() * s;
                        rate[1] += amplitude[1] * w * (w * t + shift).cos() + amplitude[1] * shift.sin() / horizon
                            - amplitude[1] * (PI * k + shift).sin() / horizon;
                    }
                    (theta, rate)
                };
                let steps = 20000;
                let (mut effort, mut holonomy) = (0.0, 0.0);
                for i in 0..steps {
                    let (theta, rate) = path((i as f64 + 0.5) * horizon / steps as f64);
                    let dt = horizon / steps as f64;
                    effort += (rate[0] * rate[0] + rate[1] * rate[1]) * dt;
                    holonomy += connection.value(&theta, &rate) * dt;
                }
                let bound = gauge.effort_bound(&start, &end, holonomy, horizon, f64::INFINITY);
                assert!(bound <= effort * (1.0 + 1e-4), "({a}, {b}): bound {bound} above the effort {effort}");
                tightest = tightest.max(bound / effort);
            }
            eprintln!("({a}, {b}): largest bound / effort {tightest:.3}");
        }
    }

    /// A search stopped at `enough` answers the caller's question as the full search does: its
    /// bound is above `enough` exactly where the full one is, never above the full one, and the
    /// full one where that is at most `enough`.
    #[test]
    fn a_search_stopped_at_enough_says_whether_the_bound_exceeds_it() {
        let mut next = rng(0x5709);
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        let gauge = Gauge::new(&Connection::new(&Arm::from_params(&robot))).expect("two joints");
        let (mut above, mut below) = (0, 0);
        for _ in 0..200 {
            let start = [TAU * next(), TAU * next()];
            let end = [start[0] + 4.0 * PI * (next() - 0.5), start[1] + 4.0 * PI * (next() - 0.5)];
            let holonomy = 8.0 * (next() - 0.5);
            let full = gauge.effort_bound(&start, &end, holonomy, 10.0, f64::INFINITY);
            let enough = full * 2.0 * next();
            let stopped = gauge.effort_bound(&start, &end, holonomy, 10.0, enough);
            assert_eq!(stopped > enough, full > enough, "full {full}, stopped {stopped}, enough {enough}");
            assert!(stopped <= full, "stopped {stopped} above the full search's {full}");
            if full <= enough {
                assert_eq!(stopped.to_bits(), full.to_bits());
                below += 1;
            } else {
                above += 1;
            }
        }
        assert!(above > 20 && below > 20, "{above} above, {below} below");
    }

    /// The hull holds every point's distance from any `-nu`: its largest is the points' largest.
    #[test]
    fn the_hull_keeps_the_farthest_point_in_every_direction() {
        let mut next = rng(0x4011);
        let points: Vec<[f64; 2]> = (0..500).map(|_| [next() - 0.5, (next() - 0.5) * next()]).collect();
        let hull = hull(points.clone());
        assert!(hull.len() < points.len());
        for _ in 0..200 {
            let nu = [4.0 * next() - 2.0, 4.0 * next() - 2.0];
            let far = |set: &[[f64; 2]]| set.iter().map(|p| (p[0] + nu[0]).hypot(p[1] + nu[1])).fold(0.0, f64::max);
            assert_eq!(far(&hull).to_bits(), far(&points).to_bits());
        }
    }
}
