// coif-gpu: camera-facing ribbons from render vertices (after types.wgsl;
// binds `hair_view`). As TressFX's strand vertex shader: each render vertex
// gives two ribbon corners, offset across the hair along tangent x view,
// the width never below `min_width_px` pixels; a hair drawn wider than it is
// keeps its coverage as `coverage` = true width / drawn width, which the
// fragment stage turns into a dithered discard (stochastic transparency:
// Enderton et al. 2010), so thin hair fades instead of aliasing, in opaque
// and shadow passes alike, without sorting.

struct RibbonCorner {
    clip: vec4<f32>,
    world: vec3<f32>,
    // Unit tangent, world space.
    tangent: vec3<f32>,
    strand_parameter: f32,
    // True width over drawn width, in (0, 1].
    coverage: f32,
};

// The ribbon corner of `v` on `side` (-1 or +1) for a view with
// `clip_from_world`, `eye` (HairView::eye's convention) and
// `pixels_per_clip` (0.5 viewport height times the projection's y scale).
fn ribbon_corner(v: RenderVertex, side: f32, clip_from_world: mat4x4<f32>, eye: vec4<f32>, pixels_per_clip: f32) -> RibbonCorner {
    let world = (hair_view.world_from_local * vec4<f32>(v.position, 1.0)).xyz;
    let t = unit_or_y((hair_view.world_from_local * vec4<f32>(v.tangent, 0.0)).xyz);
    var to_eye = eye.xyz;
    if eye.w > 0.5 {
        to_eye = eye.xyz - world;
    }
    var across = cross(t, to_eye);
    if dot(across, across) <= MIN_TANGENT_LENGTH_SQUARED {
        // Looking along the hair: any direction across it.
        across = cross(t, vec3<f32>(t.z, t.x, -t.y));
    }
    across = unit_or_y(across);
    let center = clip_from_world * vec4<f32>(world, 1.0);
    let px_per_m = pixels_per_clip / max(abs(center.w), 1e-6);
    let width_px = max(v.width, 0.0) * px_per_m;
    let drawn_px = max(width_px, hair_view.min_width_px);
    var out: RibbonCorner;
    out.coverage = 1.0;
    if drawn_px > 0.0 {
        out.coverage = clamp(width_px / drawn_px, 0.0, 1.0);
    }
    // No scale from the view (a zero viewport): the hair's own width.
    var half_width = 0.5 * max(v.width, 0.0);
    if px_per_m > 0.0 {
        half_width = 0.5 * drawn_px / px_per_m;
    }
    out.world = world + across * (half_width * side);
    out.clip = clip_from_world * vec4<f32>(out.world, 1.0);
    out.tangent = t;
    out.strand_parameter = v.strand_parameter;
    return out;
}

// Where a hair slot has nothing to draw (a hair past `hairs`): outside
// every view volume (z > w), and every triangle touching it is degenerate.
fn culled_clip() -> vec4<f32> {
    return vec4<f32>(0.0, 0.0, 2.0, 1.0);
}

// Whether a fragment of coverage `coverage` is kept: interleaved gradient
// noise (Jimenez 2014) over the pixel, offset per hair by the golden ratio
// so that overlapping thin hairs do not dither alike.
fn coverage_kept(coverage: f32, frag_xy: vec2<f32>, hair: u32) -> bool {
    let noise = fract(52.9829189 * fract(dot(floor(frag_xy), vec2<f32>(0.06711056, 0.00583715))) + f32(hair & 1023u) * 0.618034);
    return noise < coverage;
}
