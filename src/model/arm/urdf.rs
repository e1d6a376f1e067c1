//! An arm from a URDF file and back (docs/spec.md §1, URDF).
//!
//! The file is parsed by [`urdf_rs`], the URDF reader of the OpenRR project (the Rust robotics
//! framework; it follows the ROS URDF specification, URDF 1.0 to 1.2), so that freefloat reads
//! what ROS tools write; freefloat then checks that the tree is a planar serial arm:
//!
//! - **Tree.** Fixed joints merge their child link into its parent (masses added, centres of
//!   mass combined, moments of inertia moved by the parallel-axis theorem) and may branch
//!   (sensors, frames). The other joints must be `revolute` or `continuous` about `+z` (axis
//!   `0 0 1`) and form one chain from the root link, the base. An axis `0 0 -1` is refused rather
//!   than turned into a sign: freefloat's angles are counter-clockwise about `+z`. A massless root
//!   link (`world`) whose one joint is `floating` or `planar` is dropped: the base floats anyway.
//! - **Planar frames.** Every joint origin has `rpy = 0` (so at zero joint angles every link runs
//!   along the base's `x` axis); `z` offsets of joints and centres of mass are ignored (they do not
//!   change the planar dynamics). A link's `<inertial>` may have any `rpy`: its `izz` about the
//!   joint axis is what counts.
//! - **Numbers.** The base's mass and inertia are its merged body's about the merged centre of
//!   mass, which need not be at the root link's origin: the mount `(a, b)` is the first joint's
//!   origin minus the base's centre of mass. Link `k`'s centre of mass must lie on its `x` axis
//!   (within [`URDF_PLANAR_TOLERANCE`]), `com` is its `x`; its length is the `x` of the next
//!   joint's origin, which must lie on that axis too. The last link's length is the `x` of its
//!   **tool frame**: of the links fixed to it that end its fixed subtree (no joint leaves them),
//!   with or without mass, the one farthest along its `x` axis (it must lie on the axis). A fixed
//!   end-effector link with mass adds its mass and inertia to the last link (moving its centre of
//!   mass), never its length. Without a fixed child, the length is the link's `com` (the tip at
//!   the centre of mass).

use std::collections::{HashMap, HashSet};
use std::path::Path;

use urdf_rs::{Joint, JointType};

use super::{Arm, Base, Link};
use crate::model::robot_file::short_reason;
use crate::model::{InputError, Mount, excerpt};

/// Largest accepted off-plane quantity in a URDF: a joint's `rpy` \[rad\], an axis' `x, y` per unit
/// length, the `y` of a centre of mass or of a joint on its link \[m\].
pub const URDF_PLANAR_TOLERANCE: f64 = 1e-9;

/// The deepest nesting of XML elements read from a URDF (`<robot>` is level 1; a URDF needs about
/// six: `robot`, `link`, `visual`, `geometry`, `mesh`, and a vendor's extension or two).
pub const MAX_XML_DEPTH: usize = 64;

/// Refuses a text whose elements nest deeper than [`MAX_XML_DEPTH`] (an
/// [`InputError::NestedTooDeep`] naming the line), or that is not well-formed XML: one linear
/// scan by quick-xml's streaming reader, which keeps no stack of its own, before the URDF
/// reader, which recurses into every element (15000 nested elements overflowed its stack).
fn check_nesting(text: &str, path: &Path) -> Result<(), InputError> {
    use quick_xml::events::Event;
    let line_at = |offset: u64| {
        let end = usize::try_from(offset).unwrap_or(usize::MAX).min(text.len());
        text.as_bytes()[..end].iter().filter(|&&b| b == b'\n').count() + 1
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut depth = 0usize;
    loop {
        match reader.read_event() {
            Ok(Event::Start(_)) => {
                depth += 1;
                if depth > MAX_XML_DEPTH {
                    let line = line_at(reader.buffer_position());
                    return Err(InputError::NestedTooDeep { path: path.to_path_buf(), line, limit: MAX_XML_DEPTH });
                }
            }
            Ok(Event::End(_)) => depth = depth.saturating_sub(1),
            Ok(Event::Eof) => return Ok(()),
            Ok(_) => {}
            Err(e) => {
                let line = line_at(reader.error_position());
                return Err(InputError::RobotFile {
                    path: path.to_path_buf(),
                    reason: short_reason(&format!("not a valid URDF: line {line}: {e}")),
                });
            }
        }
    }
}

/// One rigid body: a link with its fixed descendants.
struct Body<'a> {
    /// The link that the entering joint moves (the root link for the base).
    root: &'a str,
    /// Masses, centres of mass in the body's frame and `izz` about them.
    parts: Vec<(f64, [f64; 2], f64)>,
    /// The fixed descendants that end the body's fixed subtree (links with no child joint, with
    /// or without mass): their names and origins in the body's frame. The last body's tool frame
    /// is one of them.
    frames: Vec<(&'a str, [f64; 2])>,
    /// The joint leaving the body and its origin in the body's frame.
    next: Option<(&'a Joint, [f64; 2])>,
    /// Its links and their origins in the body's frame, for their geometry (issue 21).
    geometry: Vec<(&'a urdf_rs::Link, [f64; 2])>,
}

impl Body<'_> {
    /// Total mass, centre of mass and moment of inertia about it (parallel-axis theorem).
    fn merged(&self) -> (f64, [f64; 2], f64) {
        let mass: f64 = self.parts.iter().map(|p| p.0).sum();
        if mass <= 0.0 {
            return (0.0, [0.0, 0.0], 0.0);
        }
        let mut com = [0.0, 0.0];
        for (m, c, _) in &self.parts {
            com = [com[0] + m * c[0], com[1] + m * c[1]];
        }
        let com = [com[0] / mass, com[1] / mass];
        let izz = self.parts.iter().map(|(m, c, i)| i + m * ((c[0] - com[0]).powi(2) + (c[1] - com[1]).powi(2))).sum();
        (mass, com, izz)
    }
}

/// The name of the root element of an XML text: after the declaration, comments, processing
/// instructions and the document type; `None` when there is none (the reader then refuses it).
fn root_element(text: &str) -> Option<&str> {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = rest.trim_start();
        let close = if rest.starts_with("<?") {
            "?>"
        } else if rest.starts_with("<!--") {
            "-->"
        } else if rest.starts_with("<!") {
            ">"
        } else {
            break;
        };
        rest = &rest[rest.find(close)? + close.len()..];
    }
    let tag = rest.strip_prefix('<')?;
    let end = tag.find(|c: char| c.is_whitespace() || c == '>' || c == '/').unwrap_or(tag.len());
    Some(&tag[..end])
}

fn link_name(name: &str) -> String {
    format!("link `{}`", excerpt(name))
}

fn joint_name(joint: &Joint) -> String {
    format!("joint `{}`", excerpt(&joint.name))
}

impl Arm {
    /// Reads an arm from a URDF's text by the rules of [the module doc](crate::model::arm::urdf) (docs/spec.md §1, URDF);
    /// `path` names the file in messages. A tree that is no planar serial arm is an
    /// [`InputError::Urdf`] naming the offending joint or link; a bad value an
    /// [`InputError::InvalidParameter`] naming the key of [`Arm::new`] and the URDF link.
    pub fn from_urdf_str(text: &str, path: &Path) -> Result<Self, InputError> {
        Self::from_urdf_str_named(text, path).map(|(arm, _)| arm)
    }

    /// [`Arm::from_urdf_str`], with the names of the arm's moving joints from the base outwards
    /// (the URDF's `<joint name>`: the names a ROS 2 `JointTrajectory` of this robot uses).
    pub fn from_urdf_str_named(text: &str, path: &Path) -> Result<(Self, Vec<String>), InputError> {
        Self::from_urdf_str_described(text, path).map(|(arm, names, _)| (arm, names))
    }

    /// [`Arm::from_urdf_str_named`], with the name of the tool frame that ends the last link
    /// (the module doc's rule); `None` when the last link has no fixed child (its tip is then its
    /// centre of mass).
    pub fn from_urdf_str_described(text: &str, path: &Path) -> Result<(Self, Vec<String>, Option<String>), InputError> {
        Self::from_urdf_str_noted(text, path).map(|(arm, names, tool, _)| (arm, names, tool))
    }

    /// [`Arm::from_urdf_str_described`], with the notes on the geometry read
    /// ([`super::shapes`]: a body whose `<visual>` stands in for its missing `<collision>`, a
    /// mesh skipped).
    #[allow(clippy::type_complexity)]
    pub fn from_urdf_str_noted(
        text: &str,
        path: &Path,
    ) -> Result<(Self, Vec<String>, Option<String>, Vec<String>), InputError> {
        check_nesting(text, path)?;
        let robot = urdf_rs::read_from_string(text).map_err(|e| InputError::RobotFile {
            path: path.to_path_buf(),
            reason: short_reason(&format!("not a valid URDF: {e}")),
        })?;
        let fail = |element: String, reason: String| InputError::Urdf { path: path.to_path_buf(), element, reason };
        // The reader takes any root element's children: only `<robot>` is a URDF.
        if let Some(name) = root_element(text).filter(|name| *name != "robot") {
            return Err(fail(
                format!("element `<{}>`", excerpt(name)),
                "the root element of a URDF is `<robot>`".into(),
            ));
        }
        let mut links = HashMap::new();
        for link in &robot.links {
            if links.insert(link.name.as_str(), link).is_some() {
                return Err(fail(link_name(&link.name), "defined twice".into()));
            }
        }
        let mut parent_of: HashMap<&str, &Joint> = HashMap::new();
        let mut children: HashMap<&str, Vec<&Joint>> = HashMap::new();
        for joint in &robot.joints {
            if let Some(mimic) = &joint.mimic {
                let reason = format!(
                    "mimics joint `{}`: mimic joints are not supported (every joint of the arm moves on its own); \
                     remove the <mimic> or the joint",
                    excerpt(&mimic.joint)
                );
                return Err(fail(joint_name(joint), reason));
            }
            for end in [&joint.parent.link, &joint.child.link] {
                if !links.contains_key(end.as_str()) {
                    return Err(fail(joint_name(joint), format!("names {}, which is not defined", link_name(end))));
                }
            }
            if let Some(other) = parent_of.insert(&joint.child.link, joint) {
                let reason = format!(
                    "is the child of two joints, `{}` and `{}`: not a tree",
                    excerpt(&other.name),
                    excerpt(&joint.name)
                );
                return Err(fail(link_name(&joint.child.link), reason));
            }
            children.entry(joint.parent.link.as_str()).or_default().push(joint);
        }
        let roots: Vec<&str> =
            robot.links.iter().map(|l| l.name.as_str()).filter(|name| !parent_of.contains_key(name)).collect();
        let [mut root] = roots[..] else {
            // At most five names: a file may have thousands of root links.
            let mut names = roots.iter().take(5).map(|r| format!("`{}`", excerpt(r))).collect::<Vec<_>>().join(", ");
            if roots.len() > 5 {
                names += &format!(" and {} more", roots.len() - 5);
            }
            let reason = format!("{} root links ({names}): expected one tree whose root is the base", roots.len());
            return Err(fail("robot".into(), reason));
        };
        if let Some([joint]) = children.get(root).map(Vec::as_slice)
            && links[root].inertial.mass.value == 0.0
            && matches!(joint.joint_type, JointType::Floating | JointType::Planar)
        {
            root = &joint.child.link;
        }
        // Walk the tree body by body: fixed joints stay in the body, the other one leaves it.
        let mut bodies: Vec<Body> = Vec::new();
        let mut entering = vec![];
        let mut start = Some(root);
        let mut visited = HashSet::new();
        while let Some(body_root) = start.take() {
            let mut body = Body { root: body_root, parts: vec![], frames: vec![], next: None, geometry: vec![] };
            let mut stack = vec![(body_root, [0.0, 0.0])];
            while let Some((name, at)) = stack.pop() {
                visited.insert(name);
                let link = links[name];
                body.geometry.push((link, at));
                let (mass, com, izz) = inertial(link).map_err(|reason| fail(link_name(name), reason))?;
                if mass > 0.0 {
                    body.parts.push((mass, [at[0] + com[0], at[1] + com[1]], izz));
                }
                if name != body_root && !children.contains_key(name) {
                    body.frames.push((name, at));
                }
                for &joint in children.get(name).into_iter().flatten() {
                    check_joint(joint).map_err(|reason| fail(joint_name(joint), reason))?;
                    let origin = joint.origin.xyz;
                    let p = [at[0] + origin[0], at[1] + origin[1]];
                    if joint.joint_type == JointType::Fixed {
                        stack.push((&joint.child.link, p));
                    } else if let Some((other, _)) = body.next {
                        let reason = format!(
                            "branches: joints `{}` and `{}` both move off the body of {}; freefloat models one serial arm",
                            excerpt(&other.name),
                            excerpt(&joint.name),
                            link_name(body_root)
                        );
                        return Err(fail(joint_name(joint), reason));
                    } else {
                        body.next = Some((joint, p));
                    }
                }
            }
            if let Some((joint, _)) = body.next {
                entering.push(joint);
                start = Some(&joint.child.link);
            }
            bodies.push(body);
        }
        if visited.len() + usize::from(root != roots[0]) != robot.links.len()
            && let Some(lost) = robot.links.iter().find(|l| l.name != roots[0] && !visited.contains(l.name.as_str()))
        {
            return Err(fail(link_name(&lost.name), format!("is not connected to the base `{}`", excerpt(root))));
        }
        if bodies.len() < 2 {
            return Err(fail("robot".into(), "no revolute or continuous joint: nothing moves".into()));
        }
        let (base, mount, arm_links) = chain(&bodies).map_err(|(element, reason)| fail(element, reason))?;
        let names = entering.iter().map(|j| j.name.clone()).collect();
        let arm = Arm::new(base, mount, arm_links).map_err(|e| match e {
            InputError::InvalidParameter { name, value, expected } => {
                let owner = match name.strip_prefix("link[").and_then(|s| s.split(']').next()) {
                    Some(k) => {
                        format!(
                            "link \"{}\"",
                            k.parse::<usize>().ok().and_then(|k| bodies.get(k)).map_or(root, |b| b.root)
                        )
                    }
                    None if name.starts_with("mount") => format!("joint \"{}\"", entering[0].name),
                    None => format!("link \"{root}\""),
                };
                InputError::InvalidParameter { name: format!("{name} (URDF {})", excerpt(&owner)), value, expected }
            }
            other => other,
        })?;
        // Issue 20: the moving joints' `<limit>`s (module `urdf_limits`).
        let moving: Vec<(String, bool)> =
            entering.iter().map(|j| (j.name.clone(), j.joint_type == JointType::Revolute)).collect();
        let arm = arm.with_limits(super::urdf_limits::read_limits(text, path, &moving)?)?;
        let tool = bodies.last().and_then(tool_frame).map(|(name, _)| name.to_string());
        let (geometry, notes) = geometry(&bodies).map_err(|(element, reason)| fail(element, reason))?;
        let arm = arm.with_geometry(geometry)?;
        Ok((arm, names, tool, notes))
    }

    /// The arm as a URDF that [`Arm::from_urdf_str`] reads back to the same arm: links `base`,
    /// `link1`..`linkN` and a massless `tool` frame at the tip, `continuous` joints
    /// `joint1`..`jointN` about `z`, the base's frame at its centre of mass. The planar model
    /// fixes only `izz`; `ixx = iyy = izz / 2` (a flat body in the plane, which keeps the tensor
    /// physical for simulators).
    pub fn to_urdf(&self) -> String {
        let inertial = |mass: f64, x: f64, izz: f64| {
            format!(
                "    <inertial>\n      <origin xyz=\"{x:?} 0 0\" rpy=\"0 0 0\"/>\n      <mass value=\"{mass:?}\"/>\n      \
                 <inertia ixx=\"{:?}\" ixy=\"0\" ixz=\"0\" iyy=\"{:?}\" iyz=\"0\" izz=\"{izz:?}\"/>\n    </inertial>\n",
                izz / 2.0,
                izz / 2.0
            )
        };
        let joint = |name: &str, kind: &str, parent: &str, child: &str, x: f64, y: f64| {
            let axis = if kind == "fixed" { "" } else { "    <axis xyz=\"0 0 1\"/>\n" };
            format!(
                "  <joint name=\"{name}\" type=\"{kind}\">\n    <parent link=\"{parent}\"/>\n    <child link=\"{child}\"/>\n    \
                 <origin xyz=\"{x:?} {y:?} 0\" rpy=\"0 0 0\"/>\n{axis}  </joint>\n"
            )
        };
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<!-- A planar free-floating arm, written by freefloat (docs/spec.md §1, URDF). -->\n\
             <robot name=\"freefloat_arm\">\n",
        );
        s += &format!("  <link name=\"base\">\n{}  </link>\n", inertial(self.base.mass, 0.0, self.base.inertia));
        let mut parent = "base".to_string();
        let (mut x, mut y) = (self.mount.a, self.mount.b);
        for (k, link) in self.links.iter().enumerate() {
            let name = format!("link{}", k + 1);
            s += &format!("  <link name=\"{name}\">\n{}  </link>\n", inertial(link.mass, link.com, link.inertia));
            s += &joint(&format!("joint{}", k + 1), "continuous", &parent, &name, x, y);
            (parent, x, y) = (name, link.length, 0.0);
        }
        s += "  <link name=\"tool\"/>\n";
        s += &joint("tool_joint", "fixed", &parent, "tool", x, y);
        s + "</robot>\n"
    }
}

/// A link's mass, centre of mass `(x, y)` in its frame and moment of inertia about the `z` axis
/// through it: `izz` of the inertia tensor turned by the `<inertial>` `rpy`.
fn inertial(link: &urdf_rs::Link) -> Result<(f64, [f64; 2], f64), String> {
    let i = &link.inertial;
    let mass = i.mass.value;
    if !(mass.is_finite() && mass >= 0.0) {
        return Err(format!("mass {mass}: expected a finite mass >= 0"));
    }
    let [roll, pitch, _] = *i.origin.rpy;
    // Third row of R = Rz(yaw) Ry(pitch) Rx(roll): the joint axis z in the inertial frame.
    let r = [-pitch.sin(), pitch.cos() * roll.sin(), pitch.cos() * roll.cos()];
    let t = &i.inertia;
    let tensor = [[t.ixx, t.ixy, t.ixz], [t.ixy, t.iyy, t.iyz], [t.ixz, t.iyz, t.izz]];
    let izz: f64 = (0..3).flat_map(|a| (0..3).map(move |b| (a, b))).map(|(a, b)| r[a] * tensor[a][b] * r[b]).sum();
    if !(izz.is_finite() && izz >= 0.0) {
        return Err(format!("moment of inertia about z {izz}: expected a finite value >= 0"));
    }
    Ok((mass, [i.origin.xyz[0], i.origin.xyz[1]], izz))
}

/// Checks a joint's type, axis and origin (module doc).
fn check_joint(joint: &Joint) -> Result<(), String> {
    let tol = URDF_PLANAR_TOLERANCE;
    match joint.joint_type {
        JointType::Fixed => {}
        JointType::Revolute | JointType::Continuous => {
            let [x, y, z] = *joint.axis.xyz;
            let norm = (x * x + y * y + z * z).sqrt();
            if !norm.is_finite() {
                return Err(format!(
                    "axis ({x}, {y}, {z}) is not finite: a planar arm's joints turn about +z (axis \"0 0 1\")"
                ));
            }
            if !(x.abs() <= tol * norm && y.abs() <= tol * norm && z > 0.0) {
                return Err(format!(
                    "axis ({x}, {y}, {z}): a planar arm's joints turn about +z (axis \"0 0 1\"; for \"0 0 -1\" \
                     flip the axis and the sign of the joint's angles)"
                ));
            }
        }
        ref other => {
            let kind = format!("{other:?}").to_lowercase();
            return Err(format!(
                "type {kind}: a planar arm has revolute or continuous joints about z, and fixed joints"
            ));
        }
    }
    let rpy = *joint.origin.rpy;
    if rpy.iter().any(|a| !(a.abs() <= tol)) {
        return Err(format!(
            "origin rpy ({}, {}, {}): every joint origin must have rpy = 0 (links along x at zero angles)",
            rpy[0], rpy[1], rpy[2]
        ));
    }
    if joint.origin.xyz.iter().any(|v| !v.is_finite()) {
        return Err("origin xyz not finite".into());
    }
    Ok(())
}

/// The tool frame of the last body: of the fixed links that end its fixed subtree (a leaf: no
/// joint leaves it), with or without mass, the one farthest along the link's `x` axis (ties: the
/// first in the file); `None` when the body has no fixed child. Its mass, if any, is merged into
/// the link's centre of mass and inertia; it never moves the tip (docs/spec.md §1, URDF).
fn tool_frame<'a>(body: &Body<'a>) -> Option<(&'a str, [f64; 2])> {
    body.frames.iter().copied().reduce(|best, f| if f.1[0] > best.1[0] { f } else { best })
}

/// The shapes of the bodies (base first) in freefloat's frames: a link body's frame is its URDF
/// root link's (joint `k` at the origin, `x` along the link), the base's is moved to its merged
/// centre of mass. Errors as `(element, reason)`.
fn geometry(bodies: &[Body]) -> Result<(super::collision::Geometry, Vec<String>), (String, String)> {
    let (mut notes, mut visual_bodies) = (Vec::new(), Vec::new());
    let mut shapes = Vec::with_capacity(bodies.len());
    for body in bodies {
        let s = super::shapes::urdf_body_shapes(&body.geometry, &excerpt(body.root), &mut notes, &mut visual_bodies)
            .map_err(|(link, reason)| (link_name(&link), reason))?;
        shapes.push(s);
    }
    notes.extend(super::shapes::visual_note(&visual_bodies));
    let com = bodies[0].merged().1;
    let mut geometry = super::collision::Geometry { base: shapes.remove(0), ..Default::default() };
    for s in &mut geometry.base {
        s.points.iter_mut().for_each(|p| *p = [p[0] - com[0], p[1] - com[1]]);
    }
    if shapes.iter().any(|s| !s.is_empty()) {
        geometry.links = shapes;
    }
    Ok((geometry, notes))
}

/// The base, mount and links from the bodies (base first); errors as `(element, reason)`.
fn chain(bodies: &[Body]) -> Result<(Base, Mount, Vec<Link>), (String, String)> {
    let tol = URDF_PLANAR_TOLERANCE;
    let mut merged = Vec::with_capacity(bodies.len());
    for body in bodies {
        let (mass, com, izz) = body.merged();
        if mass <= 0.0 {
            let reason = "has no <inertial> mass (nor any fixed child with one): every body of the arm needs a mass";
            return Err((link_name(body.root), reason.into()));
        }
        merged.push((mass, com, izz));
    }
    let (base_mass, base_com, base_izz) = merged[0];
    let first = bodies[0].next.map_or([0.0, 0.0], |(_, p)| p);
    let mount = Mount { a: first[0] - base_com[0], b: first[1] - base_com[1] };
    let mut links = Vec::with_capacity(bodies.len() - 1);
    for (k, body) in bodies.iter().enumerate().skip(1) {
        let (mass, com, inertia) = merged[k];
        if !(com[1].abs() <= tol) {
            let reason = format!("centre of mass at y = {} m off the link's x axis (joint to next joint)", com[1]);
            return Err((link_name(body.root), reason));
        }
        let length = match body.next {
            Some((joint, p)) => {
                if !(p[1].abs() <= tol) {
                    let reason = format!(
                        "origin at y = {} m off the x axis of {}: links run along x",
                        p[1],
                        link_name(body.root)
                    );
                    return Err((joint_name(joint), reason));
                }
                p[0]
            }
            None => match tool_frame(body) {
                Some((name, p)) if !(p[1].abs() <= tol) => {
                    let reason = format!("tool frame {} at y = {} m off the link's x axis", link_name(name), p[1]);
                    return Err((link_name(body.root), reason));
                }
                Some((_, p)) => p[0],
                None => com[0],
            },
        };
        links.push(Link { length, com: com[0], mass, inertia });
    }
    Ok((Base { mass: base_mass, inertia: base_izz }, mount, links))
}
