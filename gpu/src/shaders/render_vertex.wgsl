// coif-gpu: one render vertex of one render hair, from the simulated guides.
// The GPU twin of coif-lod's CPU path, the same formulas in the same order:
//   lod::refine_strands      (uniform cubic B-spline, phantom ends, pinned
//                             end points, unit tangents or +Y),
//   lod::interpolate         (barycentric blend of three guides, the blend of
//                             their unit tangents normalised),
//   lod::write_render_vertices (s = r / (R - 1), width lerp(root, tip, s)
//                             times the LOD width factor).
// gpu/tests/twin.rs runs the compute entry point over Sintel's groom and
// compares every vertex with those kernels.
//
// The module this file is part of binds three globals (see compute.wgsl and
// draw.wgsl): `hair_view` (HairView, a uniform), `guides`
// (array<vec4<f32>>, storage) and `hairs` (array<RenderHair>, storage).

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

struct GuidePoint {
    position: vec3<f32>,
    tangent: vec3<f32>,
};

const MIN_TANGENT_LENGTH_SQUARED: f32 = 1e-30;
const MAX_FINITE: f32 = 3.40282347e38;

// Control point i (-1 <= i <= V) of guide g: the phantom ends
// 2 P_0 - P_1 and 2 P_{V-1} - P_{V-2} outside 0..V (bspline::control_point).
fn control_point(g: u32, i: i32) -> vec3<f32> {
    let v = i32(hair_view.control_verts);
    let base = g * hair_view.control_verts;
    if i < 0 {
        let p0 = guides[base].xyz;
        return p0 + p0 - guides[base + 1u].xyz;
    }
    if i >= v {
        let last = guides[base + u32(v - 1)].xyz;
        return last + last - guides[base + u32(v - 2)].xyz;
    }
    return guides[base + u32(i)].xyz;
}

// (b0, b1, b2, b3) at t (bspline::basis).
fn basis(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    return vec4<f32>(
        s * s * s / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    );
}

// d b_i / dt (bspline::basis_derivative).
fn basis_derivative(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    return vec4<f32>(
        -0.5 * s * s,
        0.5 * (3.0 * t * t - 4.0 * t),
        0.5 * (-3.0 * t * t + 2.0 * t + 1.0),
        0.5 * t * t,
    );
}

// p0 w0 + p1 w1 + p2 w2 + p3 w3, fused left to right (refine_batch::combine).
fn combine(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, p3: vec3<f32>, w: vec4<f32>) -> vec3<f32> {
    return fma(p3, vec3<f32>(w.w), fma(p2, vec3<f32>(w.z), fma(p1, vec3<f32>(w.y), p0 * w.x)));
}

// d / |d|, or +Y where |d|^2 <= 1e-30 or is not finite.
fn unit_or_y(d: vec3<f32>) -> vec3<f32> {
    let l2 = dot(d, d);
    if l2 > MIN_TANGENT_LENGTH_SQUARED && l2 <= MAX_FINITE {
        return d * inverseSqrt(l2);
    }
    return vec3<f32>(0.0, 1.0, 0.0);
}

// Refined vertex r of guide g at N segments per span: span
// j = min(r / N, V - 2), t = (r - j N) / N; the end points pinned to the
// first and last control points.
fn refined_guide(g: u32, r: u32) -> GuidePoint {
    let v = hair_view.control_verts;
    let n = max(hair_view.segments_per_span, 1u);
    let j = min(r / n, v - 2u);
    let t = f32(r - j * n) / f32(n);
    let jj = i32(j);
    let p0 = control_point(g, jj - 1);
    let p1 = control_point(g, jj);
    let p2 = control_point(g, jj + 1);
    let p3 = control_point(g, jj + 2);
    var out: GuidePoint;
    out.position = combine(p0, p1, p2, p3, basis(t));
    out.tangent = unit_or_y(combine(p0, p1, p2, p3, basis_derivative(t)));
    let base = g * v;
    if r == 0u {
        out.position = guides[base].xyz;
    }
    if r == (v - 1u) * n {
        out.position = guides[base + v - 1u].xyz;
    }
    return out;
}

// w_A a + w_B b + w_C c, fused (interpolation::blend).
fn blend(w: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    return fma(vec3<f32>(w.z), c, fma(vec3<f32>(w.y), b, w.x * a));
}

// Vertex r (0 at the root) of render hair h, relative to the origin.
fn render_vertex(h: u32, r: u32) -> RenderVertex {
    let hair = hairs[h];
    let w = hair.weights.xyz;
    let a = refined_guide(hair.guide_a, r);
    let b = refined_guide(hair.guide_b, r);
    let c = refined_guide(hair.guide_c, r);
    var out: RenderVertex;
    out.position = blend(w, a.position, b.position, c.position);
    out.tangent = unit_or_y(blend(w, a.tangent, b.tangent, c.tangent));
    let verts = hair_view.verts_per_hair;
    var inv = 0.0;
    if verts > 1u {
        inv = 1.0 / f32(verts - 1u);
    }
    let s = f32(r) * inv;
    out.strand_parameter = s;
    out.width = (hair_view.root_width + (hair_view.tip_width - hair_view.root_width) * s) * hair_view.width_factor;
    return out;
}
