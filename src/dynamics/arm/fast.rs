//! The arm's dynamics on slices, from its lumped constants held once ([`ArmDynamics`]): what the
//! hot loops call (the torque certificate's right-hand side, the plant's Runge–Kutta stages, the
//! controllers at every tick). No dual numbers and no heap allocation: stack arrays of the
//! largest size ([`SIZE`]), `n` sines and cosines and `O(n^2)` products per evaluation, plus a
//! Cholesky factorisation (`O(n^3)`) for the forward dynamics.

use nalgebra::DVector;

use super::{InverseDynamics, SingularInertia};
use crate::model::arm::Arm;
use crate::model::arm::lumped::{ArmLumped, LumpedTerms, SIZE, Square};

/// The capacity of the stack arrays for arms of fewer than `SMALL` joints (the paper's robot and
/// the 3-link example): cheaper to fill and copy than [`SIZE`].
const SMALL: usize = 4;

/// The dynamics of one arm: its lumped constants ([`ArmLumped`]), built once.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmDynamics {
    table: ArmLumped,
}

/// `M(theta)` and `c(theta, q')` of a model at one state, for the computed-torque law.
#[derive(Debug, Clone)]
pub struct ModelTerms {
    n1: usize,
    m: Square,
    c: [f64; SIZE],
}

impl ModelTerms {
    /// `M_ij` [kg m^2], `i, j` in `0..=n`.
    pub fn inertia(&self, i: usize, j: usize) -> f64 {
        self.m[i][j]
    }

    /// `c_i` [N m], `i` in `0..=n`.
    pub fn coriolis(&self, i: usize) -> f64 {
        self.c[i]
    }

    /// The acceleration `q'' = (phi'', a)` into `ddq` (`n + 1` values) when the joints
    /// accelerate by `a` (`n` values): the base takes `phi'' = -(G . a + c_0) / F`, the first row
    /// of `M q'' + c = (0, tau)`.
    pub fn accelerations(&self, a: &[f64], ddq: &mut [f64]) {
        let n = self.n1 - 1;
        let g: f64 = (1..=n).map(|j| self.m[0][j] * a[j - 1]).sum();
        ddq[0] = -(g + self.c[0]) / self.m[0][0];
        ddq[1..=n].copy_from_slice(&a[..n]);
    }

    /// `M ddq + c` [N m] into `out` (`n + 1` values).
    pub fn forces(&self, ddq: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate().take(self.n1) {
            *o = (0..self.n1).map(|j| self.m[i][j] * ddq[j]).sum::<f64>() + self.c[i];
        }
    }
}

impl ArmDynamics {
    /// The dynamics of `arm`.
    pub fn new(arm: &Arm) -> Self {
        Self { table: ArmLumped::new(arm) }
    }

    /// The number `n` of joints.
    pub fn joints(&self) -> usize {
        self.table.joints()
    }

    /// The lumped constants.
    pub fn lumped(&self) -> &ArmLumped {
        &self.table
    }

    /// `M(theta)` and `c(theta, q')` at the joint angles `theta` (`n` values) \[rad\] and the
    /// velocity `dq = (phi', theta')` (`n + 1` values) [rad/s].
    pub fn model_terms(&self, theta: &[f64], dq: &[f64]) -> ModelTerms {
        let terms = self.table.terms(theta);
        let mut out = ModelTerms { n1: terms.size(), m: [[0.0; SIZE]; SIZE], c: [0.0; SIZE] };
        terms.inertia_matrix(&mut out.m);
        terms.coriolis(dq, &mut out.c);
        out
    }

    /// The base's angular velocity at zero angular momentum, `phi' = -(G . theta') / F` [rad/s]
    /// (Eq. 7), as [`Arm::base_rate`].
    pub fn base_rate(&self, theta: &[f64], dtheta: &[f64]) -> f64 {
        let mut row = [0.0; SIZE];
        self.table.terms(theta).momentum_row(&mut row);
        -(1..=self.joints()).map(|j| row[j] * dtheta[j - 1]).sum::<f64>() / row[0]
    }

    /// The inverse dynamics at zero angular momentum ([`super::inverse_dynamics`]): the joint
    /// torques into `tau` (`n` values) [N m], `q'` and `q''` into `dq`, `ddq` (`n + 1` values);
    /// returns the base row, the rate of the angular momentum (zero up to rounding).
    pub fn inverse_into(
        &self,
        theta: &[f64],
        dtheta: &[f64],
        ddtheta: &[f64],
        tau: &mut [f64],
        dq: &mut [f64],
        ddq: &mut [f64],
    ) -> f64 {
        if self.joints() < SMALL {
            self.inverse_in::<SMALL>(theta, dtheta, ddtheta, tau, dq, ddq)
        } else {
            self.inverse_in::<SIZE>(theta, dtheta, ddtheta, tau, dq, ddq)
        }
    }

    /// [`ArmDynamics::inverse_into`] in arrays of capacity `C`.
    fn inverse_in<const C: usize>(
        &self,
        theta: &[f64],
        dtheta: &[f64],
        ddtheta: &[f64],
        tau: &mut [f64],
        dq: &mut [f64],
        ddq: &mut [f64],
    ) -> f64 {
        let n = self.joints();
        assert!(theta.len() == n, "theta has n = {n} values");
        let terms = self.table.terms_in::<C>(theta);
        let mut m = [[0.0; C]; C];
        terms.inertia_matrix(&mut m);
        inverse_with(&terms, &m, dtheta, ddtheta, tau, dq, ddq)
    }

    /// The angles' part of the inverse dynamics at `theta` (`n` values) \[rad\]: their sines,
    /// cosines and inertia matrix once, for the inverse dynamics at several rates and
    /// accelerations ([`InverseAt::inverse_into`], the same values as
    /// [`ArmDynamics::inverse_into`] at `theta`).
    pub fn at_angles(&self, theta: &[f64]) -> InverseAt {
        let terms = self.table.terms_in::<SIZE>(theta);
        let mut m = [[0.0; SIZE]; SIZE];
        terms.inertia_matrix(&mut m);
        InverseAt { terms, m }
    }

    /// [`ArmDynamics::inverse_into`] as an [`InverseDynamics`].
    pub fn inverse(&self, theta: &[f64], dtheta: &[f64], ddtheta: &[f64]) -> InverseDynamics {
        let n = self.joints();
        let (mut tau, mut dq, mut ddq) = (DVector::zeros(n), DVector::zeros(n + 1), DVector::zeros(n + 1));
        let base_residual =
            self.inverse_into(theta, dtheta, ddtheta, tau.as_mut_slice(), dq.as_mut_slice(), ddq.as_mut_slice());
        InverseDynamics { tau, base_residual, dq, ddq }
    }

    /// The forward dynamics ([`super::forward_dynamics`]): `q'' = M^-1 ((0, tau) - c)` into
    /// `ddq` (`n + 1` values) [rad/s^2] at the joint angles `theta` (`n`) \[rad\], the velocity
    /// `dq` (`n + 1`) [rad/s] under the joint torques `tau` (`n`) [N m], by the Cholesky factor of
    /// `M`; one that does not exist, or a non-finite result, is a [`SingularInertia`].
    pub fn forward(&self, theta: &[f64], dq: &[f64], tau: &[f64], ddq: &mut [f64]) -> Result<(), SingularInertia> {
        if self.joints() < SMALL {
            self.forward_in::<SMALL>(theta, dq, tau, ddq)
        } else {
            self.forward_in::<SIZE>(theta, dq, tau, ddq)
        }
    }

    /// [`ArmDynamics::forward`] in arrays of capacity `C`.
    fn forward_in<const C: usize>(
        &self,
        theta: &[f64],
        dq: &[f64],
        tau: &[f64],
        ddq: &mut [f64],
    ) -> Result<(), SingularInertia> {
        let n = self.joints();
        assert!(theta.len() == n && tau.len() == n && dq.len() == n + 1, "theta and tau have n values, dq n + 1");
        let n1 = n + 1;
        let terms = self.table.terms_in::<C>(theta);
        let mut m = [[0.0; C]; C];
        terms.inertia_matrix(&mut m);
        let mut rhs = [0.0; C];
        terms.coriolis(dq, &mut rhs);
        for (i, r) in rhs.iter_mut().enumerate().take(n1) {
            *r = if i == 0 { -*r } else { tau[i - 1] - *r };
        }
        let singular = || SingularInertia { theta: theta.to_vec() };
        // Cholesky M = L L^T in place (the lower triangle of `m`).
        for j in 0..n1 {
            let d = m[j][j] - m[j][..j].iter().map(|x| x * x).sum::<f64>();
            if !(d > 0.0) {
                return Err(singular());
            }
            let d = d.sqrt();
            m[j][j] = d;
            let row_j = m[j];
            for row in m.iter_mut().take(n1).skip(j + 1) {
                let s = row[j] - row[..j].iter().zip(&row_j[..j]).map(|(a, b)| a * b).sum::<f64>();
                row[j] = s / d;
            }
        }
        // L y = rhs, then L^T x = y.
        for i in 0..n1 {
            let s = rhs[i] - (0..i).map(|k| m[i][k] * rhs[k]).sum::<f64>();
            rhs[i] = s / m[i][i];
        }
        for i in (0..n1).rev() {
            let s = rhs[i] - (i + 1..n1).map(|k| m[k][i] * rhs[k]).sum::<f64>();
            rhs[i] = s / m[i][i];
        }
        ddq[..n1].copy_from_slice(&rhs[..n1]);
        if ddq[..n1].iter().all(|x| x.is_finite()) { Ok(()) } else { Err(singular()) }
    }
}

/// The inverse dynamics at fixed joint angles ([`ArmDynamics::at_angles`]): the angles' lumped
/// terms and inertia matrix, computed once.
#[derive(Debug, Clone)]
pub struct InverseAt {
    terms: LumpedTerms<SIZE>,
    m: Square,
}

impl InverseAt {
    /// [`ArmDynamics::inverse_into`] at these angles, the rates `dtheta` and the accelerations
    /// `ddtheta` (`n` values each): the same values, without the angles' sines, cosines and
    /// inertia matrix again.
    pub fn inverse_into(
        &self,
        dtheta: &[f64],
        ddtheta: &[f64],
        tau: &mut [f64],
        dq: &mut [f64],
        ddq: &mut [f64],
    ) -> f64 {
        inverse_with(&self.terms, &self.m, dtheta, ddtheta, tau, dq, ddq)
    }

    /// `M_ij` [kg m^2] at these angles, `i, j` in `0..=n`.
    pub fn inertia(&self, i: usize, j: usize) -> f64 {
        self.m[i][j]
    }

    /// The torques' partial derivatives at these angles, the rates `dtheta` and the
    /// accelerations `ddtheta` (`n` values each), in closed form: `d tau_j / d theta_k` into
    /// `angles[j][k]` [N m/rad] and `d tau_j / d theta'_k` into `rates[j][k]` [N m s/rad]
    /// (`j, k` in `0..n`), the base's `phi'` and `phi''` following from the zero momentum.
    ///
    /// With the absolute link angles `alpha_i` (`alpha_i` grows with `theta_k` for `i >= k`),
    /// `d (K X)_ij / d theta_k = N_ij ([k <= j] - [k <= i])` and `dM/dtheta_k` from
    /// [`LumpedTerms::inertia_derivative`]; `c` is `S^T` of `-sum_j K_ij X_ij w_j^2`, `w = S q'`,
    /// so its derivatives follow from those of `K X` and of `w_j^2`; `phi' = -(G . theta') / F`
    /// and `phi'' = -(G . theta'' + c_0) / F` by the quotient rule.
    // The indices are the formulas': rows `i`, columns `j`, the joint `k` differentiated.
    #[allow(clippy::needless_range_loop)]
    pub fn sensitivities(&self, dtheta: &[f64], ddtheta: &[f64], angles: &mut Square, rates: &mut Square) {
        let n1 = self.terms.size();
        let n = n1 - 1;
        let (m, kx, nn) = (&self.m, &self.terms.kx, &self.terms.n);
        let f = m[0][0];
        let (mut tau, mut dq, mut ddq) = ([0.0; SIZE], [0.0; SIZE], [0.0; SIZE]);
        inverse_with(&self.terms, m, dtheta, ddtheta, &mut tau[..n], &mut dq[..n1], &mut ddq[..n1]);
        // `w = S q'` (prefix sums of the velocity) and its squares.
        let (mut w, mut w2) = ([0.0; SIZE], [0.0; SIZE]);
        let mut acc = 0.0;
        for j in 0..n1 {
            acc += dq[j];
            w[j] = acc;
            w2[j] = acc * acc;
        }
        // `dc_i = -sum_{i' >= i} de_i'` from the rows' derivatives `de`.
        let suffix = |de: &[f64; SIZE], dc: &mut [f64; SIZE]| {
            let mut acc = 0.0;
            for i in (0..n1).rev() {
                acc -= de[i];
                dc[i] = acc;
            }
        };
        let (mut de, mut dc) = ([0.0; SIZE], [0.0; SIZE]);
        for k in 1..=n {
            // In theta'_k: `d phi' = -G_k / F`, `d w_j = d phi' + [j >= k]`.
            let d0 = -m[0][k] / f;
            for i in 0..n1 {
                de[i] = (0..n1).map(|j| kx[i][j] * 2.0 * w[j] * (d0 + if j >= k { 1.0 } else { 0.0 })).sum();
            }
            suffix(&de, &mut dc);
            let dddq0 = -dc[0] / f;
            for i in 1..=n {
                rates[i - 1][k - 1] = m[i][0] * dddq0 + dc[i];
            }
        }
        let mut dm = [[0.0; SIZE]; SIZE];
        for k in 1..=n {
            // In theta_k: `M` through `dM/dtheta_k`, `K X` as above, `phi'` by the quotient rule.
            self.terms.inertia_derivative(k, &mut dm);
            let dgw: f64 = (1..=n).map(|j| dm[0][j] * dq[j]).sum();
            let d0 = -(dgw + dq[0] * dm[0][0]) / f;
            for i in 0..n1 {
                de[i] = (0..n1)
                    .map(|j| {
                        let s = f64::from(u8::from(k <= j)) - f64::from(u8::from(k <= i));
                        nn[i][j] * s * w2[j] + kx[i][j] * 2.0 * w[j] * d0
                    })
                    .sum();
            }
            suffix(&de, &mut dc);
            let dga: f64 = (1..=n).map(|j| dm[0][j] * ddq[j]).sum();
            let dddq0 = -(dga + dc[0] + ddq[0] * dm[0][0]) / f;
            for i in 1..=n {
                angles[i - 1][k - 1] = (0..n1).map(|j| dm[i][j] * ddq[j]).sum::<f64>() + m[i][0] * dddq0 + dc[i];
            }
        }
    }
}

/// The inverse dynamics at zero angular momentum from the angles' `terms` and inertia matrix
/// `m` ([`ArmDynamics::inverse_into`]).
fn inverse_with<const C: usize>(
    terms: &LumpedTerms<C>,
    m: &[[f64; C]; C],
    dtheta: &[f64],
    ddtheta: &[f64],
    tau: &mut [f64],
    dq: &mut [f64],
    ddq: &mut [f64],
) -> f64 {
    let n = terms.size() - 1;
    assert!(dtheta.len() == n && ddtheta.len() == n, "dtheta and ddtheta have n = {n} values");
    dq[0] = -(1..=n).map(|j| m[0][j] * dtheta[j - 1]).sum::<f64>() / m[0][0];
    dq[1..=n].copy_from_slice(dtheta);
    let mut c = [0.0; C];
    terms.coriolis(dq, &mut c);
    ddq[0] = -((1..=n).map(|j| m[0][j] * ddtheta[j - 1]).sum::<f64>() + c[0]) / m[0][0];
    ddq[1..=n].copy_from_slice(ddtheta);
    let force = |i: usize| (0..=n).map(|j| m[i][j] * ddq[j]).sum::<f64>() + c[i];
    for (i, t) in tau.iter_mut().enumerate().take(n) {
        *t = force(i + 1);
    }
    force(0)
}
