//! Position-based constraint helpers shared by the cloth patches
//! ([`crate::patch`]): the per-step constants ([`StepSetup`]), the
//! mass-weighted distance constraint (Jakobsen 2001), vertex push-out and
//! pearls against rig spheres (Nguyen and Donnelly 2005, the Nalu demo's
//! point-on-segment rule). The strand step (`step.rs`) has its own generic
//! body over [`crate::lanes::Lane`].

use crate::lanes::{inv_sqrt_simd, Vec3Lanes};
use coif_base::lanes::F32Lanes;
use glam::Vec3;

/// Coordinates beyond this (metres from the local origin) count as blown up.
pub(crate) const BLOWN_UP: f32 = 1.0e6;
/// Alternations of strain limit and vertex push-out per vertex at the end of
/// a step.
pub(crate) const STRAIN_COLLIDE_ROUNDS: usize = 2;
/// Smallest length a constraint divides by (TressFX clamps with 1e-7 too).
pub(crate) const MIN_LENGTH: f32 = 1.0e-7;

/// Per-step values shared by the SIMD and scalar paths.
pub(crate) struct StepSetup {
    pub damping: f32,
    pub gravity_dt2: Vec3,
    pub iterations: u32,
    pub pearls: u32,
    pub pearl_radius: f32,
    pub stretch_factor: f32,
    pub bend: f32,
    /// Broad-phase margin: pearl radius plus one longest rest segment.
    pub margin: f32,
}

impl StepSetup {
    /// Pearl parameter t = j / (k + 1).
    #[inline(always)]
    pub(crate) fn pearl_t(&self, j: u32) -> f32 {
        j as f32 / (self.pearls + 1) as f32
    }
}

/// `1 / max(|delta|, MIN_LENGTH)` by [`inv_sqrt_simd`] (shared with patches).
#[inline(always)]
pub(crate) fn inv_len(delta: Vec3Lanes) -> F32Lanes {
    inv_sqrt_simd(
        delta
            .length_squared()
            .fast_max(F32Lanes::splat(MIN_LENGTH * MIN_LENGTH)),
    )
}

/// Mass-weighted distance constraint between vertices `i` and `j` of one
/// lane chain (a block of strands, or a column block of a patch):
/// `k = stiffness (|delta| - l) / |delta|`, `x_i += share_i k delta`,
/// `x_j -= share_j k delta` with `share_i = w_i / (w_i + w_j)` (Jakobsen
/// 2001's rule, with `1/|delta|` from [`inv_len`]).
#[inline(always)]
pub(crate) fn distance_constraint(
    pos: &mut [Vec3Lanes],
    i: usize,
    j: usize,
    rest: F32Lanes,
    share: [F32Lanes; 2],
    stiffness: F32Lanes,
) {
    let delta = pos[j] - pos[i];
    let inv_len = inv_len(delta);
    let k = stiffness * (F32Lanes::ONE - rest * inv_len);
    // A pinned end has share 0 and does not move. (A lane whose positions
    // went NaN can move its root; the guard then restores the whole strand,
    // root included, from `Strands::roots`.)
    pos[i] = pos[i] + delta * (k * share[0]);
    pos[j] = pos[j] - delta * (k * share[1]);
}

/// Outward unit normal and distance from `d` and `d2 = |d|^2`; +y and 0
/// where the point sits on the centre.
#[inline(always)]
pub(crate) fn outward(d: Vec3Lanes, d2: F32Lanes) -> (Vec3Lanes, F32Lanes) {
    let tiny = F32Lanes::splat(1e-30);
    let inv = inv_sqrt_simd(d2.max(tiny));
    let on_centre = d2.simd_gt(tiny);
    (
        Vec3Lanes::select(on_centre, d * inv, Vec3Lanes::splat(Vec3::Y)),
        on_centre.select(d2 * inv, F32Lanes::ZERO),
    )
}

/// A rig sphere grown by the pearl radius, as lanes.
#[derive(Clone, Copy)]
pub(crate) struct Reach {
    centre: Vec3Lanes,
    reach: F32Lanes,
    reach2: F32Lanes,
}

impl Reach {
    #[inline(always)]
    pub(crate) fn new(sphere: [f32; 4], pearl_radius: f32) -> Self {
        let reach = F32Lanes::splat(sphere[3] + pearl_radius);
        Reach {
            centre: Vec3Lanes::splat(Vec3::new(sphere[0], sphere[1], sphere[2])),
            reach,
            reach2: reach * reach,
        }
    }
}

/// Pushes free vertex `i` out of the sphere to distance `R + r`; returns the
/// lanes it pushed and their outward normals.
#[inline(always)]
pub(crate) fn collide_vertex(
    pos: &mut [Vec3Lanes],
    w: &[F32Lanes],
    i: usize,
    s: &Reach,
) -> (F32Lanes, Vec3Lanes) {
    let d = pos[i] - s.centre;
    let d2 = d.length_squared();
    let hit = d2.simd_lt(s.reach2) & w[i].simd_gt(F32Lanes::ZERO);
    if !hit.any() {
        return (hit, Vec3Lanes::ZERO);
    }
    let (n, dist) = outward(d, d2);
    let pushed = pos[i] + n * (s.reach - dist);
    pos[i] = Vec3Lanes::select(hit, pushed, pos[i]);
    (hit, n)
}

/// Every pearl of one block (a slice of V vertices) against one sphere.
#[inline(always)]
pub(crate) fn collide_pearls(pos: &mut [Vec3Lanes], w: &[F32Lanes], s: &Reach, k: &StepSetup) {
    let zero = F32Lanes::ZERO;
    for j in 1..=k.pearls {
        let t = F32Lanes::splat(k.pearl_t(j));
        let u = F32Lanes::ONE - t;
        for v in 0..pos.len() - 1 {
            let p = pos[v] * u + pos[v + 1] * t;
            let d = p - s.centre;
            let d2 = d.length_squared();
            let denom = w[v] * (u * u) + w[v + 1] * (t * t);
            let both_free = w[v].simd_gt(zero) & w[v + 1].simd_gt(zero);
            let hit = d2.simd_lt(s.reach2) & both_free;
            if hit.any() {
                let (n, dist) = outward(d, d2);
                let push = (s.reach - dist) / denom;
                pos[v] = Vec3Lanes::select(hit, pos[v] + n * (w[v] * u * push), pos[v]);
                pos[v + 1] =
                    Vec3Lanes::select(hit, pos[v + 1] + n * (w[v + 1] * t * push), pos[v + 1]);
            }
        }
    }
}
