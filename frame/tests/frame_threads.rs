//! The whole frame on threads: every parallel stage (the guides' step, the
//! ribbons' patches, the shadow-map build and
//! its bounds, the prepare pass, the background, the body's vertices and
//! its binned triangles, the hair's runs of tiles) gives the same bytes on
//! the serial executor, on rayon pools of 1, 2, 3 and 8 threads and on an
//! engine-style executor that runs the tasks backwards on two threads: the
//! PNG, the simulated positions, the ribbons, the shaded vertices and the
//! shadow map. Both scenes: the small sphere head with its ribbons, and
//! the default scene, Sintel on her bust with the demo's simulation (the
//! field, volume and friction through the hair grid, the gust).

mod common;

use coif_base::tasks::{Executor, Serial};
use coif_frame::{motion, FramePipeline, FrameSettings, HairScene, PrepareMode};
use std::sync::atomic::{AtomicUsize, Ordering};

/// An engine's job system as coif sees it: the indices handed out
/// backwards, odd ones to one worker and even ones to another, and the
/// number of `run` calls counted.
struct Backwards {
    runs: AtomicUsize,
}

// SAFETY: each index runs once, on one of two scoped threads joined
// before `run` returns.
unsafe impl Executor for Backwards {
    fn threads(&self) -> usize {
        2
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        self.runs.fetch_add(1, Ordering::Relaxed);
        std::thread::scope(|s| {
            for parity in 0..2 {
                s.spawn(move || {
                    for i in (0..count).rev().filter(|i| i % 2 == parity) {
                        task(i);
                    }
                });
            }
        });
    }
}

/// What one run of the frames produced, as bits.
#[derive(PartialEq, Debug)]
struct Frames {
    png: Vec<u8>,
    positions: Vec<[u32; 3]>,
    ribbons: Vec<[u32; 3]>,
    shaded: Vec<u32>,
    shadow: Vec<u32>,
}

fn bits(v: glam::Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// The scenes the frames run on.
#[derive(Clone, Copy, Debug)]
enum Scene {
    /// The small sphere head and its two ribbons.
    Sphere,
    /// Sintel on her bust, as the demo simulates her.
    Sintel,
}

/// Three frames of the turning head (0, 2 and 4 substeps) on `executor`.
fn run(scene: Scene, prepare: PrepareMode, executor: &dyn Executor) -> Frames {
    let mut p = match scene {
        Scene::Sphere => {
            let settings = FrameSettings {
                prepare,
                render_hairs_per_cm2: 20.0,
                ..FrameSettings::small(96)
            };
            let p = FramePipeline::new(&common::small_hair_scene(), settings, 0.05).unwrap();
            assert_eq!(p.ribbons().len(), 2, "two patches to step as tasks");
            p
        }
        Scene::Sintel => {
            let settings = FrameSettings {
                prepare,
                ..FrameSettings::small(128).with_body_simulation()
            };
            FramePipeline::new(&HairScene::sintel().unwrap(), settings, 0.05).unwrap()
        }
    };
    assert!(
        p.shadow_tasks() >= 2,
        "{scene:?}: the shadow build is split ({} tasks)",
        p.shadow_tasks()
    );
    let pivot = p.pivot();
    for (f, dt) in [0.01f32, 1.0 / 30.0, 1.0 / 15.0].into_iter().enumerate() {
        let pose = match scene {
            Scene::Sphere => motion::turn_and_nod(0.4 * f as f32, pivot),
            Scene::Sintel => {
                let t = 1.6 + 0.2 * f as f32;
                p.set_wind(motion::gust(t, motion::GUST_WIND));
                p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
                motion::turn(t, pivot)
            }
        };
        p.frame_with(dt, pose, executor);
    }
    if let Scene::Sintel = scene {
        assert!(p.stats().body_pixels > 1000, "{:?}", p.stats());
    }
    let path = std::env::temp_dir().join(format!(
        "coif_frame_threads_{}_{:?}.png",
        std::process::id(),
        std::thread::current().id()
    ));
    p.image().save_png(&path).unwrap();
    let png = std::fs::read(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let map = p.shadow_map().expect("shadows are on");
    let (n, layers) = (map.settings().resolution, map.settings().layers);
    let shadow = (0..n * n * layers)
        .map(|k| {
            map.stored_opacity(k % n, (k / n) % n, k / (n * n))
                .to_bits()
        })
        .collect();
    let shaded = p
        .shaded_vertices()
        .iter()
        .flat_map(|v| {
            v.position
                .into_iter()
                .chain(v.color)
                .chain([v.width, v.strand_parameter])
        })
        .map(f32::to_bits)
        .collect();
    Frames {
        png,
        positions: p.strands().positions().into_iter().map(bits).collect(),
        ribbons: (0..p.ribbons().len())
            .flat_map(|i| p.ribbons().blended(i).iter().copied().map(bits))
            .collect(),
        shaded,
        shadow,
    }
}

/// Every executor against the serial one, for both prepare passes.
fn same_bytes_on_every_executor(scene: Scene) {
    for prepare in [PrepareMode::Fused, PrepareMode::Reference] {
        let serial = run(scene, prepare, &Serial);
        assert!(
            serial.shadow.iter().any(|&b| f32::from_bits(b) > 0.1),
            "{scene:?} {prepare:?}: the map holds hair"
        );
        assert!(
            !serial.shaded.is_empty(),
            "{scene:?} {prepare:?}: hair was drawn"
        );
        let backwards = Backwards {
            runs: AtomicUsize::new(0),
        };
        let b = run(scene, prepare, &backwards);
        // Per frame at least: 1-4 steps, shadow depth and deposit, prepare
        // (fused), runs of tiles; 3 frames.
        assert!(
            backwards.runs.load(Ordering::Relaxed) >= 9,
            "{scene:?} {prepare:?}: the stages ran on the executor ({} runs)",
            backwards.runs.load(Ordering::Relaxed)
        );
        assert!(
            b == serial,
            "{scene:?} {prepare:?}: backwards on two threads differs"
        );
        for threads in [2, 3] {
            let workers = coif_base::tasks::Workers::new(threads).unwrap();
            let w = run(scene, prepare, &workers);
            assert!(
                w == serial,
                "{scene:?} {prepare:?}: workers {threads} differs"
            );
        }
        #[cfg(feature = "rayon")]
        for threads in [1, 2, 3, 8] {
            let pool = coif_base::tasks::Rayon::new(threads).unwrap();
            let r = run(scene, prepare, &pool);
            assert!(
                r == serial,
                "{scene:?} {prepare:?}: rayon {threads} differs"
            );
        }
    }
}

#[test]
fn every_executor_gives_the_same_bytes() {
    same_bytes_on_every_executor(Scene::Sphere);
}

#[test]
fn every_executor_gives_the_same_bytes_on_sintel() {
    same_bytes_on_every_executor(Scene::Sintel);
}
