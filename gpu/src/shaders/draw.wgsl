// coif-gpu's draw stages for an engine's own pipeline (after
// hair_shading.wgsl, types.wgsl, render_vertex.wgsl and ribbon.wgsl): vertex pulling,
// no vertex buffer. Draw a triangle strip of 2 R vertices per instance,
// one instance per render hair: draw(0..2 R, 0..hairs). Vertex 2 r + k is
// render vertex r's corner on side k (0: -1, 1: +1).
//
// Group 0: 0 HairView (uniform), 1 guides, 2 hairs (storage, read);
// group 1: 0 HairShading (uniform), 1..3 coif's Marschner tables
// (rgba32float textures, read with textureLoad).

@group(0) @binding(0) var<uniform> hair_view: HairView;
@group(0) @binding(1) var<storage, read> guides: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> hairs: array<RenderHair>;
@group(1) @binding(0) var<uniform> shading: HairShading;
@group(1) @binding(1) var lut_m: texture_2d<f32>;
@group(1) @binding(2) var lut_n0: texture_2d<f32>;
@group(1) @binding(3) var lut_n1: texture_2d<f32>;

struct HairFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) strand_parameter: f32,
    @location(3) coverage: f32,
    @location(4) @interpolate(flat) hair: u32,
};

@vertex
fn vertex(@builtin(vertex_index) vertex_index: u32, @builtin(instance_index) hair: u32) -> HairFragment {
    var out: HairFragment;
    out.hair = hair;
    if hair >= hair_view.hairs {
        out.clip = culled_clip();
        return out;
    }
    let r = min(vertex_index / 2u, hair_view.verts_per_hair - 1u);
    let side = f32(vertex_index % 2u) * 2.0 - 1.0;
    let c = ribbon_corner(render_vertex(hair, r), side, hair_view.clip_from_world, hair_view.eye, hair_view.pixels_per_clip);
    out.clip = c.clip;
    out.world = c.world;
    out.tangent = c.tangent;
    out.strand_parameter = c.strand_parameter;
    out.coverage = c.coverage;
    return out;
}

@fragment
fn fragment(in: HairFragment) -> @location(0) vec4<f32> {
    if !coverage_kept(in.coverage, in.clip.xy, in.hair) {
        discard;
    }
    let t = normalize(in.tangent);
    var wo = hair_view.eye.xyz;
    if hair_view.eye.w > 0.5 {
        wo = hair_view.eye.xyz - in.world;
    }
    wo = normalize(wo);
    let wi = normalize(shading.light.xyz);
    // A little ambient so the unlit side is not black, darker at the root.
    let ambient = shading.diffuse.xyz * (0.15 + 0.1 * in.strand_parameter);
    return vec4<f32>(hair_radiance(t, wi, wo) + ambient, 1.0);
}
