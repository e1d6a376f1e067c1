//! The robot: the SRC space manipulator's parameters and the lumped constants of the
//! Lagrangian (Sec. 3.1, after Eq. (3)).

pub mod arm;
mod error;
pub mod geometry;
pub mod kinematics;
mod robot_file;
pub mod system;

pub use error::{ECHO_LIMIT, InputError, excerpt, fmt_bytes, fmt_count, fmt_value};
pub use robot_file::{ROBOT_FILE_LIMIT, read_regular_file};

use serde::{Deserialize, Serialize};

/// Physical parameters of the planar free-floating robot (Sec. 3.1, Fig. 3), SI units.
///
/// A base of mass `M` and moment of inertia `I` carries a two-link arm whose first joint sits
/// at the mounting point `(a, b)` of the base frame, measured from the base's centre of mass.
/// Build one with [`RobotParams::src`] (the paper's robot) or [`RobotParams::new`], which
/// validates every value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RobotParams {
    /// Length of link 1 \[m\].
    pub l1: f64,
    /// Length of link 2 \[m\].
    pub l2: f64,
    /// Distance from joint 1 to the centre of mass of link 1 \[m\].
    pub d1: f64,
    /// Distance from joint 2 to the centre of mass of link 2 \[m\].
    pub d2: f64,
    /// Mass of the base, `M` in the paper \[kg\].
    pub base_mass: f64,
    /// Moment of inertia of the base about its centre of mass, `I` in the paper [kg m^2].
    pub base_inertia: f64,
    /// Mass of link 1 \[kg\].
    pub m1: f64,
    /// Mass of link 2 \[kg\].
    pub m2: f64,
    /// Moment of inertia of link 1 about its centre of mass [kg m^2]; 0, the paper's point
    /// mass, by default.
    #[serde(default)]
    pub i1: f64,
    /// Moment of inertia of link 2 about its centre of mass [kg m^2]; 0 by default.
    #[serde(default)]
    pub i2: f64,
    /// Mounting point of the arm in the base frame, `(a, b)` \[m\].
    pub mount: Mount,
}

/// Mounting point `(a, b)` of the on-board manipulator in the base frame `(X_b, Y_b)` \[m\],
/// relative to the base's centre of mass (Fig. 3). `a = b = 0` is the centred case of
/// Theorem 1, item 1.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Mount {
    /// Coordinate along `X_b` \[m\].
    pub a: f64,
    /// Coordinate along `Y_b` \[m\].
    pub b: f64,
}

impl Mount {
    /// A mounting point; both coordinates finite with `|a|, |b| <=` [`MAX_MOUNT`].
    pub fn new(a: f64, b: f64) -> Result<Self, InputError> {
        check_mount("mount.a", a)?;
        check_mount("mount.b", b)?;
        Ok(Self { a, b })
    }

    /// True for the centred mounting `a = b = 0`, where Eqs. (11) and (12) apply.
    pub fn is_centred(&self) -> bool {
        self.a == 0.0 && self.b == 0.0
    }
}

impl RobotParams {
    /// The SRC space manipulator of the paper (Sec. 5, from its reference \[15\]), mounted at the
    /// base's centre of mass: l1 = 0.619, l2 = 0.6, d1 = 0.313, d2 = 0.287 m, M = 12.9 kg,
    /// I = 0.208 kg m^2, m1 = 4.5, m2 = 1.5 kg.
    ///
    /// ```
    /// let robot = freefloat::RobotParams::src();
    /// assert_eq!(robot.base_mass, 12.9);
    /// ```
    pub fn src() -> Self {
        Self {
            l1: 0.619,
            l2: 0.6,
            d1: 0.313,
            d2: 0.287,
            base_mass: 12.9,
            base_inertia: 0.208,
            m1: 4.5,
            m2: 1.5,
            i1: 0.0,
            i2: 0.0,
            mount: Mount::default(),
        }
    }

    /// Validates a full parameter set: every value finite and within its physical range
    /// ([`LENGTH_RANGE`], [`MASS_RANGE`], [`INERTIA_RANGE`], [`MAX_MOUNT`]); `0 < d_i <= l_i`
    /// (docs/spec.md §1).
    pub fn new(params: RobotParams) -> Result<Self, InputError> {
        params.validate()?;
        Ok(params)
    }

    /// The same robot with the arm mounted at `mount`.
    pub fn with_mount(self, mount: Mount) -> Result<Self, InputError> {
        Self::new(Self { mount, ..self })
    }

    /// Checks the invariants listed at [`RobotParams::new`], naming the first offending key.
    pub fn validate(&self) -> Result<(), InputError> {
        let ranged = [
            ("robot.l1", self.l1, LENGTH_RANGE),
            ("robot.l2", self.l2, LENGTH_RANGE),
            ("robot.d1", self.d1, LENGTH_RANGE),
            ("robot.d2", self.d2, LENGTH_RANGE),
            ("robot.M", self.base_mass, MASS_RANGE),
            ("robot.I", self.base_inertia, INERTIA_RANGE),
            ("robot.m1", self.m1, MASS_RANGE),
            ("robot.m2", self.m2, MASS_RANGE),
        ];
        for (name, value, (min, max)) in ranged {
            check_finite(name, value)?;
            if value <= 0.0 {
                return Err(InputError::InvalidParameter {
                    name: name.to_string(),
                    value,
                    expected: "a positive value",
                });
            }
            if !(min..=max).contains(&value) {
                return Err(InputError::InvalidParameter {
                    name: name.to_string(),
                    value,
                    expected: "a value in the physical range of docs/spec.md §1 (lengths 1e-3 to 1e3 m, \
                               masses 1e-3 to 1e6 kg, the base's inertia 1e-6 to 1e9 kg m^2)",
                });
            }
        }
        for (name, d, l) in [("robot.d1", self.d1, self.l1), ("robot.d2", self.d2, self.l2)] {
            if d > l {
                return Err(InputError::InvalidParameter {
                    name: name.to_string(),
                    value: d,
                    expected: "a centre of mass on the link: 0 < d_i <= l_i",
                });
            }
        }
        for (name, value) in [("link[1].inertia", self.i1), ("link[2].inertia", self.i2)] {
            check_finite(name, value)?;
            if !(0.0..=INERTIA_RANGE.1).contains(&value) {
                return Err(InputError::InvalidParameter {
                    name: name.to_string(),
                    value,
                    expected: "a moment of inertia about the link's centre of mass from 0 (a point mass) to 1e9 kg m^2",
                });
            }
        }
        check_mount("mount.a", self.mount.a)?;
        check_mount("mount.b", self.mount.b)
    }

    /// The lumped constants `m_c, A, B, C, D, E, I_P` of the Lagrangian (3).
    pub fn lumped(&self) -> Lumped {
        Lumped::new(self)
    }
}

/// Accepted link lengths and centre-of-mass distances `l_i, d_i` \[m\] (docs/spec.md §1).
pub const LENGTH_RANGE: (f64, f64) = (1e-3, 1e3);
/// Accepted masses `M, m_i` \[kg\] (docs/spec.md §1).
pub const MASS_RANGE: (f64, f64) = (1e-3, 1e6);
/// Accepted moments of inertia of the base `I` [kg m^2] (docs/spec.md §1).
pub const INERTIA_RANGE: (f64, f64) = (1e-6, 1e9);
/// Largest accepted `|a|`, `|b|` of a mounting point \[m\] (docs/spec.md §1).
pub const MAX_MOUNT: f64 = 1e3;

fn check_mount(name: &str, value: f64) -> Result<(), InputError> {
    check_finite(name, value)?;
    if value.abs() > MAX_MOUNT {
        return Err(InputError::InvalidParameter {
            name: name.to_string(),
            value,
            expected: "a mounting coordinate with |a|, |b| <= 1e3 m (docs/spec.md §1)",
        });
    }
    Ok(())
}

fn check_finite(name: &str, value: f64) -> Result<(), InputError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(InputError::InvalidParameter { name: name.to_string(), value, expected: "a finite number" })
    }
}

/// The constants of the Lagrangian (3), defined after Eq. (3) in Sec. 3.1 (SI units).
///
/// Field names copy the paper's symbols. `a, b` are the mounting point, repeated here so that the
/// functions of [`crate::model::system`] need nothing else.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Lumped {
    /// Total mass `m_c = M + m1 + m2` \[kg\].
    pub mc: f64,
    /// `A = (m1 m2 (l1 - d1)^2 + M (m1 d1^2 + m2 l1^2)) / m_c + I_1` [kg m^2]. The link
    /// inertias `I_1, I_2` (zero for the paper's point masses) enter the Lagrangian (3) only
    /// through `A` and `B`: link 1 turns at `phi' + theta1'`, link 2 at
    /// `phi' + theta1' + theta2'`, which adds `I_1` where `A` stands and `I_2` where `B` stands
    /// in every entry of the inertia matrix (the test `two_links_have_the_src_dynamics`
    /// holds this against the general model of [`crate::model::arm`]).
    pub A: f64,
    /// `B = (M + m1) m2 d2^2 / m_c + I_2` [kg m^2].
    pub B: f64,
    /// `C = (m1 m2 (l1 - d1) d2 + M m2 l1 d2) / m_c` [kg m^2].
    pub C: f64,
    /// `D = M (m1 d1 + m2 l1) / m_c` \[kg m\].
    pub D: f64,
    /// `E = M m2 d2 / m_c` \[kg m\].
    pub E: f64,
    /// `I_P = I + M (m1 + m2)(a^2 + b^2) / m_c` [kg m^2].
    pub IP: f64,
    /// Mounting point, `a` \[m\].
    pub a: f64,
    /// Mounting point, `b` \[m\].
    pub b: f64,
}

impl Lumped {
    /// Computes the constants from the robot's parameters (Sec. 3.1).
    #[allow(non_snake_case)]
    pub fn new(robot: &RobotParams) -> Self {
        let RobotParams { l1, d1, d2, base_mass: M, base_inertia: I, m1, m2, i1, i2, mount, .. } = *robot;
        let Mount { a, b } = mount;
        let mc = M + m1 + m2;
        Self {
            mc,
            A: (m1 * m2 * (l1 - d1).powi(2) + M * (m1 * d1 * d1 + m2 * l1 * l1)) / mc + i1,
            B: (M + m1) * m2 * d2 * d2 / mc + i2,
            C: (m1 * m2 * (l1 - d1) * d2 + M * m2 * l1 * d2) / mc,
            D: M * (m1 * d1 + m2 * l1) / mc,
            E: M * m2 * d2 / mc,
            IP: I + M * (m1 + m2) * (a * a + b * b) / mc,
            a,
            b,
        }
    }
}

/// A configuration `q = (phi, theta1, theta2)` of the driftless system (7) \[rad\]:
/// base orientation and the two joint angles, all counter-clockwise.
///
/// Angles are taken literally, not reduced modulo 2 pi (docs/spec.md §6, item 6).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Configuration {
    /// Base orientation in the inertial frame \[rad\].
    pub phi: f64,
    /// Joint 1 angle, link 1 relative to the base \[rad\].
    pub theta1: f64,
    /// Joint 2 angle, link 2 relative to link 1 \[rad\].
    pub theta2: f64,
}

impl Configuration {
    /// A configuration from its three angles \[rad\].
    pub fn new(phi: f64, theta1: f64, theta2: f64) -> Self {
        Self { phi, theta1, theta2 }
    }

    /// A configuration from angles in degrees.
    pub fn from_degrees(phi_deg: f64, theta1_deg: f64, theta2_deg: f64) -> Self {
        Self::new(phi_deg.to_radians(), theta1_deg.to_radians(), theta2_deg.to_radians())
    }

    /// `[phi, theta1, theta2]`.
    pub fn to_array(self) -> [f64; 3] {
        [self.phi, self.theta1, self.theta2]
    }

    /// From `[phi, theta1, theta2]`.
    pub fn from_array(q: [f64; 3]) -> Self {
        Self::new(q[0], q[1], q[2])
    }

    /// True when all three angles are finite.
    pub fn is_finite(&self) -> bool {
        self.to_array().iter().all(|x| x.is_finite())
    }

    /// `max_i |wrap(self_i - other_i)|`, angle differences wrapped to (-pi, pi] \[rad\]: the
    /// final-error measure of docs/spec.md §2.
    pub fn distance(&self, other: &Configuration) -> f64 {
        self.to_array().iter().zip(other.to_array()).map(|(x, y)| wrap_angle(x - y).abs()).fold(0.0, f64::max)
    }
}

/// Wraps an angle to (-pi, pi] \[rad\].
pub fn wrap_angle(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = x.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

/// The paper's planning problem (Sec. 5): `q0 = (45, 120, 80)` deg, `qd = (0, 180, 140)` deg,
/// `T = 10` s. Returns `(q0, qd, T)`.
pub fn paper_problem() -> (Configuration, Configuration, f64) {
    (Configuration::from_degrees(45.0, 120.0, 80.0), Configuration::from_degrees(0.0, 180.0, 140.0), 10.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn wrap_angle_range() {
        use std::f64::consts::PI;
        assert_relative_eq!(wrap_angle(3.0 * PI), PI, epsilon = 1e-12);
        assert_relative_eq!(wrap_angle(-PI / 2.0), -PI / 2.0, epsilon = 1e-15);
        assert_relative_eq!(wrap_angle(2.0 * PI + 0.1), 0.1, epsilon = 1e-12);
        assert!(wrap_angle(-PI) > 0.0);
    }

    #[test]
    fn src_is_valid_and_rejects_bad_values() {
        let src = RobotParams::src();
        assert!(src.validate().is_ok());
        let bad = RobotParams { m1: -1.0, ..src };
        assert!(matches!(RobotParams::new(bad), Err(InputError::InvalidParameter { name, .. }) if name == "robot.m1"));
        let bad = RobotParams { d2: 0.7, ..src };
        assert!(matches!(RobotParams::new(bad), Err(InputError::InvalidParameter { name, .. }) if name == "robot.d2"));
        let bad = RobotParams { base_inertia: f64::NAN, ..src };
        assert!(matches!(RobotParams::new(bad), Err(InputError::InvalidParameter { name, .. }) if name == "robot.I"));
    }

    /// The lumped constants against the paper's defining formulas evaluated independently as
    /// the inertia of the arm seen from the system's centre of mass: at a = b = 0 the base's
    /// total effective inertia `F` must be positive and `A, B, C` positive.
    #[test]
    fn lumped_constants_of_src_are_positive() {
        let k = RobotParams::src().lumped();
        assert_relative_eq!(k.mc, 18.9, epsilon = 1e-12);
        for x in [k.A, k.B, k.C, k.D, k.E, k.IP] {
            assert!(x > 0.0);
        }
        // Triangle-type inequality needed for F > 0 at every theta2: I_P + A + B > 2 C.
        assert!(k.IP + k.A + k.B > 2.0 * k.C);
    }
}
