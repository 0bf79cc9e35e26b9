// ---- gpu/bindings.wgsl: the GPU path's material (coif_bevy::gpu), after
// Bevy's imports and coif-gpu's types.wgsl, before its ribbon.wgsl. The
// material's bind group (MATERIAL_BIND_GROUP), laid out by
// GpuHairMaterial's AsBindGroup derive: 0 the HairShading uniform, 1..3
// coif's Marschner tables, 4 the render vertices (written by the compute
// pass every frame, vertex r of hair h at h R + r), 5 the HairView (every
// frame; storage, as Bevy binds raw buffers).

@group(#{MATERIAL_BIND_GROUP}) @binding(4) var<storage, read> render_vertices: array<RenderVertex>;
@group(#{MATERIAL_BIND_GROUP}) @binding(5) var<storage, read> hair_view: HairView;

// Render hairs per chunk entity (coif_bevy::gpu::CHUNK_HAIRS): chunk k
// (its MeshTag) draws hairs 256 k .. 256 (k + 1).
const CHUNK_HAIRS: u32 = 256u;

// The eye as HairView::eye has it, from Bevy's view: a perspective view's
// position, or an orthographic view's (a directional light's shadow) +Z,
// the direction toward the viewer.
fn bevy_eye() -> vec4<f32> {
    if view.clip_from_view[3][3] == 1.0 {
        return vec4<f32>(normalize(view.world_from_view[2].xyz), 0.0);
    }
    return vec4<f32>(view.world_position, 1.0);
}

// The ribbon corner a chunk mesh vertex stands for. The chunk mesh's
// position attribute holds (slot vertex q, hair in chunk, 0): each hair's
// slot is a triangle strip of 2 R_max + 2 vertices, the first and last
// repeated so that the strips of neighbouring hairs join by degenerate
// triangles. Corners past the current level's 2 R collapse onto the last
// one; hairs past `hairs` (the LOD prefix) are culled.
struct ChunkCorner {
    corner: RibbonCorner,
    hair: u32,
    drawn: bool,
};

fn chunk_corner(slot: vec3<f32>, instance_index: u32) -> ChunkCorner {
    var out: ChunkCorner;
    out.hair = get_tag(instance_index) * CHUNK_HAIRS + u32(slot.y);
    out.drawn = out.hair < hair_view.hairs && hair_view.verts_per_hair > 0u;
    if !out.drawn {
        out.corner.clip = culled_clip();
        return out;
    }
    let corners = 2 * i32(hair_view.verts_per_hair);
    let c = u32(clamp(i32(slot.x) - 1, 0, corners - 1));
    let side = f32(c % 2u) * 2.0 - 1.0;
    let vertex = out.hair * hair_view.verts_per_hair + c / 2u;
    if vertex >= arrayLength(&render_vertices) {
        out.drawn = false;
        out.corner.clip = culled_clip();
        return out;
    }
    let pixels_per_clip = 0.5 * view.viewport.w * view.clip_from_view[1][1];
    out.corner = ribbon_corner(render_vertices[vertex], side, view.clip_from_world, bevy_eye(), pixels_per_clip);
    return out;
}
