//! Where the robot's bodies are in the plane (Sec. 3.1): positions from the configuration, with
//! the system's centre of mass at the origin (Eq. 4 at zero linear momentum).

use serde::Serialize;

use super::{Configuration, RobotParams};

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
    let RobotParams { l1, l2, d1, d2, base_mass, m1, m2, mount, .. } = *robot;
    let (sp, cp) = q.phi.sin_cos();
    let (s1, c1) = (q.phi + q.theta1).sin_cos();
    let (s12, c12) = (q.phi + q.theta1 + q.theta2).sin_cos();
    let mount_offset = [cp * mount.a - sp * mount.b, sp * mount.a + cp * mount.b];
    let mc = base_mass + m1 + m2;
    let base: [f64; 2] = std::array::from_fn(|i| {
        let (e1, e12) = if i == 0 { (c1, c12) } else { (s1, s12) };
        -((m1 + m2) * mount_offset[i] + (m1 * d1 + m2 * l1) * e1 + m2 * d2 * e12) / mc
    });
    let joint1 = [base[0] + mount_offset[0], base[1] + mount_offset[1]];
    let joint2 = [joint1[0] + l1 * c1, joint1[1] + l1 * s1];
    let tip = [joint2[0] + l2 * c12, joint2[1] + l2 * s12];
    Pose { base, joint1, joint2, tip }
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
}
