//! Profiling harness for the prepare pass (LOD, shadow map, shading) of the
//! demo's default scene: settles it, runs `FRAMES` frames of the motion,
//! then `PREPARES` prepare passes on one thread, for callgrind instruction
//! counts per stage (or wall-clock time per stage).
//!
//! ```text
//! cargo run --release -p coif-frame --example prepare_profile -- [FRAMES] [PREPARES] [fused|reference] [K] [sphere|sintel]
//! valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*prepare_with*' \
//!     target/release/examples/prepare_profile 3 2
//! ```

use coif_base::tasks::Serial;
use coif_frame::{motion, FramePipeline, FrameSettings, HairScene, PrepareMode, ShadingModel};
use coif_geometry::scene::GrowOptions;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: usize| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let frames = arg(1, 3);
    let prepares = arg(2, 2);
    let prepare = match a.get(3).map(String::as_str) {
        Some("reference") => PrepareMode::Reference,
        _ => PrepareMode::Fused,
    };
    let thinning = arg(4, FrameSettings::default().shadow_thinning);
    // The sphere head (the default scene before Sintel, kept for the
    // figures measured on it), or Sintel with the demo's settings (pbrt
    // with dual scattering, 20 render hairs per cm^2).
    let sintel = a.get(5).is_some_and(|s| s == "sintel");
    let (scene, defaults) = if sintel {
        let settings = FrameSettings {
            shading: ShadingModel::Pbrt,
            render_hairs_per_cm2: 20.0,
            ..FrameSettings::default().with_body_simulation()
        };
        (HairScene::sintel().expect("Sintel's scene"), settings)
    } else {
        let scene = HairScene::procedural(&GrowOptions {
            strand_count: 2048,
            curl: 0.15,
            ..GrowOptions::default()
        })
        .expect("default scene");
        (scene, FrameSettings::default())
    };
    let settings = FrameSettings {
        prepare,
        shadow_thinning: thinning,
        ..defaults
    };
    let mut p = FramePipeline::new(&scene, settings, 1.5).expect("pipeline");
    let pivot = p.pivot();
    for f in 0..frames {
        p.simulate(1.0 / 30.0, motion::turn_and_nod(f as f32 / 30.0, pivot));
    }
    p.reset_timings();
    for _ in 0..prepares {
        p.prepare_with(&Serial);
    }
    let s = p.stats();
    println!(
        "{} hairs, {} vertices, {} segments per span",
        s.hairs, s.vertices, s.segments_per_span
    );
    println!("{}", p.timings());
    let checksum: f64 = p
        .shaded_vertices()
        .iter()
        .take(s.vertices)
        .map(|v| f64::from(v.color[0] + v.color[1] + v.color[2]))
        .sum();
    println!("colour sum {checksum:.6}");
    sample_stats(&p);
}

/// Splat samples per segment and rounds per group of eight segments of the
/// last frame's shadow map (the build's own sample count, recomputed).
fn sample_stats(p: &FramePipeline) {
    let Some(map) = p.shadow_map() else {
        return;
    };
    let (f, pl) = (map.frame(), map.placement());
    let verts = p.stats().vertices / p.stats().hairs.max(1);
    let pts: Vec<glam::Vec3> = p
        .shaded_vertices()
        .iter()
        .take(p.stats().vertices)
        .map(|v| glam::Vec3::from(v.position))
        .collect();
    let (mut samples, mut segs, mut rounds, mut groups) = (0usize, 0usize, 0usize, 0usize);
    let mut hist = [0usize; 8];
    for st in pts.chunks_exact(verts) {
        let ns: Vec<usize> = st
            .windows(2)
            .map(|w| {
                let d = f.to_light(w[1]) - f.to_light(w[0]);
                ((d.x * d.x + d.y * d.y).sqrt() * pl.inv_texel + 0.5)
                    .floor()
                    .max(1.0) as usize
            })
            .collect();
        for g in ns.chunks(8) {
            rounds += g.iter().max().copied().unwrap_or(0);
            groups += 1;
        }
        for n in &ns {
            hist[(*n).min(7)] += 1;
        }
        samples += ns.iter().sum::<usize>();
        segs += ns.len();
    }
    println!(
        "samples/segment {:.3}, rounds/group {:.3}, lane use {:.3}, histogram of n {:?}",
        samples as f64 / segs as f64,
        rounds as f64 / groups as f64,
        samples as f64 / (8 * rounds) as f64,
        hist
    );
}
