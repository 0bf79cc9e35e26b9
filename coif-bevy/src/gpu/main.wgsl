// ---- gpu/main.wgsl: the GPU path's main pass (after the shading
// functions, coif-gpu's types, the bindings and ribbon.wgsl). Lit by every
// Bevy directional light (colour times illuminance, its shadow map where
// it casts shadows), the view's ambient light, scaled by the view's
// exposure, as bevy_pbr's lights are.

struct HairFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) strand_parameter: f32,
    @location(3) coverage: f32,
    @location(4) @interpolate(flat) hair: u32,
};

@vertex
fn vertex(@location(0) slot: vec3<f32>, @builtin(instance_index) instance_index: u32) -> HairFragment {
    let c = chunk_corner(slot, instance_index);
    var out: HairFragment;
    out.clip = c.corner.clip;
    out.world = c.corner.world;
    out.tangent = c.corner.tangent;
    out.strand_parameter = c.corner.strand_parameter;
    out.coverage = c.corner.coverage;
    out.hair = c.hair;
    return out;
}

@fragment
fn fragment(in: HairFragment) -> @location(0) vec4<f32> {
    if !coverage_kept(in.coverage, in.clip.xy, in.hair) {
        discard;
    }
    let t = normalize(in.tangent);
    let eye = bevy_eye();
    var wo = eye.xyz;
    if eye.w > 0.5 {
        wo = eye.xyz - in.world;
    }
    wo = normalize(wo);
    // The ribbon's normal (across the hair, toward the eye) for the
    // shadow lookup's normal bias.
    var n = wo - t * dot(t, wo);
    if dot(n, n) < 1e-12 {
        n = wo;
    }
    n = normalize(n);
    let world = vec4<f32>(in.world, 1.0);
    let view_z = dot(vec4<f32>(view.view_from_world[0].z, view.view_from_world[1].z, view.view_from_world[2].z, view.view_from_world[3].z), world);
    // Ambient: the hair's diffuse colour under the view's ambient light,
    // darker toward the root (self-occlusion).
    var color = lights.ambient_color.rgb * shading.diffuse.xyz * (0.5 + 0.5 * in.strand_parameter);
    for (var i = 0u; i < lights.n_directional_lights; i = i + 1u) {
        let light = &lights.directional_lights[i];
        var shadow = 1.0;
        if ((*light).flags & DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) != 0u {
            shadow = fetch_directional_shadow(i, world, n, view_z, in.clip.xy);
        }
        // coif's scattering times the light's colour and illuminance: a
        // 4,000 lux light at Bevy's default exposure (EV100 9.7) gives
        // about the intensity HairMaterial's own light has (3).
        color = color + hair_scattering(t, (*light).direction_to_light, wo) * (*light).color.rgb * shadow;
    }
    return vec4<f32>(color * view.exposure, 1.0);
}
