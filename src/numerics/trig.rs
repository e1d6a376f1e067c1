//! `sin` and `cos` of one angle together, for the inner loops of the chain planner (the
//! connection's sums over segment pairs take `n` of them at every quadrature node, a sixth of a
//! plan's time with the C library's `sincos`).
//!
//! The angle is reduced by the nearest multiple `k pi/2` in two parts (Cody–Waite, `pi/2` split
//! as in fdlibm: the first part has 33 bits, so `k * PIO2_1` is exact for `|k| < 2^20`), and the
//! reduced angle `|y| <= pi/4` goes to fdlibm's minimax kernels (`__kernel_sin`, `__kernel_cos`,
//! error below 1 ulp on that interval). Without the reduction's tail word the result is within a
//! few units in the last place of the correctly rounded one (the test holds it to `4e-16`
//! absolute); angles beyond `|x| <= 1e5` and non-finite ones take the standard library's path.
//!
//! ## Reference
//! Sun Microsystems, fdlibm 5.3, `k_sin.c`, `k_cos.c`, `e_rem_pio2.c` (1993).

// fdlibm's constants with its digits (each rounds to the double it names).
#![allow(clippy::excessive_precision)]

use std::f64::consts::FRAC_2_PI;

/// The first 33 bits of `pi/2`.
const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
/// `pi/2 - PIO2_1`.
const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11;
/// `1.5 * 2^52`: adding and subtracting it rounds to the nearest integer (ties to even).
const ROUND: f64 = 6_755_399_441_055_744.0;
const S1: f64 = -1.666_666_666_666_663_243_48e-1;
const S2: f64 = 8.333_333_333_322_489_461_24e-3;
const S3: f64 = -1.984_126_982_985_794_931_34e-4;
const S4: f64 = 2.755_731_370_707_006_767_89e-6;
const S5: f64 = -2.505_076_025_340_686_341_95e-8;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;
const C1: f64 = 4.166_666_666_666_660_190_37e-2;
const C2: f64 = -1.388_888_888_887_410_957_49e-3;
const C3: f64 = 2.480_158_728_947_672_941_78e-5;
const C4: f64 = -2.755_731_435_139_066_330_35e-7;
const C5: f64 = 2.087_572_321_298_174_827_90e-9;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// `(sin x, cos x)`, as [`f64::sin_cos`] to a few ulp (see the [module docs](self)).
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !(x.abs() <= 1e5) {
        return x.sin_cos();
    }
    let k = (x * FRAC_2_PI + ROUND) - ROUND;
    let y = (x - k * PIO2_1) - k * PIO2_1T;
    let z = y * y;
    let s = y + z * y * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let r = z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = w + (((1.0 - w) - hz) + r);
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within `4e-16` (absolute) of the standard library's on a dense grid of `|x| <= 200`, near
    /// the multiples of `pi/4` (the ends of the reduced interval) up to `|x| = 1e5`, and the
    /// standard library's own values beyond and at non-finite angles.
    #[test]
    fn sin_cos_matches_the_standard_library() {
        let close = |x: f64| {
            let (s, c) = sin_cos(x);
            let (es, ec) = x.sin_cos();
            assert!((s - es).abs() <= 4e-16 && (c - ec).abs() <= 4e-16, "x = {x:e}: {s:e} {c:e} vs {es:e} {ec:e}");
        };
        for i in -2_000_000..=2_000_000 {
            close(i as f64 * 1e-4 + 1.3e-9 * (i % 7) as f64);
        }
        for k in -400_000..=400_000_i64 {
            let x = k as f64 * std::f64::consts::FRAC_PI_4;
            for d in [-1e-12, 0.0, 1e-12, 3e-9] {
                close(x + d);
                close(x * 0.25 + d);
            }
        }
        for x in [1e5 + 0.5, -3e7, 1e300, f64::INFINITY, f64::NAN] {
            let ((s, c), (es, ec)) = (sin_cos(x), x.sin_cos());
            assert!(s.to_bits() == es.to_bits() && c.to_bits() == ec.to_bits() || s.is_nan() && es.is_nan());
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }
}
