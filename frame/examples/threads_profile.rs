//! Sintel's frame (the default scene, as the demo runs it: 512 x 512,
//! every frame rendered) on one thread and on two, per stage, with what
//! this machine gives two threads at the same moment.
//!
//! Two pipelines run the same motion frame by frame, alternately: one on
//! the calling thread (`Serial`, as `coif --threads 1`), one on two
//! threads (`Workers::new(2)`, as `coif --threads 2`; with the word
//! `rayon` among the arguments, a rayon pool of two instead); after each
//! pair of frames, a multiply-add bound loop (twelve independent `f32x8`
//! chains, no memory) runs once on the calling thread and once as two
//! tasks on the same executor, so a slow spell of a shared
//! machine lands on both sides. Printed: per stage the median and the least time of each, their
//! ratios, and the loop's ratio (the most two threads can give SIMD code
//! on this machine just then), as a Markdown table.
//!
//! The motion (the head's turn, then the gust) loops every 3.2 s.
//!
//! With the word `simulate`, the simulation alone, and where its time
//! goes: inside the executor's runs (the tasks) and outside them (what it
//! leaves on the calling thread), the tasks' own time summed over the
//! threads, and the frame's first run apart.
//!
//! ```text
//! cargo run --release -p coif-frame --example threads_profile -- [FRAMES] [SIZE] [simulate] [rayon]
//! ```

use coif_base::tasks::{Executor, Serial, Workers};
use coif_frame::{motion, FramePipeline, FrameSettings, HairScene, ShadingModel, Stage};
use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};
use wide::f32x8;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: usize| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let frames = arg(1, 90);
    let size = arg(2, 512);
    let pool = two_threads(a.iter().any(|s| s == "rayon"));
    if a.iter().any(|s| s == "simulate") {
        return simulate_only(frames, size, &*pool);
    }
    let executors: [&dyn Executor; 2] = [&Serial, &*pool];
    let mut pipelines = two_pipelines(size);
    let pivot = pipelines[0].pivot();
    let dt = 1.0 / 30.0;
    let mut times: [Vec<[f64; ROWS]>; 2] = [Vec::new(), Vec::new()];
    let mut ceiling = Vec::new();
    let mut image = coif_render::RgbImage::new(size, size);
    for f in 0..frames {
        let t = (f as f32 * dt) % MOTION_SECONDS;
        for (k, p) in pipelines.iter_mut().enumerate() {
            p.set_wind(motion::gust(t, motion::GUST_WIND));
            p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
            p.reset_timings();
            p.frame_with(dt, motion::turn(t, pivot), executors[k]);
            let encode = Instant::now();
            p.encode_into_with(&mut image, executors[k]);
            let encode = encode.elapsed();
            let timings = p.timings();
            let mut row = [0.0; ROWS];
            for (r, stage) in STAGES.iter().enumerate() {
                row[r] = ms(timings.last(*stage));
            }
            row[ROWS - 1] = ms(encode);
            if f >= WARM_UP {
                times[k].push(row);
            }
        }
        if f >= WARM_UP {
            ceiling.push(fma_ratio(&*pool));
        }
    }
    assert!(
        pipelines[0].image().data == pipelines[1].image().data,
        "1 and 2 threads drew different pictures"
    );
    println!(
        "Sintel, {size} x {size}, {} frames (after {WARM_UP}), {} render hairs, {} vertices; \
         the same picture on both",
        frames.saturating_sub(WARM_UP),
        pipelines[0].stats().hairs,
        pipelines[0].stats().vertices
    );
    println!();
    println!("| stage | 1 thread (median / least), ms | 2 threads (median / least), ms | speed-up (medians / least) |");
    println!("|---|---|---|---|");
    for r in 0..ROWS {
        let column = |k: usize| times[k].iter().map(|row| row[r]).collect::<Vec<f64>>();
        let (one, two) = (column(0), column(1));
        let (m1, l1, m2, l2) = (median(&one), least(&one), median(&two), least(&two));
        println!(
            "| {} | {m1:.3} / {l1:.3} | {m2:.3} / {l2:.3} | {:.2}x / {:.2}x |",
            NAMES[r],
            m1 / m2,
            l1 / l2
        );
    }
    println!(
        "\nThe machine just then: a multiply-add loop (twelve f32x8 chains) on two threads ran \
         {:.2}x (median; least {:.2}x, most {:.2}x) its one-thread speed.",
        median(&ceiling),
        least(&ceiling),
        ceiling.iter().copied().fold(0.0, f64::max)
    );
}

/// Two pipelines of the default scene as the demo runs it, at `size` x
/// `size` pixels: pbrt with dual scattering, brown, 20 render hairs per
/// cm^2, the simulation of a character on a body.
fn two_pipelines(size: usize) -> [FramePipeline; 2] {
    let scene = HairScene::sintel().expect("the default scene");
    let settings = FrameSettings {
        width: size,
        height: size,
        shading: ShadingModel::Pbrt,
        render_hairs_per_cm2: 20.0,
        ..FrameSettings::default().with_body_simulation()
    };
    [(); 2].map(|_| FramePipeline::new(&scene, settings.clone(), 1.5).expect("pipeline"))
}

/// Two threads: `Workers`, or a rayon pool (feature `rayon`).
fn two_threads(rayon: bool) -> Box<dyn Executor> {
    #[cfg(feature = "rayon")]
    if rayon {
        return Box::new(coif_base::tasks::Rayon::new(2).expect("a rayon pool of two"));
    }
    if rayon {
        eprintln!("built without the rayon feature: Workers instead");
    }
    Box::new(Workers::new(2).expect("two threads"))
}

/// `frames` frames of simulation alone (no picture), alternately on one
/// thread and on two: the median and least simulate times, and the
/// median time inside the executor's runs (the tasks, the hand-out and
/// the wait for the last) and outside them (what the simulation leaves
/// on the calling thread), with the first run of each frame apart (on
/// two threads it pays for waking a worker that slept since its last
/// frame).
fn simulate_only(frames: usize, size: usize, pool: &dyn Executor) {
    let timed = [Timed::new(&Serial), Timed::new(pool)];
    let mut pipelines = two_pipelines(size);
    let pivot = pipelines[0].pivot();
    let dt = 1.0 / 30.0;
    let mut times: [Vec<[f64; 6]>; 2] = [Vec::new(), Vec::new()];
    for f in 0..frames {
        let t = (f as f32 * dt) % MOTION_SECONDS;
        for (k, p) in pipelines.iter_mut().enumerate() {
            p.set_wind(motion::gust(t, motion::GUST_WIND));
            p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
            timed[k].reset();
            let start = Instant::now();
            p.simulate_with(dt, motion::turn(t, pivot), &timed[k]);
            let total = ms(start.elapsed());
            let (runs, first, work, count) = timed[k].read();
            times[k].push([total, runs, total - runs, first, work, count]);
        }
    }
    let state = |p: &FramePipeline| -> Vec<[u32; 3]> {
        let positions = p.strands().positions_local();
        positions
            .iter()
            .map(|v| v.to_array().map(f32::to_bits))
            .collect()
    };
    assert!(
        state(&pipelines[0]) == state(&pipelines[1]),
        "1 and 2 threads simulated different states"
    );
    let column = |k: usize, c: usize| times[k].iter().map(|row| row[c]).collect::<Vec<f64>>();
    let (one, two) = (column(0, 0), column(1, 0));
    println!(
        "simulate, {frames} frames: 1 thread {:.3} / {:.3} ms, 2 threads {:.3} / {:.3} ms \
         (median / least): {:.2}x / {:.2}x; the same state on both",
        median(&one),
        least(&one),
        median(&two),
        least(&two),
        median(&one) / median(&two),
        least(&one) / least(&two)
    );
    println!();
    println!("| part of the simulation (median, ms) | 1 thread | 2 threads | speed-up |");
    println!("|---|---|---|---|");
    for (c, name) in [
        (1, "inside the executor's runs (tasks)"),
        (3, "  of which the frame's first run"),
        (2, "outside them (the calling thread alone)"),
        (4, "the tasks' own time, every thread's summed"),
        (5, "runs per frame"),
    ] {
        let (a, b) = (median(&column(0, c)), median(&column(1, c)));
        println!("| {name} | {a:.3} | {b:.3} | {:.2}x |", a / b);
    }
}

/// An executor that runs another's runs and times them: the time inside
/// `run` since the last `reset`, and the first run's alone.
struct Timed<'a> {
    inner: &'a dyn Executor,
    nanos: AtomicU64,
    first: AtomicU64,
    runs: AtomicU64,
    /// Time inside the tasks themselves, summed over threads.
    work: AtomicU64,
}

impl<'a> Timed<'a> {
    fn new(inner: &'a dyn Executor) -> Self {
        Timed {
            inner,
            nanos: AtomicU64::new(0),
            first: AtomicU64::new(0),
            runs: AtomicU64::new(0),
            work: AtomicU64::new(0),
        }
    }

    fn reset(&self) {
        self.nanos.store(0, Ordering::Relaxed);
        self.first.store(0, Ordering::Relaxed);
        self.runs.store(0, Ordering::Relaxed);
        self.work.store(0, Ordering::Relaxed);
    }

    /// Milliseconds inside runs, and inside the first run.
    fn read(&self) -> (f64, f64, f64, f64) {
        let ms = |a: &AtomicU64| a.load(Ordering::Relaxed) as f64 * 1e-6;
        (
            ms(&self.nanos),
            ms(&self.first),
            ms(&self.work),
            self.runs.load(Ordering::Relaxed) as f64,
        )
    }
}

// SAFETY: every run is the inner executor's, which keeps the contract.
unsafe impl Executor for Timed<'_> {
    fn threads(&self) -> usize {
        self.inner.threads()
    }

    fn wake(&self) {
        self.inner.wake();
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let start = Instant::now();
        self.inner.run(count, &|i| {
            let t = Instant::now();
            task(i);
            self.work
                .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        });
        let nanos = start.elapsed().as_nanos() as u64;
        self.nanos.fetch_add(nanos, Ordering::Relaxed);
        if self.runs.fetch_add(1, Ordering::Relaxed) == 0 {
            self.first.store(nanos, Ordering::Relaxed);
        }
    }
}

/// The demo's motion (the turn, then the gust), looped: the hair keeps
/// moving, as in the demo's first three seconds (still hair falls asleep
/// and its simulation costs next to nothing on any thread count).
const MOTION_SECONDS: f32 = 3.2;

/// Frames run before the times count (the motion's first frames settle).
const WARM_UP: usize = 5;

/// The stages timed, in frame order, and the encode after them.
const STAGES: [Stage; 11] = [
    Stage::Simulate,
    Stage::Prepare,
    Stage::Lod,
    Stage::Shadow,
    Stage::Shade,
    Stage::Raster,
    Stage::Head,
    Stage::Body,
    Stage::Sort,
    Stage::Hair,
    Stage::Frame,
];
const ROWS: usize = STAGES.len() + 1;
const NAMES: [&str; ROWS] = [
    "**simulate** (step with the field and the hair grid)",
    "**prepare**",
    "  LOD, cull, drawn groups",
    "  shadow map build",
    "  shade (interpolate, shade, shadow, colour per group)",
    "**raster**",
    "  background (and the head spheres, none on a body)",
    "  body (vertices, eyes, binned triangles)",
    "  sort strands",
    "  hair (project, bin, rasterise and blend tiles)",
    "**frame**",
    "encode (tone map, sRGB; after the frame)",
];

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(0.0)
}

fn least(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The same multiply-add work on the calling thread, then as two tasks on
/// `pool` (the pool the frames run on, so that its workers are not left
/// spinning beside other threads): the ratio of the times (2 when two
/// threads get two cores' worth of SIMD).
fn fma_ratio(pool: &dyn Executor) -> f64 {
    const STEPS: usize = 1_000_000;
    let chains = |steps: usize| {
        let mut acc = [f32x8::splat(1.0); 12];
        let (m, c) = (f32x8::splat(0.999_999), f32x8::splat(1e-7));
        for _ in 0..steps {
            for a in &mut acc {
                *a = a.mul_add(m, c);
            }
        }
        black_box(acc.iter().fold(f32x8::ZERO, |s, a| s + *a));
    };
    let start = Instant::now();
    chains(2 * STEPS);
    let one = start.elapsed();
    let start = Instant::now();
    pool.run(2, &|_| chains(STEPS));
    let two = start.elapsed();
    one.as_secs_f64() / two.as_secs_f64()
}
