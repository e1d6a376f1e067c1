//! The control basis of the ECSA (Sec. 5, Figs. 9-12): a constant term and the first harmonics
//! of `w = 2 pi / T`, optionally multiplied by the window `sin^2(pi t / T)`.
//!
//! Each control is `u_i(t) = W(t) (c_i0 + sum_{k=1..H} (c_i,2k-1 sin(k w t) + c_i,2k cos(k w t)))`
//! with `W = 1` ([`Window::None`], the paper's choice) or `W = sin^2(pi t / T)`
//! ([`Window::SinSquared`]). The coefficient vector of both controls is
//! `c = (c_10, ..., c_1,2H, c_20, ..., c_2,2H)`, `2 (2H + 1)` numbers.

use crate::model::InputError;
use serde::Serialize;

use crate::Scalar;
use crate::error::Error;

/// The largest number of harmonics supported.
pub const MAX_HARMONICS: usize = 4;
/// The largest number of basis functions per control, `2 MAX_HARMONICS + 1`.
pub const MAX_TERMS: usize = 2 * MAX_HARMONICS + 1;

/// A window multiplying the trigonometric series.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Window {
    /// No window: the plain trigonometric series, as in the paper (Figs. 9-12). The controls,
    /// i.e. the joint velocities, do **not** vanish at `t = 0` and `t = T` (docs/spec.md §6, item 8):
    /// the robot starts and stops with a jump in velocity. Default.
    #[default]
    None,
    /// The series times `sin^2(pi t / T) = (1 - cos(w t)) / 2`: controls and their first
    /// derivatives vanish at both ends, so the plan starts and ends at rest like the NFA's.
    SinSquared,
}

impl Window {
    /// `none` or `sin2`.
    pub fn name(self) -> &'static str {
        match self {
            Window::None => "none",
            Window::SinSquared => "sin2",
        }
    }
}

/// The basis functions of one control on `[0, T]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis {
    /// Number of harmonics `H`, 1 to [`MAX_HARMONICS`].
    harmonics: usize,
    /// The horizon `T` \[s\].
    horizon: f64,
    /// The window.
    window: Window,
}

impl Basis {
    /// A basis of `harmonics` harmonics (1 to [`MAX_HARMONICS`]) on `[0, horizon]`.
    pub fn new(harmonics: usize, horizon: f64, window: Window) -> Result<Self, Error> {
        if !(1..=MAX_HARMONICS).contains(&harmonics) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "harmonics".into(),
                value: harmonics as f64,
                expected: "1 to 4 harmonics",
            }));
        }
        if !(horizon.is_finite() && horizon > 0.0) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "time".into(),
                value: horizon,
                expected: "a positive, finite horizon [s]",
            }));
        }
        Ok(Self { harmonics, horizon, window })
    }

    /// Number of harmonics `H`.
    pub fn harmonics(&self) -> usize {
        self.harmonics
    }

    /// The window.
    pub fn window(&self) -> Window {
        self.window
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        self.horizon
    }

    /// Basis functions per control, `2H + 1`.
    pub fn terms(&self) -> usize {
        2 * self.harmonics + 1
    }

    /// The basis functions at `t` \[s\]: `W(t) (1, sin(w t), cos(w t), ..., sin(H w t),
    /// cos(H w t))` in the first [`Self::terms`] entries (the rest zero). Generic, so that a
    /// dual `t` gives the time derivatives exactly.
    pub fn values<D: Scalar>(&self, t: D) -> [D; MAX_TERMS] {
        let w = std::f64::consts::TAU / self.horizon;
        let (s1, c1) = (t * w).sin_cos();
        let window = match self.window {
            Window::None => D::one(),
            Window::SinSquared => (D::one() - c1) * 0.5,
        };
        let mut out = [D::zero(); MAX_TERMS];
        out[0] = window;
        // sin(k w t), cos(k w t) by the angle-addition recurrence: one sin_cos per call.
        let (mut s, mut c) = (s1, c1);
        for k in 1..=self.harmonics {
            out[2 * k - 1] = s * window;
            out[2 * k] = c * window;
            (s, c) = (s * c1 + c * s1, c * c1 - s * s1);
        }
        out
    }

    /// The controls `[u1, u2]` \[rad/s\] at `t` for the coefficients `c` (length `2 (2H + 1)`).
    pub fn controls<D: Scalar>(&self, c: &[f64], t: D) -> [D; 2] {
        let phi = self.values(t);
        let m = self.terms();
        let mut u = [D::zero(); 2];
        for (i, ui) in u.iter_mut().enumerate() {
            for (j, p) in phi.iter().enumerate().take(m) {
                *ui += *p * c[i * m + j];
            }
        }
        u
    }

    /// `int_0^T` of each basis function \[s\]: what the coefficients contribute to the joint
    /// displacement `theta_i(T) - theta_i(0)`. Without window: `(T, 0, ..., 0)`; with
    /// `sin^2`: `T/2` for the constant, `-T/4` for `cos(w t)`, 0 for the rest.
    pub fn integrals(&self) -> [f64; MAX_TERMS] {
        let mut out = [0.0; MAX_TERMS];
        match self.window {
            Window::None => out[0] = self.horizon,
            Window::SinSquared => {
                out[0] = self.horizon / 2.0;
                out[2] = -self.horizon / 4.0;
            }
        }
        out
    }

    /// `int_0^t` of each basis function \[s\] at `t` \[s\], in closed form: the joint angles are
    /// `theta_i(t) = theta_i(0) + sum_j c_ij A_j(t)`. With `S_k(t) = (1 - cos(k w t)) / (k w)`,
    /// `C_k(t) = sin(k w t) / (k w)` (`S_0 = 0`, `C_0 = t`): without window `(C_0, S_1, C_1, ..)`;
    /// with `sin^2 = 1/2 - cos(w t)/2` the products `cos(w t) sin(k w t)`, `cos(w t) cos(k w t)`
    /// split into harmonics `k +- 1`, so `A = (C_0/2 - C_1/2, .., S_k/2 - (S_(k+1) + S_(k-1))/4,
    /// C_k/2 - (C_(k+1) + C_(k-1))/4, ..)`. At `t = T` these are [`Self::integrals`].
    pub fn antiderivatives(&self, t: f64) -> [f64; MAX_TERMS] {
        let w = std::f64::consts::TAU / self.horizon;
        let s = |k: usize| if k == 0 { 0.0 } else { (1.0 - (k as f64 * w * t).cos()) / (k as f64 * w) };
        let c = |k: usize| if k == 0 { t } else { (k as f64 * w * t).sin() / (k as f64 * w) };
        let mut out = [0.0; MAX_TERMS];
        match self.window {
            Window::None => {
                out[0] = c(0);
                for k in 1..=self.harmonics {
                    out[2 * k - 1] = s(k);
                    out[2 * k] = c(k);
                }
            }
            Window::SinSquared => {
                out[0] = 0.5 * (c(0) - c(1));
                for k in 1..=self.harmonics {
                    out[2 * k - 1] = 0.5 * s(k) - 0.25 * (s(k + 1) + s(k - 1));
                    out[2 * k] = 0.5 * c(k) - 0.25 * (c(k + 1) + c(k - 1));
                }
            }
        }
        out
    }

    /// The initial guess of the iteration: the constant terms that move each joint from
    /// `theta_i(0)` to `theta_i(T)` with all harmonics zero, i.e. `c_i0 = (theta_id -
    /// theta_i0) / int_0^T W`: a linear joint motion without window, `sin^2`-shaped with it.
    pub fn initial_guess(&self, joint_displacement: [f64; 2]) -> Vec<f64> {
        let m = self.terms();
        let mut c = vec![0.0; 2 * m];
        let integral = self.integrals()[0];
        c[0] = joint_displacement[0] / integral;
        c[m] = joint_displacement[1] / integral;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{Dual64, first_derivative};

    /// The recurrence gives `sin(k w t)`, `cos(k w t)` to 1e-14, the dual part is the time
    /// derivative (checked against the closed form), and the integrals match a fine midpoint
    /// rule to 1e-9 s.
    #[test]
    fn basis_values_derivatives_and_integrals() {
        for window in [Window::None, Window::SinSquared] {
            let basis = Basis::new(4, 7.0, window).unwrap();
            let w = std::f64::consts::TAU / 7.0;
            for t in [0.0, 0.3, 2.9, 6.99] {
                let v = basis.values(t);
                let win = if window == Window::None { 1.0 } else { (std::f64::consts::PI * t / 7.0).sin().powi(2) };
                for k in 1..=4 {
                    let kw = k as f64 * w;
                    assert!((v[2 * k - 1] - win * (kw * t).sin()).abs() < 1e-14);
                    assert!((v[2 * k] - win * (kw * t).cos()).abs() < 1e-14);
                }
                for j in 0..MAX_TERMS {
                    let (_, d) = first_derivative(|x: Dual64| basis.values(x)[j], t);
                    let h = 1e-6;
                    let fd = (basis.values(t + h)[j] - basis.values(t - h)[j]) / (2.0 * h);
                    assert!((d - fd).abs() < 1e-8, "{window:?} j = {j}: {d} vs {fd}");
                }
            }
            let n = 200_000;
            let dt = 7.0 / n as f64;
            let mut sums = [0.0; MAX_TERMS];
            for i in 0..n {
                let v = basis.values((i as f64 + 0.5) * dt);
                for j in 0..MAX_TERMS {
                    sums[j] += v[j] * dt;
                }
            }
            for (s, exact) in sums.iter().zip(basis.integrals()) {
                assert!((s - exact).abs() < 1e-9, "{window:?}: {s} vs {exact}");
            }
        }
    }

    /// The closed-form antiderivatives match a 64-node Gauss–Legendre rule to 1e-13 s at
    /// interior times, and equal [`Basis::integrals`] at `t = T`.
    #[test]
    fn antiderivatives_match_quadrature() {
        let rule = crate::numerics::quadrature::GaussLegendre::new(64);
        for window in [Window::None, Window::SinSquared] {
            let basis = Basis::new(4, 7.0, window).unwrap();
            for t in [0.0, 0.4, 3.1, 5.9, 7.0] {
                let a = basis.antiderivatives(t);
                for (j, aj) in a.iter().enumerate() {
                    let q = rule.integrate(0.0, t, |x| basis.values(x)[j]);
                    assert!((aj - q).abs() < 1e-13, "{window:?} t = {t} j = {j}: {aj} vs {q}");
                }
            }
            for (a, i) in basis.antiderivatives(7.0).iter().zip(basis.integrals()) {
                assert!((a - i).abs() < 1e-13, "{window:?}: {a} vs {i}");
            }
        }
    }

    #[test]
    fn windowed_controls_vanish_at_the_ends() {
        let basis = Basis::new(2, 10.0, Window::SinSquared).unwrap();
        let c: Vec<f64> = (0..10).map(|i| 0.1 * i as f64 - 0.3).collect();
        for t in [0.0, 10.0] {
            let u = basis.controls(&c, Dual64::new(t, 1.0));
            for ui in u {
                assert!(ui.re.abs() < 1e-14 && ui.eps.abs() < 1e-14, "{ui:?}");
            }
        }
    }

    #[test]
    fn harmonics_out_of_range_are_rejected() {
        for h in [0, 5] {
            assert!(matches!(
                Basis::new(h, 10.0, Window::None),
                Err(Error::Input(InputError::InvalidParameter { .. }))
            ));
        }
    }
}
