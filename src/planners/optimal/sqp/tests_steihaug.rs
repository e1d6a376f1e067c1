//! Tests of the projected Steihaug CG ([`super::steihaug`]).

use super::*;

/// Near a KKT point the residual `r0` is almost parallel to `grad_c`; with an ill-conditioned
/// metric (a fourth difference, as the effort Hessian of a fine spline) and a `W` that takes
/// the CG many iterations, the Steihaug step must still lie on the tangent space, to the
/// metric's rounding, and decrease the model. (Projecting the whole residual, the normal part
/// grows as `1 / kkt`, and at `kkt = 1e-9` the projected residual is lost to rounding.)
#[test]
fn steihaug_step_stays_tangent_near_a_kkt_point() {
    let n = 120;
    let stencil = [6.0, -4.0, 1.0];
    let band = |diag: &dyn Fn(usize) -> f64| {
        DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => diag(i),
            k @ (1 | 2) => stencil[k],
            _ => 0.0,
        })
    };
    let s = band(&|_| stencil[0] + 1e-9);
    // W = 2 S + a positive diagonal, but negative in the first entry (not positive definite;
    // on the tangent space, nearly `e_0`'s complement, it is).
    let w = 2.0 * band(&|i| if i == 0 { -40.0 } else { stencil[0] + 3.0 * (1.0 + (1.7 * i as f64).cos()) });
    let chol = BandCholesky::new(&s, 2).expect("positive definite");
    let m = Metric { s: &s, chol: &chol, hb: 2 };
    let grad_c = DVector::from_fn(n, |i, _| if i == 0 { 10.0 } else { 0.01 * (1.3 * i as f64 + 0.2).sin() });
    let a_s = chol.solve(&grad_c);
    let den = grad_c.dot(&a_s);
    for kkt in [1e-3, 1e-6, 1e-9, 1e-11] {
        // A tangential part of relative size `kkt`: S u, u on the tangent space, |u|_S = 1.
        let u = DVector::from_fn(n, |i, _| (0.7 * i as f64).sin());
        let u = &u - &a_s * (grad_c.dot(&u) / den);
        let u = &u / m.norm(&u);
        let r0 = &grad_c * (-3.0 / den.sqrt()) + m.times(&u) * (3.0 * kkt);
        let t = steihaug(&m, &w, &r0, (&grad_c, &a_s, den), 1e6, n + 5);
        let normal = grad_c.dot(&t).abs() / (den.sqrt() * m.norm(&t));
        let q = r0.dot(&t) + 0.5 * t.dot(&matvec(&w, 2, &t));
        assert!(normal <= 1e-12, "kkt {kkt:e}: normal part {normal:e} of the step");
        assert!(q < 0.0, "kkt {kkt:e}: model change {q:e}");
    }
}
