
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

// What hair_mesh.wgsl's stages read of the view.
fn clip_from_world() -> mat4x4<f32> {
    return view.clip_from_world;
}

fn eye() -> vec3<f32> {
    return view.eye.xyz;
}
