//! Any planar serial arm: a free-floating base carrying `n >= 1` revolute links, each with a
//! length, a centre-of-mass distance along the link, a mass and a moment of inertia about its
//! centre of mass (the paper's robot, Sec. 3.1 and Fig. 3, is `n = 2` with point-mass links).
//!
//! Coordinates `q = (phi, theta_1, ..., theta_n)`: the base angle and the relative joint angles;
//! link `i` points along `psi_i = phi + theta_1 + ... + theta_i`. With zero linear momentum the
//! system's centre of mass stays at the origin (as for Eq. 3), so the kinetic energy is
//! `T = 1/2 q'^T M(theta) q'` with the `(n + 1) x (n + 1)` inertia matrix [`Arm::inertia_matrix`],
//! which does not depend on `phi` (the system is invariant under rotation). Its first row gives
//! the angular momentum `F phi' + G . theta'` (Eq. 5 with `G_1, G_2 = G, H` of Eq. 8), so at zero
//! momentum `phi' = -(G . theta') / F` (Eq. 7).
//!
//! Every function is generic over [`Scalar`], so derivatives of any order come from num-dual
//! exactly.

pub mod collision;
pub mod file;
mod file_limits;
pub mod kinematics;
pub mod limits;
pub mod lumped;
pub mod shapes;
pub mod urdf;
mod urdf_limits;

pub use limits::{JointLimits, Limits};
pub use urdf::URDF_PLANAR_TOLERANCE;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::{INERTIA_RANGE, InputError, LENGTH_RANGE, MASS_RANGE, Mount, RobotParams, check_finite};
use crate::Scalar;

/// The most links an [`Arm`] may have: beyond it the `(n + 1) x (n + 1)` inertia matrix and its
/// derivatives (`O(n^4)` per evaluation) stop being cheap, and no planar testbed comes near it.
pub const MAX_LINKS: usize = 15;

/// The base of the robot.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Base {
    /// Mass `M` \[kg\].
    pub mass: f64,
    /// Moment of inertia about its centre of mass, `I` [kg m^2].
    pub inertia: f64,
}

/// One link of the arm, from its joint to the next joint (or its tip).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Link {
    /// Length `l_i`, joint to next joint \[m\].
    pub length: f64,
    /// Distance `d_i` from the joint to the link's centre of mass, along the link \[m\].
    pub com: f64,
    /// Mass `m_i` \[kg\].
    pub mass: f64,
    /// Moment of inertia about the link's centre of mass [kg m^2] (0 for a point mass).
    pub inertia: f64,
}

/// A planar free-floating robot with an `n`-link serial arm mounted at `mount` in the base frame
/// (relative to the base's centre of mass).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Arm {
    /// The base.
    pub base: Base,
    /// The mounting point of joint 1 in the base frame \[m\].
    pub mount: Mount,
    /// The links, from the base outwards.
    pub links: Vec<Link>,
    /// The declared limits (issue 20): none by default.
    #[serde(default, skip_serializing_if = "Limits::is_empty")]
    pub limits: Limits,
    /// The bodies' shapes, the obstacles and the clearance to keep (issue 21): none by default.
    /// Carried by the arm, as its limits are, so that every certificate of the arm (each
    /// planner's, `check`'s, `track`'s re-plans) sees them without another argument.
    #[serde(default, skip_serializing_if = "collision::Geometry::is_unset")]
    pub geometry: collision::Geometry,
}

/// Positions of every body's centre of mass relative to the system's centre of mass, with their
/// Jacobians in `q`.
#[derive(Debug, Clone)]
pub struct BodyFrames<D> {
    /// Position of the base's centre of mass `(x, y)` \[m\].
    pub base: [D; 2],
    /// Positions of the links' centres of mass \[m\].
    pub links: Vec<[D; 2]>,
    /// `d(x, y)/dq` of the base, one `[dx, dy]` per coordinate of `q`.
    pub base_jacobian: Vec<[D; 2]>,
    /// `d(x, y)/dq` of each link's centre of mass.
    pub link_jacobians: Vec<Vec<[D; 2]>>,
}

impl Arm {
    /// Validates an arm (docs/spec.md §1): `1 <= n <=` [`MAX_LINKS`] links; the base's mass and
    /// inertia, every link's length and mass finite and within [`MASS_RANGE`], [`INERTIA_RANGE`],
    /// [`LENGTH_RANGE`]; every link inertia finite with `0 <= inertia <=` the largest of
    /// [`INERTIA_RANGE`] (0 is a point mass); every centre of mass on its link,
    /// `0 <= com <= length`; the mount within [`super::MAX_MOUNT`]; and the last link must carry
    /// some inertia about joint `n` (`com > 0` or `inertia > 0`), else the inertia matrix is
    /// singular. Errors name the key as the robot file spells it: `robot.M`, `robot.I`,
    /// `mount.a`, `link[k].mass` with `k` counted from 1 (link `k` turns with joint `k`).
    ///
    /// ```
    /// use freefloat::model::arm::{Arm, Base, Link};
    /// let link = Link { length: 0.4, com: 0.2, mass: 2.0, inertia: 2.0 * 0.4 * 0.4 / 12.0 };
    /// let arm = Arm::new(Base { mass: 15.0, inertia: 0.4 }, Default::default(), vec![link; 3]).unwrap();
    /// assert_eq!(arm.joints(), 3);
    /// assert!(Arm::new(arm.base, arm.mount, vec![]).is_err());
    /// ```
    pub fn new(base: Base, mount: Mount, links: Vec<Link>) -> Result<Self, InputError> {
        let arm = Self { base, mount, links, limits: Limits::default(), geometry: Default::default() };
        arm.validate()?;
        Ok(arm)
    }

    /// The arm with `limits` (checked by [`Limits::validate`] for its joints).
    pub fn with_limits(mut self, limits: Limits) -> Result<Self, InputError> {
        limits.validate(self.joints())?;
        self.limits = limits;
        Ok(self)
    }

    /// The arm with `geometry` (checked by [`collision::Geometry::validate`] for its links).
    pub fn with_geometry(mut self, geometry: collision::Geometry) -> Result<Self, InputError> {
        geometry.validate(self.joints())?;
        self.geometry = geometry;
        Ok(self)
    }

    /// Checks the invariants listed at [`Arm::new`], naming the first offending key.
    pub fn validate(&self) -> Result<(), InputError> {
        let n = self.links.len();
        if !(1..=MAX_LINKS).contains(&n) {
            return Err(InputError::InvalidParameter {
                name: "link".into(),
                value: n as f64,
                expected: "an arm of 1 to 15 links (docs/spec.md §1)",
            });
        }
        check_ranged("robot.M", self.base.mass, MASS_RANGE)?;
        check_ranged("robot.I", self.base.inertia, INERTIA_RANGE)?;
        Mount::new(self.mount.a, self.mount.b)?;
        for (i, link) in self.links.iter().enumerate() {
            let key = |field: &str| format!("link[{}].{field}", i + 1);
            check_ranged(&key("length"), link.length, LENGTH_RANGE)?;
            check_ranged(&key("mass"), link.mass, MASS_RANGE)?;
            check_finite(&key("inertia"), link.inertia)?;
            if !(0.0..=INERTIA_RANGE.1).contains(&link.inertia) {
                return Err(InputError::InvalidParameter {
                    name: key("inertia"),
                    value: link.inertia,
                    expected: "a moment of inertia about the link's centre of mass from 0 (a point mass) to 1e9 kg m^2",
                });
            }
            check_finite(&key("com"), link.com)?;
            if !(0.0..=link.length).contains(&link.com) {
                return Err(InputError::InvalidParameter {
                    name: key("com"),
                    value: link.com,
                    expected: "a centre of mass on the link: 0 <= com <= length",
                });
            }
        }
        let last = self.links[n - 1];
        if last.com == 0.0 && last.inertia == 0.0 {
            return Err(InputError::InvalidParameter {
                name: format!("link[{n}].com"),
                value: last.com,
                expected: "com > 0 or inertia > 0 on the last link (a point mass on the last joint gives it nothing to turn)",
            });
        }
        self.limits.validate(n)?;
        self.geometry.validate(n)
    }

    /// The arm as the paper's 2-link [`RobotParams`] when it has two links with their centres of
    /// mass off the joints (`com > 0`), so that the 2-link pipeline (the NFA among it) serves
    /// it. Link inertias fold into the lumped constants (`A += I_1`, `B += I_2`, see
    /// [`crate::model::Lumped`]). `None` otherwise.
    pub fn as_src(&self) -> Option<RobotParams> {
        let [l1, l2] = self.links.as_slice() else { return None };
        RobotParams::new(RobotParams {
            l1: l1.length,
            l2: l2.length,
            d1: l1.com,
            d2: l2.com,
            base_mass: self.base.mass,
            base_inertia: self.base.inertia,
            m1: l1.mass,
            m2: l2.mass,
            i1: l1.inertia,
            i2: l2.inertia,
            mount: self.mount,
        })
        .ok()
    }

    /// A 2-link [`RobotParams`] as an arm (the paper's SRC robot: two point-mass links).
    pub fn from_params(robot: &RobotParams) -> Self {
        Self {
            base: Base { mass: robot.base_mass, inertia: robot.base_inertia },
            mount: robot.mount,
            links: vec![
                Link { length: robot.l1, com: robot.d1, mass: robot.m1, inertia: robot.i1 },
                Link { length: robot.l2, com: robot.d2, mass: robot.m2, inertia: robot.i2 },
            ],
            limits: Limits::default(),
            geometry: Default::default(),
        }
    }

    /// The number `n` of joints.
    pub fn joints(&self) -> usize {
        self.links.len()
    }

    /// Total mass \[kg\].
    pub fn total_mass(&self) -> f64 {
        self.base.mass + self.links.iter().map(|l| l.mass).sum::<f64>()
    }

    /// Positions of the bodies relative to the system's centre of mass, and their Jacobians in
    /// `q = (phi, theta)`, at the configuration `q` (`n + 1` values).
    ///
    /// Relative to the base, link `k`'s centre of mass is at
    /// `p_k = R(phi) (a, b) + sum_{i<k} l_i e(psi_i) + d_k e(psi_k)` with `e(psi) = (cos, sin)`;
    /// the base then sits at `-sum m_k p_k / m_total`, which keeps the centre of mass at the origin.
    pub fn bodies<D: Scalar>(&self, q: &[D]) -> BodyFrames<D> {
        let n = self.joints();
        assert_eq!(q.len(), n + 1, "q has n + 1 = {} coordinates", n + 1);
        let total = self.total_mass();
        // Absolute link angles psi_i, and e(psi_i), e_perp(psi_i).
        let mut psi = q[0];
        let mut e = Vec::with_capacity(n);
        for &theta in &q[1..] {
            psi += theta;
            let (s, c) = psi.sin_cos();
            e.push(([c, s], [-s, c]));
        }
        let (sp, cp) = q[0].sin_cos();
        let (a, b) = (self.mount.a, self.mount.b);
        let mount = [cp * a - sp * b, sp * a + cp * b];
        let mount_rate = [-(sp * a) - cp * b, cp * a - sp * b];
        // Positions relative to the base's centre of mass and their Jacobians.
        let zero = D::from(0.0);
        let mut rel = Vec::with_capacity(n);
        let mut rel_jac = Vec::with_capacity(n);
        let mut joint = mount;
        for (k, link) in self.links.iter().enumerate() {
            let (ek, pk) = e[k];
            rel.push([joint[0] + ek[0] * link.com, joint[1] + ek[1] * link.com]);
            // d p_k / d q_j: q_0 = phi moves everything; theta_j moves links j.. (1-based j).
            let mut jac = vec![[zero, zero]; n + 1];
            for (j, column) in jac.iter_mut().enumerate() {
                let mut v = if j == 0 { mount_rate } else { [zero, zero] };
                let first = j.saturating_sub(1);
                for (i, item) in e.iter().enumerate().take(k).skip(first) {
                    let l = self.links[i].length;
                    v = [v[0] + item.1[0] * l, v[1] + item.1[1] * l];
                }
                if j <= k + 1 {
                    v = [v[0] + pk[0] * link.com, v[1] + pk[1] * link.com];
                }
                *column = v;
            }
            rel_jac.push(jac);
            joint = [joint[0] + ek[0] * link.length, joint[1] + ek[1] * link.length];
        }
        // The base's position keeps the centre of mass at the origin.
        let mut base = [zero, zero];
        let mut base_jacobian = vec![[zero, zero]; n + 1];
        for (k, link) in self.links.iter().enumerate() {
            let w = -link.mass / total;
            base = [base[0] + rel[k][0] * w, base[1] + rel[k][1] * w];
            for j in 0..=n {
                base_jacobian[j] =
                    [base_jacobian[j][0] + rel_jac[k][j][0] * w, base_jacobian[j][1] + rel_jac[k][j][1] * w];
            }
        }
        let links = rel.iter().map(|p| [p[0] + base[0], p[1] + base[1]]).collect();
        let link_jacobians = rel_jac
            .iter()
            .map(|jac| jac.iter().zip(&base_jacobian).map(|(p, b0)| [p[0] + b0[0], p[1] + b0[1]]).collect())
            .collect();
        BodyFrames { base, links, base_jacobian, link_jacobians }
    }

    /// The base's centre of mass relative to the system's at `q` (`n + 1` values): the
    /// [`BodyFrames::base`] of [`Arm::bodies`] by the same arithmetic, without the links'
    /// Jacobians (the collision model places every body from it at every point of every row).
    pub fn base_position<D: Scalar>(&self, q: &[D]) -> [D; 2] {
        self.base_position_each(q, |_, _| {})
    }

    /// [`Self::base_position`], handing `each` the base's angle and then every link's absolute
    /// angle, each with its sine and cosine `(s, c)` as taken there (the collision model's frames
    /// reuse them).
    pub(crate) fn base_position_each<D: Scalar>(&self, q: &[D], mut each: impl FnMut(D, (D, D))) -> [D; 2] {
        let total = self.total_mass();
        let (sp, cp) = q[0].sin_cos();
        each(q[0], (sp, cp));
        let (a, b) = (self.mount.a, self.mount.b);
        let mut joint = [cp * a - sp * b, sp * a + cp * b];
        let mut psi = q[0];
        let zero = D::from(0.0);
        let mut base = [zero, zero];
        for (link, &theta) in self.links.iter().zip(&q[1..]) {
            psi += theta;
            let (s, c) = psi.sin_cos();
            each(psi, (s, c));
            let rel = [joint[0] + c * link.com, joint[1] + s * link.com];
            let w = -link.mass / total;
            base = [base[0] + rel[0] * w, base[1] + rel[1] * w];
            joint = [joint[0] + c * link.length, joint[1] + s * link.length];
        }
        base
    }

    /// The points of the arm at `q` (`n + 1` values) relative to the system's centre of mass
    /// \[m\], for drawing it: the base's centre of mass, then joint 1 (the mounting point), joints
    /// `2..n` and the tip of link `n` (`n + 2` points). The same formulas as [`Arm::bodies`]:
    /// joint 1 at `base + R(phi) (a, b)`, joint `k + 1` at joint `k` plus `l_k e(psi_k)`.
    pub fn joint_positions(&self, q: &[f64]) -> Vec<[f64; 2]> {
        let base = self.bodies(q).base;
        let (sp, cp) = q[0].sin_cos();
        let (a, b) = (self.mount.a, self.mount.b);
        let mut joint = [base[0] + cp * a - sp * b, base[1] + sp * a + cp * b];
        let mut points = Vec::with_capacity(self.joints() + 2);
        points.extend([base, joint]);
        let mut psi = q[0];
        for (link, theta) in self.links.iter().zip(&q[1..]) {
            psi += theta;
            joint = [joint[0] + link.length * psi.cos(), joint[1] + link.length * psi.sin()];
            points.push(joint);
        }
        points
    }

    /// The inertia matrix `M(theta)` of `T = 1/2 q'^T M q'` (`(n + 1) x (n + 1)`, symmetric,
    /// positive definite), at the joint angles `theta` (`n` values): `sum_k m_k J_k^T J_k` over
    /// the bodies' centres of mass plus the rotational terms `I_k w_k w_k^T`, where
    /// `psi_k' = w_k . q'` (`w_0 = (1, 0, ..)` for the base, `w_k = (1, 1 x k, 0, ..)` for link k).
    pub fn inertia_matrix<D: Scalar>(&self, theta: &[D]) -> DMatrix<D> {
        let n = self.joints();
        let mut q = Vec::with_capacity(n + 1);
        q.push(D::from(0.0));
        q.extend_from_slice(theta);
        let frames = self.bodies(&q);
        let mut m = DMatrix::from_element(n + 1, n + 1, D::from(0.0));
        let mut add_body = |mass: f64, jac: &[[D; 2]]| {
            for i in 0..=n {
                for j in 0..=i {
                    let v = (jac[i][0] * jac[j][0] + jac[i][1] * jac[j][1]) * mass;
                    m[(i, j)] += v;
                }
            }
        };
        add_body(self.base.mass, &frames.base_jacobian);
        for (link, jac) in self.links.iter().zip(&frames.link_jacobians) {
            add_body(link.mass, jac);
        }
        // Rotational inertia: the base turns with phi, link k with phi + theta_1 + .. + theta_k.
        m[(0, 0)] += D::from(self.base.inertia);
        for (k, link) in self.links.iter().enumerate() {
            for i in 0..=k + 1 {
                for j in 0..=i {
                    m[(i, j)] += D::from(link.inertia);
                }
            }
        }
        for i in 0..=n {
            for j in i + 1..=n {
                m[(i, j)] = m[(j, i)];
            }
        }
        m
    }

    /// The angular-momentum coefficients `(F, G_1..G_n)`: the first row of
    /// [`Arm::inertia_matrix`], so that the angular momentum is `F phi' + G . theta'` (Eq. 5; for
    /// the SRC robot `G_1, G_2` are `G, H` of Eq. 8). `F > 0` at every configuration.
    ///
    /// Only that row is formed (`m_k J_k^T J_k e_0` and the rotational terms, the same sums in
    /// the same order as the matrix, so the values are identical): the velocity certificates
    /// evaluate it at every right-hand side of their integration.
    pub fn momentum_coefficients<D: Scalar>(&self, theta: &[D]) -> (D, Vec<D>) {
        let n = self.joints();
        let mut q = Vec::with_capacity(n + 1);
        q.push(D::from(0.0));
        q.extend_from_slice(theta);
        let frames = self.bodies(&q);
        let mut row = vec![D::from(0.0); n + 1];
        let mut add_body = |mass: f64, jac: &[[D; 2]]| {
            for (r, column) in row.iter_mut().zip(jac) {
                *r += (column[0] * jac[0][0] + column[1] * jac[0][1]) * mass;
            }
        };
        add_body(self.base.mass, &frames.base_jacobian);
        for (link, jac) in self.links.iter().zip(&frames.link_jacobians) {
            add_body(link.mass, jac);
        }
        row[0] += D::from(self.base.inertia);
        for (k, link) in self.links.iter().enumerate() {
            for r in &mut row[..=k + 1] {
                *r += D::from(link.inertia);
            }
        }
        let f = row[0];
        row.remove(0);
        (f, row)
    }

    /// The base's angular velocity at zero angular momentum, `phi' = -(G . theta') / F`
    /// [rad/s] (Eq. 7 for any `n`), at the joint angles `theta` \[rad\] and joint velocities
    /// `dtheta` [rad/s] (`n` values each).
    pub fn base_rate<D: Scalar>(&self, theta: &[D], dtheta: &[D]) -> D {
        assert_eq!(dtheta.len(), self.joints(), "dtheta has n = {} values", self.joints());
        let (f, g) = self.momentum_coefficients(theta);
        let mut p = D::from(0.0);
        for (gj, w) in g.iter().zip(dtheta) {
            p += *gj * *w;
        }
        -p / f
    }
}

#[cfg(test)]
pub(crate) mod tests;
#[cfg(test)]
mod tests_limits;

/// A value that must be finite, positive and in `range`.
fn check_ranged(name: &str, value: f64, (min, max): (f64, f64)) -> Result<(), InputError> {
    check_finite(name, value)?;
    if !(min..=max).contains(&value) {
        return Err(InputError::InvalidParameter {
            name: name.to_string(),
            value,
            expected: "a positive value in the physical range of docs/spec.md §1 (lengths 1e-3 to 1e3 m, \
                       masses 1e-3 to 1e6 kg, the base's inertia 1e-6 to 1e9 kg m^2)",
        });
    }
    Ok(())
}
