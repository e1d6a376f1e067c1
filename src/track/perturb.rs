//! The true robot of a simulation: the planning model with every physical parameter perturbed
//! at random, within stated bounds (a model error the controllers must live with).

use serde::Serialize;

use super::noise::Noise;
use crate::error::Error;
use crate::model::{InputError, Mount, RobotParams};

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

    /// The perturbed robot of trial `seed` (stream 0 of [`Noise`]): reproducible. A centre of
    /// mass pushed past its link's end is put back at the end (`d_i <= l_i`).
    pub fn apply(&self, robot: &RobotParams, seed: u64) -> Result<RobotParams, Error> {
        self.validate()?;
        let mut n = Noise::new(seed, 0);
        let relative = self.relative;
        let scale = |n: &mut Noise, x: f64| x * (1.0 + relative * n.symmetric());
        let (l1, l2) = (scale(&mut n, robot.l1), scale(&mut n, robot.l2));
        let (d1, d2) = (scale(&mut n, robot.d1).min(l1), scale(&mut n, robot.d2).min(l2));
        let (base_mass, base_inertia) = (scale(&mut n, robot.base_mass), scale(&mut n, robot.base_inertia));
        let (m1, m2) = (scale(&mut n, robot.m1), scale(&mut n, robot.m2));
        let a = robot.mount.a + self.mount * n.symmetric();
        let b = robot.mount.b + self.mount * n.symmetric();
        let mount = Mount::new(a, b)?;
        // Drawn last, so that the trials of point-mass robots are those of earlier versions.
        let (i1, i2) = (scale(&mut n, robot.i1), scale(&mut n, robot.i2));
        Ok(RobotParams::new(RobotParams { l1, l2, d1, d2, base_mass, base_inertia, m1, m2, i1, i2, mount })?)
    }
}
