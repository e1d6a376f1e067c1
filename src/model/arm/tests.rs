//! Tests of the arm model: the energy and momentum identities by AD for n = 1..7, the n = 2
//! point-mass equivalence with the SRC robot, the robot file and the URDF round trips and errors.

use super::*;
use crate::model::system::shape;

/// At n = 2 with point-mass links the general model's `F, G_1, G_2` are the SRC robot's
/// `F, G, H` of Eq. (8), at random configurations and mounts.
#[test]
fn two_point_mass_links_are_the_src_robot() {
    for (i, (a, b)) in [(0.0, 0.0), (0.1, 0.1), (1.0, -1.0), (-0.7, 0.3)].into_iter().enumerate() {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
        let arm = Arm::from_params(&robot);
        let k = robot.lumped();
        for j in 0..20 {
            let t1 = -3.0 + 0.31 * j as f64 + 0.1 * i as f64;
            let t2 = 2.9 - 0.27 * j as f64;
            let s = shape(&k, t1, t2);
            let (f, g) = arm.momentum_coefficients(&[t1, t2]);
            for (x, y) in [(f, s.F), (g[0], s.G), (g[1], s.H)] {
                assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{x} vs {y}");
            }
        }
    }
}
