
// ---- hair_material.wgsl: appended to hair.wgsl (HAIR_MATERIAL_WGSL) ----
// The vertex and fragment shaders of coif_bevy::HairMaterial, a bevy_pbr
// Material over the plugin's hair mesh (world-space positions at the
// identity transform, so no mesh uniform is read).
//
// Group 0 is Bevy's mesh view bind group; binding 0 there is Bevy's `View`
// uniform (bevy_render::view::View). This declares its leading fields only
// (a shader may read a prefix of a bound buffer), so the file needs no
// Bevy import and naga validates it as it is. Group 3 is the material's
// (bevy_pbr::MATERIAL_BIND_GROUP_INDEX, checked by tests/wgsl.rs), laid out
// by HairMaterial's AsBindGroup derive.

struct BevyViewPrefix {
    clip_from_world: mat4x4<f32>,
    unjittered_clip_from_world: mat4x4<f32>,
    world_from_clip: mat4x4<f32>,
    world_from_view: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    clip_from_view: mat4x4<f32>,
    view_from_clip: mat4x4<f32>,
    world_position: vec3<f32>,
    exposure: f32,
};

@group(0) @binding(0) var<uniform> view: BevyViewPrefix;
@group(3) @binding(0) var<uniform> shading: HairShading;
@group(3) @binding(1) var lut_m: texture_2d<f32>;
@group(3) @binding(2) var lut_n0: texture_2d<f32>;
@group(3) @binding(3) var lut_n1: texture_2d<f32>;

// The plugin's mesh: ATTRIBUTE_POSITION (world), ATTRIBUTE_TANGENT (xyz the
// hair's unit tangent, w the position along the hair), ATTRIBUTE_UV_0.
struct HairVertex {
    @location(0) position: vec3<f32>,
    @location(1) tangent: vec4<f32>,
    @location(2) uv: vec2<f32>,
};

struct HairFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) along: f32,
};

@vertex
fn vertex(in: HairVertex) -> HairFragment {
    var out: HairFragment;
    out.clip = view.clip_from_world * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.tangent = in.tangent.xyz;
    out.along = in.tangent.w;
    return out;
}

@fragment
fn fragment(in: HairFragment) -> @location(0) vec4<f32> {
    let t = normalize(in.tangent);
    let wo = normalize(view.world_position - in.world);
    let wi = normalize(shading.light.xyz);
    // A little ambient so the unlit side is not black, darker at the root.
    let ambient = shading.diffuse.xyz * (0.15 + 0.1 * in.along);
    return vec4<f32>(hair_radiance(t, wi, wo) + ambient, 1.0);
}
