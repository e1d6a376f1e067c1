//! Numerical building blocks with nothing robot-specific: the adaptive integrator that certifies
//! every plan, Gauss–Legendre quadrature, Chebyshev interpolation and the refined maximum of
//! sampled functions, and a fast `sin_cos`.

pub mod chebyshev;
pub mod extremum;
pub mod format;
pub mod iteration;
pub mod ode;
pub mod quadrature;
