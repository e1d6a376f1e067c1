//! Tests of the polynomial steering of Sec. 5: end conditions, the chained form (10), rest and
//! the degenerate `w2 = 0`.

use super::*;
use crate::error::Error;
use approx::assert_relative_eq;
use proptest::prelude::*;

proptest! {
    /// The controls vanish at both ends, `z(T) = zd`, and `z(t)` solves the chained form
    /// (checked through the derivative polynomials).
    #[test]
    fn reaches_goal_with_zero_end_controls(
        z0 in prop::array::uniform3(-3.0..3.0f64),
        w in prop::array::uniform3(-3.0..3.0f64),
        t in 0.5..20.0f64,
    ) {
        prop_assume!(w[1].abs() > 0.05);
        let zd = [z0[0] + w[0], z0[1] + w[1], z0[2] + w[2]];
        let s = PolynomialSteering::new(z0, zd, t).unwrap();
        let end = s.at(t);
        let start = s.at(0.0);
        for i in 0..3 {
            prop_assert!((end.z[i] - zd[i]).abs() < 1e-12 * (1.0 + zd[i].abs()) * (1.0 + w[0].abs() / w[1].abs()));
            prop_assert!((start.z[i] - z0[i]).abs() < 1e-15 * (1.0 + z0[i].abs()));
        }
        let scale = 1.0 + (w[0].abs() + w[2].abs() + z0[1].abs()) / w[1].abs();
        for v in end.v.iter().chain(start.v.iter()) {
            prop_assert!(v.abs() < 1e-13 * scale / t);
        }
        // z1' = v1, z2' = v2, z3' = z2 v1 at a few interior times.
        for k in 1..5 {
            let tk = t * k as f64 / 5.0;
            let p = s.at(tk);
            prop_assert!((s.z[0].derivative().eval(tk) - p.v[0]).abs() < 1e-12 * scale);
            prop_assert!((s.z[1].derivative().eval(tk) - p.v[1]).abs() < 1e-12 * scale);
            prop_assert!((s.z[2].derivative().eval(tk) - p.z[1] * p.v[0]).abs() < 1e-11 * scale * (1.0 + p.z[1].abs()));
        }
    }
}

/// The end conditions hold in exact arithmetic: with rational inputs the coefficients of
/// `v1(T)`, `z1(T) - z01`, `z3(T) - z03` reduce to `0`, `w1`, `w3` (checked here with inputs
/// that are exact binary fractions, where every operation is exact up to one rounding).
#[test]
fn end_conditions_on_a_simple_case() {
    let s = PolynomialSteering::new([0.0, 1.0, 0.0], [1.0, 2.0, 0.5], 2.0).unwrap();
    let e = s.at(2.0);
    assert_relative_eq!(e.z[0], 1.0, epsilon = 1e-13);
    assert_relative_eq!(e.z[1], 2.0, epsilon = 1e-13);
    assert_relative_eq!(e.z[2], 0.5, epsilon = 1e-13);
    assert_relative_eq!(e.v[0], 0.0, epsilon = 1e-13);
    assert_relative_eq!(e.v[1], 0.0, epsilon = 1e-13);
}

#[test]
fn goal_equal_to_start_rests() {
    let s = PolynomialSteering::new([0.3, 1.0, -0.2], [0.3, 1.0, -0.2], 2.0).unwrap();
    for t in [0.0, 0.7, 2.0] {
        let p = s.at::<f64>(t);
        for (z, want) in p.z.iter().zip([0.3, 1.0, -0.2]) {
            assert_relative_eq!(*z, want, epsilon = 1e-15);
        }
        assert!(p.v.iter().all(|v| v.abs() < 1e-15));
    }
}

#[test]
fn zero_w2_is_a_typed_error() {
    assert!(matches!(
        PolynomialSteering::new([0.0, 1.0, 0.0], [1.0, 1.0, 0.5], 2.0),
        Err(Error::DegenerateSteering { .. })
    ));
}
