//! The GPU twin: the compute entry point (`shaders::COMPUTE_WGSL`) on a
//! real adapter against coif-lod's CPU kernels (`refine_strands`,
//! `interpolate`, `write_render_vertices`), as each SIMD kernel is checked
//! against its scalar twin. Sintel's groom after 60 steps of her head turn,
//! at two levels (1 and 4 segments per span) and two render-hair counts
//! (every group, and a quarter of them), every render vertex compared.
//!
//! Tolerances: positions 1e-5 m (what the issue allows; measured: the
//! largest difference is printed: 4.5e-8 m on lavapipe); unit tangents 3e-5
//! (measured 8.9e-6: a tangent is a normalised difference, so it loses the
//! digits its short derivatives lack); the parameter along
//! the hair exactly; widths 1e-6 relative. Where they differ, it is the
//! GPU's own rounding: WGSL lets `fma` and `inverseSqrt` round differently
//! from the CPU's fused multiply-add and its rsqrt plus Newton step.
//!
//! Without an adapter (no Vulkan driver) the test says so and passes; CI
//! installs Mesa's lavapipe (.ci/run).

use coif_frame::style::StyleScene;
use coif_gpu::shaders::{dispatch_size, COMPUTE_WGSL};
use coif_gpu::{pack_guides, pack_hairs, render_hair_count, GuideVertex, HairView, RenderHair};
use coif_kernels::{step_colliders, Colliders, SimParams, Strands};
use coif_lod::{
    interpolate, refine_strands, write_render_vertices, HairWidth, Interpolation, RefinedGuides,
    RenderHairs, RenderVertex,
};
use glam::Vec3;
use wgpu::util::DeviceExt;

const POSITION_TOLERANCE: f32 = 1e-5;
const TANGENT_TOLERANCE: f32 = 3e-5;

fn device() -> Option<(wgpu::Device, wgpu::Queue, String)> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter =
        futures_lite::future::block_on(instance.request_adapter(&Default::default())).ok()?;
    let name = adapter.get_info().name;
    let (device, queue) =
        futures_lite::future::block_on(adapter.request_device(&Default::default())).ok()?;
    Some((device, queue, name))
}

/// Sintel's strands after 60 steps of the head turn (the style scene's
/// turn, default parameters at the scene's stiffness, her bust's field).
fn sintel_after_turn() -> (StyleScene, Strands) {
    let scene = StyleScene::sintel().expect("Sintel's scene");
    let mut strands = scene.strands().expect("strands");
    let params = SimParams {
        local_shape_stiffness: coif_frame::style::SCENE_STIFFNESS,
        ..SimParams::default()
    };
    let mut field = scene.field.clone();
    {
        let colliders = Colliders {
            sdfs: field.as_slice(),
            ..Colliders::default()
        };
        strands.solve_sag_free(&params, &colliders).expect("rest");
    }
    for i in 0..60 {
        let pose = scene.pose((i + 1) as f32 * params.dt);
        strands.set_head_pose(pose).expect("pose");
        if let Some(f) = field.as_mut() {
            f.set_transform(pose).expect("field pose");
        }
        let colliders = Colliders {
            sdfs: field.as_slice(),
            ..Colliders::default()
        };
        step_colliders(&mut strands, &params, &colliders);
    }
    (scene, strands)
}

struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pipeline: wgpu::ComputePipeline,
}

impl Gpu {
    fn new(device: wgpu::Device, queue: wgpu::Queue) -> Gpu {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("coif-gpu compute"),
            source: wgpu::ShaderSource::Wgsl(COMPUTE_WGSL.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("write_render_vertices"),
            layout: None,
            module: &module,
            entry_point: Some("write_render_vertices"),
            compilation_options: Default::default(),
            cache: None,
        });
        Gpu {
            device,
            queue,
            pipeline,
        }
    }

    /// Runs the compute entry point; returns the render vertices.
    fn run(
        &self,
        view: &HairView,
        guides: &[GuideVertex],
        hairs: &[RenderHair],
    ) -> Vec<RenderVertex> {
        let count = view.hairs as usize * view.verts_per_hair as usize;
        let size = (count.max(1) * std::mem::size_of::<RenderVertex>()) as u64;
        let d = &self.device;
        let uniform = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("view"),
            contents: bytemuck::bytes_of(view),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let guides = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("guides"),
            contents: bytemuck::cast_slice(guides),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let hairs = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("hairs"),
            contents: bytemuck::cast_slice(hairs),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let out = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("vertices"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: guides.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: hairs.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        let mut encoder = d.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            let (x, y) = dispatch_size(count);
            pass.dispatch_workgroups(x, y, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, size);
        self.queue.submit([encoder.finish()]);
        let slice = read.slice(..);
        slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        d.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
        let bytes = slice.get_mapped_range();
        bytemuck::cast_slice::<u8, RenderVertex>(&bytes)[..count].to_vec()
    }
}

#[test]
fn compute_entry_point_matches_the_cpu_kernels_on_sintel() {
    let Some((device, queue, name)) = device() else {
        eprintln!(
            "no GPU adapter (install mesa-vulkan-drivers for lavapipe): the GPU twin is skipped"
        );
        return;
    };
    eprintln!("GPU twin on {name}");
    let gpu = Gpu::new(device, queue);
    let (scene, strands) = sintel_after_turn();
    let v = scene.verts;
    let roots: Vec<Vec3> = scene.guides.iter().step_by(v).copied().collect();
    let triangles = coif_geometry::triangulate::scalp_triangles(
        &roots,
        coif_geometry::scene::fit_sphere(&roots)
            .expect("a head")
            .center,
    );
    let interpolation = Interpolation::new(&roots, &triangles, 20.0, 7).expect("interpolation");
    let mut guides = vec![GuideVertex::default(); strands.strand_count() * v];
    pack_guides(strands.blocks(), &mut guides).expect("guides");
    let mut hairs = vec![RenderHair::default(); interpolation.hair_count()];
    pack_hairs(&interpolation, &mut hairs).expect("hairs");
    let width = HairWidth::default();
    let mut refined = RefinedGuides::new(strands.blocks(), 4).expect("refined");
    let mut cpu_hairs = RenderHairs::new(&interpolation, &refined);
    let mut cpu =
        vec![RenderVertex::default(); interpolation.hair_count() * coif_lod::refined_len(v, 4)];
    let mut checked = 0;
    for segments in [1, 4] {
        for groups in [interpolation.group_count(), interpolation.group_count() / 4] {
            refined.set_segments_per_span(segments).expect("level");
            refine_strands(strands.blocks(), None, &mut refined).expect("refine");
            interpolate(&interpolation, &refined, None, groups, &mut cpu_hairs)
                .expect("interpolate");
            let width_factor = if groups == interpolation.group_count() {
                1.0
            } else {
                1.7
            };
            let n = write_render_vertices(
                &interpolation,
                &cpu_hairs,
                groups,
                width,
                width_factor,
                &mut cpu,
            )
            .expect("render vertices");
            let mut view = HairView {
                root_width: width.root,
                tip_width: width.tip,
                width_factor,
                ..HairView::default()
            };
            view.set_level(v, segments, render_hair_count(&interpolation, groups));
            let gpu_vertices = gpu.run(&view, &guides, &hairs);
            assert_eq!(
                gpu_vertices.len(),
                n,
                "vertex count at N = {segments}, {groups} groups"
            );
            let (mut dp, mut dt) = (0f32, 0f32);
            for (i, (g, c)) in gpu_vertices.iter().zip(&cpu[..n]).enumerate() {
                let p = Vec3::from(g.position).distance(Vec3::from(c.position));
                let t = Vec3::from(g.tangent).distance(Vec3::from(c.tangent));
                assert!(
                    p <= POSITION_TOLERANCE && t <= TANGENT_TOLERANCE,
                    "vertex {i} (N = {segments}, {groups} groups): GPU {g:?}, CPU {c:?}"
                );
                assert_eq!(g.strand_parameter, c.strand_parameter, "vertex {i}: s");
                assert!(
                    (g.width - c.width).abs() <= 1e-6 * c.width.abs(),
                    "vertex {i}: width"
                );
                dp = dp.max(p);
                dt = dt.max(t);
            }
            eprintln!(
                "N = {segments}, {groups} groups: {n} render vertices, largest difference: position {dp:.2e} m, tangent {dt:.2e}"
            );
            checked += n;
        }
    }
    assert!(checked > 1_000_000, "a real check: {checked} vertices");
}
