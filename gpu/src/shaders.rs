//! The WGSL, as sources to hand to a shader compiler. Each module is the
//! files it is made of, concatenated (WGSL has no includes):
//!
//! | module | files | entry points |
//! |---|---|---|
//! | [`COMPUTE_WGSL`] | types, render_vertex, compute | `write_render_vertices` (compute, 64 per workgroup) |
//! | [`DRAW_WGSL`] | hair_shading, types, render_vertex, ribbon, draw | `vertex`, `fragment` |
//!
//! An engine with its own bindings takes the pieces: [`TYPES_WGSL`] always
//! first, [`RENDER_VERTEX_WGSL`] where it makes render vertices (binding
//! `hair_view`, `guides`, `hairs`), [`RIBBON_WGSL`] where it expands them
//! (binding `hair_view`), [`HAIR_SHADING_WGSL`] where it shades (binding
//! `shading`, `lut_m`, `lut_n0`, `lut_n1`). coif-bevy runs [`COMPUTE_WGSL`]
//! once a frame and its material's vertex stages read the render vertices
//! it wrote, with the types and the ribbons only.

/// coif's hair shading: `kajiya_kay`, `marschner` (from coif's tables),
/// `hair_scattering` (their blend) and `hair_radiance`.
pub const HAIR_SHADING_WGSL: &str = include_str!("shaders/hair_shading.wgsl");

/// The structs (`HairView`, `RenderHair`, `RenderVertex`, the buffers'
/// layouts), the constants and `unit_or_y`: first in every module.
pub const TYPES_WGSL: &str = include_str!("shaders/types.wgsl");

/// `render_vertex(hair, r)` (after [`TYPES_WGSL`]): refinement,
/// interpolation and width, the GPU twin of coif-lod's CPU path.
pub const RENDER_VERTEX_WGSL: &str = include_str!("shaders/render_vertex.wgsl");

/// `ribbon_corner` (camera-facing expansion with a minimum width in pixels
/// and its coverage), `culled_clip`, `coverage_kept` (the dithered fade).
pub const RIBBON_WGSL: &str = include_str!("shaders/ribbon.wgsl");

/// The compute module: every render vertex into a storage buffer.
pub const COMPUTE_WGSL: &str = concat!(
    include_str!("shaders/types.wgsl"),
    include_str!("shaders/render_vertex.wgsl"),
    include_str!("shaders/compute.wgsl")
);

/// The draw module: vertex pulling of camera-facing ribbons, shaded with
/// coif's Kajiya-Kay and Marschner under one directional light.
pub const DRAW_WGSL: &str = concat!(
    include_str!("shaders/hair_shading.wgsl"),
    include_str!("shaders/types.wgsl"),
    include_str!("shaders/render_vertex.wgsl"),
    include_str!("shaders/ribbon.wgsl"),
    include_str!("shaders/draw.wgsl")
);

/// Workgroup size of the compute entry point.
pub const COMPUTE_WORKGROUP_SIZE: u32 = 64;

/// A shader stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Vertex.
    Vertex,
    /// Fragment.
    Fragment,
    /// Compute.
    Compute,
}

/// One WGSL module and its entry points.
#[derive(Clone, Copy, Debug)]
pub struct Module {
    /// A file name without extension (`hair_draw`, `hair_compute`).
    pub name: &'static str,
    /// The source.
    pub source: &'static str,
    /// Entry points and their stages.
    pub entry_points: &'static [(&'static str, Stage)],
}

/// Every module, for tools that translate them all (the `emit` example).
pub const MODULES: [Module; 2] = [
    Module {
        name: "hair_draw",
        source: DRAW_WGSL,
        entry_points: &[("vertex", Stage::Vertex), ("fragment", Stage::Fragment)],
    },
    Module {
        name: "hair_compute",
        source: COMPUTE_WGSL,
        entry_points: &[("write_render_vertices", Stage::Compute)],
    },
];

/// Workgroups to dispatch for `vertices` render vertices: `(x, y)` with at
/// most 65,535 along x (the compute entry point reads `x + 65535 * 64 y`).
pub fn dispatch_size(vertices: usize) -> (u32, u32) {
    let groups = vertices.div_ceil(COMPUTE_WORKGROUP_SIZE as usize);
    let x = groups.min(65_535);
    let y = groups.div_ceil(65_535).max(1);
    (x as u32, y.min(u32::MAX as usize) as u32)
}
