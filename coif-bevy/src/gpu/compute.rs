//! The GPU path's compute pass: every render vertex of every hair made
//! once a frame, before the cameras' passes (the main pass and each
//! shadow pass) expand them into ribbons.
//!
//! It runs coif-gpu's compute module (`coif_gpu::shaders::COMPUTE_WGSL`,
//! entry point `write_render_vertices`): the shader the GPU twin test
//! (`gpu/tests/twin.rs`) checks against coif-lod's CPU kernels. Group 0:
//! the hair's view (uniform), guides, render hairs and render vertices.
//!
//! In the render world:
//! - [`RenderStartup`]: the pipeline is queued;
//! - [`ExtractSchedule`]: each hair with [`GpuHair`] gets a job (its four
//!   buffers; nothing is copied but handles, and nothing allocated once
//!   every hair has its job);
//! - `PrepareBindGroups`: a job's bind group is made once;
//! - the [`RenderGraph`] schedule, before `camera_driver`: one compute pass
//!   with a dispatch per hair.
//!
//! Each dispatch covers the hair's capacity (render hairs times the finest
//! level's vertices per hair); invocations past the frame's
//! `hairs x verts_per_hair` return at once. The view buffer of the frame
//! decides both what the pass writes and what the draws read, so they
//! agree even when Bevy's pipelined rendering draws one frame while the
//! next one's buffers are written.

use super::GpuHair;
use bevy::asset::uuid_handle;
use bevy::core_pipeline::schedule::camera_driver;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{
    storage_buffer_read_only_sized, storage_buffer_sized, uniform_buffer_sized,
};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, Buffer,
    CachedComputePipelineId, ComputePassDescriptor, ComputePipelineDescriptor, PipelineCache,
    ShaderStages,
};
use bevy::render::renderer::{RenderContext, RenderDevice, RenderGraph};
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use coif_gpu::shaders::dispatch_size;
use coif_gpu::HairView;
use std::num::NonZeroU64;

/// The compute module's shader (coif-gpu's `COMPUTE_WGSL`).
pub const GPU_HAIR_COMPUTE_SHADER: Handle<Shader> =
    uuid_handle!("3d6a91f2-0b7e-4c58-8e14-5a2f6c9d0b37");

/// Bytes per render vertex (`coif_lod::RenderVertex`: position, width,
/// tangent, parameter along the hair; the WGSL struct the compute pass
/// writes has the same 32-byte layout).
pub const RENDER_VERTEX_BYTES: u64 = std::mem::size_of::<coif::lod::RenderVertex>() as u64;
const _: () = assert!(
    RENDER_VERTEX_BYTES == 32,
    "the WGSL RenderVertex is 32 bytes"
);

/// The label of the pass, its pipeline and bind groups (for GPU
/// debuggers and profilers).
const LABEL: &str = "coif render vertices";

/// Adds the pass to the app's render world (none: nothing to do).
pub(crate) fn add_compute_pass(app: &mut App) {
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    render_app
        .init_resource::<HairVertexJobs>()
        .add_systems(RenderStartup, init_pipeline)
        .add_systems(ExtractSchedule, extract_jobs)
        .add_systems(
            Render,
            prepare_bind_groups.in_set(RenderSystems::PrepareBindGroups),
        )
        .add_systems(RenderGraph, write_render_vertices.before(camera_driver));
}

/// The pipeline and its bind group layout (render world).
#[derive(Resource)]
pub struct HairVertexPipeline {
    layout: BindGroupLayoutDescriptor,
    id: CachedComputePipelineId,
}

/// One hair's dispatch.
struct HairVertexJob {
    /// The hair entity (main world), to find the job again.
    hair: Entity,
    view: Buffer,
    guides: Buffer,
    hairs: Buffer,
    vertices: Buffer,
    invocations: u32,
    bind_group: Option<BindGroup>,
    seen: bool,
}

/// Every hair's dispatch (render world), kept from frame to frame.
#[derive(Resource, Default)]
pub struct HairVertexJobs(Vec<HairVertexJob>);

impl HairVertexJobs {
    /// Hairs the pass dispatches for.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the pass has nothing to do.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

fn init_pipeline(mut commands: Commands, cache: Res<PipelineCache>) {
    let layout = BindGroupLayoutDescriptor::new(
        LABEL,
        &BindGroupLayoutEntries::sequential(
            ShaderStages::COMPUTE,
            (
                uniform_buffer_sized(false, NonZeroU64::new(size_of::<HairView>() as u64)),
                storage_buffer_read_only_sized(false, None),
                storage_buffer_read_only_sized(false, None),
                storage_buffer_sized(false, NonZeroU64::new(RENDER_VERTEX_BYTES)),
            ),
        ),
    );
    let id = cache.queue_compute_pipeline(ComputePipelineDescriptor {
        label: Some(LABEL.into()),
        layout: vec![layout.clone()],
        shader: GPU_HAIR_COMPUTE_SHADER,
        entry_point: Some("write_render_vertices".into()),
        zero_initialize_workgroup_memory: false,
        ..default()
    });
    commands.insert_resource(HairVertexPipeline { layout, id });
}

/// A job per hair: new hairs get one, gone hairs lose theirs, a hair whose
/// buffers were made anew gets a new bind group.
fn extract_jobs(mut jobs: ResMut<HairVertexJobs>, hairs: Extract<Query<(Entity, &GpuHair)>>) {
    for job in &mut jobs.0 {
        job.seen = false;
    }
    for (hair, gpu) in &hairs {
        let existing = jobs.0.iter_mut().find(|job| job.hair == hair);
        if let Some(job) = existing {
            if job.vertices.id() == gpu.vertices_buffer.id()
                && job.view.id() == gpu.view_buffer.id()
            {
                job.seen = true;
                continue;
            }
            job.hair = Entity::PLACEHOLDER;
        }
        jobs.0.push(HairVertexJob {
            hair,
            view: gpu.view_buffer.clone(),
            guides: gpu.guides_buffer.clone(),
            hairs: gpu.hairs_buffer.clone(),
            vertices: gpu.vertices_buffer.clone(),
            invocations: gpu.vertex_capacity,
            bind_group: None,
            seen: true,
        });
    }
    jobs.0.retain(|job| job.seen);
}

fn prepare_bind_groups(
    mut jobs: ResMut<HairVertexJobs>,
    pipeline: Option<Res<HairVertexPipeline>>,
    cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
) {
    let Some(pipeline) = pipeline else {
        return;
    };
    for job in jobs.0.iter_mut().filter(|job| job.bind_group.is_none()) {
        let layout = cache.get_bind_group_layout(&pipeline.layout);
        job.bind_group = Some(device.create_bind_group(
            LABEL,
            &layout,
            &BindGroupEntries::sequential((
                job.view.as_entire_binding(),
                job.guides.as_entire_binding(),
                job.hairs.as_entire_binding(),
                job.vertices.as_entire_binding(),
            )),
        ));
    }
}

/// The pass: one dispatch per hair (nothing until the pipeline is
/// compiled; the draws then read zeroed vertices, degenerate ribbons).
fn write_render_vertices(
    mut context: RenderContext,
    jobs: Res<HairVertexJobs>,
    pipeline: Option<Res<HairVertexPipeline>>,
    cache: Res<PipelineCache>,
) {
    let Some(pipeline) = pipeline else {
        return;
    };
    let Some(compute) = cache.get_compute_pipeline(pipeline.id) else {
        return;
    };
    if jobs.0.is_empty() {
        return;
    }
    let mut pass = context
        .command_encoder()
        .begin_compute_pass(&ComputePassDescriptor {
            label: Some(LABEL),
            ..default()
        });
    pass.set_pipeline(compute);
    for job in &jobs.0 {
        let Some(bind_group) = &job.bind_group else {
            continue;
        };
        let (x, y) = dispatch_size(job.invocations as usize);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}
