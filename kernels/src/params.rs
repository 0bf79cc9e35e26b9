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
    /// of 1/240 s one converges, a second changed no measured figure);
    /// with `local_shape_stiffness` above 0 the strain limit holds the
    /// lengths and these run the bending sweeps alone.
    /// Patches: Gauss-Seidel sweeps per step. At most [`MAX_ITERATIONS`].
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
    /// Contact friction, Coulomb's law: the kinetic coefficient (>= 0).
    /// A vertex that a collider (sphere, capsule or field) pushes out by
    /// `d` does not slide while its motion along the surface, relative to
    /// the collider, is within `static_friction d` per substep, and slides
    /// against `friction d` otherwise (position-based, Macklin et al. 2014,
    /// 6.1; `collide/narrow.rs`). So hair rests on a slope of angle theta
    /// exactly when `static_friction > tan(theta)`. 0 and 0 =
    /// frictionless. Default 0.3.
    pub friction: f32,
    /// Contact friction, Coulomb's law: the static coefficient (>= 0; see
    /// `friction`). Default 0.5 (1.7 times the kinetic one, as Unity's hair
    /// package sets it): hair holds on slopes up to 26.6 degrees.
    pub static_friction: f32,
    /// Air velocity in m/s, world frame (default zero: still air). Acts
    /// through `drag`.
    pub wind: Vec3,
    /// Linear aerodynamic drag in 1/s (>= 0; 0 = none, the default): air
    /// moving at `wind` pulls a vertex moving at `v` with acceleration
    /// `drag (wind - v)`, in full (the share along the strand is 1: crate
    /// README, "Wind and drag", says why). So a strand in a steady wind
    /// hangs straight along `gravity + drag wind`, and small swings decay
    /// as `exp(-drag t / 2)` when nothing else damps them. A single hair
    /// fibre in air has about 100 /s; hair in a clump, shielded by its
    /// neighbours, far less (1 to 10 /s).
    pub drag: f32,
    /// The roots rule (>= 0): a strand whose root lies `depth_root` inside
    /// a collider's skin (a scalp that is part of the body mesh, a head
    /// sphere that cuts the roots) may have vertex `v` up to
    /// `max(0, depth_root - root_exit arc(v))` inside it, `arc(v)` its rest
    /// arc length from the root: the depth a strand leaving the surface at
    /// `asin(root_exit)` would have. A root outside changes nothing; large
    /// values push every vertex but the root to the surface (what the step
    /// did before the rule, which stretched the root segments and pushed
    /// hair off the scalp). Default 0.25: measured at rest with the groom
    /// held, Sintel's groom on a 4 mm field of her bust (103 of 228 roots
    /// in the 2 mm skin, 5 inside the mesh) has root segments stretched
    /// 1.2 % (39 % with the rule off, 2.8 % at 0.5) and tips drifting 1.37 %
    /// of the length; the mohawk under a head sphere that cuts a seventh of
    /// its roots, 1.05 % (as without the sphere; the rule off: 200x) and
    /// 0.96 % (crate README, "Roots on or in a collider";
    /// `examples/roots_rule.rs`).
    pub root_exit: f32,
    /// Gusts: the RMS speed in m/s of a turbulent wind field added to
    /// `wind` (0 = none, the default), varying over `turbulence_scale` in
    /// space and `turbulence_period` in time, deterministic (`wind.rs`:
    /// the same field for every run and thread count). Acts through
    /// `drag`. Hair in gusts does not fall asleep.
    pub turbulence: f32,
    /// Gusts: the size of their features in metres (> 0, default 0.2).
    pub turbulence_scale: f32,
    /// Gusts: how long a gust lasts, seconds (> 0, default 1).
    pub turbulence_period: f32,
    /// Hair-hair volume in [0, 1] (0 = off, the default): hair packed
    /// denser than its target is pushed apart, down the gradient of the
    /// density's excess on a grid of the hair rebuilt every step (Petrovic
    /// et al. 2005; `hair_grid/`): each step moves a vertex by
    /// `volume_stiffness` times a quarter cell per unit of excess gradient
    /// (at most a quarter cell). Only compression is pushed back. The
    /// target is the densest packing of the groomed pose away from the
    /// roots.
    pub volume_stiffness: f32,
    /// Hair-hair friction in [0, 1] (0 = off, the default): the share of
    /// each vertex's velocity relative to the hair around it (the grid's
    /// mass-weighted velocity there) removed per step; the hair's common
    /// motion is kept (a PIC blend, as in Petrovic et al. 2005 and
    /// McAdams et al. 2009).
    pub hair_friction: f32,
    /// Cell of the hair grid in metres (default 0.015; measured in
    /// `kernels/README.md`, "Hair against hair"). A hair whose box needs
    /// more nodes than the grid was sized for is gridded coarser for that
    /// step, never allocated.
    pub hair_grid_cell: f32,
    /// Local shape in [0, 1]: how stiffly each segment keeps its groomed
    /// vector in the head's frame (0, the default, switches it off).
    /// Linear springs on the segment vectors, `E = sum_s (c / l_s)^2 / 2
    /// |e_s - R t_s|^2` per unit mass, solved implicitly every substep
    /// (`kernels/src/shape.rs`): stiffness means a wave speed
    /// `c = 4 m/s x 10^(-2 (1 - k))` ([`crate::shape::wave_speed`]: 4 m/s
    /// at 1, 1 m/s at 0.7, 0.4 m/s at 0.5), so a strand of length `L`
    /// swings about its groom at `(pi / 2) c / L` rad/s: softer bends more
    /// and swings slower, smoothly, whatever its vertex count. The springs
    /// alone sag under gravity by `g M l^2 / c^2` per segment (`M` the
    /// vertices below); [`crate::Strands::solve_sag_free`] gives them the
    /// rest vectors that make the groom the equilibrium. Measured on
    /// Sintel's groom with the solve (`kernels/README.md`, "Styled hair
    /// that moves"): at 0.7 the tips swing 13 mm RMS in a 40-degree head
    /// turn and are back within 0.2 mm 2.5 s after; from 0.5 to 1 under
    /// 0.5 % of the vertices kink and the rest drift is under 1 mm. While it
    /// is on, the strain limit (`max_stretch`) holds the segment lengths
    /// and `iterations` run only the bending sweeps (`shape.rs`,
    /// "Lengths").
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
    /// `teleport`, `reset_to_rest`, `set_velocity`, `set_state`,
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
            static_friction: 0.5,
            wind: Vec3::ZERO,
            drag: 0.0,
            root_exit: 0.25,
            turbulence: 0.0,
            turbulence_scale: 0.2,
            turbulence_period: 1.0,
            volume_stiffness: 0.0,
            hair_friction: 0.0,
            hair_grid_cell: 0.015,
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
    /// Substeps per strand step: `ceil(dt / h_max)` within
    /// `1 ..= MAX_SUBSTEPS` (a ratio within 1e-4 of a whole number counts as
    /// that number, so 1/60 over 1/240 is 4), where `h_max` is
    /// `max_substep`, shortened by `sqrt(2 g0 / |a|)` when the steady
    /// acceleration `a = gravity + drag wind` is stronger than `2 g0`
    /// (`g0 = 9.81 m/s^2`): the one-projection solve converges while the
    /// move `|a| h^2` per substep stays within that of 2 g at 1/240 s
    /// (measured on a 31 cm strand settling in a steady wind: 2 g, 0.09
    /// degrees off its equilibrium at 1/240 s; 3.2 g, 1.0 degree at 1/240
    /// and exact at 1/480; 14 g, 5 degrees and 8 % short at 1/240, exact at
    /// 1/480; two or four projections per substep instead made it worse).
    pub fn substeps(&self) -> u32 {
        let accel = self.steady_acceleration().length() as f64;
        let strong = if accel.is_finite() && accel > 2.0 * STANDARD_GRAVITY {
            (accel / (2.0 * STANDARD_GRAVITY)).sqrt()
        } else {
            1.0
        };
        let r = self.dt as f64 / self.max_substep as f64 * strong;
        if r.is_finite() && r > 0.0 {
            ((r - 1e-4).ceil().min(MAX_SUBSTEPS as f64) as u32).clamp(1, MAX_SUBSTEPS)
        } else {
            1
        }
    }
}

impl SimParams {
    /// The drag coefficient the step uses: `drag` if finite and >= 0,
    /// else 0.
    pub fn effective_drag(&self) -> f32 {
        if self.drag.is_finite() {
            self.drag.max(0.0)
        } else {
            0.0
        }
    }

    /// The steady acceleration `gravity + drag wind` (a non-finite wind
    /// counts as still air): what a vertex at rest feels.
    pub fn steady_acceleration(&self) -> Vec3 {
        let wind = if self.wind.is_finite() {
            self.wind
        } else {
            Vec3::ZERO
        };
        self.gravity + wind * self.effective_drag()
    }
}

/// 1 g in m/s^2: the acceleration at which `max_substep` was measured.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Largest accepted `pearls_per_segment`.
pub const MAX_PEARLS_PER_SEGMENT: u32 = 64;

/// Most projections per substep (strands) or sweeps per step (patches)
/// [`SimParams::validate`] accepts: 256, the report's converged reference.
/// Without a bound a step's cost had none (`u32::MAX` iterations ran for
/// minutes per step).
pub const MAX_ITERATIONS: u32 = 256;

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
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] for the first field outside its range.
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
            "iterations",
            self.iterations as f32,
            self.iterations <= MAX_ITERATIONS,
            "at most 256 iterations",
        )?;
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
            self.friction >= 0.0,
            "friction >= 0",
        )?;
        check(
            "static_friction",
            self.static_friction,
            self.static_friction >= 0.0,
            "static_friction >= 0",
        )?;
        for w in self.wind.to_array() {
            check("wind", w, true, "finite components")?;
        }
        check("drag", self.drag, self.drag >= 0.0, "drag >= 0")?;
        check(
            "root_exit",
            self.root_exit,
            self.root_exit >= 0.0,
            "root_exit >= 0",
        )?;
        check(
            "turbulence",
            self.turbulence,
            self.turbulence >= 0.0,
            "turbulence >= 0",
        )?;
        check(
            "turbulence_scale",
            self.turbulence_scale,
            self.turbulence_scale > 0.0,
            "turbulence_scale > 0",
        )?;
        check(
            "volume_stiffness",
            self.volume_stiffness,
            (0.0..=1.0).contains(&self.volume_stiffness),
            "0 <= volume_stiffness <= 1",
        )?;
        check(
            "hair_friction",
            self.hair_friction,
            (0.0..=1.0).contains(&self.hair_friction),
            "0 <= hair_friction <= 1",
        )?;
        check(
            "hair_grid_cell",
            self.hair_grid_cell,
            self.hair_grid_cell >= 1e-4 && self.hair_grid_cell <= 1.0,
            "1e-4 <= hair_grid_cell <= 1 (metres)",
        )?;
        check(
            "turbulence_period",
            self.turbulence_period,
            self.turbulence_period > 0.0,
            "turbulence_period > 0",
        )?;
        Ok(())
    }
}
