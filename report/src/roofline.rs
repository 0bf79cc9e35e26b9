//! A roofline of the per-frame kernels, measured in one run: this
//! machine's floors (stream bandwidth and instruction throughput, timed by
//! the same program) beside each kernel's time per element in cache and
//! streaming from DRAM, and the ratio of the two.
//!
//! For every kernel, per element: the bytes it must move to or from
//! memory when its batch does not fit the caches (inputs read, outputs
//! written, counted from the code), and the instructions it retires
//! (counted with `valgrind --tool=callgrind` on the in-cache batch by
//! `report/roofline_count.sh`, which does not depend on the machine's
//! load; the counts are recorded in [`KERNELS`]). The floor of an element
//! is the larger of `bytes / bandwidth` and `instructions / rate`, where
//! the bandwidth is the measured copy bandwidth (in cache or from DRAM)
//! and the rate the measured instructions per nanosecond of a loop of
//! independent 8-lane loads and fused multiply-adds (the best mix the core
//! sustains; a kernel of divides, square roots and gathers cannot reach
//! it). A ratio of 1 means the kernel runs at that floor; the report asks
//! every per-frame kernel to be within 2x of it or to say why beside it.
//!
//! Adding a kernel is one [`Kernel`] entry: its name, element, bytes and
//! instructions per element, a note, and a function that builds a batch of
//! a given [`Size`] and returns the closure to time.

use super::timing::{time_batch, Timing};
use super::Options;
use coif::base::lanes::F32Lanes;
use coif::base::LANES;
use coif::geometry::scene::{grow_on_sphere, GrowOptions};
use coif::kernels::{self, Strands};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::shadow::{OpacityShadowMap, ShadowSettings};
use coif::shading::{marschner, pbrt, RgbBuffer, ShadingSamples};
use glam::Vec3;
use std::hint::black_box;

/// Which batch a kernel is timed on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Size {
    /// A batch whose data fits the core's L2 cache (about 100-300 KiB).
    Cache,
    /// A batch several times the last-level cache (32 MiB here): DRAM bound
    /// if the kernel is.
    Stream,
    /// Small batches for `--quick` (stream sizes shrunk: not DRAM bound).
    Quick,
}

/// A batch ready to time: `elements` per run of `run`.
pub struct Case {
    /// Elements one call of `run` processes.
    pub elements: usize,
    /// Runs the kernel once over the batch.
    pub run: Box<dyn FnMut()>,
}

/// One kernel of the roofline.
#[derive(Clone, Copy, Debug)]
pub struct Kernel {
    /// The row's name.
    pub name: &'static str,
    /// What one element is.
    pub element: &'static str,
    /// Bytes moved to or from memory per element when streaming (counted
    /// from the code: inputs read, outputs written, plus the write-allocate
    /// read of each written line).
    pub bytes: f64,
    /// Instructions retired per element (callgrind, in-cache batch,
    /// `report/roofline_count.sh`).
    pub instructions: f64,
    /// Why the kernel stands where it does (read beside the ratio).
    pub note: &'static str,
    /// Builds a batch of the given size.
    pub make: fn(Size) -> Case,
}

/// The machine's floors, measured by [`measure_floors`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floors {
    /// Read, write and copy bandwidth in bytes per nanosecond (GB/s) on a
    /// 256 KiB buffer (in cache).
    pub cache: [f64; 3],
    /// The same on 256 MiB buffers (from DRAM).
    pub dram: [f64; 3],
    /// Independent 8-lane fused multiply-adds per nanosecond.
    pub fma_x8_per_ns: f64,
    /// Instructions per nanosecond of the mixed loop (two 8-lane loads and
    /// four independent fused multiply-adds per iteration, from L1).
    pub instructions_per_ns: f64,
}

/// Instructions in one iteration of the mixed loop of [`measure_floors`]
/// (two loads, four FMAs, the index wrap and the bounds checks), counted
/// with callgrind by `report/roofline_count.sh`.
pub const MIXED_LOOP_INSTRUCTIONS: f64 = 18.0;

/// One kernel's measurement against the floors.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The kernel's name.
    pub name: &'static str,
    /// What one element is.
    pub element: &'static str,
    /// Bytes per element when streaming.
    pub bytes: f64,
    /// Instructions per element.
    pub instructions: f64,
    /// Nanoseconds per element on the in-cache batch.
    pub in_cache: Timing,
    /// Nanoseconds per element on the streaming batch.
    pub streaming: Timing,
    /// Floor in cache: `max(bytes / copy bandwidth in cache, instructions / rate)`.
    pub floor_cache: f64,
    /// Floor streaming: `max(bytes / DRAM copy bandwidth, instructions / rate)`.
    pub floor_stream: f64,
    /// The note.
    pub note: &'static str,
}

impl Measured {
    /// In-cache median over its floor.
    pub fn ratio_cache(&self) -> f64 {
        self.in_cache.median / self.floor_cache
    }

    /// Streaming median over its floor.
    pub fn ratio_stream(&self) -> f64 {
        self.streaming.median / self.floor_stream
    }
}

/// Times one f32 buffer pass `reps` times and returns bytes per ns.
fn bandwidth(reps: usize, bytes: usize, pass: impl FnMut()) -> f64 {
    let t = time_batch(reps, bytes, pass);
    // Fastest run: the floor is what the machine can do.
    1.0 / t.min
}

/// The floors: read, write and copy bandwidth in cache and from DRAM, and
/// the instruction throughput of independent FMAs and of the mixed loop.
pub fn measure_floors(options: Options) -> Floors {
    let reps = if options.quick { 3 } else { 9 };
    let level = |bytes: usize, reps: usize| -> [f64; 3] {
        let n = bytes / 4;
        let src = vec![1.0f32; n];
        let mut dst = vec![0.0f32; n];
        let read = bandwidth(reps, bytes, || {
            black_box(sum_simd(black_box(&src)));
        });
        let write = bandwidth(reps, bytes, || {
            fill(black_box(&mut dst), 2.0);
            black_box(&dst);
        });
        let copy = bandwidth(reps, 2 * bytes, || {
            dst.copy_from_slice(black_box(&src));
            black_box(&dst);
        });
        [read, write, copy]
    };
    let cache = level(256 << 10, reps * 50);
    let dram_bytes = if options.quick { 32 << 20 } else { 256 << 20 };
    let dram = level(dram_bytes, reps);
    let iters = 1 << 20;
    let fma = time_batch(reps, iters * 8 * 4, || {
        black_box(fma_loop(iters));
    });
    let buf = vec![1.0f32; 2048];
    let mixed = time_batch(reps * 4, iters, || {
        black_box(mixed_loop(black_box(&buf), iters));
    });
    Floors {
        cache,
        dram,
        fma_x8_per_ns: 1.0 / (fma.min * 8.0),
        instructions_per_ns: MIXED_LOOP_INSTRUCTIONS / mixed.min,
    }
}

/// Sum of a buffer, eight independent accumulators of a block's lanes (a
/// read stream).
#[inline(never)]
fn sum_simd(a: &[f32]) -> f32 {
    let mut acc = [F32Lanes::ZERO; 8];
    let chunks = a.chunks_exact(8 * LANES);
    for c in chunks {
        for (k, acc) in acc.iter_mut().enumerate() {
            let v: [f32; LANES] = c[LANES * k..LANES * (k + 1)].try_into().expect("a block");
            *acc += F32Lanes::new(v);
        }
    }
    acc.iter().fold(F32Lanes::ZERO, |s, a| s + *a).reduce_add()
}

/// Fills a buffer (a write stream).
#[inline(never)]
fn fill(a: &mut [f32], v: f32) {
    a.fill(v);
}

/// `iters` rounds of eight independent chains of four 8-lane FMAs each
/// (32 FMAs per round, enough chains to cover the FMA latency).
#[inline(never)]
fn fma_loop(iters: usize) -> f32 {
    let (a, b) = (
        black_box(F32Lanes::splat(0.999)),
        black_box(F32Lanes::splat(1e-3)),
    );
    let mut acc = [F32Lanes::ONE; 8];
    for _ in 0..iters {
        for _ in 0..4 {
            for x in acc.iter_mut() {
                *x = x.mul_add(a, b);
            }
        }
    }
    acc.iter().fold(F32Lanes::ZERO, |s, a| s + *a).reduce_add()
}

/// `iters` iterations of two 8-lane loads from an L1-resident buffer and
/// four independent FMAs: a kernel's best instruction mix.
#[inline(never)]
fn mixed_loop(buf: &[f32], iters: usize) -> f32 {
    let blocks = buf.len() / 16;
    let mut acc = [F32Lanes::ZERO; 4];
    let mut k = 0;
    for _ in 0..iters {
        let s = &buf[16 * k..16 * k + 16];
        let x = F32Lanes::new(s[..8].try_into().expect("8"));
        let y = F32Lanes::new(s[8..].try_into().expect("8"));
        acc[0] = x.mul_add(y, acc[0]);
        acc[1] = y.mul_add(x, acc[1]);
        acc[2] = x.mul_add(x, acc[2]);
        acc[3] = y.mul_add(y, acc[3]);
        k += 1;
        if k == blocks {
            k = 0;
        }
    }
    acc.iter().fold(F32Lanes::ZERO, |s, a| s + *a).reduce_add()
}

/// Times every kernel of `kernels` in cache and streaming against `floors`.
pub fn measure(options: Options, floors: &Floors, kernels: &[Kernel]) -> Vec<Measured> {
    let reps = options.reps();
    kernels
        .iter()
        .map(|k| {
            let (cache_size, stream_size) = if options.quick {
                (Size::Cache, Size::Quick)
            } else {
                (Size::Cache, Size::Stream)
            };
            let mut c = (k.make)(cache_size);
            let in_cache = time_batch(reps * 4, c.elements, &mut c.run);
            drop(c);
            let mut s = (k.make)(stream_size);
            let streaming = time_batch(reps, s.elements, &mut s.run);
            drop(s);
            let compute = k.instructions / floors.instructions_per_ns;
            Measured {
                name: k.name,
                element: k.element,
                bytes: k.bytes,
                instructions: k.instructions,
                in_cache,
                streaming,
                floor_cache: compute.max(k.bytes / floors.cache[2]),
                floor_stream: compute.max(k.bytes / floors.dram[2]),
                note: k.note,
            }
        })
        .collect()
}

/// The roofline as a Markdown section: the floors, then one table row per
/// kernel.
pub fn to_markdown(floors: &Floors, rows: &[Measured]) -> String {
    let mut s = String::new();
    s += "## Roofline\n\n";
    s += "Floors of this machine, measured in the same run (one core; fastest of the runs):\n\n";
    s += "| floor | in cache (256 KiB) | DRAM |\n|---|---|---|\n";
    for (k, name) in ["read", "write", "copy (read + write)"].iter().enumerate() {
        s += &format!(
            "| {name} bandwidth | {:.1} GB/s | {:.1} GB/s |\n",
            floors.cache[k], floors.dram[k]
        );
    }
    s += &format!(
        "| independent 8-lane FMAs | {:.2} per ns | |\n| mixed loop (2 loads + 4 FMAs) | {:.2} instructions per ns | |\n\n",
        floors.fma_x8_per_ns, floors.instructions_per_ns
    );
    s += "Per element: bytes moved when streaming (from the code), instructions \
          (callgrind, in cache), floor = max(bytes / copy bandwidth, instructions / mixed-loop rate), \
          time = median ns (fastest-slowest), ratio = time / floor.\n\n";
    s += "| kernel | element | bytes | instructions | floor cache / DRAM (ns) | in cache (ns) | ratio | streaming (ns) | ratio | why |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        s += &format!(
            "| {} | {} | {:.0} | {:.0} | {} / {} | {} ({}-{}) | {:.1} | {} ({}-{}) | {:.1} | {} |\n",
            r.name,
            r.element,
            r.bytes,
            r.instructions,
            sig(r.floor_cache),
            sig(r.floor_stream),
            sig(r.in_cache.median),
            sig(r.in_cache.min),
            sig(r.in_cache.max),
            r.ratio_cache(),
            sig(r.streaming.median),
            sig(r.streaming.min),
            sig(r.streaming.max),
            r.ratio_stream(),
            r.note
        );
    }
    s
}

/// Three significant digits.
fn sig(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else if x >= 1.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.3}")
    }
}

// --- The kernels ------------------------------------------------------------

/// Random unit (t, wi, wo) samples.
fn samples(n: usize, seed: u64) -> ShadingSamples {
    let mut rng = coif::base::SplitMix64::new(seed);
    let mut s = ShadingSamples::with_capacity(n);
    for _ in 0..n {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    s
}

/// Samples per batch: 2048 in cache (96 KiB in and out), 4 Mi streaming
/// (192 MiB), 64 Ki in quick mode.
fn shading_count(size: Size) -> usize {
    match size {
        Size::Cache => 2048,
        Size::Stream => 4 << 20,
        Size::Quick => 64 << 10,
    }
}

/// A shading batch of random samples timed with `shade` into a caller-owned
/// buffer.
fn shading_case(
    size: Size,
    seed: u64,
    mut shade: impl FnMut(&ShadingSamples, &mut RgbBuffer) + 'static,
) -> Case {
    let s = samples(shading_count(size), seed);
    let mut out = RgbBuffer::zeros(s.len());
    Case {
        elements: s.len(),
        run: Box::new(move || {
            shade(black_box(&s), &mut out);
            black_box(&out);
        }),
    }
}

fn kajiya_kay_case(size: Size) -> Case {
    let kk = KajiyaKay::default();
    shading_case(size, 1, move |s, out| kk.shade_batch(s, out))
}

fn marschner_case(size: Size) -> Case {
    let lut = marschner::Lut::new(&marschner::Params::default(), 128);
    shading_case(size, 2, move |s, out| lut.scattering_batch(s, out))
}

fn pbrt_case(size: Size) -> Case {
    let table = pbrt::Table::new(&pbrt::Params::default(), 64).expect("default table");
    shading_case(size, 3, move |s, out| table.scattering_batch(s, out))
}

/// Draped-like hair on a sphere head (grown, curled), `copies` copies side
/// by side for the streaming sets: (points, vertices per strand).
fn hair(strands: usize, copies: usize) -> (Vec<Vec3>, usize) {
    let g = grow_on_sphere(&GrowOptions {
        strand_count: strands,
        verts_per_strand: 32,
        curl: 0.15,
        ..Default::default()
    });
    let mut pts = Vec::with_capacity(g.points.len() * copies);
    for c in 0..copies {
        let shift = Vec3::new(0.4 * c as f32, 0.0, 0.0);
        pts.extend(g.points.iter().map(|p| *p + shift));
    }
    (pts, g.verts_per_strand)
}

/// Strands per hair set: 512 x 32 in cache (the map and 192 KiB of
/// points), the demo's 27,000 render hairs x 32 times 4 copies streaming.
fn hair_size(size: Size) -> (usize, usize) {
    match size {
        Size::Cache => (512, 1),
        Size::Stream => (27_000, 4),
        Size::Quick => (4096, 1),
    }
}

/// The frame's shadow map: deep, 3 layers, 128^2.
fn frame_shadow_settings() -> ShadowSettings {
    ShadowSettings {
        resolution: 128,
        hair_radius: 0.0004,
        ..ShadowSettings::deep()
    }
}

fn light() -> Vec3 {
    Vec3::new(1.0, -0.5, 0.3).normalize()
}

fn shadow_build_case(size: Size) -> Case {
    let (strands, copies) = hair_size(size);
    let (pts, verts) = hair(strands, copies);
    let mut map = OpacityShadowMap::new(frame_shadow_settings()).expect("valid settings");
    Case {
        elements: pts.len() / verts * (verts - 1),
        run: Box::new(move || {
            map.build(light(), black_box(&pts), verts);
            black_box(&map);
        }),
    }
}

fn shadow_lookup_case(size: Size) -> Case {
    let (strands, copies) = hair_size(size);
    let (pts, verts) = hair(strands, copies);
    let mut map = OpacityShadowMap::new(frame_shadow_settings()).expect("valid settings");
    map.build(light(), &pts, verts);
    let mut out = vec![0.0f32; pts.len()];
    Case {
        elements: pts.len(),
        run: Box::new(move || {
            map.transmittance_batch(black_box(&pts), &mut out).unwrap();
            black_box(&out);
        }),
    }
}

fn step_case(size: Size) -> Case {
    let strands = match size {
        Size::Cache => 64,
        Size::Stream => 32_768,
        Size::Quick => 2048,
    };
    let g = grow_on_sphere(&GrowOptions {
        strand_count: strands,
        verts_per_strand: 32,
        ..Default::default()
    });
    let mut s = Strands::from_polylines(&g.points, g.verts_per_strand).expect("grown hair");
    let params = kernels::SimParams::default();
    let rig = [g.head];
    Case {
        elements: g.points.len(),
        run: Box::new(move || {
            kernels::step(&mut s, &params, &rig);
            black_box(&s);
        }),
    }
}

fn patch_case(size: Size) -> Case {
    use coif::kernels::patch::{self, quality, Patch};
    // 16 x 32 particles per patch: one in cache, 4096 (about 100 MiB of
    // state) streaming.
    let count = match size {
        Size::Cache => 1,
        Size::Stream => 4096,
        Size::Quick => 64,
    };
    let (points, pinned) = quality::flag_scene(16, 32);
    let one = Patch::new(&points, 16, 32, &pinned).expect("valid flag");
    let mut patches = vec![one; count];
    let params = kernels::SimParams::default();
    let rig = [coif::kernels::Sphere {
        center: Vec3::new(0.32, 0.8, 0.0),
        radius: 0.1,
    }];
    Case {
        elements: count * 16 * 32,
        run: Box::new(move || {
            for p in patches.iter_mut() {
                patch::step(p, &params, &rig);
            }
            black_box(&patches);
        }),
    }
}

/// The built-in head after one frame of the pipeline (shadows and shading
/// on): guides, interpolation, render vertices, colours and camera.
struct FrameScene {
    pipeline: coif::frame::FramePipeline,
    interp: coif::lod::Interpolation,
}

fn frame_scene(strand_count: usize) -> FrameScene {
    frame_scene_at(strand_count, coif::frame::FrameSettings::default())
}

/// [`frame_scene`] with other frame settings.
fn frame_scene_at(strand_count: usize, settings: coif::frame::FrameSettings) -> FrameScene {
    use coif::frame::{FramePipeline, HairScene};
    let scene = HairScene::procedural(&GrowOptions {
        strand_count,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .expect("built-in head");
    let roots: Vec<Vec3> = scene.roots().collect();
    let interp = coif::lod::Interpolation::new(
        &roots,
        &scene.triangles,
        settings.render_hairs_per_cm2,
        settings.seed,
    )
    .expect("default interpolation");
    let mut pipeline = FramePipeline::new(&scene, settings, 0.0).expect("default pipeline");
    pipeline.frame(0.0, glam::Affine3A::IDENTITY);
    FrameScene { pipeline, interp }
}

/// Guides of the built-in head, every render hair at the default density:
/// 16 guides in cache (about 200 hairs, 200 KiB of output), the demo's 2048
/// streaming (about 27,000 hairs, 27 MiB of output).
fn lod_case(size: Size) -> Case {
    use coif::lod::{self, RefinedGuides, RenderHairs};
    let guides = match size {
        Size::Cache => 16,
        Size::Stream => 2048,
        Size::Quick => 512,
    };
    let FrameScene { pipeline, interp } = frame_scene(guides);
    let strands = pipeline.strands().clone();
    let segments = pipeline.settings().max_segments_per_span;
    let mut refined = RefinedGuides::new(strands.blocks(), segments).expect("refinable guides");
    lod::refine_strands(strands.blocks(), None, &mut refined).unwrap();
    let mut hairs = RenderHairs::new(&interp, &refined);
    let verts = refined.verts_per_strand();
    let groups = interp.group_count();
    let written = lod::interpolate(&interp, &refined, None, groups, &mut hairs).unwrap();
    let out_verts = written.max(1) * LANES * verts;
    Case {
        elements: out_verts,
        run: Box::new(move || {
            lod::refine_strands(strands.blocks(), None, &mut refined).unwrap();
            lod::interpolate(&interp, &refined, None, groups, &mut hairs).unwrap();
            black_box(&hairs);
        }),
    }
}

/// The render hairs of the built-in head at 512 x 512 after one frame,
/// sorted back to front: 512 hairs in cache, every hair (about 27,000)
/// streaming.
struct RasterInput {
    camera: coif::render::Camera,
    vertices: Vec<coif::render::ShadedVertex>,
    verts: usize,
    order: coif::render::sort::DepthOrder,
    frame: coif::render::Framebuffer,
    opacity: f32,
}

fn raster_input(size: Size) -> RasterInput {
    use coif::render::{sort::DepthOrder, Framebuffer};
    let guides = if size == Size::Quick { 512 } else { 2048 };
    let FrameScene { pipeline, .. } = frame_scene(guides);
    let (_, verts) = pipeline.render_vertices();
    let all = pipeline.shaded_vertices();
    let hairs = match size {
        Size::Cache => 512.min(all.len() / verts),
        _ => all.len() / verts,
    };
    let vertices = all[..hairs * verts].to_vec();
    let camera = pipeline
        .camera()
        .shifted(pipeline.strands().origin().as_vec3());
    let mut order = DepthOrder::with_capacity(hairs);
    order.sort(&camera, &vertices, verts);
    let settings = pipeline.settings();
    RasterInput {
        camera,
        vertices,
        verts,
        order,
        frame: Framebuffer::new(settings.width, settings.height),
        opacity: settings.hair_opacity,
    }
}

/// `draw_strands` (the direct reference) over [`raster_input`].
fn raster_case(size: Size) -> Case {
    let mut r = raster_input(size);
    Case {
        elements: r.order.len() * (r.verts - 1),
        run: Box::new(move || {
            r.frame.clear_gradient(Vec3::ZERO, Vec3::ONE);
            black_box(coif::render::hair::draw_shaded(
                &mut r.frame,
                &r.camera,
                &r.vertices,
                r.verts,
                &r.order,
                r.opacity,
            ));
        }),
    }
}

/// The frame's binned rasteriser (`HairRaster::draw`, SIMD, on the calling
/// thread) over [`raster_input`].
fn binned_raster_case(size: Size) -> Case {
    use coif::base::tasks::Serial;
    use coif::render::raster::HairRaster;
    let mut r = raster_input(size);
    let (w, h) = (r.frame.width(), r.frame.height());
    let mut raster = HairRaster::new(w, h, r.vertices.len()).expect("raster buffers");
    Case {
        elements: r.order.len() * (r.verts - 1),
        run: Box::new(move || {
            r.frame.clear_gradient(Vec3::ZERO, Vec3::ONE);
            black_box(raster.draw(
                &mut r.frame,
                &r.camera,
                &r.vertices,
                r.verts,
                &r.order,
                r.opacity,
                &Serial,
            ));
        }),
    }
}

/// The frame's fused prepare pass (`FramePipeline::prepare_with` on the
/// calling thread: LOD set-up, shadow map, then refine, interpolate, shadow
/// lookup and shade per group of hairs into the shaded vertices), per
/// shaded vertex, on the demo's density (40 hairs per cm^2, about 848,000
/// shaded vertices, 27 MiB: the output always streams; each group's work
/// is in cache by design): 256 guides as "in cache" (their refined
/// positions, 1.5 MiB, fit L2 and L3), the demo's 2048 streaming.
fn prepare_case(size: Size) -> Case {
    use coif::base::tasks::Serial;
    let settings = coif::frame::FrameSettings::default();
    let guides = match size {
        Size::Stream => 2048,
        _ => 256,
    };
    let FrameScene { mut pipeline, .. } = frame_scene_at(guides, settings);
    pipeline.prepare_with(&Serial);
    let elements = pipeline.shaded_vertices().len().max(1);
    Case {
        elements,
        run: Box::new(move || {
            pipeline.prepare_with(&Serial);
            black_box(pipeline.shaded_vertices());
        }),
    }
}

/// Every hot kernel of a frame that the roofline times.
pub const KERNELS: &[Kernel] = &[
    Kernel {
        name: "strand step (defaults, 4 substeps)",
        element: "vertex-step",
        bytes: 112.0,
        instructions: 176.3,
        note: "4 substeps of about 44 instructions per vertex (FMA; the tridiagonal solve 18, collisions 29): latency bound, not compute bound: every stage is a root-to-tip sweep where vertex v waits for v - 1 and one block of 8 strands is in flight (kernels/README.md; two blocks per sweep spilled registers and measured 6-10 % slower)",
        make: step_case,
    },
    Kernel {
        name: "patch step (16 x 32, defaults)",
        element: "particle-step",
        bytes: 100.0,
        instructions: 154.4,
        note: "one patch is small by nature (a ribbon, 16 KiB); the streaming batch (4,096 patches) only shows what a crowd of patches would cost",
        make: patch_case,
    },
    Kernel {
        name: "lod refine + interpolate",
        element: "output vertex",
        bytes: 64.0,
        instructions: 9.2,
        note: "a weighted sum of three refined guide vertices per output vertex: store bound, 32 B written (plus the write-allocate read) per output vertex",
        make: lod_case,
    },
    Kernel {
        name: "Kajiya-Kay",
        element: "sample",
        bytes: 60.0,
        instructions: 43.6,
        note: "about 44 instructions per sample (two powers as log2/exp2 series, four square roots, three divisions; one-instruction min/max): the 1 ns goal needs under 15 and is not met with this model",
        make: kajiya_kay_case,
    },
    Kernel {
        name: "Marschner Lut 128",
        element: "sample",
        bytes: 60.0,
        instructions: 169.0,
        note: "two asin and one acos, then two bilinear fetches per lane in scalar code (16 texel loads of 16-32 B per sample: no gather instruction used)",
        make: marschner_case,
    },
    Kernel {
        name: "pbrt table 64",
        element: "sample",
        bytes: 60.0,
        instructions: 217.0,
        note: "three acos, then per-lane bilinear fetches of 4 corners x 3 vectors of 8 channels",
        make: pbrt_case,
    },
    Kernel {
        name: "shadow build (deep 3, 128^2)",
        element: "segment",
        bytes: 24.0,
        instructions: 263.9,
        note: "deep maps rasterise twice (first depth, then deposits), about one sample per texel of projected length (round, not ceil: 328.6 instructions before); each sample's four deposits are scalar read-modify-writes at scattered texels (a scatter: no SIMD store), and neighbouring hairs in the eight lanes hit the same texels; the map (256 KiB) stays in cache; index clamps instead of bounds checks",
        make: shadow_build_case,
    },
    Kernel {
        name: "shadow lookup (deep 3, 128^2)",
        element: "vertex",
        bytes: 20.0,
        instructions: 101.9,
        note: "per lane 4 texel loads (16 B: three opacity planes and the first depth in the fourth) transposed into plane vectors, planes picked by selects; no vector sqrt or division; one exp (an AVX2 gather measured slower here)",
        make: shadow_lookup_case,
    },
    Kernel {
        name: "hair raster (draw_strands, 512^2)",
        element: "segment",
        bytes: 44.0,
        instructions: 950.7,
        note: "the direct reference: one segment at a time over the whole frame (set-up, row spans, coverage and blend per pixel, about 12 candidate pixels for 5 covered); kept as the bit-for-bit yardstick of the binned rasteriser below",
        make: raster_case,
    },
    Kernel {
        name: "hair raster (binned SIMD, 512^2)",
        element: "segment",
        bytes: 160.0,
        instructions: 558.1,
        note: "the frame's rasteriser: projection (read 32 B, write 28 B screen vertex and 16 B planes per vertex), tile ranges and binning (rects written once, read twice; 1.12 list entries of 4 B at 64 x 64 tiles), then eight segments per register, each lane walking its own segment's candidate band, fragments blended in list order into one 16-byte slot per pixel (about 5 per tile entry): latency bound; same bits as the reference",
        make: binned_raster_case,
    },
    Kernel {
        name: "fused prepare (LOD, shadow map, shade)",
        element: "shaded vertex",
        bytes: 64.0,
        instructions: 396.8,
        note: "per shaded vertex: the shadow-map build of about one segment (two rasterisations of the deep map, scalar deposits), then refine, interpolate, shadow lookup (about 100) and Kajiya-Kay (about 40) in registers, both skipped for rows in the head's shadow, one 32 B write: compute and scatter bound, far from the 12 ms goal (439.6 instructions before the build's round and the skip)",
        make: prepare_case,
    },
];

/// Runs the kernel named `name` on its in-cache batch `reps` times inside
/// [`counted_region`] (for callgrind: `roofline_count.sh`). Returns the
/// elements per run, or `None` for an unknown name.
pub fn run_for_count(name: &str, reps: usize) -> Option<usize> {
    let k = KERNELS.iter().find(|k| k.name == name)?;
    let mut c = (k.make)(Size::Cache);
    (c.run)();
    counted_region(&mut c.run, reps);
    Some(c.elements)
}

/// The in-cache time per element of the kernel named `name` over `reps`
/// runs, or `None` for an unknown name.
pub fn time_in_cache(name: &str, reps: usize) -> Option<Timing> {
    let k = KERNELS.iter().find(|k| k.name == name)?;
    let mut c = (k.make)(Size::Cache);
    Some(time_batch(reps, c.elements, &mut c.run))
}

/// The region callgrind counts (`--toggle-collect=*counted_region*`).
#[inline(never)]
pub fn counted_region(run: &mut dyn FnMut(), reps: usize) {
    for _ in 0..reps {
        run();
    }
}

/// Runs the mixed loop of [`measure_floors`] inside a counted region (to
/// check [`MIXED_LOOP_INSTRUCTIONS`]).
pub fn mixed_loop_for_count(iters: usize) {
    let buf = vec![1.0f32; 2048];
    let mut run = || {
        black_box(mixed_loop(black_box(&buf), iters));
    };
    counted_region(&mut run, 1);
}
