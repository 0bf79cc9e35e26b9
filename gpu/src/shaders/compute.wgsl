// coif-gpu's compute entry point (after types.wgsl and render_vertex.wgsl):
// every render vertex of the first `hair_view.hairs` hairs, hair after
// hair, root first, into `vertices` (coif_lod::RenderVertex's layout), as
// lod::write_render_vertices writes them. Vertex r of hair h is at
// h R + r. coif-bevy runs it once a frame before its passes; the GPU twin
// test (gpu/tests/twin.rs) compares it with the CPU kernels.
//
// Group 0: 0 HairView (uniform), 1 guides, 2 hairs (storage, read), 3 the
// render vertices (storage, read-write).

@group(0) @binding(0) var<uniform> hair_view: HairView;
@group(0) @binding(1) var<storage, read> guides: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> hairs: array<RenderHair>;
@group(0) @binding(3) var<storage, read_write> vertices: array<RenderVertex>;

// Dispatch ceil(hairs R / 64) workgroups (x, or spread over x and y with
// x = 65535 workgroups per row).
@compute @workgroup_size(64)
fn write_render_vertices(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * 65535u * 64u;
    let verts = hair_view.verts_per_hair;
    if verts == 0u || i >= hair_view.hairs * verts || i >= arrayLength(&vertices) {
        return;
    }
    vertices[i] = render_vertex(i / verts, i % verts);
}
