//! The integrand at points whose links' sines and cosines another pass kept: the base angle's
//! path of the clearance rows ([`crate::planners::chain::limits`]) is taken at the same
//! quadrature nodes and coefficients by the merit's trial (values), the accepted iterate's rows
//! (first derivatives) and their curvature (second), and each took the `n` sines and cosines of
//! every node again.

use super::{Connection, Local, specialised};

impl Connection {
    /// [`Self::value`], the sines and cosines of the links' angles kept in `keep` (`n` of them).
    pub fn value_keeping(&self, theta: &[f64], rate: &[f64], keep: &mut [(f64, f64)]) -> f64 {
        specialised!(self.n, |n| self.value_of(n, theta, rate, Some(keep)))
    }

    /// [`Self::first_order`] with the sines and cosines of the links' angles `known` (those
    /// [`Self::value_keeping`] kept at the same `theta`: the same bits).
    pub fn first_order_known(&self, theta: &[f64], rate: &[f64], out: &mut Local, known: &[(f64, f64)]) {
        specialised!(self.n, |n| self.local_with::<false>(n, theta, rate, out, Some(known)))
    }

    /// [`Self::local`] with the sines and cosines of the links' angles `known` (those
    /// [`Self::value_keeping`] kept at the same `theta`: the same bits).
    pub fn local_known(&self, theta: &[f64], rate: &[f64], out: &mut Local, known: &[(f64, f64)]) {
        specialised!(self.n, |n| self.local_of(n, theta, rate, out, Some(known)))
    }
}
