//! The lumped constants against the paper's (Eq. 3 at n = 2) and the closed forms against the
//! body-Jacobian model of [`Arm::inertia_matrix`].

use super::*;
use crate::model::arm::tests::{Rng, random_arm};
use crate::model::{Mount, RobotParams};

fn close(x: f64, y: f64, scale: f64) -> bool {
    (x - y).abs() <= 1e-12 * scale.max(1.0)
}

/// At n = 2 the constants are the paper's lumped constants of Sec. 3.1 (Eq. 3):
/// `K_00 (a^2 + b^2) + I = I_P`, `K_11 + I_1 = A`, `K_22 + I_2 = B`, `K_12 = C`, `K_01 = D`,
/// `K_02 = E`; and the first row of `M` is `F, G, H` of Eq. (8), with link inertias too.
#[test]
fn two_links_give_the_papers_constants() {
    for (a, b, i1, i2) in [(0.0, 0.0, 0.0, 0.0), (0.1, 0.1, 0.0, 0.0), (1.0, -1.0, 0.02, 0.01), (-0.7, 0.3, 0.1, 0.0)] {
        let robot = RobotParams { i1, i2, ..RobotParams::src() }.with_mount(Mount::new(a, b).unwrap()).unwrap();
        let k = robot.lumped();
        let t = ArmLumped::new(&Arm::from_params(&robot));
        let r2 = a * a + b * b;
        let pairs = [
            (t.constant(0, 0) * r2 + t.rotational(0), k.IP),
            (t.constant(1, 1) + t.rotational(1), k.A),
            (t.constant(2, 2) + t.rotational(2), k.B),
            (t.constant(1, 2), k.C),
            (t.constant(0, 1), k.D),
            (t.constant(0, 2), k.E),
        ];
        for (i, (x, y)) in pairs.into_iter().enumerate() {
            assert!(close(x, y, y.abs()), "constant {i}: {x} vs {y}");
        }
        for (t1, t2) in [(0.3, -1.2), (2.5, 0.7), (-3.0, 3.0)] {
            let s = crate::model::system::shape(&k, t1, t2);
            let mut row = [0.0; SIZE];
            t.terms(&[t1, t2]).momentum_row(&mut row);
            for (x, y) in [(row[0], s.F), (row[1], s.G), (row[2], s.H)] {
                assert!(close(x, y, y.abs()), "{x} vs {y}");
            }
        }
    }
}

/// On random arms of 1 to 8 links at random configurations, the closed-form `M`, its first row
/// and `dM/dtheta_k` equal the body-Jacobian [`Arm::inertia_matrix`], its
/// [`Arm::momentum_coefficients`] and its dual-number derivatives to 1e-12 of `|M|`.
#[test]
fn closed_forms_equal_the_body_model_for_n_1_to_8() {
    let mut rng = Rng::new(20);
    for n in 1..=8 {
        for _ in 0..6 {
            let arm = random_arm(n, &mut rng);
            let theta = rng.vec(n, -7.0, 7.0);
            let table = ArmLumped::new(&arm);
            let terms = table.terms(&theta);
            let mut m = [[0.0; SIZE]; SIZE];
            terms.inertia_matrix(&mut m);
            let reference = arm.inertia_matrix(&theta);
            let scale = reference.amax();
            for i in 0..=n {
                for j in 0..=n {
                    assert!(close(m[i][j], reference[(i, j)], scale), "n = {n} M[{i}][{j}]");
                }
            }
            let (f, g) = arm.momentum_coefficients(&theta);
            let mut row = [0.0; SIZE];
            terms.momentum_row(&mut row);
            assert!(close(row[0], f, scale));
            for j in 0..n {
                assert!(close(row[j + 1], g[j], scale), "n = {n} G[{j}]");
            }
            for k in 1..=n {
                let seeded: Vec<num_dual::Dual64> = theta
                    .iter()
                    .enumerate()
                    .map(|(j, &t)| num_dual::Dual64::new(t, if j + 1 == k { 1.0 } else { 0.0 }))
                    .collect();
                let dual = arm.inertia_matrix(&seeded);
                terms.inertia_derivative(k, &mut m);
                for i in 0..=n {
                    for j in 0..=n {
                        assert!(close(m[i][j], dual[(i, j)].eps, scale), "n = {n} dM/dtheta_{k}[{i}][{j}]");
                    }
                }
            }
        }
    }
}
