//! An adaptive Dormand–Prince 5(4) integrator, generic over the scalar so that dual numbers
//! (forward sensitivities) can ride along the real part that controls the step size.
//!
//! Used to verify every plan: system (7), and the full dynamics, are integrated with the planned
//! controls and the final error is reported.
//!
//! ## Reference
//! J. R. Dormand, P. J. Prince, *A family of embedded Runge–Kutta formulae*, J. Comput. Appl.
//! Math. 6 (1980) 19–26, doi:10.1016/0771-050X(80)90013-3. Step-size control after Hairer,
//! Nørsett, Wanner, *Solving Ordinary Differential Equations I*, Sec. II.4.

use nalgebra::SVector;

use crate::Scalar;

/// The integrator could not continue.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("integration failed at t = {t}: {reason}")]
pub struct OdeError {
    /// Time reached \[s\].
    pub t: f64,
    /// Why.
    pub reason: &'static str,
}

/// Options of [`integrate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdeOptions {
    /// Relative tolerance per component; default 1e-12 (docs/spec.md §2).
    pub rtol: f64,
    /// Absolute tolerance per component; default 1e-12 (docs/spec.md §2).
    pub atol: f64,
    /// Largest number of steps (accepted + rejected) before giving up; default 1_000_000.
    pub max_steps: usize,
}

impl Default for OdeOptions {
    fn default() -> Self {
        Self { rtol: 1e-12, atol: 1e-12, max_steps: 1_000_000 }
    }
}

/// Work done by [`integrate`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct OdeStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Evaluations of the right-hand side.
    pub evaluations: usize,
}

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
/// Fifth-order weights minus the embedded fourth-order weights.
const E: [f64; 7] =
    [71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0];

/// Integrates `y' = f(t, y)` from `(t0, y0)` to `t1 > t0`, calling `observe(t, y)` after every
/// accepted step (and at `t0`). Returns `y(t1)` and the work done.
///
/// The step is chosen from the real parts only: dual parts of `y` are carried along exactly as
/// the derivative of the discrete solution.
pub fn integrate<S, const N: usize, E, F, O>(
    mut f: F,
    t0: f64,
    y0: SVector<S, N>,
    t1: f64,
    options: &OdeOptions,
    mut observe: O,
) -> Result<(SVector<S, N>, OdeStats), E>
where
    S: Scalar + nalgebra::Scalar,
    E: From<OdeError>,
    F: FnMut(f64, &SVector<S, N>) -> Result<SVector<S, N>, E>,
    O: FnMut(f64, &SVector<S, N>),
{
    if !(t1 > t0) || !t0.is_finite() || !t1.is_finite() {
        return Err(OdeError { t: t0, reason: "the interval must be finite with t1 > t0" }.into());
    }
    let mut stats = OdeStats::default();
    let mut t = t0;
    let mut y = y0;
    let mut k1 = f(t, &y)?;
    stats.evaluations += 1;
    observe(t, &y);
    let span = t1 - t0;
    let mut h = initial_step(&y, &k1, span, options);
    let mut previous_error = 1e-4_f64;
    let h_min = 1e-14 * span;
    loop {
        if stats.accepted + stats.rejected >= options.max_steps {
            return Err(OdeError { t, reason: "too many steps" }.into());
        }
        let last = t + h >= t1 - 1e-15 * span;
        if last {
            h = t1 - t;
        }
        let mut k: [SVector<S, N>; 7] = [k1; 7];
        for stage in 1..7 {
            let mut yi = y;
            for (j, kj) in k.iter().enumerate().take(stage) {
                if A[stage][j] != 0.0 {
                    yi += kj * S::from(h * A[stage][j]);
                }
            }
            k[stage] = f(t + C[stage] * h, &yi)?;
            stats.evaluations += 1;
        }
        // y_new from the fifth-order weights, which are the last row of A (FSAL).
        let mut y_new = y;
        for j in 0..6 {
            if A[6][j] != 0.0 {
                y_new += k[j] * S::from(h * A[6][j]);
            }
        }
        let mut err2 = 0.0;
        for i in 0..N {
            let mut e = 0.0;
            for j in 0..7 {
                e += E[j] * k[j][i].re();
            }
            let scale = options.atol + options.rtol * y[i].re().abs().max(y_new[i].re().abs());
            err2 += (h * e / scale).powi(2);
        }
        let err = (err2 / N as f64).sqrt();
        if !err.is_finite() {
            stats.rejected += 1;
            h *= 0.25;
            if h.abs() < h_min {
                return Err(OdeError { t, reason: "non-finite derivative" }.into());
            }
            continue;
        }
        if err <= 1.0 {
            stats.accepted += 1;
            t = if last { t1 } else { t + h };
            y = y_new;
            k1 = k[6];
            observe(t, &y);
            if last {
                return Ok((y, stats));
            }
            // PI step-size control (Hairer–Wanner, II.4, Eq. 4.13 with beta = 0.04).
            let factor = (0.9 * err.max(1e-10).powf(-0.7 / 5.0) * previous_error.powf(0.04)).clamp(0.2, 5.0);
            previous_error = err.max(1e-4);
            h *= factor;
        } else {
            stats.rejected += 1;
            h *= (0.9 * err.powf(-0.2)).max(0.2);
        }
        if h < h_min {
            return Err(OdeError { t, reason: "step size too small" }.into());
        }
    }
}

fn initial_step<S: Scalar + nalgebra::Scalar, const N: usize>(
    y: &SVector<S, N>,
    dy: &SVector<S, N>,
    span: f64,
    options: &OdeOptions,
) -> f64 {
    let mut d0 = 0.0;
    let mut d1 = 0.0;
    for i in 0..N {
        let scale = options.atol + options.rtol * y[i].re().abs();
        d0 += (y[i].re() / scale).powi(2);
        d1 += (dy[i].re() / scale).powi(2);
    }
    let (d0, d1) = ((d0 / N as f64).sqrt(), (d1 / N as f64).sqrt());
    let h = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h.min(span).max(1e-12 * span)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::Vector2;
    use num_dual::Dual64;

    /// The harmonic oscillator: `y(t) = (cos t, -sin t)` exactly.
    #[test]
    fn harmonic_oscillator_to_tolerance() {
        let (y, stats) = integrate(
            |_, y: &Vector2<f64>| Ok::<_, OdeError>(Vector2::new(y[1], -y[0])),
            0.0,
            Vector2::new(1.0, 0.0),
            10.0,
            &OdeOptions::default(),
            |_, _| {},
        )
        .unwrap();
        assert_relative_eq!(y[0], 10f64.cos(), epsilon = 1e-10);
        assert_relative_eq!(y[1], -10f64.sin(), epsilon = 1e-10);
        assert!(stats.accepted > 10);
    }

    /// Fifth order: halving a fixed step (tolerances loose, steps forced by max) is checked through
    /// the error's scaling with the tolerance: 1e-3 smaller tolerance => about 10^(3/5) more steps.
    #[test]
    fn step_count_scales_as_fifth_order() {
        let run = |tol: f64| {
            let o = OdeOptions { rtol: tol, atol: tol, ..Default::default() };
            integrate(
                |t, y: &Vector2<f64>| Ok::<_, OdeError>(Vector2::new(y[1], -y[0] * (1.0 + 0.1 * t.sin()))),
                0.0,
                Vector2::new(1.0, 0.0),
                20.0,
                &o,
                |_, _| {},
            )
            .unwrap()
            .1
            .accepted as f64
        };
        let ratio = run(1e-12) / run(1e-9);
        assert!(ratio > 3.0 && ratio < 5.0, "ratio {ratio}");
    }

    /// Non-autonomous, non-linear: `y' = t y^2`, `y(0) = 1` => `y = 2 / (2 - t^2)`.
    #[test]
    fn nonlinear_nonautonomous() {
        let (y, _) = integrate(
            |t, y: &SVector<f64, 1>| Ok::<_, OdeError>(SVector::<f64, 1>::new(t * y[0] * y[0])),
            0.0,
            SVector::<f64, 1>::new(1.0),
            1.2,
            &OdeOptions::default(),
            |_, _| {},
        )
        .unwrap();
        assert_relative_eq!(y[0], 2.0 / (2.0 - 1.44), max_relative = 1e-10);
    }

    /// A dual-number initial condition gives the exact sensitivity `dy(T)/dy0 = exp(-T)` for
    /// `y' = -y`.
    #[test]
    fn dual_numbers_carry_sensitivities() {
        let y0 = SVector::<Dual64, 1>::new(Dual64::new(2.0, 1.0));
        let (y, _) = integrate(
            |_, y: &SVector<Dual64, 1>| Ok::<_, OdeError>(-y),
            0.0,
            y0,
            3.0,
            &OdeOptions::default(),
            |_, _| {},
        )
        .unwrap();
        assert_relative_eq!(y[0].re, 2.0 * (-3f64).exp(), max_relative = 1e-10);
        assert_relative_eq!(y[0].eps, (-3f64).exp(), max_relative = 1e-10);
    }

    #[test]
    fn bad_interval_is_an_error() {
        let r = integrate(|_, y: &Vector2<f64>| Ok(*y), 1.0, Vector2::zeros(), 0.0, &OdeOptions::default(), |_, _| {});
        assert!(matches!(r, Err(OdeError { .. })));
    }
}
