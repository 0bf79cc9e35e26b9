//! Simulation parameters and the collision rig.

use crate::Error;
use glam::Vec3;

/// Parameters of one fixed simulation step ([`crate::step`]).
///
/// All fields are public; build with `..Default::default()`. [`SimParams::validate`]
/// reports values outside their ranges. `step` never panics on bad values: a
/// strand they drive non-finite is restored to its rest pose and counted.
#[derive(Clone, Debug, PartialEq)]
pub struct SimParams {
    /// Fixed step in seconds (default 1/60). Verlet needs a fixed dt: handle a
    /// variable frame time with [`crate::FixedStep`].
    pub dt: f32,
    /// `d` in `x + d (x - x_prev) + a dt^2` (Yip 2011): 1 = no damping,
    /// 0 = no velocity carried over. Default 0.97.
    pub damping: f32,
    /// Acceleration in m/s^2, default (0, -9.81, 0).
    pub gravity: Vec3,
    /// Gauss-Seidel constraint sweeps per step (default 4).
    pub iterations: u32,
    /// Collision points per segment besides its two end vertices, at
    /// t = j / (k + 1) (Nalu's pearls). Default 1. At most 64.
    pub pearls_per_segment: u32,
    /// Collision radius of vertices and pearls in metres (default 2 mm).
    pub pearl_radius: f32,
    /// Strain limit: `|x_i - root| <= (1 + max_stretch) * rest arc length(i)`
    /// (Yip's root spheres; Long Range Attachments, Kim et al. 2012).
    /// Default 0.01 (visible stretch stays near 1 %).
    pub max_stretch: f32,
    /// Stiffness in [0, 1] of the bending constraints between vertices i and
    /// i + 2 (Yip 2011). 0 (default) switches them off.
    pub bend_stiffness: f32,
    /// Pull in [0, 1] per step toward the groomed rest shape, strongest at the
    /// root and fading linearly to 0 at the tip (Yip 2011; TressFX's shape
    /// constraints). 0 (default) switches it off.
    pub shape_stiffness: f32,
    /// Contact friction in [0, 1]: the share of a vertex's tangential
    /// velocity removed when a sphere pushes it out (0 = frictionless).
    /// Default 0.3: hair rests on a scalp rather than sliding off it, and
    /// draped tips stop jittering (measured at rest with 4 iterations: the
    /// fastest vertex 0.10 m/s frictionless, 0.04 m/s with 0.3).
    pub friction: f32,
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            dt: 1.0 / 60.0,
            damping: 0.97,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            iterations: 4,
            pearls_per_segment: 1,
            pearl_radius: 0.002,
            max_stretch: 0.01,
            bend_stiffness: 0.0,
            shape_stiffness: 0.0,
            friction: 0.3,
        }
    }
}

/// Largest accepted `pearls_per_segment`.
pub const MAX_PEARLS_PER_SEGMENT: u32 = 64;

fn check(name: &'static str, value: f32, ok: bool, expected: &'static str) -> Result<(), Error> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

impl SimParams {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<(), Error> {
        check("dt", self.dt, self.dt > 0.0, "a finite dt > 0")?;
        check(
            "damping",
            self.damping,
            (0.0..=1.0).contains(&self.damping),
            "0 <= damping <= 1",
        )?;
        for g in self.gravity.to_array() {
            check("gravity", g, true, "finite components")?;
        }
        check(
            "pearls_per_segment",
            self.pearls_per_segment as f32,
            self.pearls_per_segment <= MAX_PEARLS_PER_SEGMENT,
            "at most 64 pearls per segment",
        )?;
        check(
            "pearl_radius",
            self.pearl_radius,
            self.pearl_radius >= 0.0,
            "pearl_radius >= 0",
        )?;
        check(
            "max_stretch",
            self.max_stretch,
            self.max_stretch >= 0.0,
            "max_stretch >= 0",
        )?;
        check(
            "bend_stiffness",
            self.bend_stiffness,
            (0.0..=1.0).contains(&self.bend_stiffness),
            "0 <= bend_stiffness <= 1",
        )?;
        check(
            "shape_stiffness",
            self.shape_stiffness,
            (0.0..=1.0).contains(&self.shape_stiffness),
            "0 <= shape_stiffness <= 1",
        )?;
        check(
            "friction",
            self.friction,
            (0.0..=1.0).contains(&self.friction),
            "0 <= friction <= 1",
        )?;
        Ok(())
    }
}
