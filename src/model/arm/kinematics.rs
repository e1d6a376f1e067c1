//! Where an arm's tool point is, how fast it moves, and which configurations put it at a given
//! pose: the free-floating forward and inverse kinematics of any planar serial arm (Sec. 3.1 for
//! `n` links), the system's centre of mass at the origin (zero linear momentum, Eq. 4).
//!
//! The tool point is the tip of link `n`: for a robot file with `[[link]]` the end of the last
//! link, for a URDF the origin of its tool frame (docs/spec.md §1, URDF), which sets the last
//! link's length. Its orientation `psi` is the last link's absolute angle
//! `psi_n = phi + theta_1 + .. + theta_n`.
//!
//! With the centre of mass at the origin the tool point is a planar chain of effective lengths
//! (the base moves so that the centre of mass stays put):
//! `p = rho e(phi + mu) + sum_k L_k e(psi_k)` with `rho = (M / m_c) |(a, b)|`, `mu` the mount's
//! direction in the base frame and `L_k = l_k - (m_k d_k + l_k sum_{j > k} m_j) / m_c > 0`
//! ([`Arm::reach_chain`]). For a pose `(x, y, psi)` the wrist point `w = (x, y) - L_n e(psi)`
//! must then be reached by the chain `rho, L_1, .., L_{n-1}` with free directions.

use num_dual::Dual64;
use serde::Serialize;

use super::Arm;
use crate::Scalar;
use crate::model::kinematics::{TaskPoint, Unreachable};

/// The effective chain of the tool point ([the module doc](self)).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReachChain {
    /// `rho = (M / m_c) |(a, b)|` \[m\]: the mount's arm, turning with `phi + mu`.
    pub rho: f64,
    /// `mu`: the direction of the mount `(a, b)` in the base frame \[rad\].
    pub mu: f64,
    /// `L_1..L_n` \[m\], each positive.
    pub lengths: Vec<f64>,
}

/// One solution branch tried by [`Arm::inverse_kinematics`]: the closed form's (`unique`, `up`,
/// `down`), or a damped Newton (Levenberg–Marquardt) run from a named seed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkBranch {
    /// The branch: `unique`, `up`/`down` (the sign of the bend between the two free links of the
    /// closed form), or `seed: ...` (where the iteration started).
    pub branch: String,
    /// The configuration `(phi, theta_1..theta_n)` \[rad\], each angle the representative nearest
    /// the start's.
    pub q: Vec<f64>,
    /// Distance of the tool point of `q` from the pose's `(x, y)` \[m\] (the forward kinematics,
    /// [`Arm::tool_point`]); its orientation is exact by construction.
    pub residual: f64,
    /// `residual <= ` [`IK_TOLERANCE`] times the arm's reach.
    pub reached: bool,
    /// Damped Newton iterations (0 for the closed form).
    pub iterations: usize,
}

/// Relative tolerance of the inverse kinematics: a branch reaches the pose when its tool point is
/// within this times the reach (`rho + sum L_k`) of it.
pub const IK_TOLERANCE: f64 = 1e-10;

/// Iterations of the damped Newton method per seed.
const IK_ITERATIONS: usize = 200;

impl Arm {
    /// The tool point `(x, y)` \[m\] at `q = (phi, theta_1..theta_n)`, relative to the system's
    /// centre of mass: the last point of [`Arm::joint_positions`], generic over [`Scalar`].
    pub fn tool_point<D: Scalar>(&self, q: &[D]) -> [D; 2] {
        let base = self.bodies(q).base;
        let (sp, cp) = q[0].sin_cos();
        let (a, b) = (self.mount.a, self.mount.b);
        let mut p = [base[0] + cp * a - sp * b, base[1] + sp * a + cp * b];
        let mut psi = q[0];
        for (link, &theta) in self.links.iter().zip(&q[1..]) {
            psi += theta;
            let (s, c) = psi.sin_cos();
            p = [p[0] + c * link.length, p[1] + s * link.length];
        }
        p
    }

    /// The task-space state at `q` (`n + 1` values) moving with `dq = q'` \[rad/s\]: the base's
    /// centre of mass, the tool's pose `(x, y, psi)` and its velocity, exact (a dual number
    /// along `dq`). The same [`TaskPoint`] as the 2-link robot's
    /// ([`crate::model::kinematics::task_point`]).
    pub fn task_point(&self, q: &[f64], dq: &[f64]) -> TaskPoint {
        let qd: Vec<Dual64> = q.iter().zip(dq).map(|(x, v)| Dual64::new(*x, *v)).collect();
        let base = self.bodies(&qd).base;
        let tip = self.tool_point(&qd);
        TaskPoint {
            base: [base[0].re, base[1].re],
            end_effector: [tip[0].re, tip[1].re, q.iter().sum()],
            end_effector_velocity: [tip[0].eps, tip[1].eps, dq.iter().sum()],
        }
    }

    /// The effective chain of the tool point ([the module doc](self)).
    pub fn reach_chain(&self) -> ReachChain {
        let total = self.total_mass();
        let mut beyond: f64 = self.links.iter().map(|l| l.mass).sum();
        let mut lengths = Vec::with_capacity(self.joints());
        for link in &self.links {
            beyond -= link.mass;
            lengths.push(link.length - (link.mass * link.com + link.length * beyond) / total);
        }
        ReachChain {
            rho: self.base.mass / total * self.mount.a.hypot(self.mount.b),
            mu: self.mount.b.atan2(self.mount.a),
            lengths,
        }
    }

    /// The configurations that put the tool at `(x, y, psi)` (\[m, m, rad\], the system's centre of
    /// mass at the origin), every branch tried, near `start` (`n + 1` values: each angle is
    /// returned as the representative nearest the start's, and `phi` is the start's where the
    /// pose leaves it free, i.e. at a mount on the base's centre of mass).
    ///
    /// The wrist point `w` ([the module doc](self)) is reached by the free links of the chain
    /// `rho, L_1..L_{n-1}` (`rho` only when it is not 0). One free link (`n = 1`, or `n = 2` at a
    /// centred mount): the unique solution. Two (`n = 2`, or `n = 3` at a centred mount): the
    /// closed form's two bends, `up` and `down` (one at the edge of the reach), as the 2-link
    /// robot's ([`crate::model::kinematics::inverse_kinematics`]). More (`n >= 3`): a redundant
    /// family; a damped Newton (Levenberg–Marquardt, minimum-norm steps) from four seeds (the
    /// start, the start mirrored about the line to `w`, and the chain curled either way towards
    /// `w`). Each branch carries its residual by the forward kinematics; the caller keeps those
    /// that reach.
    ///
    /// A wrist point outside the annulus `[max(0, 2 max - sum), sum]` of the free lengths is
    /// [`Unreachable`], with the reach.
    pub fn inverse_kinematics(
        &self,
        (x, y, psi): (f64, f64, f64),
        start: &[f64],
    ) -> Result<Vec<IkBranch>, Unreachable> {
        let n = self.joints();
        let chain = self.reach_chain();
        let scale = chain.rho + chain.lengths.iter().sum::<f64>();
        let last = chain.lengths[n - 1];
        let w = [x - last * psi.cos(), y - last * psi.sin()];
        let distance = w[0].hypot(w[1]);
        // The free links: (length, index in the chain's directions alpha_0 = phi + mu, alpha_k = psi_k).
        let fixed_mount = chain.rho <= 1e-12 * scale;
        let mut free: Vec<(f64, usize)> = Vec::with_capacity(n);
        if !fixed_mount {
            free.push((chain.rho, 0));
        }
        free.extend(chain.lengths[..n - 1].iter().enumerate().map(|(k, &l)| (l, k + 1)));
        let sum: f64 = free.iter().map(|f| f.0).sum();
        let longest = free.iter().map(|f| f.0).fold(0.0, f64::max);
        let (min, max) = ((2.0 * longest - sum).max(0.0), sum);
        let tolerance = if free.len() == 1 { 1e-9 * scale } else { 1e-12 * scale };
        if !(distance >= min - tolerance && distance <= max + tolerance) {
            return Err(Unreachable { x, y, psi_deg: psi.to_degrees(), distance, min, max });
        }
        // The start's chain directions; the fixed ones stay.
        let mut alpha_start = Vec::with_capacity(n);
        alpha_start.push(start[0] + chain.mu);
        let mut s = start[0];
        for theta in &start[1..n] {
            s += theta;
            alpha_start.push(s);
        }
        let beta = w[1].atan2(w[0]);
        let mut candidates: Vec<(String, Vec<f64>, usize)> = Vec::new();
        match free.as_slice() {
            [] => candidates.push(("unique".into(), alpha_start.clone(), 0)),
            [(_, k)] => {
                let mut alpha = alpha_start.clone();
                alpha[*k] = beta;
                candidates.push(("unique".into(), alpha, 0));
            }
            [(r1, k1), (r2, k2)] => {
                let cos_delta = ((distance * distance - r1 * r1 - r2 * r2) / (2.0 * r1 * r2)).clamp(-1.0, 1.0);
                let delta = cos_delta.acos();
                for (name, d) in [("up", delta), ("down", -delta)] {
                    let mut alpha = alpha_start.clone();
                    alpha[*k1] = beta - (r2 * d.sin()).atan2(r1 + r2 * d.cos());
                    alpha[*k2] = alpha[*k1] + d;
                    candidates.push((name.into(), alpha, 0));
                    if cos_delta.abs() >= 1.0 {
                        break;
                    }
                }
            }
            _ => {
                let m = free.len() as f64;
                let curl = |sign: f64| {
                    let mut alpha = alpha_start.clone();
                    for (i, (_, k)) in free.iter().enumerate() {
                        alpha[*k] = beta + sign * 0.6 * (i as f64 - (m - 1.0) / 2.0);
                    }
                    alpha
                };
                let mut mirrored = alpha_start.clone();
                for (_, k) in &free {
                    mirrored[*k] = 2.0 * beta - alpha_start[*k];
                }
                let seeds = [
                    ("seed: the start", alpha_start.clone()),
                    ("seed: the start mirrored about the line to the wrist point", mirrored),
                    ("seed: curled counter-clockwise towards the wrist point", curl(1.0)),
                    ("seed: curled clockwise towards the wrist point", curl(-1.0)),
                ];
                for (name, seed) in seeds {
                    let (alpha, iterations) = damped_newton(&chain, &free, seed, w, scale);
                    candidates.push((name.into(), alpha, iterations));
                }
            }
        }
        let near =
            |x: f64, reference: f64| x + std::f64::consts::TAU * ((reference - x) / std::f64::consts::TAU).round();
        Ok(candidates
            .into_iter()
            .map(|(branch, alpha, iterations)| {
                // alpha -> q: phi = alpha_0 - mu, theta_k = psi_k - psi_{k-1}, psi_n = psi.
                let phi = if fixed_mount { start[0] } else { alpha[0] - chain.mu };
                let mut q = Vec::with_capacity(n + 1);
                q.push(near(phi, start[0]));
                let mut previous = phi;
                for k in 1..=n {
                    let psi_k = if k == n { psi } else { alpha[k] };
                    q.push(near(psi_k - previous, start[k]));
                    previous = psi_k;
                }
                let tip = self.tool_point(&q);
                let residual = (tip[0] - x).hypot(tip[1] - y);
                let reached = residual <= IK_TOLERANCE * scale.max(1e-3);
                IkBranch { branch, q, residual, reached, iterations }
            })
            .collect())
    }
}

/// Damped Newton (Levenberg–Marquardt) on the chain's free directions: minimum-norm steps
/// `J^T (J J^T + lambda I)^-1 (w - p)` with the damping `lambda` lowered after a step that
/// shrinks the residual and raised after one that does not.
///
/// ## Reference
/// Wampler, C. W. (1986). Manipulator inverse kinematic solutions based on vector formulations
/// and damped least-squares methods. IEEE Trans. Systems, Man, and Cybernetics 16(1), 93–101.
/// <https://doi.org/10.1109/TSMC.1986.289285>
fn damped_newton(
    chain: &ReachChain,
    free: &[(f64, usize)],
    mut alpha: Vec<f64>,
    w: [f64; 2],
    scale: f64,
) -> (Vec<f64>, usize) {
    let lengths: Vec<f64> =
        std::iter::once(chain.rho).chain(chain.lengths[..chain.lengths.len() - 1].iter().copied()).collect();
    let point = |alpha: &[f64]| {
        let mut p = [0.0, 0.0];
        for (l, a) in lengths.iter().zip(alpha) {
            p = [p[0] + l * a.cos(), p[1] + l * a.sin()];
        }
        [w[0] - p[0], w[1] - p[1]]
    };
    let norm = |r: [f64; 2]| r[0].hypot(r[1]);
    let mut r = point(&alpha);
    let mut lambda = 1e-2 * scale * scale;
    let target = 1e-2 * IK_TOLERANCE * scale.max(1e-3);
    for iteration in 0..IK_ITERATIONS {
        if norm(r) <= target {
            return (alpha, iteration);
        }
        // J: 2 x free, column k = L_k e_perp(alpha_k).
        let columns: Vec<[f64; 2]> = free.iter().map(|(l, k)| [-l * alpha[*k].sin(), l * alpha[*k].cos()]).collect();
        let mut jjt = [[lambda, 0.0], [0.0, lambda]];
        for c in &columns {
            jjt[0][0] += c[0] * c[0];
            jjt[0][1] += c[0] * c[1];
            jjt[1][1] += c[1] * c[1];
        }
        jjt[1][0] = jjt[0][1];
        let det = jjt[0][0] * jjt[1][1] - jjt[0][1] * jjt[1][0];
        if !(det.is_finite() && det > 0.0) {
            lambda *= 4.0;
            continue;
        }
        let y = [(jjt[1][1] * r[0] - jjt[0][1] * r[1]) / det, (jjt[0][0] * r[1] - jjt[1][0] * r[0]) / det];
        let mut trial = alpha.clone();
        for ((_, k), c) in free.iter().zip(&columns) {
            trial[*k] += c[0] * y[0] + c[1] * y[1];
        }
        let r_trial = point(&trial);
        if norm(r_trial) < norm(r) {
            (alpha, r) = (trial, r_trial);
            lambda = (lambda / 3.0).max(1e-30 * scale * scale);
        } else {
            lambda *= 4.0;
        }
    }
    (alpha, IK_ITERATIONS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::arm::{Base, Link};
    use crate::model::{Configuration, Mount, RobotParams};

    fn arm(n: usize, mount: (f64, f64)) -> Arm {
        let links = (0..n)
            .map(|k| {
                let length = 0.5 - 0.05 * k as f64;
                let mass = 3.0 - 0.5 * k as f64;
                Link { length, com: 0.45 * length, mass, inertia: mass * length * length / 12.0 }
            })
            .collect();
        Arm::new(Base { mass: 15.0, inertia: 0.4 }, Mount::new(mount.0, mount.1).unwrap(), links).unwrap()
    }

    /// The tool point is the tip of [`Arm::joint_positions`], and its velocity is the central
    /// difference of positions along `q'` (to 1e-7: the difference's truncation at h = 1e-5).
    #[test]
    fn the_task_point_is_the_tip_and_moves_with_q() {
        let a = arm(4, (0.2, -0.1));
        let q = [0.3, 0.7, -1.1, 0.4, 2.0];
        let dq = [-0.2, 0.5, 0.3, -0.7, 0.1];
        let tip = a.task_point(&q, &dq);
        let drawn = *a.joint_positions(&q).last().unwrap();
        assert!((tip.end_effector[0] - drawn[0]).abs() < 1e-14 && (tip.end_effector[1] - drawn[1]).abs() < 1e-14);
        assert!((tip.end_effector[2] - q.iter().sum::<f64>()).abs() < 1e-15);
        let h = 1e-5;
        let at = |s: f64| a.tool_point(&q.iter().zip(&dq).map(|(x, v)| x + s * v).collect::<Vec<_>>());
        let (plus, minus) = (at(h), at(-h));
        for i in 0..2 {
            assert!(((plus[i] - minus[i]) / (2.0 * h) - tip.end_effector_velocity[i]).abs() < 1e-7);
        }
    }

    /// The effective chain reproduces the tool point: `rho e(phi + mu) + sum L_k e(psi_k)`.
    #[test]
    fn the_reach_chain_is_the_tool_point() {
        let a = arm(3, (0.3, 0.4));
        let c = a.reach_chain();
        assert!(c.lengths.iter().all(|l| *l > 0.0));
        let q = [0.9, -0.4, 1.2, 0.3];
        let mut p = [c.rho * (q[0] + c.mu).cos(), c.rho * (q[0] + c.mu).sin()];
        let mut psi = q[0];
        for (l, th) in c.lengths.iter().zip(&q[1..]) {
            psi += th;
            p = [p[0] + l * psi.cos(), p[1] + l * psi.sin()];
        }
        let tip = a.tool_point(&q);
        assert!((p[0] - tip[0]).abs() < 1e-14 && (p[1] - tip[1]).abs() < 1e-14);
    }

    /// At `n = 2` the branches are the 2-link closed form's two elbows (same configurations).
    #[test]
    fn two_links_give_the_closed_form_elbows() {
        let robot = RobotParams::src().with_mount(Mount::new(1.0, -1.0).unwrap()).unwrap();
        let a = Arm::from_params(&robot);
        let start = [0.2, 1.0, 0.5];
        let target = a.task_point(&[0.5, 2.0, 0.7], &[0.0; 3]).end_effector;
        let pose = (target[0], target[1], target[2]);
        let ours = a.inverse_kinematics(pose, &start).unwrap();
        let theirs = crate::model::kinematics::inverse_kinematics(&robot, pose, start[0]).unwrap();
        assert_eq!(ours.len(), 2);
        for ((_, q), b) in theirs.iter().zip(&ours) {
            assert!(b.reached, "{b:?}");
            let d = q.distance(&Configuration::from_array([b.q[0], b.q[1], b.q[2]]));
            assert!(d < 1e-9, "{q:?} vs {:?}", b.q);
        }
    }

    /// `n = 1`: the unique solution; `n = 4`: every seed reaches a pose made by forward kinematics
    /// (checked by the forward kinematics), distinct branches among them; out of reach is an
    /// [`Unreachable`] with the annulus.
    #[test]
    fn any_n_reaches_what_forward_kinematics_made() {
        for (n, mount) in [(1, (0.3, 0.1)), (3, (0.0, 0.0)), (4, (0.2, -0.3)), (6, (0.1, 0.1))] {
            let a = arm(n, mount);
            let goal: Vec<f64> = (0..=n).map(|k| 0.4 + 0.3 * k as f64).collect();
            let p = a.task_point(&goal, &vec![0.0; n + 1]).end_effector;
            let start = vec![0.0; n + 1];
            let branches = a.inverse_kinematics((p[0], p[1], p[2]), &start).unwrap();
            assert!(branches.iter().any(|b| b.reached), "n = {n}: {branches:?}");
            for b in branches.iter().filter(|b| b.reached) {
                let tip = a.task_point(&b.q, &vec![0.0; n + 1]).end_effector;
                assert!((tip[0] - p[0]).hypot(tip[1] - p[1]) < 1e-9, "n = {n}: {b:?}");
                assert!(crate::model::wrap_angle(tip[2] - p[2]).abs() < 1e-12);
            }
            if n >= 4 {
                assert_eq!(branches.len(), 4);
            }
            let e = a.inverse_kinematics((10.0, 0.0, 0.0), &start).unwrap_err();
            assert!(e.distance > e.max && e.max > 0.0, "{e}");
        }
    }
}
