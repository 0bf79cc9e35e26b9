
// ---- hair_material.wgsl: appended to hair.wgsl (HAIR_MATERIAL_WGSL) ----
// The bindings of coif_bevy::HairMaterial (its stages: hair_mesh.wgsl), a bevy_pbr
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

// What hair_mesh.wgsl's stages read of the view.
fn clip_from_world() -> mat4x4<f32> {
    return view.clip_from_world;
}

fn eye() -> vec3<f32> {
    return view.world_position;
}
