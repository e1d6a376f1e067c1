//! Beyond the paper: band steering of the chained form (10) inside the domain of the global
//! normal form (Sec. 6, item 3), with its options, its choice and the Chebyshev fit of the band.

use super::{ChainedPoint, PolynomialSteering};
use crate::Scalar;
use crate::error::Error;
use crate::model::Configuration;
use crate::numerics::chebyshev::Chebyshev;
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::nfa::normal_form::NormalForm;

/// Options of the [`BandSteering`] search.
#[derive(Debug, Clone, PartialEq)]
pub struct BandOptions {
    /// Margin `eps`: `lambda` is kept in `[eps, 1 - eps]`; default 0.05.
    pub margin: f64,
    /// Largest number of loops `N` tried; default 12.
    pub max_loops: usize,
    /// Loop amplitudes `A` tried \[rad\]; default 0.5, 1.0, .., 3.0.
    pub amplitudes: Vec<f64>,
}

impl Default for BandOptions {
    fn default() -> Self {
        Self { margin: 0.05, max_loops: 12, amplitudes: vec![0.5, 1.0, 1.5, 2.0, 2.5, 3.0] }
    }
}

/// The choice made by [`BandSteering::new`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BandChoice {
    /// Number of loops `N` of `z1`.
    pub loops: usize,
    /// Loop amplitude `A` \[rad\].
    pub amplitude: f64,
    /// Margin `eps` of `lambda`.
    pub margin: f64,
    /// The solved scalar `kappa` (amplitude of the `lambda` modulation).
    pub kappa: f64,
    /// Range of `lambda(t)` along the path.
    pub lambda_range: [f64; 2],
}

/// Beyond the paper: steering the chained form inside the band of the global normal form
/// (Sec. 6, item 3's domain of existence, made explicit), for mounting points where the
/// polynomial path of Sec. 5 leaves the band.
///
/// In band coordinates `z2 = L(z1) + lambda W(z1)`, where `(L, L + W)` is the range of `h3` over
/// the band `{sigma != 0}` at `theta1 = z1` (smooth functions of `z1`, fitted by a Chebyshev
/// series: any smooth `L, W` inside the band define an exact path), with `s(t)` the quintic
/// smoothstep (`s' = s'' = 0` at both ends):
/// `z1 = z01 + w1 s + A sin(2 pi N s)` (N loops of amplitude A),
/// `lambda = (1 - e(s)) (lambda0 + (lambdad - lambda0) s) + e(s) (1/2 + kappa cos(2 pi N s))`
/// with the flat-topped envelope `e(s) = 1 - (2s - 1)^8`,
/// `z3 = z03 + integral z2 dz1`. `z3(T) = zd3` is linear in `kappa`, which is solved exactly;
/// `(N, A)` is the cheapest pair (smallest `|w1| + 2 pi N A`, which bounds the peak `|v1|`) that
/// keeps `lambda` in `[eps, 1 - eps]`. The controls vanish at both ends.
#[derive(Debug, Clone, PartialEq)]
pub struct BandSteering {
    /// Horizon `T` \[s\].
    pub horizon: f64,
    /// Start `z0`.
    pub z0: [f64; 3],
    /// Goal `zd`.
    pub zd: [f64; 3],
    /// The choice of `(N, A, eps, kappa)`.
    pub choice: BandChoice,
    lower: Chebyshev,
    lower_integral: Chebyshev,
    width: Chebyshev,
    lambda: [f64; 2],
    rule: GaussLegendre,
    /// Cumulative `integral_0^t lambda W z1' dt` at `knots` equal steps.
    knots: Vec<f64>,
}

/// Number of quadrature intervals of `z3` of the final path, whose `kappa` and `lambda` range are
/// checked on this quadrature. 500 intervals give the `kappa` of 1000, 2000 and 4000 to round-off
/// (relative differences below 1e-14 at `a = 1, b = -1` and `a = b = 0.5`; 250 differ by 3e-12).
const Z3_KNOTS: usize = 500;

/// Number of quadrature intervals of `z3` on which the candidates are screened (each at most a
/// quarter of a loop, with at most 12 loops). The screening's `kappa` is within 1e-4 of the final
/// quadrature's (4.8e-5 relative at `a = 1, b = -1` with 9 loops, 1e-9 with one loop), which
/// moves `lambda` by far less than the band's margin (0.05). The chosen path is checked again on
/// [`Z3_KNOTS`], and the next candidate taken if it fails there.
const SCREEN_KNOTS: usize = 50;

impl BandSteering {
    /// The band-steered path from `z0` to `zd` in time `horizon`; `nf` must be the global normal
    /// form on the start's band and `start` the start configuration.
    pub fn new(
        nf: &NormalForm,
        start: &Configuration,
        z0: [f64; 3],
        zd: [f64; 3],
        horizon: f64,
        options: &BandOptions,
    ) -> Result<Self, Error> {
        let w1 = zd[0] - z0[0];
        let reach = options.amplitudes.iter().copied().fold(0.0, f64::max) + 0.1;
        let (lo, hi) = (z0[0].min(zd[0]) - reach, z0[0].max(zd[0]) + reach);
        let (lower, width) = fit_band(nf, start, lo, hi)?;
        let lower_integral = lower.integral();
        let lambda_of = |z: [f64; 3]| (z[1] - lower.eval(z[0])) / width.eval(z[0]);
        let lambda = [lambda_of(z0), lambda_of(zd)];
        let margin = band_margin(options, lambda);
        let fixed = lower_integral.eval(zd[0]) - lower_integral.eval(z0[0]);
        let rule = GaussLegendre::new(5);
        let template = Self {
            horizon,
            z0,
            zd,
            choice: BandChoice { loops: 0, amplitude: 0.0, margin, kappa: 0.0, lambda_range: [0.0; 2] },
            lower: lower.clone(),
            lower_integral: lower_integral.clone(),
            width: width.clone(),
            lambda,
            rule,
            knots: Vec::new(),
        };
        let w3 = zd[2] - z0[2] - fixed;
        // Candidates are screened on a coarse quadrature of z3; the chosen one's kappa comes from
        // the fine quadrature that the final path uses, and its lambda range is checked again at
        // that kappa: the accepted path is the path.
        let check = |mut path: Self, panels: usize| -> Option<Self> {
            if !w1.is_finite() || !path.tabulate_z3(w3, panels) {
                return None;
            }
            let range = path.lambda_range();
            path.choice.lambda_range = range;
            (range[0] >= margin && range[1] <= 1.0 - margin).then_some(path)
        };
        let try_candidate = |(loops, amplitude): (usize, f64)| -> Option<Self> {
            let mut path = template.clone();
            path.choice.loops = loops;
            path.choice.amplitude = amplitude;
            check(path, SCREEN_KNOTS)
        };
        // No loops if a single pass suffices; else, for each amplitude, the fewest loops that keep
        // lambda inside (binary search: the loops' area grows with N), and of those the pair with
        // the smallest estimated peak joint velocity.
        let mut feasible: Vec<Self> = try_candidate((0, 0.0)).into_iter().collect();
        if feasible.is_empty() {
            for &amplitude in &options.amplitudes {
                let (mut lo_n, mut hi_n) = (1, options.max_loops + 1);
                let mut found = None;
                while lo_n < hi_n {
                    let mid = (lo_n + hi_n) / 2;
                    match try_candidate((mid, amplitude)) {
                        Some(path) => {
                            found = Some(path);
                            hi_n = mid;
                        }
                        None => lo_n = mid + 1,
                    }
                }
                feasible.extend(found);
            }
        }
        let mut ranked: Vec<(f64, Self)> = feasible
            .into_iter()
            .map(|p| (p.peak_velocity_estimate(nf, start), p))
            .filter(|(peak, _)| peak.is_finite())
            .collect();
        ranked.sort_by(|x, y| x.0.total_cmp(&y.0));
        ranked
            .into_iter()
            .find_map(|(_, path)| check(path, Z3_KNOTS))
            .ok_or(Error::NoBandSteering { loops: options.max_loops, amplitude: reach - 0.1 })
    }

    /// The peak joint velocity `max(|u1|, |u2|)` over 33 times (the inverse map needs only
    /// `z1, z2`, not the quadrature of `z3`); infinite when the path cannot be inverted.
    fn peak_velocity_estimate(&self, nf: &NormalForm, start: &Configuration) -> f64 {
        let mut peak = 0.0f64;
        let mut theta2 = start.theta2;
        for i in 0..=32 {
            let t = self.horizon * i as f64 / 32.0;
            let s = smoothstep(num_dual::Dual64::new(t / self.horizon, 1.0 / self.horizon));
            let (z1, l0, l1) = self.path_terms(s);
            let z2 = self.lower.eval(z1) + (l0 + l1 * self.choice.kappa) * self.width.eval(z1);
            let band = nf.band(z1.re, theta2);
            match crate::planners::nfa::normal_form::global::solve_in_band(nf.lumped(), z1.re, z2.re, band, theta2) {
                Ok(x) => theta2 = x,
                Err(_) => return f64::INFINITY,
            }
            let u = nf.control([0.0, z1.re, theta2], [z1.eps, z2.eps]);
            peak = peak.max(u[0].abs()).max(u[1].abs());
        }
        peak
    }

    /// `(integral_a^b lambda W z1' dt at kappa = 0, its derivative in kappa)` over one panel
    /// `[a, b]`, with the Gauss–Legendre rule.
    fn area_panel(&self, a: f64, b: f64) -> [f64; 2] {
        let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
        let mut out = [0.0; 2];
        for (x, w) in self.rule.nodes.iter().zip(&self.rule.weights) {
            let t = mid + half * x;
            let s = smoothstep(num_dual::Dual64::new(t / self.horizon, 1.0 / self.horizon));
            let (z1, l0, l1) = self.path_terms(s);
            let wz = self.width.eval(z1.re) * z1.eps * w * half;
            out[0] += l0.re * wz;
            out[1] += l1.re * wz;
        }
        out
    }

    /// `lambda(t)`: where the path is across the band at `t` \[s\], 0 at its lower edge `L`, 1
    /// at its upper edge `L + W`.
    pub fn lambda_at(&self, t: f64) -> f64 {
        let s = smoothstep(t / self.horizon);
        self.lambda_parts(s, self.choice.kappa)
    }

    /// `[min lambda, max lambda]` over `[0, T]` at the path's `kappa`: a grid of
    /// `max(128, 32 (N + 1))` intervals (at least 32 per loop of `cos(2 pi N s)`) with every
    /// local extremum refined by golden-section search, so the range is the path's to
    /// `1e-12 T` in time, independent of any sampling of the plan.
    fn lambda_range(&self) -> [f64; 2] {
        use crate::numerics::extremum::{refined_max, uniform_times};
        let times = uniform_times(self.horizon, 128.max(32 * (self.choice.loops + 1)));
        let values: Vec<f64> = times.iter().map(|&t| self.lambda_at(t)).collect();
        let negated: Vec<f64> = values.iter().map(|v| -v).collect();
        let tolerance = 1e-12 * self.horizon;
        let infallible = |r: Result<(f64, f64), std::convert::Infallible>| match r {
            Ok(found) => found.1,
            Err(never) => match never {},
        };
        let max = infallible(refined_max(|t| Ok(self.lambda_at(t)), &times, &values, f64::INFINITY, tolerance));
        let min = -infallible(refined_max(|t| Ok(-self.lambda_at(t)), &times, &negated, f64::INFINITY, tolerance));
        [min, max]
    }

    /// `lambda(s) = (1 - e) (lambda0 + (lambdad - lambda0) s) + e/2 + kappa e cos(2 pi N s)` with
    /// the flat-topped envelope `e(s) = 1 - (2s - 1)^8`: `lambda` leaves the ends' values for the
    /// band's middle, where the loops have the whole width to swing in.
    fn lambda_parts<D: Scalar>(&self, s: D, kappa: f64) -> D {
        let (_, l0, l1) = self.path_terms(s);
        l0 + l1 * kappa
    }

    /// `z1(s) = z01 + w1 s + A sin(2 pi N s)`.
    fn z1_of<D: Scalar>(&self, s: D) -> D {
        self.path_terms(s).0
    }

    /// `(z1(s), lambda(s) at kappa = 0, d lambda / d kappa)`, from one `sin_cos`.
    fn path_terms<D: Scalar>(&self, s: D) -> (D, D, D) {
        let n = self.choice.loops as f64;
        let (sin, cos) = (s * (2.0 * std::f64::consts::PI * n)).sin_cos();
        let z1 = s * (self.zd[0] - self.z0[0]) + self.z0[0] + sin * self.choice.amplitude;
        let e = -(s * 2.0 - 1.0).powi(8) + 1.0;
        let straight = s * (self.lambda[1] - self.lambda[0]) + self.lambda[0];
        (z1, straight * (-e + 1.0) + e * 0.5, e * cos)
    }

    /// `lambda W(z1) z1'` at `t`, with the given `kappa`.
    fn area_rate(&self, t: f64, kappa: f64) -> f64 {
        let s = smoothstep(num_dual::Dual64::new(t / self.horizon, 1.0 / self.horizon));
        let (z1, l0, l1) = self.path_terms(s);
        (l0.re + l1.re * kappa) * self.width.eval(z1.re) * z1.eps
    }

    /// Tabulates `integral_0^t lambda W z1' dt` at `panels + 1` knots, solving on the way for the `kappa`
    /// that makes `z3(T) - z03 - (FL(zd1) - FL(z01)) = w3`; false when `kappa` does not move
    /// `z3(T)` (no such `kappa`).
    fn tabulate_z3(&mut self, w3: f64, panels: usize) -> bool {
        let h = self.horizon / panels as f64;
        let mut parts = Vec::with_capacity(panels + 1);
        let mut acc = [0.0; 2];
        parts.push(acc);
        for i in 0..panels {
            let p = self.area_panel(i as f64 * h, (i + 1) as f64 * h);
            acc = [acc[0] + p[0], acc[1] + p[1]];
            parts.push(acc);
        }
        if !(acc[1].abs() >= 1e-12) {
            return false;
        }
        let kappa = (w3 - acc[0]) / acc[1];
        self.choice.kappa = kappa;
        self.knots = parts.iter().map(|p| p[0] + kappa * p[1]).collect();
        kappa.is_finite()
    }

    /// The path at `t` \[s\] with exact first and second time derivatives: `z` carries `z'` and `v`
    /// carries `v'` in their dual parts.
    pub fn at_dual(&self, t: f64) -> ChainedPoint<num_dual::Dual64> {
        use num_dual::{Dual2, Dual64};
        let tau = Dual2::new(t / self.horizon, 1.0 / self.horizon, 0.0);
        let s = smoothstep(tau);
        let (z1, l0, l1) = self.path_terms(s);
        let lambda = l0 + l1 * self.choice.kappa;
        let z2 = self.lower.eval(z1) + lambda * self.width.eval(z1);
        let z3 = self.z3_at(t);
        ChainedPoint {
            z: [Dual64::new(z1.re, z1.v1), Dual64::new(z2.re, z2.v1), Dual64::new(z3, z2.re * z1.v1)],
            v: [Dual64::new(z1.v1, z1.v2), Dual64::new(z2.v1, z2.v2)],
        }
    }

    /// `((z1, z2), (v1, v2))` at `t` \[s\]: what the joint velocities need, without the
    /// quadrature of `z3`.
    pub fn joints(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        let s = smoothstep(num_dual::Dual64::new(t / self.horizon, 1.0 / self.horizon));
        let (z1, l0, l1) = self.path_terms(s);
        let z2 = self.lower.eval(z1) + (l0 + l1 * self.choice.kappa) * self.width.eval(z1);
        ([z1.re, z2.re], [z1.eps, z2.eps])
    }

    /// The path at `t` \[s\].
    pub fn at(&self, t: f64) -> ChainedPoint<f64> {
        let p = self.at_dual(t);
        ChainedPoint { z: [p.z[0].re, p.z[1].re, p.z[2].re], v: [p.v[0].re, p.v[1].re] }
    }

    /// `z3(t) = z03 + (FL(z1(t)) - FL(z01)) + integral_0^t lambda W z1' dt`.
    fn z3_at(&self, t: f64) -> f64 {
        let panels = self.knots.len() - 1;
        let h = self.horizon / panels as f64;
        let i = ((t / h).round().max(0.0) as usize).min(panels);
        let kappa = self.choice.kappa;
        let knot = i as f64 * h;
        let partial = if (t - knot).abs() <= 1e-13 * self.horizon {
            self.knots[i]
        } else {
            self.knots[i] + self.rule.integrate(knot, t, |s| self.area_rate(s, kappa))
        };
        let z1 = self.z1_of(smoothstep(t / self.horizon));
        self.z0[2] + self.lower_integral.eval(z1) - self.lower_integral.eval(self.z0[0]) + partial
    }
}

/// The margin `eps` kept by the band steering: [`BandOptions::margin`], less when an end is
/// nearer the band's edge (half its distance, so that the ends themselves are inside).
fn band_margin(options: &BandOptions, lambda: [f64; 2]) -> f64 {
    let edge = |l: f64| l.min(1.0 - l);
    options.margin.min(edge(lambda[0]) / 2.0).min(edge(lambda[1]) / 2.0)
}

/// Number of equal intervals of `[0, T]` on which [`keeps_to_band`] starts (then refined).
const BAND_CHECK_INTERVALS: usize = 1024;

/// Beyond the paper: whether the polynomial path of Sec. 5 keeps to the band of the global
/// normal form as the band steering would, with `lambda(t) = (z2 - L(z1)) / W(z1)` in
/// `[eps, 1 - eps]` and the same margin `eps` ([`BandSteering`]). Decided on the path itself,
/// not on the plan's samples: the band's edges exactly (zeros of sigma, tracked from the start),
/// `lambda` on a fixed grid of 1024 intervals, every local extremum refined
/// by golden-section search. Where sigma has no zero the band has no edge to keep from.
pub fn keeps_to_band(nf: &NormalForm, start: &Configuration, path: &PolynomialSteering, options: &BandOptions) -> bool {
    use crate::numerics::extremum::{refined_max, uniform_times};
    let horizon = path.horizon;
    let n = BAND_CHECK_INTERVALS;
    let h = horizon / n as f64;
    let times = uniform_times(horizon, n);
    // `(lambda, the band's centre)` at `t`, the band nearest `centre`; lambda `None` without edges.
    let lambda_at = |t: f64, centre: f64| -> (Option<f64>, f64) {
        let z = path.at(t).z;
        match nf.band_edges(z[0], centre) {
            Some((a, b)) => {
                let (ha, hb) = (nf.h([0.0, z[0], a])[1], nf.h([0.0, z[0], b])[1]);
                (Some((z[1] - ha.min(hb)) / (ha - hb).abs()), 0.5 * (a + b))
            }
            None => (None, centre),
        }
    };
    let mut centre = start.theta2;
    let mut lambdas = Vec::with_capacity(n + 1);
    let mut centres = Vec::with_capacity(n + 1);
    for &t in &times {
        let (lambda, c) = lambda_at(t, centre);
        centre = c;
        lambdas.push(lambda);
        centres.push(c);
    }
    let margin = match (lambdas[0], lambdas[n]) {
        (Some(l0), Some(ld)) => band_margin(options, [l0, ld]),
        _ => options.margin,
    };
    // How far lambda is outside [eps, 1 - eps] (negative inside), largest nearest an edge.
    let excess = |lambda: Option<f64>| lambda.map_or(-1.0, |l| (margin - l).max(l - (1.0 - margin)));
    let values: Vec<f64> = lambdas.iter().map(|&l| excess(l)).collect();
    if values.iter().any(|v| !v.is_finite()) {
        return false;
    }
    let refine = |t: f64| {
        let i = ((t / h).round().max(0.0) as usize).min(n);
        Ok::<_, std::convert::Infallible>(excess(lambda_at(t, centres[i]).0))
    };
    // Only maxima of the grid that the largest step between grid points could lift past the
    // grid's largest value are refined.
    let slack = values.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
    match refined_max(refine, &times, &values, 2.0 * slack, 1e-12 * horizon) {
        Ok((_, worst)) => worst <= 0.0,
        Err(never) => match never {},
    }
}

/// The quintic smoothstep `10 x^3 - 15 x^4 + 6 x^5`: 0 and 1 at the ends with zero first and
/// second derivatives.
fn smoothstep<D: Scalar>(x: D) -> D {
    x * x * x * (x * (x * 6.0 - 15.0) + 10.0)
}

/// Chebyshev fits of `L(theta1)` and `W(theta1)` over `[lo, hi]`, the band tracked continuously
/// from the start.
fn fit_band(nf: &NormalForm, start: &Configuration, lo: f64, hi: f64) -> Result<(Chebyshev, Chebyshev), Error> {
    // Walk theta1 from the start to both ends in small steps, following the band's centre.
    let step = 0.02;
    let mut walk: Vec<(f64, f64)> = Vec::new();
    for direction in [-1.0, 1.0] {
        let mut theta1 = start.theta1;
        let mut centre = start.theta2;
        loop {
            let (a, b) = nf.band(theta1, centre);
            centre = 0.5 * (a + b);
            walk.push((theta1, centre));
            if (direction < 0.0 && theta1 <= lo) || (direction > 0.0 && theta1 >= hi) {
                break;
            }
            theta1 += direction * step;
        }
    }
    walk.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = 64;
    let points = Chebyshev::points(lo, hi, n);
    let mut lower = Vec::with_capacity(n);
    let mut width = Vec::with_capacity(n);
    for &theta1 in &points {
        let i = walk.partition_point(|w| w.0 < theta1).min(walk.len() - 1);
        let (a, b) = nf.band(theta1, walk[i].1);
        let (ha, hb) = (nf.h([0.0, theta1, a])[1], nf.h([0.0, theta1, b])[1]);
        lower.push(ha.min(hb));
        width.push((ha - hb).abs());
    }
    if width.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(Error::NoBandSteering { loops: 0, amplitude: 0.0 });
    }
    Ok((Chebyshev::from_values(lo, hi, &lower), Chebyshev::from_values(lo, hi, &width)))
}
