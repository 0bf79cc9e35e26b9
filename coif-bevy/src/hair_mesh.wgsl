
// ---- hair_mesh.wgsl: appended after the bindings (hair_standalone.wgsl
// or hair_material.wgsl), which define `clip_from_world()` and `eye()` ----
// The vertex and fragment stages over the plugin's hair mesh:
// ATTRIBUTE_POSITION (world), ATTRIBUTE_TANGENT (xyz the hair's unit
// tangent, w the position along the hair), ATTRIBUTE_UV_0.

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
    out.clip = clip_from_world() * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.tangent = in.tangent.xyz;
    out.along = in.tangent.w;
    return out;
}

@fragment
fn fragment(in: HairFragment) -> @location(0) vec4<f32> {
    let t = normalize(in.tangent);
    let wo = normalize(eye() - in.world);
    let wi = normalize(shading.light.xyz);
    // A little ambient so the unlit side is not black, darker at the root.
    let ambient = shading.diffuse.xyz * (0.15 + 0.1 * in.along);
    return vec4<f32>(hair_radiance(t, wi, wo) + ambient, 1.0);
}
