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
// After types.wgsl. The module this file is part of binds three globals
// (see compute.wgsl and draw.wgsl): `hair_view` (HairView), `guides`
// (array<vec4<f32>>, storage) and `hairs` (array<RenderHair>, storage).

struct GuidePoint {
    position: vec3<f32>,
    tangent: vec3<f32>,
};

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
