//! The fused prepare pass: everything between the simulation and the
//! pixels, one block of interpolation groups at a time, written once as
//! [`ShadedVertex`]es. A group is up to eight render hairs of one scalp
//! triangle (`R` vertices each); a block holds `GROUPS_PER_BLOCK` of them,
//! one per eight lanes of `F32Lanes` (one group at 8 lanes, two at 16), so
//! no lane is padding at either width and every lane's arithmetic is the
//! same at both.
//!
//! Per block, per vertex row `r` (the groups' hairs in the lanes):
//!
//! 1. interpolate: `P = b_A A + b_B B + b_C C` of the refined guides and
//!    the normalised blend of their tangents `t` (`coif_lod::GroupBlend`);
//! 2. shade: `S = model_simd(t, wi, wo)` with `wi` toward the light (one
//!    vector per frame) and `wo = unit(eye - P)` (`+Z` where `P` is the eye);
//! 3. visibility: the shadow map's transmittance at `P` times 0 where the
//!    ray toward the light meets a head sphere ([`occluded_simd`]); with dual
//!    scattering (`Shader::dual_scattering`) the map's hair count and
//!    transmittance make `S` the model's multiple-scattering `F` instead,
//!    and only the head's 0 remains (the hair behind the point, for its
//!    backscatter, is the map's last plane minus the point's count);
//! 4. colour: `c = (S E V [sin theta_i] + ambient) tint`, `ambient` alone
//!    where that is not finite (the reference's `write_colors` formula);
//! 5. width `lerp(root, tip, s) x width_factor`, written with `P`, `c`
//!    and `s = r / (R - 1)` for the group's real hairs.
//!
//! A row whose hair lanes are all in the head's shadow skips steps 2 and
//! 3's shadow map (its direct light is 0 whatever they give; the colour is
//! the same bits).
//!
//! Nothing frame-sized is read or written besides the refined guides (a
//! few hundred kilobytes), the shadow map and the output: the group's
//! vertices live in registers from interpolation to the one store.

use super::{Light, Shader, HAIR_AMBIENT_ALBEDO};
use coif_base::lanes::lanes_of_bits;
use coif_base::lanes::F32Lanes;
use coif_base::lanes::{GROUPS_PER_BLOCK, GROUP_LANES};
use coif_base::{Vec3Lanes, LANES};
use coif_kernels::Sphere;
use coif_lod::{GroupBlend, HairWidth};
use coif_render::ShadedVertex;
use coif_shading::shadow::OpacityShadowMap;
use glam::Vec3;

/// What every group of one frame's prepare pass reads.
pub(crate) struct GroupShading<'a> {
    pub shader: &'a Shader,
    pub shadow: Option<&'a OpacityShadowMap>,
    pub head: &'a [Sphere],
    pub light: Light,
    pub eye: Vec3,
    /// Widths of a render hair at root and tip.
    pub width: HairWidth,
    /// The distance-LOD width multiplier.
    pub width_factor: f32,
}

/// Whether the ray from each lane's point toward the light (`to_light`,
/// unit) meets one of `spheres` ahead of it, the point being outside the
/// sphere by more than `epsilon r` in `|m|^2 - r^2`: the lane-wise twin of
/// `coif_render::head::occluded` (same expressions in the same order).
#[inline(always)]
pub(crate) fn occluded_simd(
    p: Vec3Lanes,
    to_light: Vec3,
    spheres: &[Sphere],
    epsilon: f32,
) -> F32Lanes {
    let l = Vec3Lanes::splat(to_light);
    let mut hit = F32Lanes::ZERO;
    for s in spheres {
        let m = p - Vec3Lanes::splat(s.center);
        let b = m.dot(l);
        let c = m.length_squared() - F32Lanes::splat(s.radius * s.radius);
        let disc = b * b - c;
        hit |= c.simd_gt(F32Lanes::splat(epsilon * s.radius))
            & b.simd_lt(F32Lanes::ZERO)
            & disc.simd_gt(F32Lanes::ZERO);
    }
    hit
}

/// Steps 1-5 for one block of groups: writes its `blend.hairs()` real
/// hairs, group after group and hair after hair, root first, into `out`
/// (`hairs x R` vertices; a shorter `out` leaves the block out).
/// `first_hair` is the index of the block's first hair in the frame's order
/// (for [`super::strand_tint`]): the groups' hairs are consecutive there.
pub(crate) fn shade_block(
    ctx: &GroupShading<'_>,
    blend: &GroupBlend<'_>,
    first_hair: usize,
    out: &mut [ShadedVertex],
) {
    let r_len = blend.verts();
    let hairs = blend.hairs().min(LANES);
    if r_len == 0 || out.len() < hairs.saturating_mul(r_len) {
        return;
    }
    // Lane `8 k + i` holds hair `first[k] + i` of the block, for
    // `i < group_hairs(k)`; the other lanes repeat their group's last hair.
    let mut first = [0usize; GROUPS_PER_BLOCK];
    let mut counts = [0usize; GROUPS_PER_BLOCK];
    let mut before = 0;
    for (k, (f, c)) in first.iter_mut().zip(&mut counts).enumerate() {
        (*f, *c) = (before, blend.group_hairs(k));
        before += *c;
    }
    let light = ctx.light;
    let wi = Vec3Lanes::splat(light.to_light);
    let eye = Vec3Lanes::splat(ctx.eye);
    let irradiance = light.irradiance * ctx.shader.light_scale();
    let ambient = HAIR_AMBIENT_ALBEDO * light.ambient;
    let cosine = ctx.shader.needs_cosine();
    let mut tint = [0.0f32; LANES];
    for (l, t) in tint.iter_mut().enumerate() {
        let (k, i) = (l / GROUP_LANES, l % GROUP_LANES);
        let last = counts[k].max(1) - 1;
        *t = super::strand_tint(first_hair + first[k] + i.min(last));
    }
    let tint = F32Lanes::new(tint);
    let inv = if r_len > 1 {
        1.0 / (r_len - 1) as f32
    } else {
        0.0
    };
    // The lanes holding one of the group's hairs.
    let real = lanes_of_bits(blend.hair_bits());
    for r in 0..r_len {
        // 1. Interpolate.
        let p = blend.position_simd(r);
        let t = blend.tangent_simd(r);
        // 2. Shade.
        let wo = (eye - p).normalize_or(Vec3Lanes::splat(Vec3::Z));
        let head = occluded_simd(p, light.to_light, ctx.head, 1e-3);
        // A lane in the head's shadow gets no direct light (`visible` is
        // 0 below). When every hair lane is, with finite directions (so a
        // finite scattering value, which times 0 is 0), the model and the
        // shadow map are not evaluated: `direct` is the zero they would
        // give, the same bits after the ambient term is added.
        let dark = (head | !real).all() && (t.finite() & wo.finite()).all();
        let direct = if dark {
            Vec3Lanes::ZERO
        } else {
            let s = ctx.shader.scattering_simd(t, wi, wo);
            // 3. Visibility: shadow map, head. With dual scattering the
            // map's hair count and transmittance go into the model's `F`
            // and the head alone remains as a visibility.
            let (s, visible) = match ctx.shader.dual_scattering() {
                Some(ds) => {
                    let (fibres, behind, transmittance) = match ctx.shadow {
                        Some(m) => {
                            // In front of the point, and on the light's
                            // whole ray through it (the last plane).
                            let (sigma, through) = m.hairs_in_front_and_through_simd(p);
                            (
                                sigma,
                                (through - sigma).fast_max(F32Lanes::ZERO),
                                (F32Lanes::splat(-m.hair_opacity()) * sigma).exp(),
                            )
                        }
                        // No map: nothing known in front, deep hair behind.
                        None => (
                            F32Lanes::ZERO,
                            F32Lanes::splat(f32::INFINITY),
                            F32Lanes::ONE,
                        ),
                    };
                    let lit = ds.shade_layered_simd(s, t, wi, wo, fibres, behind, transmittance);
                    (lit, head.select(F32Lanes::ZERO, F32Lanes::ONE))
                }
                None => {
                    let transmittance = ctx
                        .shadow
                        .map_or(F32Lanes::ONE, |m| m.transmittance_simd(p));
                    (s, head.select(F32Lanes::ZERO, transmittance))
                }
            };
            // 4. Colour.
            let direct = Vec3Lanes::new(
                s.x * F32Lanes::splat(irradiance.x) * visible,
                s.y * F32Lanes::splat(irradiance.y) * visible,
                s.z * F32Lanes::splat(irradiance.z) * visible,
            );
            if cosine {
                let c = t.dot(wi);
                direct * (F32Lanes::ONE - c * c).max(F32Lanes::ZERO).sqrt()
            } else {
                direct
            }
        };
        let c = (direct + Vec3Lanes::splat(ambient)) * tint;
        let c = Vec3Lanes::select(c.finite(), c, Vec3Lanes::splat(ambient));
        // 5. Write: the lanes' eight fields (the `ShadedVertex` order)
        // transposed, so lane l's vertex is one row of eight floats.
        let sp = r as f32 * inv;
        let width = (ctx.width.root + (ctx.width.tip - ctx.width.root) * sp) * ctx.width_factor;
        let rows = coif_base::lanes::planes_to_rows([
            p.x,
            p.y,
            p.z,
            F32Lanes::splat(width),
            c.x,
            c.y,
            c.z,
            F32Lanes::splat(sp),
        ]);
        for (k, group) in rows.chunks_exact(GROUP_LANES).enumerate() {
            for (i, row) in group.iter().take(counts[k]).enumerate() {
                let v = row.to_array();
                let vertex = ShadedVertex {
                    position: [v[0], v[1], v[2]],
                    width: v[3],
                    color: [v[4], v[5], v[6]],
                    strand_parameter: v[7],
                };
                // SAFETY: first[k] + i < hairs (the groups' hairs add up
                // to `hairs`) and r < r_len, so the index is below
                // hairs r_len <= out.len() (checked at the top).
                unsafe { *out.get_unchecked_mut((first[k] + i) * r_len + r) = vertex };
            }
        }
    }
}

/// The output pointer shared by the tasks of one prepare pass; each task
/// writes only its group's range (offsets from a prefix sum, checked
/// before the tasks start).
pub(crate) struct SharedOut(pub *mut ShadedVertex);
// SAFETY: the tasks write disjoint ranges of one `&mut [ShadedVertex]`
// that outlives the executor's `run` (see `FramePipeline::shade_fused`).
unsafe impl Send for SharedOut {}
// SAFETY: as above.
unsafe impl Sync for SharedOut {}

impl SharedOut {
    /// `len` vertices from `start`.
    ///
    /// # Safety
    /// `start + len` is within the slice the pointer came from, that slice
    /// outlives `'a`, and no other live reference covers the range.
    pub(crate) unsafe fn range<'a>(&self, start: usize, len: usize) -> &'a mut [ShadedVertex] {
        // SAFETY: the caller's promise.
        unsafe { std::slice::from_raw_parts_mut(self.0.add(start), len) }
    }
}
