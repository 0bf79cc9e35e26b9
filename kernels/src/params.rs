//! Simulation parameters and the collision rig.

use crate::Error;
use glam::Vec3;

/// Parameters of one fixed simulation step ([`crate::step`], and the cloth
/// [`crate::patch::step`], which reads the fields it shares).
///
/// All fields are public; build with `..Default::default()`. [`SimParams::validate`]
/// reports values outside their ranges. `step` never panics on bad values: a
/// strand they drive non-finite is restored to its rest pose and counted.
#[derive(Clone, Debug, PartialEq)]
pub struct SimParams {
    /// Fixed step in seconds (default 1/60). Handle a variable frame time
    /// with [`crate::FixedStep`]. A strand step runs
    /// `ceil(dt / max_substep)` substeps inside it.
    pub dt: f32,
    /// Velocity kept per step of `dt`: `x + d^(1/n) (x - x_prev) + g h^2`
    /// per substep of `h = dt / n` (Yip 2011's `d`, spread over the
    /// substeps so that it means the same at any substep count): 1 = no
    /// damping, 0 = no velocity carried over. Default 0.97.
    pub damping: f32,
    /// Acceleration in m/s^2, default (0, -9.81, 0).
    pub gravity: Vec3,
    /// Strands: projections of the length constraints per substep (Newton
    /// iterations of the chain's tridiagonal solve; default 1: at substeps
    /// of 1/240 s one converges, a second changed no measured figure).
    /// Patches: Gauss-Seidel sweeps per step.
    pub iterations: u32,
    /// Collision points per segment besides its two end vertices, at
    /// t = j / (k + 1) (Nalu's pearls). Default 1. At most 64.
    pub pearls_per_segment: u32,
    /// Collision radius of vertices and pearls in metres (default 2 mm).
    pub pearl_radius: f32,
    /// Two-sided strain limit per segment:
    /// `(1 - max_stretch) l <= |x_v - x_{v-1}| <= (1 + max_stretch) l`
    /// (Provot 1995, in Follow-The-Leader order, Muller et al. 2012).
    /// Summed over segments this bounds `|x_i - root|` by
    /// `(1 + max_stretch)` times the rest arc length. Default 0.01.
    pub max_stretch: f32,
    /// Strands: stiffness in [0, 1] of the bending constraints between
    /// vertices i and i + 2 (Yip 2011), per step (applied per substep as
    /// `1 - (1 - k)^(1/n)`); it keeps the angle between neighbouring
    /// segments, not their direction in the parent's frame (that is
    /// `local_shape_stiffness`). Patches: the cloth's bending. 0 (default)
    /// switches them off.
    pub bend_stiffness: f32,
    /// Pull in [0, 1] per step toward the groomed rest shape at the root,
    /// strongest at the root and fading linearly to 0 at the tip (Yip 2011;
    /// TressFX's global shape constraints), applied per substep as
    /// `1 - (1 - k)^(1/n)`. 0 (default) switches it off.
    pub shape_stiffness: f32,
    /// Contact friction in [0, 1]: the share of a vertex's tangential
    /// velocity removed when a sphere pushes it out (0 = frictionless).
    /// Default 0.3: hair rests on a scalp rather than sliding off it.
    pub friction: f32,
    /// TressFX-style local shape constraints in [0, 1] (TressFX 4, AMD
    /// 2017): each segment keeps its groomed direction in its parent
    /// segment's frame (the root segment in the groom frame, which follows
    /// [`crate::Strands::set_rest_rotation`] and `teleport`). 0 (default)
    /// switches them off. Substep-independent: a substep of `h` corrects the
    /// share `c` of the error with `c / (1 - c) = (c_ref / (1 - c_ref))
    /// (h / (1/240 s))`, `c_ref = 0.99 k` (measured on the TressFX mohawk:
    /// 0.99 per 1/240 s keeps the groom within 1.1 % at rest, lags 6 % when
    /// shaken and returns; 0.97 does not return).
    pub local_shape_stiffness: f32,
    /// Longest substep in seconds (default 1/240): a step runs
    /// `n = ceil(dt / max_substep)` substeps (at most [`MAX_SUBSTEPS`]).
    /// Measured on a hanging chain of 1 cm links: the one-projection solve
    /// converges at h <= 1/240 s and diverges (zig-zags at the root) at 1/120
    /// and above, with every direction weighting.
    pub max_substep: f32,
    /// The blend `a` in [0, 0.25] of the constraint directions
    /// `n_s = (1/4 + a) d_s(x_{n+1}) + 1/2 d_s(x_n) + (1/4 - a) d_s(x_{n-1})`
    /// (a = 0: the trapezoidal rule, Newmark 1959, energy-conserving; 1/4 +
    /// a = 1 alone would be fast projection). Per substep a transverse mode
    /// of frequency w keeps `|z|^2 = (1 + A (1/4 - a)) / (1 + A (1/4 + a))`,
    /// `A = (w h)^2`: the stiff modes lose about `a A` per substep (6 % at
    /// 330 rad/s and h = 1/240 s), the swing of a 31 cm chain keeps 100 %
    /// over 12 s. Default 0.05.
    pub stiff_mode_damping: f32,
    /// Sleeping, in m/s: a block of [`crate::LANES`] strands whose vertices
    /// all moved slower than this for [`SLEEP_AFTER`] seconds of steps in a
    /// row, with its roots still and no moving rig sphere near it, is not
    /// stepped until something moves it: its roots (any change), a rig
    /// sphere whose sweep since the last step reaches the block's box,
    /// `teleport`, `reset_to_rest`, `set_velocity`, `set_positions`,
    /// `set_rest_rotation`, `rebase` or different parameters. It wakes in
    /// the step that sees the change. A block falls asleep at rest (its
    /// velocity is zeroed). 0 = never sleep. Default 0.02: on the built-in
    /// head (1 s still, 3 s of turn and nod, 6 s still) it steps 77 % of
    /// the strand-steps at 0.79 mm RMS from never sleeping (0.01: 85 %,
    /// 0.74 mm; 0.05: 67 %, 1.19 mm); a 25 cm strand swinging slower than
    /// this moves less than about 3 mm (`v / sqrt(g / L)`), and resting hair
    /// moves below 1e-3 m/s a few seconds after it lands (crate README).
    pub sleep_speed: f32,
}

/// Seconds a block must stay below `sleep_speed` before it sleeps
/// (`ceil(SLEEP_AFTER / dt)` steps in a row).
pub const SLEEP_AFTER: f32 = 0.5;

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            dt: 1.0 / 60.0,
            damping: 0.97,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            iterations: 1,
            pearls_per_segment: 1,
            pearl_radius: 0.002,
            max_stretch: 0.01,
            bend_stiffness: 0.0,
            shape_stiffness: 0.0,
            friction: 0.3,
            local_shape_stiffness: 0.0,
            max_substep: 1.0 / 240.0,
            stiff_mode_damping: 0.05,
            sleep_speed: 0.02,
        }
    }
}

/// Most substeps one strand step runs (a `dt` far above `max_substep` is
/// clamped here rather than looping without bound).
pub const MAX_SUBSTEPS: u32 = 64;

impl SimParams {
    /// Substeps per strand step: `ceil(dt / max_substep)` within
    /// `1 ..= MAX_SUBSTEPS` (a ratio within 1e-4 of a whole number counts as
    /// that number, so 1/60 over 1/240 is 4).
    pub fn substeps(&self) -> u32 {
        let r = self.dt as f64 / self.max_substep as f64;
        if r.is_finite() && r > 0.0 {
            ((r - 1e-4).ceil() as u32).clamp(1, MAX_SUBSTEPS)
        } else {
            1
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
            "local_shape_stiffness",
            self.local_shape_stiffness,
            (0.0..=1.0).contains(&self.local_shape_stiffness),
            "0 <= local_shape_stiffness <= 1",
        )?;
        check(
            "max_substep",
            self.max_substep,
            self.max_substep > 0.0,
            "a finite max_substep > 0",
        )?;
        check(
            "stiff_mode_damping",
            self.stiff_mode_damping,
            (0.0..=0.25).contains(&self.stiff_mode_damping),
            "0 <= stiff_mode_damping <= 0.25",
        )?;
        check(
            "sleep_speed",
            self.sleep_speed,
            self.sleep_speed >= 0.0,
            "sleep_speed >= 0 (0 = never sleep)",
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
