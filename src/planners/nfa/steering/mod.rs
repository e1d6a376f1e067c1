//! Steering the chained form (10) `z1' = v1, z2' = v2, z3' = z2 v1` with the polynomial
//! controls of Sec. 5: `v1 = b1 t + c1 t^2 + d1 t^3`, `v2 = b2 t + c2 t^2`, zero at both ends,
//! `z(T) = zd`, and `z(t)` in closed form.
//!
//! The paths themselves have a file each: [`PolynomialSteering`] (Sec. 5) and [`BandSteering`]
//! (beyond the paper, for the global normal form); [`Steering`] is either.

mod band;
mod polynomial;
#[cfg(test)]
mod tests;

pub use band::{BandChoice, BandOptions, BandSteering, keeps_to_band};
pub use polynomial::{Polynomial, PolynomialSteering};

/// A point of a chained-form path: state `z`, controls `v` and their time derivatives `dv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainedPoint<D> {
    /// `(z1, z2, z3)`.
    pub z: [D; 3],
    /// `(v1, v2)`.
    pub v: [D; 2],
}

/// The chained-form path of a plan: the paper's polynomials, or the band steering.
#[derive(Debug, Clone, PartialEq)]
pub enum Steering {
    /// Sec. 5's polynomial controls.
    Polynomial(PolynomialSteering),
    /// [`BandSteering`] (global normal form only).
    Band(BandSteering),
}

impl Steering {
    /// Horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        match self {
            Steering::Polynomial(p) => p.horizon,
            Steering::Band(b) => b.horizon,
        }
    }

    /// `(z0, zd)`.
    pub fn ends(&self) -> ([f64; 3], [f64; 3]) {
        match self {
            Steering::Polynomial(p) => (p.z0, p.zd),
            Steering::Band(b) => (b.z0, b.zd),
        }
    }

    /// The path at `t`.
    pub fn at(&self, t: f64) -> ChainedPoint<f64> {
        match self {
            Steering::Polynomial(p) => p.at(t),
            Steering::Band(b) => b.at(t),
        }
    }

    /// The path at `t` with its time derivatives in the dual parts (`z'` and `v'`).
    pub fn at_dual(&self, t: f64) -> ChainedPoint<num_dual::Dual64> {
        match self {
            Steering::Polynomial(p) => p.at(num_dual::Dual64::new(t, 1.0)),
            Steering::Band(b) => b.at_dual(t),
        }
    }

    /// The band choice, for band steering.
    pub fn band_choice(&self) -> Option<BandChoice> {
        match self {
            Steering::Polynomial(_) => None,
            Steering::Band(b) => Some(b.choice),
        }
    }
}
