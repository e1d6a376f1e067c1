//! Tests of the n-link dynamics: the Christoffel form against the Euler–Lagrange equations of
//! the Lagrangian by nested dual numbers, inverse then forward dynamics, conservation of energy
//! and angular momentum along a torque-free motion for n = 1..7, and the n = 2 point-mass arm
//! against the SRC robot's hand-derived dynamics.

use super::*;
use crate::Scalar;
use crate::dynamics;
use crate::model::arm::tests::{Rng, random_arm};
use crate::model::system::MotionPoint;
use crate::model::{Configuration, Mount, RobotParams};
use num_dual::Dual;

type Dual2 = Dual<Dual64>;

/// `L = 1/2 q'^T M(theta) q'`, generic.
fn lagrangian<D: Scalar>(arm: &Arm, q: &[D], dq: &[D]) -> D {
    let m = arm.inertia_matrix(&q[1..]);
    let mut l = D::from(0.0);
    for i in 0..dq.len() {
        for j in 0..dq.len() {
            l += dq[i] * m[(i, j)] * dq[j] * 0.5;
        }
    }
    l
}

/// `d/dt dL/dq' - dL/dq` by nested dual numbers: outer derivative along time
/// (`q + q' t`, `q' + q'' t`), inner the partial derivative.
fn euler_lagrange_by_ad(arm: &Arm, q: &[f64], dq: &[f64], ddq: &[f64]) -> Vec<f64> {
    let n = q.len();
    let seed = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    (0..n)
        .map(|i| {
            let qa: Vec<Dual2> = (0..n).map(|j| Dual2::new(Dual64::new(q[j], dq[j]), Dual64::from_re(0.0))).collect();
            let dqa: Vec<Dual2> =
                (0..n).map(|j| Dual2::new(Dual64::new(dq[j], ddq[j]), Dual64::from_re(seed(i, j)))).collect();
            let momentum_rate = lagrangian(arm, &qa, &dqa).eps.eps;
            let qb: Vec<Dual64> = (0..n).map(|j| Dual64::new(q[j], seed(i, j))).collect();
            let dqb: Vec<Dual64> = dq.iter().map(|&v| Dual64::from_re(v)).collect();
            momentum_rate - lagrangian(arm, &qb, &dqb).eps
        })
        .collect()
}

fn max_abs(v: &DVector<f64>) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// For n = 1..7 random arms and motion points: `M q'' + c` equals the Euler–Lagrange equations
/// of the Lagrangian by AD (1e-12 relative); the inverse dynamics keeps the momentum's rate zero
/// (base residual <= 1e-12 relative) and the forward dynamics under its torques returns its
/// acceleration (1e-10 relative).
#[test]
fn christoffel_form_matches_ad_and_inverse_then_forward_is_the_identity() {
    let mut rng = Rng::new(6);
    for n in 1..=7 {
        for _ in 0..10 {
            let arm = random_arm(n, &mut rng);
            let q = rng.vec(n + 1, -7.0, 7.0);
            let dq = DVector::from_vec(rng.vec(n + 1, -3.0, 3.0));
            let ddq = DVector::from_vec(rng.vec(n + 1, -3.0, 3.0));
            let f = generalized_forces(&arm, &q[1..], &dq, &ddq);
            let ad = DVector::from_vec(euler_lagrange_by_ad(&arm, &q, dq.as_slice(), ddq.as_slice()));
            assert!(max_abs(&(&f - &ad)) <= 1e-12 * (1.0 + max_abs(&f)), "n = {n}: {f} vs AD {ad}");
            let c = coriolis(&arm, &q[1..], &dq);
            assert!(max_abs(&(&f - &c - arm.inertia_matrix(&q[1..]) * &ddq)) <= 1e-12 * (1.0 + max_abs(&f)));

            let theta = &q[1..];
            let inv = inverse_dynamics(&arm, theta, &dq.as_slice()[1..], &ddq.as_slice()[1..]);
            let scale = 1.0 + max_abs(&inv.tau);
            assert!(inv.base_residual.abs() <= 1e-12 * scale, "n = {n}: base residual {}", inv.base_residual);
            assert!(angular_momentum(&arm, theta, &inv.dq).abs() <= 1e-12 * (1.0 + max_abs(&inv.dq)));
            let back = forward_dynamics(&arm, theta, &inv.dq, &inv.tau).unwrap();
            let err = max_abs(&(&back - &inv.ddq));
            assert!(err <= 1e-10 * (1.0 + max_abs(&inv.ddq)), "n = {n}: forward(inverse) off by {err}");
        }
    }
}

/// One classical Runge–Kutta step of the torque-free arm, state `(q, q')`.
fn rk4_step(arm: &Arm, q: &DVector<f64>, dq: &DVector<f64>, h: f64) -> (DVector<f64>, DVector<f64>) {
    let n = arm.joints();
    let zero = DVector::zeros(n);
    let acc = |q: &DVector<f64>, dq: &DVector<f64>| forward_dynamics(arm, &q.as_slice()[1..], dq, &zero).unwrap();
    let k1 = (dq.clone(), acc(q, dq));
    let k2 = (dq + &k1.1 * (h / 2.0), acc(&(q + &k1.0 * (h / 2.0)), &(dq + &k1.1 * (h / 2.0))));
    let k3 = (dq + &k2.1 * (h / 2.0), acc(&(q + &k2.0 * (h / 2.0)), &(dq + &k2.1 * (h / 2.0))));
    let k4 = (dq + &k3.1 * h, acc(&(q + &k3.0 * h), &(dq + &k3.1 * h)));
    let q1 = q + (&k1.0 + &k2.0 * 2.0 + &k3.0 * 2.0 + &k4.0) * (h / 6.0);
    let dq1 = dq + (&k1.1 + &k2.1 * 2.0 + &k3.1 * 2.0 + &k4.1) * (h / 6.0);
    (q1, dq1)
}

/// The relative energy drift and the momentum (relative to `sqrt(2 T F)`) after `steps` RK4
/// steps of `h` from a torque-free start at zero momentum.
fn drift(arm: &Arm, theta: &[f64], dtheta: &[f64], h: f64, steps: usize) -> (f64, f64) {
    let n = arm.joints();
    let phi_rate = arm.base_rate(theta, dtheta);
    let mut q = DVector::from_iterator(n + 1, std::iter::once(0.3).chain(theta.iter().copied()));
    let mut dq = DVector::from_iterator(n + 1, std::iter::once(phi_rate).chain(dtheta.iter().copied()));
    let energy0 = kinetic_energy(arm, theta, &dq);
    let (f, _) = arm.momentum_coefficients(theta);
    let p_scale = (2.0 * energy0 * f).sqrt();
    for _ in 0..steps {
        (q, dq) = rk4_step(arm, &q, &dq, h);
    }
    let theta = &q.as_slice()[1..];
    let de = (kinetic_energy(arm, theta, &dq) - energy0).abs() / energy0;
    (de, angular_momentum(arm, theta, &dq).abs() / p_scale)
}

/// With zero torques the kinetic energy and the angular momentum (zero at the start) stay
/// constant: 0.5 s of RK4 from random joint velocities up to 1 rad/s, n = 1..7, at h = 1 ms and
/// h = 0.5 ms. Energy drift and momentum (relative to `sqrt(2 T F)`) <= 1e-10 at h = 1 ms (measured: 2e-12 and 8e-12), and
/// they shrink by at least 8 when h halves (RK4 is 4th order: 16), or are at rounding (1e-13):
/// the drift is the integrator's, not the model's.
#[test]
fn torque_free_motion_conserves_energy_and_momentum() {
    let mut rng = Rng::new(21);
    let mut worst = (0.0_f64, 0.0_f64);
    for n in 1..=7 {
        let arm = random_arm(n, &mut rng);
        let theta = rng.vec(n, -3.0, 3.0);
        let dtheta = rng.vec(n, -1.0, 1.0);
        let coarse = drift(&arm, &theta, &dtheta, 1e-3, 500);
        let fine = drift(&arm, &theta, &dtheta, 5e-4, 1000);
        worst = (worst.0.max(coarse.0), worst.1.max(coarse.1));
        for (what, c, f) in [("energy", coarse.0, fine.0), ("momentum", coarse.1, fine.1)] {
            assert!(c <= 1e-10, "n = {n}: {what} drift {c:e} at h = 1 ms");
            assert!(c <= 1e-13 || f <= c / 8.0, "n = {n}: {what} drift {c:e} -> {f:e} as h halves");
        }
    }
    eprintln!("torque-free 0.5 s, RK4 h = 1 ms, n = 1..7: worst energy drift {:e}, momentum {:e}", worst.0, worst.1);
}

/// The n = 2 arm is the SRC robot: the inertia matrix, Coriolis terms and forward dynamics of
/// [`crate::dynamics`] and the joint torques of its [`dynamics::joint_torques`] at random motion
/// points (theta relative angles in both), 1e-12 relative, at several mounts, for point-mass links
/// and for links with inertia (folded into the lumped `A`, `B`).
#[test]
fn two_links_have_the_src_dynamics() {
    let mut rng = Rng::new(2);
    // Point masses (the paper's robot), then links with inertia, which the 2-link model folds
    // into its lumped constants A and B.
    for (a, b, i1, i2) in [(0.0, 0.0, 0.0, 0.0), (0.1, 0.1, 0.0, 0.0), (0.3, 0.3, 0.05, 0.02), (-0.7, 0.4, 0.2, 0.01)] {
        let robot = RobotParams { i1, i2, ..RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap() };
        let arm = Arm::from_params(&robot);
        let k = robot.lumped();
        for _ in 0..50 {
            let [phi, t1, t2] = [rng.uniform(-7.0, 7.0), rng.uniform(-7.0, 7.0), rng.uniform(-7.0, 7.0)];
            let dq = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
            let (u, du) = ([dq[1], dq[2]], [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)]);
            let theta = [t1, t2];
            let config = Configuration::new(phi, t1, t2);
            let m = arm.inertia_matrix(&theta);
            let m_src = dynamics::inertia_matrix(&k, t1, t2);
            let scale = m_src.abs().max();
            assert!(
                (0..3).all(|i| (0..3).all(|j| (m[(i, j)] - m_src[(i, j)]).abs() <= 1e-12 * scale)),
                "{m} vs {m_src}"
            );
            let w = DVector::from_column_slice(&dq);
            let c = coriolis(&arm, &theta, &w);
            let c_src = dynamics::coriolis(&k, &config, dq);
            let scale = 1.0 + c_src.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!((0..3).all(|i| (c[i] - c_src[i]).abs() <= 1e-12 * scale), "{c} vs {c_src:?}");
            let tau = inverse_dynamics(&arm, &theta, &u, &du).tau;
            let tau_src = dynamics::joint_torques(&k, &MotionPoint { q: config, u, du });
            let scale = 1.0 + tau_src[0].abs().max(tau_src[1].abs());
            assert!((0..2).all(|i| (tau[i] - tau_src[i]).abs() <= 1e-12 * scale), "{tau} vs {tau_src:?}");
            let forces = [0.0, tau_src[0], tau_src[1]];
            let acc = forward_dynamics(&arm, &theta, &w, &DVector::from_column_slice(&tau_src)).unwrap();
            let acc_src = dynamics::forward_dynamics(&k, &config, dq, forces);
            let scale = 1.0 + acc_src.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!((0..3).all(|i| (acc[i] - acc_src[i]).abs() <= 1e-10 * scale), "{acc} vs {acc_src:?}");
        }
    }
}

#[test]
fn non_finite_angles_are_a_singular_inertia_not_a_panic() {
    let arm = Arm::from_params(&RobotParams::src());
    let e = forward_dynamics(&arm, &[f64::NAN, 0.0], &DVector::zeros(3), &DVector::zeros(2)).unwrap_err();
    assert!(e.to_string().contains("not positive definite"), "{e}");
}

/// The Christoffel terms from the dual-number partials, as the generic path computed them
/// before the lumped constants: `M' q' - 1/2 (q'^T dM/dq_i q')_i`.
fn coriolis_by_partials(partials: &[DMatrix<f64>], dq: &DVector<f64>) -> DVector<f64> {
    let mut m_dot = DMatrix::zeros(dq.len(), dq.len());
    for (k, dm) in partials.iter().enumerate() {
        m_dot += dm * dq[k + 1];
    }
    let mut c = m_dot * dq;
    for (k, dm) in partials.iter().enumerate() {
        c[k + 1] -= 0.5 * dq.dot(&(dm * dq));
    }
    c
}

/// The fast path ([`ArmDynamics`], the lumped constants) equals the generic one (the body
/// Jacobians of [`Arm::inertia_matrix`] and their dual-number derivatives) on random arms of 1
/// to 8 links at random states, to 1e-12 of the values' size: `M` and every `dM/dtheta_k`
/// ([`inertia_matrix_derivatives`] against [`inertia_matrix_derivatives_ad`]), `c`, the inverse
/// dynamics (with `phi'` and `phi''` from the momentum), the forward dynamics (solved from the
/// generic `M` by nalgebra's Cholesky) and the base rate.
#[test]
fn fast_path_equals_the_generic_one_for_n_1_to_8() {
    let mut rng = Rng::new(22);
    let close = |x: f64, y: f64, scale: f64| (x - y).abs() <= 1e-12 * scale.max(1.0);
    for n in 1..=8 {
        for _ in 0..8 {
            let arm = random_arm(n, &mut rng);
            let fast = ArmDynamics::new(&arm);
            let theta = rng.vec(n, -7.0, 7.0);
            let dq = DVector::from_vec(rng.vec(n + 1, -3.0, 3.0));
            let ddtheta = rng.vec(n, -3.0, 3.0);
            let tau = DVector::from_vec(rng.vec(n, -5.0, 5.0));
            let (m, partials) = inertia_matrix_derivatives(&arm, &theta);
            let (m_ad, partials_ad) = inertia_matrix_derivatives_ad(&arm, &theta);
            let scale = m_ad.amax();
            assert!(m.iter().zip(m_ad.iter()).all(|(x, y)| close(*x, *y, scale)), "n = {n}: M");
            for (k, (d, d_ad)) in partials.iter().zip(&partials_ad).enumerate() {
                assert!(d.iter().zip(d_ad.iter()).all(|(x, y)| close(*x, *y, scale)), "n = {n}: dM/dtheta_{}", k + 1);
            }
            let c_ad = coriolis_by_partials(&partials_ad, &dq);
            let c = coriolis(&arm, &theta, &dq);
            let c_scale = max_abs(&c_ad);
            assert!(c.iter().zip(c_ad.iter()).all(|(x, y)| close(*x, *y, c_scale)), "n = {n}: c {c} vs {c_ad}");

            // Inverse dynamics as the generic path did it, from the dual-number M and partials.
            let phi_rate = -(1..=n).map(|j| m_ad[(0, j)] * dq[j]).sum::<f64>() / m_ad[(0, 0)];
            let mut dq0 = dq.clone();
            dq0[0] = phi_rate;
            let c0 = coriolis_by_partials(&partials_ad, &dq0);
            let phi_acc = -((1..=n).map(|j| m_ad[(0, j)] * ddtheta[j - 1]).sum::<f64>() + c0[0]) / m_ad[(0, 0)];
            let ddq = DVector::from_iterator(n + 1, std::iter::once(phi_acc).chain(ddtheta.iter().copied()));
            let forces = &m_ad * &ddq + &c0;
            let inv = fast.inverse(&theta, &dq.as_slice()[1..], &ddtheta);
            let f_scale = max_abs(&forces).max(max_abs(&(&m_ad * &ddq)));
            assert!(close(inv.dq[0], phi_rate, phi_rate.abs()), "n = {n}: phi'");
            assert!(close(inv.ddq[0], phi_acc, phi_acc.abs()), "n = {n}: phi''");
            for j in 0..n {
                assert!(close(inv.tau[j], forces[j + 1], f_scale), "n = {n}: tau_{}", j + 1);
            }
            assert!(inv.base_residual.abs() <= 1e-12 * f_scale.max(1.0));
            let rate = arm.base_rate(&theta, &dq.as_slice()[1..]);
            assert!(close(fast.base_rate(&theta, &dq.as_slice()[1..]), rate, rate.abs()), "n = {n}: base rate");

            let mut rhs = -c_ad;
            for j in 0..n {
                rhs[j + 1] += tau[j];
            }
            let generic = m_ad.clone().cholesky().unwrap().solve(&rhs);
            let mut ddq_fast = vec![0.0; n + 1];
            fast.forward(&theta, dq.as_slice(), tau.as_slice(), &mut ddq_fast).unwrap();
            // The solve amplifies rounding by the condition number of M.
            let a_scale = max_abs(&generic);
            let cond = m_ad.clone().symmetric_eigenvalues();
            let kappa = cond.max() / cond.min();
            for (x, y) in ddq_fast.iter().zip(generic.iter()) {
                assert!((x - y).abs() <= 1e-13 * kappa * a_scale.max(1.0), "n = {n}: q'' {x} vs {y}, cond {kappa}");
            }
        }
    }
}

/// The torques' closed-form sensitivities ([`InverseAt::sensitivities`]) against central
/// differences of the inverse dynamics in the angles and the rates, for n = 1..8 (the torque is
/// quadratic in the rates, so there the differences are exact up to rounding).
#[test]
fn torque_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(20);
    for n in 1..=8 {
        for _ in 0..6 {
            let arm = random_arm(n, &mut rng);
            let fast = ArmDynamics::new(&arm);
            let theta = rng.vec(n, -7.0, 7.0);
            let dtheta = rng.vec(n, -3.0, 3.0);
            let ddtheta = rng.vec(n, -3.0, 3.0);
            let (mut angles, mut rates) = ([[0.0; SIZE]; SIZE], [[0.0; SIZE]; SIZE]);
            fast.at_angles(&theta).sensitivities(&dtheta, &ddtheta, &mut angles, &mut rates);
            let tau = |th: &[f64], w: &[f64]| fast.inverse(th, w, &ddtheta).tau;
            let scale = tau(&theta, &dtheta).amax().max(1.0);
            for k in 0..n {
                for (which, exact) in [(0, &angles), (1, &rates)] {
                    let h = 1e-5;
                    let (mut up, mut down) = ([theta.clone(), dtheta.clone()], [theta.clone(), dtheta.clone()]);
                    up[which][k] += h;
                    down[which][k] -= h;
                    let diff = (tau(&up[0], &up[1]) - tau(&down[0], &down[1])) / (2.0 * h);
                    for j in 0..n {
                        assert!(
                            (exact[j][k] - diff[j]).abs() <= 1e-6 * scale,
                            "n = {n}, d tau_{j} / d {}_{k}: {} vs {}",
                            ["theta", "theta'"][which],
                            exact[j][k],
                            diff[j]
                        );
                    }
                }
            }
        }
    }
}
