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

#[cfg(test)]
mod tests {
    use super::super::tests::arm;
    use super::super::{Connection, Local, MAX_JOINTS};

    /// With the sines and cosines that [`Connection::value_keeping`] kept, the value, the first
    /// order and the whole local integrand are those computed afresh, bit for bit (the rows and
    /// their curvature read them at the same nodes: the plan must not move), for n = 2..15.
    #[test]
    fn the_kept_sines_give_the_same_bits() {
        for n in 2..=MAX_JOINTS {
            let c = Connection::new(&arm(n));
            let (mut fresh, mut known) = (Local::new(n), Local::new(n));
            let mut keep = vec![(0.0, 0.0); n];
            for trial in 0..10 {
                let theta: Vec<f64> = (0..n).map(|i| ((i * 7 + trial * 3) as f64 * 0.77).sin() * 3.0).collect();
                let rate: Vec<f64> = (0..n).map(|i| ((i * 5 + trial) as f64 * 1.3).cos()).collect();
                let value = c.value_keeping(&theta, &rate, &mut keep);
                assert_eq!(value.to_bits(), c.value(&theta, &rate).to_bits(), "n {n}");
                let bits = |l: &Local, second: bool| -> Vec<u64> {
                    let mut all = [[l.value, l.plain].as_slice(), &l.a, &l.gradient].concat();
                    if second {
                        all.extend_from_slice(&l.hessian);
                        all.extend_from_slice(&l.mixed);
                    }
                    all.iter().map(|x| x.to_bits()).collect()
                };
                c.first_order(&theta, &rate, &mut fresh);
                c.first_order_known(&theta, &rate, &mut known, &keep);
                assert_eq!(bits(&fresh, false), bits(&known, false), "n {n}");
                c.local(&theta, &rate, &mut fresh);
                c.local_known(&theta, &rate, &mut known, &keep);
                assert_eq!(bits(&fresh, true), bits(&known, true), "n {n}");
            }
        }
    }
}
