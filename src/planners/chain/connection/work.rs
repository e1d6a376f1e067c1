//! The work space of the holonomy integrand's derivatives ([`Connection::local`]): on the stack
//! up to [`STACK_JOINTS`] joints, on the heap beyond.

#[cfg(doc)]
use super::Connection;

/// Joints up to which the work space of [`Connection::local`] is on the stack: arrays of a
/// size known at compile time, which the compiler keeps in registers where the joint count is
/// a constant (the same operations in the same order as on the heap, so the same bits).
pub(super) const STACK_JOINTS: usize = 7;

/// Work space of [`Connection::local`] for `n` joints: F's gradient and Hessian, G's Jacobian
/// `[j * n + m]`, the angles, the prefix sums of theta', the segments' sines and cosines, and
/// the pair sums with their suffix and prefix sums (`(n + 1) x (n + 1)`).
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Work {
    pub(super) f_grad: Vec<f64>,
    pub(super) f_hess: Vec<f64>,
    pub(super) g_jac: Vec<f64>,
    pub(super) psi: Vec<f64>,
    pub(super) rate_sum: Vec<f64>,
    pub(super) cs: Vec<(f64, f64)>,
    pub(super) pairs: Vec<[f64; 4]>,
    pub(super) suffix: Vec<[f64; 4]>,
    pub(super) prefix: Vec<[f64; 4]>,
}

impl Work {
    pub(super) fn new(n: usize) -> Self {
        let (n1, sq) = (n + 1, (n + 1) * (n + 1));
        Self {
            f_grad: vec![0.0; n],
            f_hess: vec![0.0; n * n],
            g_jac: vec![0.0; n * n],
            psi: vec![0.0; n1],
            rate_sum: vec![0.0; n1],
            cs: vec![(0.0, 0.0); n1],
            pairs: vec![[0.0; 4]; sq],
            suffix: vec![[0.0; 4]; sq],
            prefix: vec![[0.0; 4]; sq],
        }
    }
}

/// [`Work`] as slices (of the heap's or of stack arrays).
pub(super) struct WorkSlices<'a> {
    pub(super) f_grad: &'a mut [f64],
    pub(super) f_hess: &'a mut [f64],
    pub(super) g_jac: &'a mut [f64],
    pub(super) psi: &'a mut [f64],
    pub(super) rate_sum: &'a mut [f64],
    pub(super) cs: &'a mut [(f64, f64)],
    pub(super) pairs: &'a mut [[f64; 4]],
    pub(super) suffix: &'a mut [[f64; 4]],
    pub(super) prefix: &'a mut [[f64; 4]],
}
