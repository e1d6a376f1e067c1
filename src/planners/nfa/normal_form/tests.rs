//! Property tests of the feedback transformations: the chained-form identity (derivatives by
//! forward-mode AD), the inverse map, and the printed formulas.

use super::*;
use crate::model::Mount;
use crate::model::system::vector_fields;
use num_dual::{Dual64, first_derivative};
use proptest::prelude::*;

/// A small deterministic generator (SplitMix64) for loops over many random points.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn robot(a: f64, b: f64) -> RobotParams {
    RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * 1f64.max(a.abs()).max(b.abs())
}

/// A random configuration inside the domain of `transform`, well inside (margins not tiny, so
/// that relative accuracy is meaningful), with its normal form.
fn random_point(rng: &mut Rng, transform: Transform, mount_range: f64) -> (NormalForm, Configuration) {
    loop {
        let (a, b) = match transform {
            Transform::Eq14 | Transform::Global => {
                (rng.uniform(-mount_range, mount_range), rng.uniform(-mount_range, mount_range))
            }
            _ => (0.0, 0.0),
        };
        let q = Configuration::new(rng.uniform(-7.0, 7.0), rng.uniform(-7.0, 7.0), rng.uniform(-7.0, 7.0));
        let r = robot(a, b);
        let Ok(nf) = NormalForm::new(&r, transform, &q) else { continue };
        let s = shape(&nf.lumped, q.theta1, q.theta2);
        let near_p = s.P.abs() < 1e-3 && transform != Transform::Global;
        let near_s2 = q.theta2.sin().abs() < 1e-3 && matches!(transform, Transform::Eq11 | Transform::Eq12);
        if near_p || near_s2 || s.sigma.abs() < 1e-3 {
            continue;
        }
        return (nf, q);
    }
}

/// Chained-form identity: along `q' = g1 u1 + g2 u2`, `d/dt h(q) = (v1, v2, z2 v1)` with
/// `v = feedback(q, u)`; the time derivative of `h` by forward-mode AD. >= 1000 random points
/// per transformation, relative 1e-10 (docs/spec.md §4).
fn chained_form_identity(transform: Transform, seed: u64) {
    let mut rng = Rng(seed);
    for _ in 0..1000 {
        let (nf, q) = random_point(&mut rng, transform, 1.0);
        let u = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        let (g1, g2) = vector_fields(&nf.lumped, q.theta1, q.theta2);
        let qa = q.to_array();
        let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(qa[i], g1[i] * u[0] + g2[i] * u[1]));
        let z = nf.h(qd);
        let v = nf.feedback(qa, u);
        let expected = [v[0], v[1], z[1].re * v[0]];
        for i in 0..3 {
            assert!(
                close(z[i].eps, expected[i], 1e-10),
                "{transform:?} at {q:?}, u {u:?}: dz{} = {} vs {}",
                i + 1,
                z[i].eps,
                expected[i]
            );
        }
        // The inverse feedback undoes the feedback.
        let back = nf.control(qa, v);
        assert!(close(back[0], u[0], 1e-11) && close(back[1], u[1], 1e-10), "{back:?} vs {u:?}");
    }
}

#[test]
fn chained_form_identity_eq11() {
    chained_form_identity(Transform::Eq11, 11);
}

#[test]
fn chained_form_identity_eq12() {
    chained_form_identity(Transform::Eq12, 12);
}

#[test]
fn chained_form_identity_eq14() {
    chained_form_identity(Transform::Eq14, 14);
}

/// The global normal form at random points of the whole torus (and beyond: theta2 over several
/// turns), mounting points with |a|, |b| <= 1.
#[test]
fn chained_form_identity_global() {
    chained_form_identity(Transform::Global, 15);
}

/// `h^-1(h(q)) = q` to 1e-12 at random points of each domain; Newton for Eq. (14) starts from
/// a guess up to 0.05 rad away.
#[test]
fn inverse_map_round_trip() {
    let mut rng = Rng(7);
    for transform in [Transform::Eq11, Transform::Eq12, Transform::Eq14, Transform::Global] {
        for _ in 0..1000 {
            let (nf, q) = random_point(&mut rng, transform, 1.0);
            let z = nf.h(q.to_array());
            let mut guess = q.theta2 + rng.uniform(-0.05, 0.05);
            if transform == Transform::Eq14 && !nf.on_branch(q.theta1, guess) {
                guess = q.theta2;
            }
            let back = nf.invert(z, guess, None);
            let back = back.unwrap_or_else(|e| panic!("{transform:?} at {q:?}: {e}"));
            for (x, y) in back.to_array().iter().zip(q.to_array()) {
                assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{transform:?}: {back:?} vs {q:?}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// `dh3/dtheta2 = sign(P) 2 sigma / F^2` (used by Newton and the feedback) against AD.
    #[test]
    fn dh3_dtheta2_matches_ad(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -4.0..4.0f64, t2 in -4.0..4.0f64) {
        let k = robot(a, b).lumped();
        let s = shape(&k, t1, t2);
        prop_assume!(s.P.abs() > 1e-3);
        let branch = s.P.signum();
        let (_, ad) = first_derivative(|x: Dual64| general::h3(&k, branch, Dual64::from_re(t1), x), t2);
        let closed = general::dh3_dtheta2(&k, branch, t1, t2);
        prop_assert!(close(ad, closed, 1e-10), "{ad} vs {closed}");
    }

    /// The `atan2` form of `R` equals Eq. (14) as printed (with arcsin) on its branch.
    #[test]
    fn r_function_equals_printed_formula(a in -1.0..1.0f64, b in -1.0..1.0f64, t1 in -4.0..4.0f64, t2 in -4.0..4.0f64) {
        let k = robot(a, b).lumped();
        let s = shape(&k, t1, t2);
        prop_assume!(s.P.abs() > 1e-3);
        let ours = general::r_function(&k, s.P.signum(), t1, t2);
        let printed = general::r_function_printed(&k, t1, t2);
        prop_assert!((ours - printed).abs() < 1e-12, "{ours} vs {printed}");
    }

    /// At `a = b = 0` Eq. (14) reduces to Eq. (12) in its corrected form (docs/spec.md §6, item 1),
    /// on both branches `sign(s2)`; the printed Eq. (12) (`+ theta2/2`) agrees only for s2 > 0.
    #[test]
    fn eq14_at_centre_is_eq12(phi in -4.0..4.0f64, t1 in -4.0..4.0f64, t2 in -4.0..4.0f64) {
        prop_assume!(t2.sin().abs() > 1e-3);
        let r = RobotParams::src();
        let q = Configuration::new(phi, t1, t2);
        let z12 = NormalForm::new(&r, Transform::Eq12, &q).unwrap().h(q.to_array());
        let k = r.lumped();
        let z14 = general::eq14_h(&k, -t2.sin().signum(), q.to_array());
        for i in 0..2 {
            prop_assert!((z12[i] - z14[i]).abs() < 1e-12, "z{}: {} vs {}", i + 1, z12[i], z14[i]);
        }
        // z3 agrees up to a constant on each interval of theta2 (a multiple of pi, from the
        // branches of arcsin), which the chained form does not see.
        let offset = (z12[2] - z14[2]) / std::f64::consts::PI;
        prop_assert!((offset - offset.round()).abs() < 1e-12, "z3: {} vs {}", z12[2], z14[2]);
    }
}

/// Eq. (12) as printed (`+ theta2/2`, no sign) fails the chained-form identity where s2 < 0:
/// `dh2 . g2 = 0` needs `sign(s2) theta2 / 2` (erratum 1 of docs/spec.md §6).
#[test]
fn printed_eq12_fails_for_negative_s2() {
    let r = RobotParams::src();
    let k = r.lumped();
    let q = Configuration::new(0.3, 1.0, -1.2);
    let nf = NormalForm::new(&r, Transform::Eq12, &q).unwrap();
    let printed = |q: [Dual64; 3]| {
        let mut z = nf.h(q);
        // Undo the correction: printed z3 has +theta2/2 where ours has sign(s2) theta2/2 = -theta2/2.
        z[2] += q[2];
        z
    };
    let (_, g2) = vector_fields(&k, q.theta1, q.theta2);
    let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(q.to_array()[i], g2[i]));
    // Along g2 (u = (0, 1)): v1 = 0, so dz3/dt must vanish.
    assert!(nf.h(qd)[2].eps.abs() < 1e-12);
    assert!((printed(qd)[2].eps - 1.0).abs() < 1e-12);
}

#[test]
fn singular_start_and_unavailable_transform() {
    let r = RobotParams::src();
    let q = Configuration::new(0.0, 1.0, 0.0);
    assert!(matches!(
        NormalForm::new(&r, Transform::Eq12, &q),
        Err(Error::Singular { which: Singularity::SinTheta2, .. })
    ));
    assert!(matches!(NormalForm::new(&r, Transform::Eq14, &q), Err(Error::Singular { .. })));
    let off = robot(0.1, 0.1);
    assert!(matches!(
        NormalForm::new(&off, Transform::Eq11, &Configuration::new(0.0, 1.0, 1.0)),
        Err(Error::TransformUnavailable { .. })
    ));
}
