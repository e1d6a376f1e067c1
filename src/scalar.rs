//! The scalar type of every formula.

/// The scalar type of every formula: `f64` or a (nested) dual number of `num-dual`, so that
/// exact derivatives come from forward-mode automatic differentiation.
pub trait Scalar: num_dual::DualNum<Primitive = f64> + Copy {}
impl<T: num_dual::DualNum<Primitive = f64> + Copy> Scalar for T {}
