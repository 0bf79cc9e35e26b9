// ---- gpu/prepass.wgsl: the GPU path's prepass, which Bevy's shadow
// passes run (after coif-gpu's types, the bindings and ribbon.wgsl):
// the same ribbons, facing the light, into the shadow map. Where the
// device cannot clamp depth for orthographic views, the depth is written
// by the fragment stage as bevy_pbr's own prepass does.

struct HairShadowFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) coverage: f32,
    @location(1) @interpolate(flat) hair: u32,
#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
    @location(2) unclipped_depth: f32,
#endif
};

@vertex
fn vertex(@location(0) slot: vec3<f32>, @builtin(instance_index) instance_index: u32) -> HairShadowFragment {
    let c = chunk_corner(slot, instance_index);
    var out: HairShadowFragment;
    out.clip = c.corner.clip;
    out.coverage = c.corner.coverage;
    out.hair = c.hair;
#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
    out.unclipped_depth = out.clip.z;
    out.clip.z = min(out.clip.z, 1.0);
#endif
    return out;
}

#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
@fragment
fn fragment(in: HairShadowFragment) -> @builtin(frag_depth) f32 {
    if !coverage_kept(in.coverage, in.clip.xy, in.hair) {
        discard;
    }
    return in.unclipped_depth;
}
#else
@fragment
fn fragment(in: HairShadowFragment) {
    if !coverage_kept(in.coverage, in.clip.xy, in.hair) {
        discard;
    }
}
#endif
