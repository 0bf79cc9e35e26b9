//! The hair material's data for the GPU: the WGSL source, its uniform
//! block and coif's Marschner tables as texel arrays (built by coif, only
//! looked up by the shader).

use coif::glam::{Vec3, Vec4};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{Lut, LutLayout};

/// The shading functions alone (`hair.wgsl`): `kajiya_kay`, `marschner`
/// (table lookups), `hair_radiance`; they read the `shading` uniform and
/// the `lut_m`, `lut_n0`, `lut_n1` textures, which the file after them
/// binds.
pub const HAIR_FUNCTIONS_WGSL: &str = include_str!("../../gpu/src/shaders/hair_shading.wgsl");

/// A standalone shader: the functions and a vertex/fragment pair over the
/// plugin's hair mesh with its own bind group 0 (view, `HairShading`, three
/// tables), for a renderer that is not Bevy's.
pub const HAIR_WGSL: &str = concat!(
    include_str!("../../gpu/src/shaders/hair_shading.wgsl"),
    include_str!("hair_standalone.wgsl"),
    include_str!("hair_mesh.wgsl")
);

/// The shader of the Bevy material (`HairMaterial`, feature `render`): the
/// functions, Bevy's view uniform (group 0, binding 0), the material's
/// bindings in group 3 and the vertex/fragment pair.
pub const HAIR_MATERIAL_WGSL: &str = concat!(
    include_str!("../../gpu/src/shaders/hair_shading.wgsl"),
    include_str!("hair_material.wgsl"),
    include_str!("hair_mesh.wgsl")
);

/// The `HairShading` uniform block of [`HAIR_WGSL`], 6 vec4s.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairShadingUniform {
    /// K_d (w unused).
    pub diffuse: [f32; 4],
    /// Primary highlight colour, exponent in w.
    pub primary: [f32; 4],
    /// Secondary highlight colour, exponent in w.
    pub secondary: [f32; 4],
    /// Tangent shifts: x primary, y secondary.
    pub shifts: [f32; 4],
    /// x resolution of the tables, y 1 for the angular layout (0: Nalu's
    /// sin-theta axes and cos-phi), z the Marschner weight in [0, 1].
    pub lut: [f32; 4],
    /// Direction to the light (xyz), intensity (w).
    pub light: [f32; 4],
}

impl HairShadingUniform {
    /// The block for `kk` and `lut` blended with `marschner_weight`, lit
    /// from `to_light` at `intensity`. The shader reads the layout from
    /// `lut.y`: only [`LutLayout::Angular`] and [`LutLayout::Nalu`] are
    /// ported (others give `None`).
    pub fn new(
        kk: &KajiyaKay,
        lut: &Lut,
        marschner_weight: f32,
        to_light: Vec3,
        intensity: f32,
    ) -> Option<HairShadingUniform> {
        let angular = match lut.layout() {
            LutLayout::Angular => 1.0,
            LutLayout::Nalu => 0.0,
            _ => return None,
        };
        let rgb = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
        Some(HairShadingUniform {
            diffuse: rgb(kk.diffuse, 0.0),
            primary: rgb(kk.primary.color, kk.primary.exponent),
            secondary: rgb(kk.secondary.color, kk.secondary.exponent),
            shifts: [kk.primary.shift, kk.secondary.shift, 0.0, 0.0],
            lut: [
                lut.resolution() as f32,
                angular,
                marschner_weight.clamp(0.0, 1.0),
                0.0,
            ],
            light: rgb(to_light, intensity),
        })
    }

    /// The block as floats, in WGSL's order.
    pub fn to_floats(&self) -> [f32; 24] {
        let mut out = [0.0; 24];
        for (k, v) in [
            self.diffuse,
            self.primary,
            self.secondary,
            self.shifts,
            self.lut,
            self.light,
        ]
        .iter()
        .enumerate()
        {
            out[4 * k..4 * k + 4].copy_from_slice(v);
        }
        out
    }
}

/// coif's tables as the shader's three `rgba32float` textures (`lut_m`,
/// `lut_n0`, `lut_n1`), each `resolution x resolution`, row after row.
pub fn lut_textures(lut: &Lut) -> [Vec<[f32; 4]>; 3] {
    let m = lut.table_m().iter().map(|v| v.to_array()).collect();
    let n0 = lut.table_n().iter().map(|n| n[0].to_array()).collect();
    let n1 = lut.table_n().iter().map(|n| n[1].to_array()).collect();
    [m, n0, n1]
}

/// A texel of a table as the shader loads it.
pub fn texel(table: &[[f32; 4]], resolution: usize, x: usize, y: usize) -> Vec4 {
    Vec4::from_array(table[y * resolution + x])
}
