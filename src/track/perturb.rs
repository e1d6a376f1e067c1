//! The true robot of a simulation: the planning model with every physical parameter perturbed
//! at random, within stated bounds (a model error the controllers must live with).

use serde::Serialize;

use super::noise::Noise;
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::{InputError, Mount};

/// Bounds of a random model error.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Perturbation {
    /// Each mass, inertia, length and centre-of-mass distance is multiplied by `1 + r`, `r`
    /// uniform in `[-relative, relative]`; default 0. Must lie in `[0, 0.5]`.
    pub relative: f64,
    /// Each mounting coordinate `a, b` moves by a uniform amount in `[-mount, mount]` \[m\];
    /// default 0. Must lie in `[0, 0.5]` m.
    pub mount: f64,
}

impl Perturbation {
    /// Checks the bounds (see the fields).
    pub fn validate(&self) -> Result<(), Error> {
        for (name, value, expected) in [
            ("perturb", self.relative, "a relative bound in [0, 0.5]"),
            ("perturb-mount", self.mount, "a bound in [0, 0.5] m"),
        ] {
            if !(0.0..=0.5).contains(&value) {
                return Err(InputError::InvalidParameter { name: name.into(), value, expected }.into());
            }
        }
        Ok(())
    }

    /// True when both bounds are zero: the true robot is the model.
    pub fn is_zero(&self) -> bool {
        self.relative == 0.0 && self.mount == 0.0
    }

    /// The perturbed arm of trial `seed` (stream 0 of [`Noise`]): reproducible. Every link's
    /// length, centre-of-mass distance, mass and inertia, the base's mass and inertia are scaled,
    /// the mount moved. A centre of mass pushed past its link's end is put back at the end
    /// (`com <= length`). The draws come in the order lengths, distances, base mass and inertia,
    /// masses, mount, link inertias: for the SRC robot those of earlier versions' 2-link robot.
    pub fn apply(&self, arm: &Arm, seed: u64) -> Result<Arm, Error> {
        self.validate()?;
        let mut n = Noise::new(seed, 0);
        let relative = self.relative;
        let scale = |n: &mut Noise, x: f64| x * (1.0 + relative * n.symmetric());
        let mut out = arm.clone();
        for link in &mut out.links {
            link.length = scale(&mut n, link.length);
        }
        for link in &mut out.links {
            link.com = scale(&mut n, link.com).min(link.length);
        }
        out.base.mass = scale(&mut n, arm.base.mass);
        out.base.inertia = scale(&mut n, arm.base.inertia);
        for link in &mut out.links {
            link.mass = scale(&mut n, link.mass);
        }
        let a = arm.mount.a + self.mount * n.symmetric();
        let b = arm.mount.b + self.mount * n.symmetric();
        out.mount = Mount::new(a, b)?;
        // Drawn last, so that the trials of point-mass robots are those of earlier versions.
        for link in &mut out.links {
            link.inertia = scale(&mut n, link.inertia);
        }
        out.validate()?;
        Ok(out)
    }
}
