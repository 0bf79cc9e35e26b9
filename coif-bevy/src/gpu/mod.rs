//! The GPU draw path ([`crate::HairDrawPath::Gpu`], feature `render`):
//! render hairs made in the vertex shader from the simulated guides
//! (coif-gpu), lit by Bevy's lights, casting into Bevy's shadow maps.
//!
//! Per hair, made once when its state is built ([`init_gpu_hairs`]):
//! - four buffers: the guides (storage, `COPY_DST`, 16 bytes per guide
//!   vertex), the render hairs (storage, 32 bytes per hair, written once
//!   from coif's `Interpolation` by `coif_gpu::pack_hairs`), the
//!   [`coif_gpu::HairView`] (192 bytes) and the render vertices (32 bytes
//!   per render vertex of the finest level, written by the GPU only);
//! - a [`GpuHairMaterial`] binding the render vertices and the view with
//!   coif's shading uniform and Marschner tables;
//! - a chunk mesh: [`CHUNK_HAIRS`] hair slots of `2 R_max + 2` vertices in
//!   one triangle strip, whose only attribute says which slot vertex each
//!   is (it is the same for every chunk and never changes);
//! - one entity per chunk of [`CHUNK_HAIRS`] render hairs, the chunk mesh
//!   with the material and a `MeshTag` (the chunk's index).
//!
//! Per frame ([`update_gpu_hairs`], `PostUpdate`): the level from the
//! camera (as the CPU mesh path chooses it), the guides packed straight
//! from coif's SoA blocks into a persistent buffer and written with
//! `write_buffer` with the view (no buffer created, nothing allocated), and
//! chunks past the LOD's hair count hidden. The GPU does the rest:
//! - a compute pass ([`compute`], before the cameras' passes) runs
//!   coif-gpu's `write_render_vertices`: `render_vertex(hair, r)`
//!   (refinement, interpolation, width) once for every render vertex;
//! - the material's vertex stages, in the main pass and in every shadow
//!   pass, read the two render vertices of a ribbon segment and expand
//!   them with `ribbon_corner` (camera-facing, at least `min_width_px`
//!   wide, thinner hair dithered by its coverage).
//!
//! Why a compute pass rather than `render_vertex` in the vertex stage (as
//! coif-gpu's `draw.wgsl` does): a render vertex is used by two ribbon
//! corners in each pass, and the hair is drawn by the main pass and each
//! shadow cascade; the pass makes it once, with the very shader the GPU
//! twin test checks. On lavapipe the frame is bound by rasterisation
//! instead and the pass did not make it faster (the crate's README has
//! the figures).
//!
//! Why a `Material` over chunk meshes rather than a custom phase item:
//! the material gets Bevy's lights, shadow maps, exposure and shadow
//! passes with their pipelines, batching and culling rules for free, and
//! keeps working as Bevy's renderer changes. Its price is a static mesh
//! per hair (12 bytes per slot vertex, uploaded once) and vertex shader
//! work for the slot vertices a lower level leaves degenerate.

use crate::components::Hair;
use crate::material::{HairLook, HairMaterial, HairShadingGpu};
use crate::render::{active_view, choose_level, HairMeshOf};
use crate::sim::HairState;
use bevy::asset::{uuid_handle, RenderAssetUsages};
use bevy::mesh::{MeshTag, MeshVertexBufferLayoutRef, PrimitiveTopology, VertexBufferLayout};
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, Buffer, BufferDescriptor, BufferInitDescriptor, BufferUsages,
    RenderPipelineDescriptor, SpecializedMeshPipelineError,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::shader::ShaderRef;
use coif_gpu::{pack_guides, pack_hairs, render_hair_count, GuideVertex, HairView, RenderHair};
use std::time::Instant;

/// Render hairs per chunk entity (the shader's `CHUNK_HAIRS`).
pub const CHUNK_HAIRS: usize = 256;

pub mod compute;

/// The main pass's shader.
pub const GPU_HAIR_SHADER: Handle<Shader> = uuid_handle!("0b8f4c1e-6a53-4d0e-9f59-3c8a2d7e5b10");
/// The prepass's (shadow) shader.
pub const GPU_HAIR_PREPASS_SHADER: Handle<Shader> =
    uuid_handle!("7e21c9a4-58d2-4b6f-a0c3-91d54e8f2a66");

const IMPORTS_MAIN: &str = "#import bevy_pbr::mesh_view_bindings::{view, lights}
#import bevy_pbr::mesh_view_types::DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT
#import bevy_pbr::shadows::fetch_directional_shadow
#import bevy_pbr::mesh_functions::get_tag

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> shading: HairShading;
@group(#{MATERIAL_BIND_GROUP}) @binding(1) var lut_m: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(2) var lut_n0: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(3) var lut_n1: texture_2d<f32>;
";

const IMPORTS_PREPASS: &str = "#import bevy_pbr::mesh_view_bindings::view
#import bevy_pbr::mesh_functions::get_tag
";

/// The main pass's WGSL: Bevy's imports, coif's shading functions,
/// coif-gpu's types, the material's bindings, coif-gpu's ribbons, the
/// stages.
pub fn main_pass_wgsl() -> String {
    [
        IMPORTS_MAIN,
        coif_gpu::shaders::HAIR_SHADING_WGSL,
        coif_gpu::shaders::TYPES_WGSL,
        include_str!("bindings.wgsl"),
        coif_gpu::shaders::RIBBON_WGSL,
        include_str!("main.wgsl"),
    ]
    .concat()
}

/// The prepass's WGSL (what Bevy's shadow passes run).
pub fn prepass_wgsl() -> String {
    [
        IMPORTS_PREPASS,
        coif_gpu::shaders::TYPES_WGSL,
        include_str!("bindings.wgsl"),
        coif_gpu::shaders::RIBBON_WGSL,
        include_str!("prepass.wgsl"),
    ]
    .concat()
}

/// Registers the three shaders (at plugin build).
pub(crate) fn register_shaders(app: &mut App) {
    if let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() {
        let _ = shaders.insert(
            &GPU_HAIR_SHADER,
            Shader::from_wgsl(main_pass_wgsl(), "coif_bevy/hair_gpu_main.wgsl"),
        );
        let _ = shaders.insert(
            &GPU_HAIR_PREPASS_SHADER,
            Shader::from_wgsl(prepass_wgsl(), "coif_bevy/hair_gpu_prepass.wgsl"),
        );
        let _ = shaders.insert(
            &compute::GPU_HAIR_COMPUTE_SHADER,
            Shader::from_wgsl(
                coif_gpu::shaders::COMPUTE_WGSL,
                "coif_gpu/hair_compute.wgsl",
            ),
        );
    }
}

/// The GPU path's material: coif's shading (uniform and tables, as
/// [`HairMaterial`]), the hair's render vertices and its view. Never
/// changed after it is made: the buffers' contents change (the view by
/// `write_buffer`, the render vertices by the compute pass).
#[derive(Asset, AsBindGroup, Clone, TypePath)]
pub struct GpuHairMaterial {
    /// The `HairShading` uniform.
    #[uniform(0)]
    pub shading: HairShadingGpu,
    /// coif's M table.
    #[texture(1, sample_type = "float", filterable = false)]
    pub lut_m: Handle<Image>,
    /// coif's N table, first half.
    #[texture(2, sample_type = "float", filterable = false)]
    pub lut_n0: Handle<Image>,
    /// coif's N table, second half.
    #[texture(3, sample_type = "float", filterable = false)]
    pub lut_n1: Handle<Image>,
    /// The render vertices (`coif_lod::RenderVertex`'s 32 bytes each),
    /// vertex `r` of render hair `h` at `h R + r`.
    #[storage(4, read_only, buffer, visibility(vertex))]
    pub vertices: Buffer,
    /// The [`HairView`].
    #[storage(5, read_only, buffer, visibility(vertex))]
    pub view: Buffer,
}

impl Material for GpuHairMaterial {
    fn vertex_shader() -> ShaderRef {
        GPU_HAIR_SHADER.into()
    }

    fn fragment_shader() -> ShaderRef {
        GPU_HAIR_SHADER.into()
    }

    fn prepass_vertex_shader() -> ShaderRef {
        GPU_HAIR_PREPASS_SHADER.into()
    }

    fn prepass_fragment_shader() -> ShaderRef {
        GPU_HAIR_PREPASS_SHADER.into()
    }

    // Shadows only: a camera's depth or normal prepass would need
    // outputs the hair does not write.
    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        true
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        layout: &MeshVertexBufferLayoutRef,
        _key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        let vertex: VertexBufferLayout = layout
            .0
            .get_layout(&[Mesh::ATTRIBUTE_POSITION.at_shader_location(0)])?;
        descriptor.vertex.buffers = vec![vertex];
        // Ribbons face the eye (or the light): both faces.
        descriptor.primitive.cull_mode = None;
        Ok(())
    }
}

/// On a chunk entity: its hair and the chunk's index.
#[derive(Component, Clone, Copy, Debug)]
pub struct GpuHairChunk {
    /// The hair entity.
    pub hair: Entity,
    /// The chunk: render hairs `CHUNK_HAIRS * index ..`.
    pub index: usize,
}

/// A hair's GPU data, on the hair entity.
#[derive(Component)]
pub struct GpuHair {
    guides: Vec<GuideVertex>,
    guides_buffer: Buffer,
    hairs_buffer: Buffer,
    view_buffer: Buffer,
    vertices_buffer: Buffer,
    /// Render vertices the buffer holds: render hairs times the finest
    /// level's vertices per hair.
    vertex_capacity: u32,
    view: HairView,
    chunks: Vec<Entity>,
}

impl GpuHair {
    /// The view written last.
    pub fn view(&self) -> &HairView {
        &self.view
    }

    /// The guides written last.
    pub fn guides(&self) -> &[GuideVertex] {
        &self.guides
    }
}

/// The chunk mesh: `CHUNK_HAIRS` slots of `2 r_max + 2` vertices in one
/// triangle strip; vertex `q` of slot `h` holds `(q, h, 0)`.
pub fn chunk_mesh(r_max: usize) -> Mesh {
    let slot = 2 * r_max + 2;
    let positions: Vec<[f32; 3]> = (0..CHUNK_HAIRS)
        .flat_map(|h| (0..slot).map(move |q| [q as f32, h as f32, 0.0]))
        .collect();
    Mesh::new(
        PrimitiveTopology::TriangleStrip,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
}

/// The level and placement of one hair for this frame, into `view`, and
/// its guides packed into `guides` (no allocation: both are the hair's
/// own). Returns the render hairs drawn. What [`update_gpu_hairs`] does
/// before the upload, apart so that it can be measured and tested
/// without a GPU.
pub fn prepare_frame(
    hair: &Hair,
    state: &HairState,
    camera: Option<crate::render::View>,
    guides: &mut [GuideVertex],
    view: &mut HairView,
) -> usize {
    let Some(interp) = state.interpolation.as_ref() else {
        return 0;
    };
    let strands = &state.strands;
    let center = state.pose.translation.into();
    let (segments, groups) = choose_level(hair, strands, interp, center, state.extent, camera);
    let hairs = render_hair_count(interp, groups);
    // A buffer too small cannot happen (sized from the strands); an empty
    // draw rather than a panic all the same.
    if pack_guides(strands.blocks(), guides).is_err() {
        return 0;
    }
    let r = &hair.render;
    view.set_level(strands.verts_per_strand(), segments, hairs);
    view.root_width = r.root_width;
    view.tip_width = r.tip_width;
    view.width_factor = r.width_scale;
    view.min_width_px = r.min_width_px.max(0.0);
    // While following, the strands stay where they were last stepped and
    // the head has carried them on.
    let carry = state.pose * state.stepped_pose.inverse();
    view.set_placement(strands.origin(), carry);
    hairs
}

/// Builds the GPU data of hairs whose state is new (`PostUpdate`).
#[allow(clippy::too_many_arguments)]
pub fn init_gpu_hairs(
    mut commands: Commands,
    hairs: Query<(Entity, &Hair, &HairState), Without<GpuHair>>,
    device: Option<Res<RenderDevice>>,
    look: Option<Res<HairLook>>,
    mut materials: ResMut<Assets<GpuHairMaterial>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut images: ResMut<Assets<Image>>,
) {
    let Some(device) = device else {
        return;
    };
    for (entity, hair, state) in &hairs {
        let Some(interp) = state.interpolation.as_ref() else {
            continue;
        };
        let guide_count = state.strands.strand_count() * state.strands.verts_per_strand();
        let mut packed_hairs = vec![RenderHair::default(); interp.hair_count().max(1)];
        if pack_hairs(interp, &mut packed_hairs).is_err() {
            continue;
        }
        let guides_buffer = device.create_buffer(&BufferDescriptor {
            label: Some("coif guides"),
            size: (guide_count.max(1) * std::mem::size_of::<GuideVertex>()) as u64,
            usage: BufferUsages::STORAGE | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let hairs_buffer = device.create_buffer_with_data(&BufferInitDescriptor {
            label: Some("coif render hairs"),
            contents: bytemuck::cast_slice(&packed_hairs),
            usage: BufferUsages::STORAGE,
        });
        // A uniform for the compute pass, storage for the material.
        let view_buffer = device.create_buffer(&BufferDescriptor {
            label: Some("coif hair view"),
            size: std::mem::size_of::<HairView>() as u64,
            usage: BufferUsages::STORAGE | BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let r_max = coif::lod::refined_len(
            state.strands.verts_per_strand(),
            hair.render.max_segments.max(1),
        );
        let Ok(vertex_capacity) = u32::try_from(interp.hair_count().max(1) * r_max) else {
            crate::warn_once!("coif-bevy: a hair with over 2^32 render vertices is not drawn");
            continue;
        };
        let vertices_buffer = device.create_buffer(&BufferDescriptor {
            label: Some("coif render vertices"),
            size: u64::from(vertex_capacity) * compute::RENDER_VERTEX_BYTES,
            usage: BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let look = look.as_deref().cloned().unwrap_or_default();
        let shading = HairMaterial::new(&look, &mut images);
        let material = materials.add(GpuHairMaterial {
            shading: shading.shading,
            lut_m: shading.lut_m,
            lut_n0: shading.lut_n0,
            lut_n1: shading.lut_n1,
            vertices: vertices_buffer.clone(),
            view: view_buffer.clone(),
        });
        let mesh = meshes.add(chunk_mesh(r_max));
        let chunks = (0..interp.hair_count().div_ceil(CHUNK_HAIRS))
            .map(|k| {
                commands
                    .spawn((
                        Mesh3d(mesh.clone()),
                        MeshMaterial3d(material.clone()),
                        MeshTag(k as u32),
                        Transform::IDENTITY,
                        Visibility::Visible,
                        HairMeshOf(entity),
                        GpuHairChunk {
                            hair: entity,
                            index: k,
                        },
                        // The chunk mesh's positions are slot numbers, not
                        // places: its bounds mean nothing.
                        bevy::camera::visibility::NoFrustumCulling,
                    ))
                    .id()
            })
            .collect();
        commands.entity(entity).insert(GpuHair {
            guides: vec![GuideVertex::default(); guide_count],
            guides_buffer,
            hairs_buffer,
            view_buffer,
            vertices_buffer,
            vertex_capacity,
            view: HairView::default(),
            chunks,
        });
    }
}

/// Each hair's level, guides and view for this frame, written into its
/// buffers; chunks past the level's hair count hidden (`PostUpdate`).
pub fn update_gpu_hairs(
    cameras: Query<(&Camera, &GlobalTransform, Option<&Projection>)>,
    mut hairs: Query<(&Hair, &mut HairState, &mut GpuHair)>,
    mut chunks: Query<&mut Visibility, With<GpuHairChunk>>,
    queue: Option<Res<RenderQueue>>,
) {
    let Some(queue) = queue else {
        return;
    };
    let camera = active_view(&cameras);
    for (hair, mut state, mut gpu) in &mut hairs {
        let start = Instant::now();
        let gpu = &mut *gpu;
        let drawn = prepare_frame(hair, &state, camera, &mut gpu.guides, &mut gpu.view);
        let guide_bytes: &[u8] = bytemuck::cast_slice(&gpu.guides);
        queue.write_buffer(&gpu.guides_buffer, 0, guide_bytes);
        queue.write_buffer(&gpu.view_buffer, 0, bytemuck::bytes_of(&gpu.view));
        for (k, &chunk) in gpu.chunks.iter().enumerate() {
            if let Ok(mut visibility) = chunks.get_mut(chunk) {
                let wanted = if k * CHUNK_HAIRS < drawn {
                    Visibility::Visible
                } else {
                    Visibility::Hidden
                };
                visibility.set_if_neq(wanted);
            }
        }
        let stats = &mut state.stats;
        stats.render_hairs = drawn;
        stats.mesh_vertices = 0;
        stats.upload_bytes = guide_bytes.len() + std::mem::size_of::<HairView>();
        stats.plugin_ms = start.elapsed().as_secs_f32() * 1e3;
        stats.mesh_ms = stats.plugin_ms;
        stats.lod_ms = stats.plugin_ms;
    }
}
