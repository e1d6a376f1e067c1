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

/// The elbow of an inverse-kinematics solution: the sign of `sin(theta1 - mu)`, where `mu` is
/// the direction of the mounting point `(a, b)` in the base frame (for `a = b = 0`, of
/// `sin theta1`'s solution family, see [`inverse_kinematics`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Elbow {
    /// `sin(theta1 - mu) >= 0`.
    Up,
    /// `sin(theta1 - mu) < 0`.
    Down,
}

/// An end-effector pose the arm cannot take: the wrist point's distance from the system's centre
/// of mass and the reachable range.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "the end-effector pose (x, y, psi) = ({x:.4} m, {y:.4} m, {psi_deg:.2} deg) is out of reach: its wrist point \
     lies {distance:.4} m from the system's centre of mass, reachable is {min:.4} to {max:.4} m"
)]
pub struct Unreachable {
    /// `x` \[m\].
    pub x: f64,
    /// `y` \[m\].
    pub y: f64,
    /// `psi` \[deg\].
    pub psi_deg: f64,
    /// Distance of the wrist point `(x, y) - L2 (cos psi, sin psi)` from the origin \[m\].
    pub distance: f64,
    /// Smallest reachable distance \[m\].
    pub min: f64,
    /// Largest reachable distance \[m\].
    pub max: f64,
}

/// The configurations that put the end-effector at `(x, y, psi)` (inertial frame, the system's
/// centre of mass at the origin; `psi = phi + theta1 + theta2`): the free-floating inverse
/// kinematics, in closed form.
///
/// From [`bodies`], the tip is `(M/m_c) R(phi) (a, b) + L1 e(phi + theta1) + L2 e(psi)` with
/// `L1 = l1 - (m1 d1 + m2 l1)/m_c`, `L2 = l2 - m2 d2/m_c` (the base moves so that the centre of
/// mass stays put). So the wrist point `p = (x, y) - L2 e(psi)` is reached by a two-link chain
/// of lengths `rho = (M/m_c) |(a, b)|` (the mount, turning with `phi`) and `L1`: two solutions,
/// [`Elbow::Up`] and [`Elbow::Down`], when `|rho - L1| <= |p| <= rho + L1`. At `a = b = 0` the
/// pose fixes `phi + theta1` but not `phi`: `phi` is taken as `phi_hint` and the two solutions
/// coincide. Angles are returned in `(-pi, pi]`.
pub fn inverse_kinematics(
    robot: &RobotParams,
    (x, y, psi): (f64, f64, f64),
    phi_hint: f64,
) -> Result<Vec<(Elbow, Configuration)>, Unreachable> {
    let RobotParams { l1, l2, d1, d2, base_mass, m1, m2, mount, .. } = *robot;
    let mc = base_mass + m1 + m2;
    let (big_l1, big_l2) = (l1 - (m1 * d1 + m2 * l1) / mc, l2 - m2 * d2 / mc);
    let rho = base_mass / mc * mount.a.hypot(mount.b);
    let mu = mount.b.atan2(mount.a);
    let p = [x - big_l2 * psi.cos(), y - big_l2 * psi.sin()];
    let distance = p[0].hypot(p[1]);
    let (min, max) = ((rho - big_l1).abs(), rho + big_l1);
    let tolerance = 1e-12 * max;
    let unreachable = Unreachable { x, y, psi_deg: psi.to_degrees(), distance, min, max };
    if !(distance >= min - tolerance && distance <= max + tolerance) {
        return Err(unreachable);
    }
    let wrap = |a: f64| crate::model::wrap_angle(a);
    let direction = p[1].atan2(p[0]);
    if rho <= 1e-12 * big_l1 {
        // a = b = 0: phi + theta1 = direction, phi free.
        let phi = phi_hint;
        let theta1 = wrap(direction - phi);
        let q = Configuration::new(phi, theta1, wrap(psi - phi - theta1));
        let elbow = if (theta1 - mu).sin() >= 0.0 { Elbow::Up } else { Elbow::Down };
        return Ok(vec![(elbow, q)]);
    }
    let cos_delta = ((distance * distance - rho * rho - big_l1 * big_l1) / (2.0 * rho * big_l1)).clamp(-1.0, 1.0);
    let delta = cos_delta.acos();
    let mut out = Vec::with_capacity(2);
    for (elbow, d) in [(Elbow::Up, delta), (Elbow::Down, -delta)] {
        // p = rho e(phi + mu) + L1 e(phi + mu + d): the chain's first direction phi + mu; at the
        // edge of the reach (|cos d| = 1) the two elbows coincide.
        let phi = wrap(direction - (big_l1 * d.sin()).atan2(rho + big_l1 * d.cos()) - mu);
        let theta1 = wrap(d + mu);
        out.push((elbow, Configuration::new(phi, theta1, wrap(psi - phi - theta1))));
        if cos_delta.abs() >= 1.0 {
            break;
        }
    }
    Ok(out)
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

    /// Inverse kinematics inverts the forward kinematics: at random configurations and mounts,
    /// every solution returned puts the end-effector at the pose (1e-12), one of them is the
    /// configuration the pose came from (angles mod 2 pi), and the elbows differ.
    #[test]
    fn inverse_kinematics_round_trips() {
        let mut x = 0.61_f64;
        let mut next = || {
            x = (x * 991.0 + 0.317).fract();
            x
        };
        for k in 0..300 {
            let (a, b) = if k % 10 == 0 { (0.0, 0.0) } else { (3.0 * next() - 1.5, 3.0 * next() - 1.5) };
            let robot = RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap();
            let q = Configuration::new(6.0 * next() - 3.0, 6.0 * next() - 3.0, 6.0 * next() - 3.0);
            let tip = pose(&robot, &q).tip;
            let psi = q.phi + q.theta1 + q.theta2;
            let solutions = inverse_kinematics(&robot, (tip[0], tip[1], psi), q.phi).expect("reachable");
            let mut found = false;
            for (_, s) in &solutions {
                let t = pose(&robot, s).tip;
                assert!((t[0] - tip[0]).abs() < 1e-12 && (t[1] - tip[1]).abs() < 1e-12, "{q:?} -> {s:?}");
                assert!(crate::model::wrap_angle(s.phi + s.theta1 + s.theta2 - psi).abs() < 1e-12);
                found |= s.distance(&q) < 1e-9;
            }
            assert!(found, "{q:?} not among {solutions:?} (a, b = {a}, {b})");
            if solutions.len() == 2 {
                assert_ne!(solutions[0].0, solutions[1].0);
            }
        }
        let robot = RobotParams::src().with_mount(Mount::new(0.2, 0.1).unwrap()).unwrap();
        let e = inverse_kinematics(&robot, (5.0, 0.0, 0.0), 0.0).unwrap_err();
        assert!(e.distance > e.max && e.to_string().contains("out of reach"), "{e}");
    }
}
