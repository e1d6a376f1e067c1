//! Where the robot's bodies are in the plane (Sec. 3.1): positions from the configuration, with
//! the system's centre of mass at the origin (Eq. 4 at zero linear momentum).

use num_dual::Dual64;
use serde::Serialize;

use super::{Configuration, RobotParams};
use crate::Scalar;

/// Where the robot's bodies are in the plane for a configuration \[m\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pose {
    /// Centre of mass of the base.
    pub base: [f64; 2],
    /// The mounting point (joint 1).
    pub joint1: [f64; 2],
    /// Joint 2 (the elbow).
    pub joint2: [f64; 2],
    /// The end of link 2 (the end-effector).
    pub tip: [f64; 2],
}

/// The pose of `robot` at `q`, with the system's centre of mass at the origin: Eq. (4) with zero
/// linear momentum (`p1 = p2 = 0`) keeps it there. The base's centre of mass `r_b` solves
/// `M r_b + m1 r_1 + m2 r_2 = 0`, where `r_1`, `r_2` are the links' centres of mass; link 1
/// points at the absolute angle `phi + theta1`, link 2 at `phi + theta1 + theta2` (Eq. 3).
pub fn pose(robot: &RobotParams, q: &Configuration) -> Pose {
    let b = bodies(robot, q.to_array());
    Pose { base: b.base, joint1: b.joint1, joint2: b.joint2, tip: b.tip }
}

/// The points of the robot at `q` \[m\], generic over [`Scalar`] so that their velocities come
/// from a dual number along `q'`: see [`pose`] for the frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bodies<D> {
    /// Centre of mass of the base.
    pub base: [D; 2],
    /// The mounting point (joint 1).
    pub joint1: [D; 2],
    /// Joint 2 (the elbow).
    pub joint2: [D; 2],
    /// The end of link 2 (the end-effector).
    pub tip: [D; 2],
    /// Centre of mass of link 1.
    pub link1: [D; 2],
    /// Centre of mass of link 2.
    pub link2: [D; 2],
}

/// [`Bodies`] of `robot` at `q = (phi, theta1, theta2)` \[rad\].
pub fn bodies<D: Scalar>(robot: &RobotParams, q: [D; 3]) -> Bodies<D> {
    let RobotParams { l1, l2, d1, d2, base_mass, m1, m2, mount, .. } = *robot;
    let (sp, cp) = q[0].sin_cos();
    let (s1, c1) = (q[0] + q[1]).sin_cos();
    let (s12, c12) = (q[0] + q[1] + q[2]).sin_cos();
    let offset = [cp * mount.a - sp * mount.b, sp * mount.a + cp * mount.b];
    let mc = base_mass + m1 + m2;
    let (e1, e12) = ([c1, s1], [c12, s12]);
    let base: [D; 2] =
        std::array::from_fn(|i| -(offset[i] * (m1 + m2) + e1[i] * (m1 * d1 + m2 * l1) + e12[i] * (m2 * d2)) / mc);
    let joint1 = [base[0] + offset[0], base[1] + offset[1]];
    let joint2 = [joint1[0] + e1[0] * l1, joint1[1] + e1[1] * l1];
    let tip = [joint2[0] + e12[0] * l2, joint2[1] + e12[1] * l2];
    let link1 = [joint1[0] + e1[0] * d1, joint1[1] + e1[1] * d1];
    let link2 = [joint2[0] + e12[0] * d2, joint2[1] + e12[1] * d2];
    Bodies { base, joint1, joint2, tip, link1, link2 }
}

/// The task-space state of the robot at one instant, in the inertial frame with the system's
/// centre of mass at the origin (SI units, radians, counter-clockwise).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct TaskPoint {
    /// Base centre of mass `(xb, yb)` \[m\].
    pub base: [f64; 2],
    /// End-effector pose `(xe, ye, psie)`: the tip of link 2 \[m\] and the link's absolute angle
    /// `psie = phi + theta1 + theta2` \[rad\].
    pub end_effector: [f64; 3],
    /// Its velocity `(xe', ye', psie')` \[m/s, rad/s\].
    pub end_effector_velocity: [f64; 3],
}

/// The [`TaskPoint`] at `q` moving with `dq = q'` \[rad/s\] (exact: a dual number along `dq`).
pub fn task_point(robot: &RobotParams, q: [f64; 3], dq: [f64; 3]) -> TaskPoint {
    let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(q[i], dq[i]));
    let b = bodies(robot, qd);
    TaskPoint {
        base: [b.base[0].re, b.base[1].re],
        end_effector: [b.tip[0].re, b.tip[1].re, q[0] + q[1] + q[2]],
        end_effector_velocity: [b.tip[0].eps, b.tip[1].eps, dq[0] + dq[1] + dq[2]],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mount;

    /// The pose keeps the system's centre of mass at the origin and the links at their lengths.
    #[test]
    fn pose_has_the_centre_of_mass_at_the_origin() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        for q in [[0.3, 2.0, 1.4], [-1.0, 0.2, -2.5], [4.0, -3.0, 0.7]] {
            let p = pose(&robot, &Configuration::from_array(q));
            let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
            assert!((dist(p.joint1, p.joint2) - robot.l1).abs() < 1e-12);
            assert!((dist(p.joint2, p.tip) - robot.l2).abs() < 1e-12);
            assert!((dist(p.base, p.joint1) - 2f64.sqrt()).abs() < 1e-12);
            let at = |a: [f64; 2], b: [f64; 2], f: f64| [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])];
            let r1 = at(p.joint1, p.joint2, robot.d1 / robot.l1);
            let r2 = at(p.joint2, p.tip, robot.d2 / robot.l2);
            for i in 0..2 {
                let com = robot.base_mass * p.base[i] + robot.m1 * r1[i] + robot.m2 * r2[i];
                assert!(com.abs() < 1e-12, "{com}");
            }
        }
    }

    /// Along a motion of system (7) (`q' = g1 u1 + g2 u2`, Eq. 7) the bodies, moved by dual
    /// numbers, keep the centre of mass at rest and carry zero angular momentum about it: the
    /// momentum equations (4)-(5) recomputed from the bodies, at random configurations.
    #[test]
    fn task_velocities_conserve_both_momenta() {
        let robot = RobotParams::src().with_mount(Mount::new(0.3, -0.7).unwrap()).unwrap();
        let k = robot.lumped();
        let mut x = 0.37_f64;
        let mut next = || {
            x = (x * 997.0 + 0.123).fract();
            6.0 * x - 3.0
        };
        for _ in 0..200 {
            let q = [next(), next(), next()];
            let dq = crate::model::system::velocity(&k, q, [next(), next()]);
            let qd: [Dual64; 3] = std::array::from_fn(|i| Dual64::new(q[i], dq[i]));
            let b = bodies(&robot, qd);
            let masses = [(b.base, robot.base_mass), (b.link1, robot.m1), (b.link2, robot.m2)];
            let (mut p, mut l) = ([0.0; 2], 0.0);
            for (r, m) in masses {
                for i in 0..2 {
                    p[i] += m * r[i].eps;
                }
                l += m * (r[0].re * r[1].eps - r[1].re * r[0].eps);
            }
            // Point-mass links (Sec. 3.1): only the base has a moment of inertia.
            l += robot.base_inertia * dq[0];
            assert!(p[0].abs() < 1e-12 && p[1].abs() < 1e-12, "linear momentum {p:?}");
            assert!(l.abs() < 1e-12, "angular momentum {l}");
            let t = task_point(&robot, q, dq);
            let tip = pose(&robot, &Configuration::from_array(q)).tip;
            assert!((t.end_effector[0] - tip[0]).abs() < 1e-15 && (t.end_effector[1] - tip[1]).abs() < 1e-15);
            assert!((t.end_effector_velocity[0] - b.tip[0].eps).abs() < 1e-15);
        }
    }
}
