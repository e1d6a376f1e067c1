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

/// A small seeded generator (SplitMix64): the same random arms on every run.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    }

    pub(crate) fn vec(&mut self, len: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..len).map(|_| self.uniform(lo, hi)).collect()
    }
}

/// A realistic random arm of `n` links: a 5-30 kg base with 0.1-1 kg m^2, links 0.2-0.7 m of
/// 0.5-5 kg, centres of mass anywhere on the link, inertias from 0 (point mass) to a slender
/// rod's `m l^2 / 12`, mounts within 0.3 m.
pub(crate) fn random_arm(n: usize, rng: &mut Rng) -> Arm {
    let base = Base { mass: rng.uniform(5.0, 30.0), inertia: rng.uniform(0.1, 1.0) };
    let mount = Mount::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)).expect("a small mount");
    let links = (0..n)
        .map(|_| {
            let length = rng.uniform(0.2, 0.7);
            let mass = rng.uniform(0.5, 5.0);
            let com = rng.uniform(0.05, 1.0) * length;
            Link { length, com, mass, inertia: rng.uniform(0.0, 1.0) * mass * length * length / 12.0 }
        })
        .collect();
    Arm::new(base, mount, links).expect("a valid random arm")
}

/// Positions and velocities of every body (base first) and its angular velocity at `(q, dq)`,
/// by dual numbers along `q + t dq` (independent of the hand-written Jacobians).
#[allow(clippy::type_complexity)]
fn motion_by_ad(arm: &Arm, q: &[f64], dq: &[f64]) -> Vec<(f64, f64, [f64; 2], [f64; 2], f64)> {
    use num_dual::Dual64;
    let qd: Vec<Dual64> = q.iter().zip(dq).map(|(&x, &v)| Dual64::new(x, v)).collect();
    let frames = arm.bodies(&qd);
    let mut out = vec![(
        arm.base.mass,
        arm.base.inertia,
        [frames.base[0].re, frames.base[1].re],
        [frames.base[0].eps, frames.base[1].eps],
        dq[0],
    )];
    let mut psi_rate = dq[0];
    for (k, link) in arm.links.iter().enumerate() {
        psi_rate += dq[k + 1];
        let p = frames.links[k];
        out.push((link.mass, link.inertia, [p[0].re, p[1].re], [p[0].eps, p[1].eps], psi_rate));
    }
    out
}

fn close(x: f64, y: f64, rel: f64, scale: f64) -> bool {
    (x - y).abs() <= rel * scale.max(x.abs()).max(y.abs())
}

/// For n = 1..7 random arms at random configurations with `phi != 0`: `M` is symmetric and
/// positive definite; the kinetic energy of the bodies' velocities (AD) equals
/// `1/2 q'^T M(theta) q'` (so `M` does not depend on `phi`); the centre of mass stays at the
/// origin; the linear momentum is zero; the angular momentum about the centre of mass equals the
/// first row of `M q'` (Eq. 5), and `momentum_coefficients` is that row exactly; the Jacobians of
/// `bodies` are the AD velocities. All to 1e-12 relative.
#[test]
fn energy_and_momentum_identities_for_one_to_seven_links() {
    let mut rng = Rng::new(14);
    for n in 1..=7 {
        for _ in 0..20 {
            let arm = random_arm(n, &mut rng);
            let q = rng.vec(n + 1, -7.0, 7.0);
            let dq = rng.vec(n + 1, -3.0, 3.0);
            let m = arm.inertia_matrix(&q[1..]);
            assert!((&m - m.transpose()).abs().max() == 0.0);
            let eig = m.clone().symmetric_eigen().eigenvalues;
            assert!(eig.min() > 1e-9 * eig.max(), "n = {n}: eigenvalues {eig}");
            let w = nalgebra::DVector::from_column_slice(&dq);
            let energy = 0.5 * w.dot(&(&m * &w));
            let motion = motion_by_ad(&arm, &q, &dq);
            let mut ad_energy = 0.0;
            let (mut com, mut linear, mut angular) = ([0.0; 2], [0.0; 2], 0.0);
            let mut scale_p = 0.0_f64;
            for &(mass, inertia, r, v, rate) in &motion {
                ad_energy += 0.5 * mass * (v[0] * v[0] + v[1] * v[1]) + 0.5 * inertia * rate * rate;
                com = [com[0] + mass * r[0], com[1] + mass * r[1]];
                linear = [linear[0] + mass * v[0], linear[1] + mass * v[1]];
                angular += mass * (r[0] * v[1] - r[1] * v[0]) + inertia * rate;
                scale_p = scale_p.max(mass * (r[0].hypot(r[1]) + v[0].hypot(v[1])));
            }
            assert!(close(energy, ad_energy, 1e-12, 0.0), "n = {n}: T {energy} vs {ad_energy}");
            for x in com.iter().chain(&linear) {
                assert!(x.abs() <= 1e-12 * scale_p, "n = {n}: centre of mass or momentum {x}");
            }
            let p = (&m * &w)[0];
            assert!(close(p, angular, 1e-12, scale_p), "n = {n}: momentum {p} vs {angular}");
            let (f, g) = arm.momentum_coefficients(&q[1..]);
            assert!(
                std::iter::once(&f).chain(&g).zip(m.row(0).iter()).all(|(x, y)| x.to_bits() == y.to_bits()),
                "n = {n}: row 0"
            );
            assert!(close(f * dq[0] + g.iter().zip(&dq[1..]).map(|(g, w)| g * w).sum::<f64>(), p, 1e-12, scale_p));
            let phi_rate = arm.base_rate(&q[1..], &dq[1..]);
            let mut at_rest = dq.clone();
            at_rest[0] = phi_rate;
            let p0 = (&m * nalgebra::DVector::from_column_slice(&at_rest))[0];
            assert!(p0.abs() <= 1e-12 * scale_p, "n = {n}: momentum at Eq. (7) rate {p0}");
            let frames = arm.bodies(&q);
            let base = arm.base_position(&q);
            assert!(base.iter().zip(&frames.base).all(|(x, y)| x.to_bits() == y.to_bits()), "n = {n}: base");
            for (k, jac) in std::iter::once(&frames.base_jacobian).chain(&frames.link_jacobians).enumerate() {
                for i in 0..2 {
                    let v: f64 = jac.iter().zip(&dq).map(|(c, w)| c[i] * w).sum();
                    assert!(close(v, motion[k].3[i], 1e-12, scale_p), "n = {n}, body {k}: {v} vs AD");
                }
            }
        }
    }
}

#[test]
fn validation_names_the_key() {
    let mut rng = Rng::new(7);
    let arm = random_arm(3, &mut rng);
    let name_of = |arm: &Arm| match arm.validate() {
        Err(InputError::InvalidParameter { name, .. }) => name,
        other => panic!("{other:?}"),
    };
    let with = |k: usize, f: &dyn Fn(&mut Link)| {
        let mut a = arm.clone();
        f(&mut a.links[k]);
        a
    };
    assert_eq!(name_of(&with(2, &|l| l.mass = -1.0)), "link[3].mass");
    assert_eq!(name_of(&with(0, &|l| l.com = l.length * 1.5)), "link[1].com");
    assert_eq!(name_of(&with(0, &|l| l.com = -0.1)), "link[1].com");
    assert_eq!(name_of(&with(1, &|l| l.inertia = -1e-3)), "link[2].inertia");
    assert_eq!(name_of(&with(1, &|l| l.length = f64::NAN)), "link[2].length");
    assert_eq!(name_of(&with(2, &|l| (l.com, l.inertia) = (0.0, 0.0))), "link[3].com");
    assert!(with(1, &|l| (l.com, l.inertia) = (0.0, 0.0)).validate().is_ok(), "com = 0 inside the chain is fine");
    assert_eq!(name_of(&Arm { base: Base { mass: 0.0, inertia: 1.0 }, ..arm.clone() }), "robot.M");
    assert_eq!(name_of(&Arm { mount: Mount { a: 2e3, b: 0.0 }, ..arm.clone() }), "mount.a");
    assert_eq!(name_of(&Arm { links: vec![], ..arm.clone() }), "link");
    assert_eq!(name_of(&Arm { links: vec![arm.links[0]; MAX_LINKS + 1], ..arm.clone() }), "link");
    assert!(Arm { links: vec![arm.links[0]; MAX_LINKS], ..arm.clone() }.validate().is_ok());
    let e = with(0, &|l| l.com = 1.0).validate().unwrap_err().to_string();
    assert!(e.contains("link[1].com") && e.contains("0 <= com <= length"), "{e}");
}

#[test]
fn as_src_for_two_links_only() {
    let src = RobotParams::src();
    assert_eq!(Arm::from_params(&src).as_src(), Some(src));
    // Link inertias fold into the 2-link model's A and B (see the dynamics test
    // `two_links_have_the_src_dynamics`).
    let mut arm = Arm::from_params(&src);
    arm.links[1].inertia = 1e-3;
    assert_eq!(arm.as_src(), Some(RobotParams { i2: 1e-3, ..src }));
    assert_eq!(Arm::from_params(&arm.as_src().unwrap()), arm);
    let mut rng = Rng::new(3);
    assert_eq!(random_arm(3, &mut rng).as_src(), None);
    assert_eq!(random_arm(1, &mut rng).as_src(), None);
}

const SRC_FILE: &str = "[robot]\nl1 = 0.619\nl2 = 0.6\nd1 = 0.313\nd2 = 0.287\nM = 12.9\nI = 0.208\nm1 = 4.5\nm2 = 1.5\n[mount]\na = 0.1\nb = -0.2\n";

#[test]
fn robot_file_with_links_round_trips_and_the_old_format_is_point_masses() {
    let p = std::path::Path::new("arm.toml");
    let old = Arm::from_toml(SRC_FILE, p).unwrap();
    let src = RobotParams::src().with_mount(Mount::new(0.1, -0.2).unwrap()).unwrap();
    assert_eq!(old, Arm::from_params(&src));
    assert!(old.links.iter().all(|l| l.inertia == 0.0));
    assert_eq!(Arm::from_toml(&old.to_toml(), p).unwrap(), old);
    let mut rng = Rng::new(11);
    for n in 1..=7 {
        let arm = random_arm(n, &mut rng);
        assert_eq!(Arm::from_toml(&arm.to_toml(), p).unwrap(), arm, "n = {n}");
    }
    let example = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link.toml"))
        .expect("the example robot file");
    assert_eq!(Arm::from_toml(&example, p).unwrap().joints(), 3);
}

#[test]
fn robot_file_with_links_names_bad_values_and_keys() {
    let p = std::path::Path::new("arm.toml");
    let good = Arm::from_params(&RobotParams::src()).to_toml();
    assert!(Arm::from_toml(&good, p).is_ok());
    let second = good.rfind("mass = 1.5").expect("link 2's mass");
    let bad = format!("{}mass = -1.5{}", &good[..second], &good[second + "mass = 1.5".len()..]);
    let e = Arm::from_toml(&bad, p).unwrap_err();
    assert!(matches!(&e, InputError::InvalidParameter { name, .. } if name == "link[2].mass"), "{e}");
    let bad = good.replacen("com = 0.313", "com = 0.7", 1);
    let e = Arm::from_toml(&bad, p).unwrap_err().to_string();
    assert!(e.contains("link[1].com"), "{e}");
    for (typo, key) in [("inertia = 0.0", "inertai = 0.0"), ("M = 12.9", "m = 12.9")] {
        let e = Arm::from_toml(&good.replacen(typo, key, 1), p).unwrap_err().to_string();
        assert!(e.contains(key.split(' ').next().unwrap()), "{e}");
    }
    let mixed = good.replacen("[robot]\n", "[robot]\nl1 = 0.6\n", 1);
    assert!(Arm::from_toml(&mixed, p).unwrap_err().to_string().contains("l1"));
    let e = Arm::from_toml("link = []\n[robot]\nM = 10.0\nI = 0.1\n", p).unwrap_err().to_string();
    assert!(e.contains("link"), "{e}");
}

fn urdf(text: &str) -> Result<Arm, InputError> {
    Arm::from_urdf_str(text, std::path::Path::new("robot.urdf"))
}

fn assert_same_arm(a: &Arm, b: &Arm, rel: f64) {
    assert_eq!(a.joints(), b.joints());
    let values = |arm: &Arm| {
        let mut v = vec![arm.base.mass, arm.base.inertia, arm.mount.a, arm.mount.b];
        for l in &arm.links {
            v.extend([l.length, l.com, l.mass, l.inertia]);
        }
        v
    };
    for (x, y) in values(a).into_iter().zip(values(b)) {
        assert!(close(x, y, rel, 1.0), "{x} vs {y}:\n{a:?}\n{b:?}");
    }
}

/// SRC robot (point masses, several mounts) and random arms with link inertias, n = 1..7:
/// `to_urdf` then `from_urdf_str` gives the same arm to 1e-12.
#[test]
fn urdf_round_trip() {
    for (a, b) in [(0.0, 0.0), (0.1, 0.1), (-0.3, 0.25)] {
        let arm = Arm::from_params(&RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap());
        let back = urdf(&arm.to_urdf()).unwrap();
        assert_same_arm(&arm, &back, 1e-12);
        assert_eq!(back.as_src(), arm.as_src());
    }
    let mut rng = Rng::new(5);
    for n in 1..=7 {
        let arm = random_arm(n, &mut rng);
        assert_same_arm(&arm, &urdf(&arm.to_urdf()).unwrap(), 1e-12);
    }
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/robots/three_link");
    let toml = Arm::load(format!("{path}.toml").as_ref()).unwrap();
    if std::env::var_os("FREEFLOAT_REGENERATE").is_some() {
        std::fs::write(format!("{path}.urdf"), toml.to_urdf()).unwrap();
    }
    let from_urdf = Arm::load(format!("{path}.urdf").as_ref()).unwrap();
    assert_same_arm(&toml, &from_urdf, 1e-12);
    assert_eq!(
        std::fs::read_to_string(format!("{path}.urdf")).unwrap(),
        toml.to_urdf(),
        "regenerate the example: FREEFLOAT_REGENERATE=1 cargo test --lib urdf_round_trip"
    );
}

const LINK: &str = r#"<inertial><origin xyz="0.2 0 0"/><mass value="2"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0.03"/></inertial>"#;

fn joint(name: &str, kind: &str, parent: &str, child: &str, xyz: &str, extra: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}"/>{extra}</joint>"#
    )
}

/// A URDF as robotics tools write it: a massless `world` root floating the base, the base's
/// centre of mass off its frame, a fixed sensor on the base, a fixed gripper (with mass) and a
/// tool frame on the last link, an `<inertial>` turned about z. The merged numbers by hand.
#[test]
fn urdf_merges_fixed_joints_and_reads_the_tool_frame() {
    let z = r#"<axis xyz="0 0 1"/>"#;
    let text = format!(
        r#"<robot name="r">
  <link name="world"/>
  <link name="base"><inertial><origin xyz="0.05 -0.02 0.1"/><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="0.5"/></inertial></link>
  <link name="camera"><inertial><origin xyz="0 0 0"/><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0.01"/></inertial></link>
  <link name="upper">{LINK}</link>
  <link name="fore"><inertial><origin xyz="0.1 0 0" rpy="0 0 0.7"/><mass value="1"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
  <link name="gripper"><inertial><origin xyz="0 0 0"/><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0.002"/></inertial></link>
  <link name="tool"/>
  {}{}{}{}{}{}
</robot>"#,
        joint("float", "floating", "world", "base", "0 0 0", ""),
        joint("cam", "fixed", "base", "camera", "-0.1 0.3 0", ""),
        joint(
            "shoulder",
            "revolute",
            "base",
            "upper",
            "0.3 0.1 0.05",
            &format!(r#"{z}<limit lower="-3" upper="3" effort="10" velocity="1"/>"#)
        ),
        joint("elbow", "continuous", "upper", "fore", "0.4 0 0", z),
        joint("wrist", "fixed", "fore", "gripper", "0.3 0 0", ""),
        joint("tip", "fixed", "gripper", "tool", "0.05 0 0", ""),
    );
    let arm = urdf(&text).unwrap();
    // Base: 10 kg at (0.05, -0.02), 1 kg at (-0.1, 0.3): 11 kg at (0.5/11 - 0.1/11, -0.2/11 + 0.3/11).
    let com: [f64; 2] = [0.4 / 11.0, 0.1 / 11.0];
    let izz = 0.5
        + 0.01
        + 10.0 * ((0.05 - com[0]).powi(2) + (-0.02 - com[1]).powi(2))
        + ((-0.1 - com[0]).powi(2) + (0.3 - com[1]).powi(2));
    let forearm_com = (0.1 + 0.3) / 2.0;
    let expected = Arm::new(
        Base { mass: 11.0, inertia: izz },
        Mount::new(0.3 - com[0], 0.1 - com[1]).unwrap(),
        vec![
            Link { length: 0.4, com: 0.2, mass: 2.0, inertia: 0.03 },
            Link { length: 0.35, com: forearm_com, mass: 2.0, inertia: 0.01 + 0.002 + 2.0 * 0.1 * 0.1 },
        ],
    )
    .unwrap();
    assert_same_arm(&arm, &expected, 1e-12);
}

/// An end-effector link with mass fixed 0.5 m along the last link (as SPART's
/// `floating_planar_4dof_manipulator.urdf` has it): the tip is that link's origin, 0.5 m along,
/// not the merged centre of mass; the mass moves the link's centre of mass and inertia only.
/// Checked against forward kinematics written here from the URDF's frames (the system's centre of
/// mass at the origin), at random configurations; with a massless `tool0` 0.05 m beyond the end
/// effector, the tip is `tool0`.
#[test]
fn urdf_tool_point_is_the_fixed_end_effector_frame_whatever_its_mass() {
    let z = r#"<axis xyz="0 0 1"/>"#;
    let inertial = |x: f64, m: f64, izz: f64| {
        format!(
            r#"<inertial><origin xyz="{x} 0 0"/><mass value="{m}"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="{izz}"/></inertial>"#
        )
    };
    let file = |tool0: bool| {
        let (link, joint_tool) = if tool0 {
            (
                r#"<link name="tool0"/>"#.to_string(),
                joint("tool_joint", "fixed", "end_effector", "tool0", "0.05 0 0", ""),
            )
        } else {
            (String::new(), String::new())
        };
        format!(
            r#"<robot name="r">
  <link name="base">{}</link><link name="l1">{}</link><link name="l2">{}</link>
  <link name="end_effector">{}</link>{link}
  {}{}{}{joint_tool}
</robot>"#,
            inertial(0.0, 10.0, 1.0),
            inertial(0.25, 2.0, 0.02),
            inertial(0.25, 2.0, 0.02),
            inertial(0.0, 1.0, 0.001),
            joint("j1", "continuous", "base", "l1", "0.3 0 0", z),
            joint("j2", "continuous", "l1", "l2", "0.5 0 0", z),
            joint("ee", "fixed", "l2", "end_effector", "0.5 0 0", ""),
        )
    };
    for (tool0, tip) in [(false, 0.5), (true, 0.55)] {
        let arm = urdf(&file(tool0)).unwrap();
        let last = arm.links[1];
        assert!(close(last.length, tip, 1e-15, 1.0), "tool0 {tool0}: length {}", last.length);
        let com = (2.0 * 0.25 + 1.0 * 0.5) / 3.0;
        assert!(close(last.com, com, 1e-14, 1.0) && close(last.mass, 3.0, 1e-15, 1.0), "{last:?}");
        let inertia = 0.02 + 0.001 + 2.0 * (0.25 - com).powi(2) + (0.5 - com).powi(2);
        assert!(close(last.inertia, inertia, 1e-14, 1.0), "{last:?}");
        let mut rng = Rng::new(11);
        for _ in 0..20 {
            let q: Vec<f64> = (0..3).map(|_| rng.uniform(-std::f64::consts::PI, std::f64::consts::PI)).collect();
            let e = |psi: f64| [psi.cos(), psi.sin()];
            let (p1, p2) = (e(q[0] + q[1]), e(q[0] + q[1] + q[2]));
            // Frames relative to the base's centre of mass (the base frame's origin here).
            let j1 = [0.3 * q[0].cos(), 0.3 * q[0].sin()];
            let j2 = [j1[0] + 0.5 * p1[0], j1[1] + 0.5 * p1[1]];
            let at = |from: [f64; 2], d: f64, dir: [f64; 2]| [from[0] + d * dir[0], from[1] + d * dir[1]];
            let bodies = [([0.0, 0.0], 10.0), (at(j1, 0.25, p1), 2.0), (at(j2, 0.25, p2), 2.0), (at(j2, 0.5, p2), 1.0)];
            let total: f64 = bodies.iter().map(|b| b.1).sum();
            let centre = [0, 1].map(|i| bodies.iter().map(|b| b.1 * b.0[i]).sum::<f64>() / total);
            let tool = at(j2, tip, p2);
            let expected = [tool[0] - centre[0], tool[1] - centre[1]];
            let points = arm.joint_positions(&q);
            let got = points[points.len() - 1];
            assert!((got[0] - expected[0]).hypot(got[1] - expected[1]) < 1e-14, "{got:?} vs {expected:?}");
        }
    }
}

fn urdf_error(text: &str) -> (String, String) {
    match urdf(text) {
        Err(e @ InputError::Urdf { .. }) => {
            let InputError::Urdf { ref element, .. } = e else { unreachable!() };
            (element.clone(), e.to_string())
        }
        other => panic!("expected a URDF error, got {other:?}"),
    }
}

/// Branched, prismatic, non-z axis, missing inertial, turned origin, off-axis centre of mass,
/// nothing moving: an [`InputError::Urdf`] whose element and message name the joint or link.
#[test]
fn bad_urdfs_name_the_joint_or_link() {
    let good = Arm::from_params(&RobotParams::src()).to_urdf();
    assert!(urdf(&good).is_ok());
    let branched = good.replace(
        "</robot>",
        &format!(
            r#"<link name="spare">{LINK}</link>{}</robot>"#,
            joint("extra", "revolute", "link1", "spare", "0.1 0 0", r#"<axis xyz="0 0 1"/>"#)
        ),
    );
    let cases = [
        (branched, "joint `extra`", "branches"),
        (
            good.replacen(r#"name="joint2" type="continuous""#, r#"name="joint2" type="prismatic""#, 1),
            "joint `joint2`",
            "type prismatic",
        ),
        (good.replacen(r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 1 0"/>"#, 1), "joint `joint1`", "axis"),
        (good.replacen(r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 0 -1"/>"#, 1), "joint `joint1`", "axis"),
        (
            good.replacen(
                r#"rpy="0 0 0"/>
    <axis"#,
                r#"rpy="0 0 0.5"/>
    <axis"#,
                1,
            ),
            "joint `joint1`",
            "rpy",
        ),
        (strip_inertial(&good, "link2"), "link `link2`", "<inertial>"),
        (
            good.replacen(r#"<origin xyz="0.313 0 0""#, r#"<origin xyz="0.313 0.01 0""#, 1),
            "link `link1`",
            "off the link's x axis",
        ),
        (
            good.replacen(r#"<origin xyz="0.619 0.0 0""#, r#"<origin xyz="0.619 0.02 0""#, 1),
            "joint `joint2`",
            "off the x axis",
        ),
        (good.replace("continuous", "fixed"), "robot", "nothing moves"),
        (good.replacen(r#"<parent link="base"/>"#, r#"<parent link="nowhere"/>"#, 1), "joint `joint1`", "`nowhere`"),
        (
            good.replacen(r#"<parent link="link1"/>"#, r#"<parent link="base"/>"#, 1).replacen(
                "</robot>",
                &format!("{}</robot>", joint("again", "fixed", "link1", "link2", "0 0 0", "")),
                1,
            ),
            "link `link2`",
            "two joints",
        ),
        (good.replacen("</robot>", r#"<link name="loose"/></robot>"#, 1), "robot", "2 root links (`base`, `loose`)"),
        (
            good.replacen(
                "</robot>",
                &format!(
                    r#"<link name="c1"/><link name="c2"/>{}{}</robot>"#,
                    joint("c12", "fixed", "c1", "c2", "0 0 0", ""),
                    joint("c21", "fixed", "c2", "c1", "0 0 0", "")
                ),
                1,
            ),
            "link `c1`",
            "not connected to the base",
        ),
    ];
    for (text, element, reason) in cases {
        let (got, message) = urdf_error(&text);
        assert_eq!(got, element, "{message}");
        assert!(message.contains(element) && message.contains(reason), "{message}");
    }
    let e = urdf("<robot><link").unwrap_err().to_string();
    assert!(e.contains("not a valid URDF"), "{e}");
    // A bad value names the key and the URDF link.
    let e = urdf(&good.replacen(r#"<origin xyz="0.287 0 0""#, r#"<origin xyz="0.9 0 0""#, 1)).unwrap_err().to_string();
    assert!(e.contains("link[2].com (URDF link \"link2\")"), "{e}");
}

/// `good` with the `<inertial>` of link `name` removed.
fn strip_inertial(good: &str, name: &str) -> String {
    let start = good.find(&format!(r#"<link name="{name}">"#)).expect("the link");
    let from = start + good[start..].find("<inertial>").expect("its inertial");
    let to = from + good[from..].find("</inertial>").expect("its end") + "</inertial>".len();
    format!("{}{}", &good[..from], &good[to..])
}

/// [`Arm::joint_positions`] agrees with [`Arm::bodies`]: each link's centre of mass lies
/// `d_k` along the segment from its joint to the next (1e-12), the links keep their lengths;
/// and at n = 2 the points are [`crate::model::kinematics::pose`]'s.
#[test]
fn joint_positions_agree_with_bodies_and_the_two_link_pose() {
    use crate::model::Configuration;
    use crate::model::kinematics::pose;
    let three = Arm::from_toml(include_str!("../../../examples/robots/three_link.toml"), "three_link.toml".as_ref())
        .expect("the example robot file loads");
    let mut rng = Rng::new(7);
    for arm in [three, Arm::from_params(&RobotParams::src().with_mount(Mount::new(0.2, -0.1).unwrap()).unwrap())] {
        for _ in 0..20 {
            let q: Vec<f64> = (0..=arm.joints()).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let points = arm.joint_positions(&q);
            assert_eq!(points.len(), arm.joints() + 2);
            let frames = arm.bodies(&q);
            let close = |x: [f64; 2], y: [f64; 2]| (x[0] - y[0]).hypot(x[1] - y[1]) <= 1e-12;
            assert!(close(points[0], frames.base));
            for (k, link) in arm.links.iter().enumerate() {
                let (j, next) = (points[k + 1], points[k + 2]);
                assert!(((next[0] - j[0]).hypot(next[1] - j[1]) - link.length).abs() <= 1e-12);
                let s = link.com / link.length;
                let com = [j[0] + s * (next[0] - j[0]), j[1] + s * (next[1] - j[1])];
                assert!(close(com, frames.links[k]), "link {k}: {com:?} vs {:?}", frames.links[k]);
            }
            if let Some(robot) = arm.as_src() {
                let p = pose(&robot, &Configuration::from_array([q[0], q[1], q[2]]));
                for (x, y) in points.iter().zip([p.base, p.joint1, p.joint2, p.tip]) {
                    assert!(close(*x, y), "{x:?} vs {y:?}");
                }
            }
        }
    }
}
