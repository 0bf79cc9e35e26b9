
// ---- hair_standalone.wgsl: appended to hair.wgsl (HAIR_WGSL) ----
// A pipeline of its own over the plugin's hair mesh, for a renderer that is
// not Bevy's: its view, the shading uniform and the three tables in group 0.

struct HairView {
    clip_from_world: mat4x4<f32>,
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> view: HairView;
@group(0) @binding(1) var<uniform> shading: HairShading;
@group(0) @binding(2) var lut_m: texture_2d<f32>;
@group(0) @binding(3) var lut_n0: texture_2d<f32>;
@group(0) @binding(4) var lut_n1: texture_2d<f32>;

// A standalone pipeline over the plugin's hair mesh: world positions,
// ATTRIBUTE_TANGENT (xyz the hair's tangent, w along the hair), UV_0.
struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) tangent: vec4<f32>,
    @location(2) uv: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) along: f32,
};

@vertex
fn vertex(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = view.clip_from_world * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.tangent = in.tangent.xyz;
    out.along = in.tangent.w;
    return out;
}

@fragment
fn fragment(in: VertexOut) -> @location(0) vec4<f32> {
    let t = normalize(in.tangent);
    let wo = normalize(view.eye.xyz - in.world);
    let wi = normalize(shading.light.xyz);
    // A little ambient so the unlit side is not black, darker at the root.
    let ambient = shading.diffuse.xyz * (0.15 + 0.1 * in.along);
    return vec4<f32>(hair_radiance(t, wi, wo) + ambient, 1.0);
}
