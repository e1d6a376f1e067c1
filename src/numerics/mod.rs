//! Numerical building blocks with nothing robot-specific: the adaptive integrator that certifies
//! every plan, Gauss–Legendre quadrature and Chebyshev interpolation.

pub mod chebyshev;
pub mod iteration;
pub mod ode;
pub mod quadrature;
