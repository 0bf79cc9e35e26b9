//! Shading straight from LOD's render vertices into a caller's buffer.
//!
//! `coif_lod::write_render_vertices` writes interleaved
//! [`RenderVertex`]es (position relative to the strands' origin, width,
//! tangent, strand parameter); [`shade_vertices`] shades them with any of
//! the three models ([`VertexModel`]: Kajiya-Kay, the Marschner table,
//! the pbrt table) for one directional light, eight vertices per SIMD step
//! (the models' `_x8` kernels, the same ones their batch paths run), no
//! transposing by hand and no allocation:
//!
//! ```text
//! colour_i = S(t_i, wi, wo_i),   wo_i = normalize(eye - p_i)
//! ```
//!
//! with `t_i` the vertex tangent, `wi` the unit direction toward the light
//! and `eye` in the vertices' space (the camera position minus
//! `Strands::origin`). `S` is the model's scattering without the cosine
//! factor (what `shade_batch` / `scattering_batch` return); multiply by
//! the light's irradiance and a shadow term as the frame does.

use crate::kajiya_kay::KajiyaKay;
use crate::marschner::Lut;
use crate::pbrt::Table;
use crate::Error;
use coif_base::{Vec3Lanes, LANES};
use coif_lod::RenderVertex;
use glam::Vec3;

/// A hair shading model that shades eight samples at a time.
pub trait VertexModel {
    /// `S(t, wi, wo)` for eight samples (unit tangent, toward the light,
    /// toward the eye), linear RGB.
    fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes;
}

impl VertexModel for KajiyaKay {
    #[inline(always)]
    fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        self.shade_simd(t, wi, wo)
    }
}

impl VertexModel for Lut {
    #[inline(always)]
    fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        Lut::scattering_simd(self, t, wi, wo)
    }
}

impl VertexModel for Table {
    #[inline(always)]
    fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        Table::scattering_simd(self, t, wi, wo)
    }
}

/// Shades `vertices` with `model` for the light toward `to_light` (unit)
/// seen from `eye` (the vertices' space), writing one linear-RGB colour per
/// vertex into `out[..vertices.len()]` (the module doc's formula). A vertex
/// with a non-finite position or tangent gets a non-finite colour in its
/// own slot only. Allocates nothing.
///
/// # Errors
/// [`Error::BufferTooSmall`] when `out` is shorter than `vertices` (nothing
/// written); [`Error::InvalidParameter`] for a non-finite `to_light` or
/// `eye`.
///
/// ```
/// use coif_lod::RenderVertex;
/// use coif_shading::kajiya_kay::KajiyaKay;
/// use coif_shading::vertices::shade_vertices;
/// use glam::Vec3;
/// let hair = [RenderVertex { tangent: [0.0, -1.0, 0.0], ..Default::default() }; 3];
/// let mut colours = [Vec3::ZERO; 3];
/// shade_vertices(&KajiyaKay::default(), &hair, Vec3::Z, Vec3::Z * 2.0, &mut colours).unwrap();
/// assert!(colours.iter().all(|c| c.x > 0.0));
/// assert!(shade_vertices(&KajiyaKay::default(), &hair, Vec3::Z, Vec3::Z, &mut colours[..2]).is_err());
/// ```
pub fn shade_vertices(
    model: &impl VertexModel,
    vertices: &[RenderVertex],
    to_light: Vec3,
    eye: Vec3,
    out: &mut [Vec3],
) -> Result<(), Error> {
    if out.len() < vertices.len() {
        return Err(Error::BufferTooSmall {
            needed: vertices.len(),
            got: out.len(),
        });
    }
    for (name, v) in [("to_light", to_light), ("eye", eye)] {
        if !v.is_finite() {
            return Err(Error::InvalidParameter {
                name,
                value: v.x + v.y + v.z,
            });
        }
    }
    let wi = Vec3Lanes::splat(to_light);
    for (block, dst) in vertices.chunks(LANES).zip(out.chunks_mut(LANES)) {
        let (mut t, mut wo) = (Vec3Lanes::ZERO, Vec3Lanes::ZERO);
        for l in 0..LANES {
            // Spare lanes repeat the block's first vertex.
            let v = block.get(l).unwrap_or(&block[0]);
            let p = Vec3::from(v.position);
            t.set_lane(l, Vec3::from(v.tangent));
            wo.set_lane(l, (eye - p).normalize_or_zero());
        }
        let c = model.scattering_simd(t, wi, wo);
        for (l, d) in dst.iter_mut().enumerate().take(block.len()) {
            *d = c.lane(l);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::marschner::Params;

    /// Every model's colour per vertex equals its one-sample shade (the
    /// same kernel as its batch path), for counts around the lane width.
    #[test]
    fn vertices_shade_as_the_models_do_one_sample_at_a_time() {
        let lut = Lut::new(&Params::default(), 32);
        let kk = KajiyaKay::default();
        let eye = Vec3::new(0.3, 0.2, 1.5);
        let light = Vec3::new(-0.5, 0.7, 0.5).normalize();
        for n in [0, 1, 7, 8, 9, 23] {
            let verts: Vec<RenderVertex> = (0..n)
                .map(|i| {
                    let a = i as f32 * 0.7;
                    RenderVertex {
                        position: [0.01 * i as f32, 0.1 * a.sin(), 0.0],
                        width: 1e-4,
                        tangent: Vec3::new(a.cos(), -1.0, a.sin()).normalize().to_array(),
                        strand_parameter: 0.5,
                    }
                })
                .collect();
            let mut out = vec![Vec3::splat(-1.0); n + 2];
            shade_vertices(&kk, &verts, light, eye, &mut out).unwrap();
            for (v, c) in verts.iter().zip(&out) {
                let wo = (eye - Vec3::from(v.position)).normalize();
                let one = kk.shade(Vec3::from(v.tangent), light, wo);
                assert!(
                    (one - *c).length() <= 1e-5 * (1.0 + one.length()),
                    "{one} {c}"
                );
            }
            assert_eq!(
                out[n..],
                [Vec3::splat(-1.0); 2],
                "nothing past the vertices"
            );
            shade_vertices(&lut, &verts, light, eye, &mut out).unwrap();
            for (v, c) in verts.iter().zip(&out) {
                let wo = (eye - Vec3::from(v.position)).normalize();
                let one = lut.scattering(Vec3::from(v.tangent), light, wo);
                assert!(
                    (one - *c).length() <= 1e-4 * (1.0 + one.length()),
                    "{one} {c}"
                );
            }
        }
        let one = [RenderVertex::default()];
        assert!(shade_vertices(&kk, &one, Vec3::NAN, eye, &mut [Vec3::ZERO]).is_err());
        assert!(shade_vertices(&kk, &one, light, eye, &mut []).is_err());
    }
}
