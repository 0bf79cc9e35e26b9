// coif-gpu: the buffer layouts as WGSL structs (coif_gpu::HairView,
// RenderHair and coif_lod::RenderVertex, byte for byte), the constants
// and the unit-vector helper every other file uses. First in every module.

// coif_gpu::HairView, 192 bytes. Positions in the guides buffer are
// relative to the strands' origin; world_from_local takes them to world
// space (the origin's translation, and any rigid carry of the hair).
struct HairView {
    clip_from_world: mat4x4<f32>,
    world_from_local: mat4x4<f32>,
    // xyz: the eye (w = 1, a perspective view) or the direction toward the
    // viewer (w = 0, an orthographic view such as a directional shadow).
    eye: vec4<f32>,
    // V: control points per guide (>= 2).
    control_verts: u32,
    // N: segments per span (>= 1).
    segments_per_span: u32,
    // Render hairs drawn: the first `hairs` entries of the hairs buffer.
    hairs: u32,
    // R = (V - 1) N + 1.
    verts_per_hair: u32,
    root_width: f32,
    tip_width: f32,
    // The LOD width factor (coverage kept when fewer hairs are drawn).
    width_factor: f32,
    // Ribbons are never drawn thinner than this many pixels; thinner hair
    // keeps its coverage by fading (dithered) instead of aliasing.
    min_width_px: f32,
    // Pixels per unit of clip w per metre: 0.5 viewport height times the
    // projection's y scale (clip_from_view[1][1]); pixels per metre at a
    // point is this over its clip w.
    pixels_per_clip: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

// coif_gpu::RenderHair, 32 bytes: the three corner guides of the hair's
// scalp triangle and its barycentric weights (coif-lod's Interpolation).
struct RenderHair {
    guide_a: u32,
    guide_b: u32,
    guide_c: u32,
    _reserved: u32,
    // xyz: (b_A, b_B, b_C); w unused.
    weights: vec4<f32>,
};

// coif_lod::RenderVertex, 32 bytes.
struct RenderVertex {
    position: vec3<f32>,
    width: f32,
    tangent: vec3<f32>,
    strand_parameter: f32,
};

const MIN_TANGENT_LENGTH_SQUARED: f32 = 1e-30;
const MAX_FINITE: f32 = 3.40282347e38;

// d / |d|, or +Y where |d|^2 <= 1e-30 or is not finite.
fn unit_or_y(d: vec3<f32>) -> vec3<f32> {
    let l2 = dot(d, d);
    if l2 > MIN_TANGENT_LENGTH_SQUARED && l2 <= MAX_FINITE {
        return d * inverseSqrt(l2);
    }
    return vec3<f32>(0.0, 1.0, 0.0);
}
