//! The strand grower: every built-in strand in coif grows here.
//!
//! [`grow`] takes roots and unit normals and grows one strand per root,
//! straight out along its normal, optionally curling around it. The two
//! sources of roots call it:
//!
//! - [`crate::scalp::ScalpMesh::grow_guides`]: one guide per mesh vertex,
//!   along its area-weighted vertex normal;
//! - [`crate::scene::grow_on_sphere`]: roots on a Fibonacci spiral over a
//!   cap of a sphere head ([`crate::scene::fibonacci_cap`]), along the radial
//!   normals.
//!
//! Growth is pure geometry: the strands leave the scalp sticking straight
//! out. Draping them under gravity is a simulation, done by the frame crate
//! (`coif_frame::drape`).
//!
//! Curl: strand point `v` of `n` (arc parameter `s = v / (n - 1)`, segment
//! length `seg = length / (n - 1)`) is
//!
//! ```text
//! p_v = root + normal * seg * v + (u cos a + w sin a) * curl * seg * 5 min(s, 0.2),
//! a   = phase + turns * 2 pi * s
//! ```
//!
//! with `(u, w)` an orthonormal pair across the normal, and per strand a
//! random `phase` in `[0, 2 pi)` and `turns` in `[2, 4)` drawn in that order
//! from one [`SplitMix64`] stream seeded with [`Growth::seed`]: a helix whose
//! radius grows in over the first fifth of the strand, so the root leaves
//! the scalp along the normal.

use coif_base::SplitMix64;
use glam::Vec3;
use std::fmt;

/// How strands grow from their roots.
#[derive(Clone, Debug, PartialEq)]
pub struct Growth {
    /// Strand length in metres (the straight strand's; curl adds a little arc).
    pub length: f32,
    /// Points per strand, root first (at least 2).
    pub verts_per_strand: usize,
    /// Curl amplitude as a fraction of the segment length (0 = straight).
    pub curl: f32,
    /// Seed of the random phase and number of turns of each strand's curl.
    pub seed: u64,
}

impl Default for Growth {
    /// 25 cm, 32 points, straight, seed 1.
    fn default() -> Self {
        Growth {
            length: 0.25,
            verts_per_strand: 32,
            curl: 0.0,
            seed: 1,
        }
    }
}

/// Why a [`Growth`] is out of range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidGrowth(pub &'static str);

impl fmt::Display for InvalidGrowth {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid growth option: {}", self.0)
    }
}

impl std::error::Error for InvalidGrowth {}

impl Growth {
    /// Checks the options: a finite length > 0, at least 2 points per
    /// strand, a finite curl. [`grow`] itself does not check (it clamps the
    /// point count to 2 and lets non-finite input through as non-finite
    /// points, which the simulation refuses).
    ///
    /// # Errors
    ///
    /// [`InvalidGrowth`] naming the first option out of range.
    pub fn validate(&self) -> Result<(), InvalidGrowth> {
        if !(self.length > 0.0 && self.length.is_finite()) {
            return Err(InvalidGrowth("length must be finite and > 0"));
        }
        if !(2..=MAX_GROWN_VERTS).contains(&self.verts_per_strand) {
            return Err(InvalidGrowth("2 to 4096 vertices per strand"));
        }
        if !self.curl.is_finite() {
            return Err(InvalidGrowth("curl must be finite"));
        }
        Ok(())
    }
}

/// Most vertices per grown strand ([`Growth::validate`]; [`grow`] clamps to
/// it).
pub const MAX_GROWN_VERTS: usize = 4096;

/// Grows one strand per root along its unit normal (curling around it, see
/// the module docs). Returns `n * verts` points, `n` the shorter of `roots`
/// and `normals` (one normal per root) and `verts` = `verts_per_strand`
/// clamped to `2..=MAX_GROWN_VERTS`, strand after strand, root first;
/// strand i grows from `roots[i]`.
pub fn grow(roots: &[Vec3], normals: &[Vec3], growth: &Growth) -> Vec<Vec3> {
    let verts = growth.verts_per_strand.clamp(2, MAX_GROWN_VERTS);
    let roots = &roots[..roots.len().min(normals.len())];
    let seg = growth.length / (verts - 1) as f32;
    let mut rng = SplitMix64::new(growth.seed);
    let mut points = Vec::with_capacity(roots.len() * verts);
    for (root, normal) in roots.iter().zip(normals) {
        grow_strand(
            *root,
            *normal,
            seg,
            verts,
            growth.curl,
            &mut rng,
            &mut points,
        );
    }
    points
}

/// Appends one strand of `verts` points `seg` apart growing from `root`
/// along the unit `normal`, curling around it (the module docs' helix).
fn grow_strand(
    root: Vec3,
    normal: Vec3,
    seg: f32,
    verts: usize,
    curl: f32,
    rng: &mut SplitMix64,
    out: &mut Vec<Vec3>,
) {
    let (u, w) = normal.any_orthonormal_pair();
    let phase = rng.range(0.0, std::f32::consts::TAU);
    let turns = rng.range(2.0, 4.0);
    for v in 0..verts {
        let s = v as f32 / (verts - 1) as f32;
        let angle = phase + turns * std::f32::consts::TAU * s;
        let around = (u * angle.cos() + w * angle.sin()) * (curl * seg * s.min(0.2) * 5.0);
        out.push(root + normal * (seg * v as f32) + around);
    }
}
