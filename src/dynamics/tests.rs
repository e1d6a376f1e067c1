//! Tests of the dynamics: the hand-derived inertia matrix and Coriolis terms against automatic
//! differentiation of the Lagrangian (3), the momentum identity (5), inverse then forward
//! dynamics on the paper's five cases and on random smooth joint trajectories.

use super::*;
use crate::model::system::momentum;
use crate::model::{Mount, RobotParams};
use num_dual::{Dual, Dual64, DualNum};
use proptest::prelude::*;

fn lumped(a: f64, b: f64) -> Lumped {
    RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap().lumped()
}

type Dual2 = Dual<Dual64>;

/// `d/dt dL/dq' - dL/dq` of the generic [`lagrangian`] by nested dual numbers: the outer
/// derivative is along time (`q + q' t + q'' t^2 / 2`), the inner one the partial derivative.
fn euler_lagrange_by_ad(k: &Lumped, q: [f64; 3], dq: [f64; 3], ddq: [f64; 3]) -> [f64; 3] {
    let seed = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    std::array::from_fn(|i| {
        let qa: [Dual2; 3] = std::array::from_fn(|j| Dual2::new(Dual64::new(q[j], dq[j]), Dual64::from_re(0.0)));
        let dqa: [Dual2; 3] =
            std::array::from_fn(|j| Dual2::new(Dual64::new(dq[j], ddq[j]), Dual64::from_re(seed(i, j))));
        let momentum_rate = lagrangian(k, qa, dqa).eps.eps;
        let qb: [Dual64; 3] = std::array::from_fn(|j| Dual64::new(q[j], seed(i, j)));
        let dl_dq = lagrangian(k, qb, dq.map(Dual64::from_re)).eps;
        momentum_rate - dl_dq
    })
}

/// `d^2 L / dq'_i dq'_j` by nested dual numbers.
fn inertia_by_ad(k: &Lumped, q: [f64; 3], dq: [f64; 3]) -> Matrix3<f64> {
    let seed = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    Matrix3::from_fn(|i, j| {
        let dqa: [Dual2; 3] =
            std::array::from_fn(|l| Dual2::new(Dual64::new(dq[l], seed(l, i)), Dual64::new(seed(l, j), 0.0)));
        lagrangian(k, q.map(|x| Dual2::from_re(Dual64::from_re(x))), dqa).eps.eps
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// `M` is symmetric positive definite, equals the Hessian of the Lagrangian (3) in `q'`
    /// (AD), and the first row of `M q'` is the angular momentum of Eq. (5) to 1e-12.
    #[test]
    fn inertia_matrix_is_spd_and_gives_the_momentum(
        a in -1.0..1.0f64, b in -1.0..1.0f64,
        phi in -7.0..7.0f64, t1 in -7.0..7.0f64, t2 in -7.0..7.0f64,
        dq in prop::array::uniform3(-3.0..3.0f64),
    ) {
        let k = lumped(a, b);
        let q = Configuration::new(phi, t1, t2);
        let m = inertia_matrix(&k, t1, t2);
        prop_assert!((m - m.transpose()).abs().max() == 0.0);
        let eig = m.symmetric_eigen().eigenvalues;
        prop_assert!(eig.min() > 1e-6 * eig.max(), "eigenvalues {eig:?}");
        let ad = inertia_by_ad(&k, q.to_array(), dq);
        prop_assert!((m - ad).abs().max() < 1e-13 * (1.0 + m.abs().max()), "M {m} vs AD {ad}");
        let p = (m * Vector3::from(dq))[0];
        let p5 = momentum(&k, &q, dq);
        prop_assert!((p - p5).abs() < 1e-12, "{p} vs {p5}");
    }

    /// `M q'' + c` equals `d/dt dL/dq' - dL/dq` of the Lagrangian (3) by AD (relative 1e-12),
    /// the forward dynamics inverts it (1e-10 relative), and along system (7) the base row
    /// vanishes and [`joint_torques`] equals [`inverse_dynamics`] (1e-12 relative).
    #[test]
    fn euler_lagrange_matches_ad_and_forward_inverts_it(
        a in -1.0..1.0f64, b in -1.0..1.0f64,
        q in prop::array::uniform3(-7.0..7.0f64),
        dq in prop::array::uniform3(-3.0..3.0f64),
        ddq in prop::array::uniform3(-3.0..3.0f64),
    ) {
        let k = lumped(a, b);
        let qc = Configuration::from_array(q);
        let f = generalized_forces(&k, &qc, dq, ddq);
        let ad = euler_lagrange_by_ad(&k, q, dq, ddq);
        let scale = 1.0 + f.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for i in 0..3 {
            prop_assert!((f[i] - ad[i]).abs() < 1e-12 * scale, "row {i}: {} vs AD {}", f[i], ad[i]);
        }
        // The one-pass torques agree with the reference inverse dynamics along system (7).
        let point = MotionPoint { q: qc, u: [dq[1], dq[2]], du: [ddq[1], ddq[2]] };
        let reference = inverse_dynamics(&k, &point);
        let fast = joint_torques(&k, &point);
        prop_assert!(reference.base_residual.abs() < 1e-12 * scale, "base row {}", reference.base_residual);
        for i in 0..2 {
            let tol = 1e-12 * (1.0 + reference.tau[i].abs());
            prop_assert!((fast[i] - reference.tau[i]).abs() < tol, "{fast:?} vs {:?}", reference.tau);
        }
        let back = forward_dynamics(&k, &qc, dq, f);
        for i in 0..3 {
            prop_assert!((back[i] - ddq[i]).abs() < 1e-10 * (1.0 + ddq[i].abs()), "{back:?} vs {ddq:?}");
        }
    }
}

/// Kinetic energy of the robot from first principles [J]: the base (mass `M`, inertia `I`) and
/// two point-mass links (the model of Sec. 3.1 has no link inertias), positions relative to the
/// system's centre of mass held at the origin, velocities by a dual number along `dq`.
fn kinetic_energy_from_bodies(robot: &RobotParams, q: [f64; 3], dq: [f64; 3]) -> f64 {
    let RobotParams { l1, d1, d2, base_mass, base_inertia, m1, m2, mount, .. } = *robot;
    let [phi, t1, t2] = std::array::from_fn::<Dual64, 3, _>(|i| Dual64::new(q[i], dq[i]));
    let (sp, cp) = phi.sin_cos();
    let joint1 = [cp * mount.a - sp * mount.b, sp * mount.a + cp * mount.b];
    let (s1, c1) = (phi + t1).sin_cos();
    let (s12, c12) = (phi + t1 + t2).sin_cos();
    let link1 = [joint1[0] + c1 * d1, joint1[1] + s1 * d1];
    let link2 = [joint1[0] + c1 * l1 + c12 * d2, joint1[1] + s1 * l1 + s12 * d2];
    let mc = base_mass + m1 + m2;
    let centre: [Dual64; 2] = std::array::from_fn(|i| (link1[i] * m1 + link2[i] * m2) / mc);
    let speed2 = |p: [Dual64; 2]| (p[0] - centre[0]).eps.powi(2) + (p[1] - centre[1]).eps.powi(2);
    let zero = Dual64::from_re(0.0);
    0.5 * (base_mass * speed2([zero, zero]) + m1 * speed2(link1) + m2 * speed2(link2))
        + 0.5 * base_inertia * dq[0] * dq[0]
}

proptest! {
    /// The Lagrangian (3) with the constants after it equals the kinetic energy computed from the
    /// bodies' positions (centre of mass at rest), to 1e-12 relative: Eq. (3) is right.
    #[test]
    fn lagrangian_is_the_kinetic_energy_of_the_bodies(
        a in -1.0..1.0f64, b in -1.0..1.0f64,
        q in prop::array::uniform3(-7.0..7.0f64),
        dq in prop::array::uniform3(-3.0..3.0f64),
    ) {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
        let from_bodies = kinetic_energy_from_bodies(&robot, q, dq);
        let eq3 = lagrangian(&robot.lumped(), q, dq);
        prop_assert!((eq3 - from_bodies).abs() <= 1e-12 * from_bodies.abs().max(1e-3), "{eq3} vs {from_bodies}");
    }
}
