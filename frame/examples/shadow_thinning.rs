//! The error of the fused pass's thinned shadow map against the exact
//! reference, for thinning k = 1 (every hair, the reference pipeline's
//! map) to 32: `cargo run --release -p coif-frame --example shadow_thinning
//! [HAIRS_SAMPLED] [FRAMES] [PER_HAIR_CSV]`.
//!
//! The default scene (built-in head, 512 x 512, 40 render hairs per cm^2)
//! after `FRAMES` (30) frames of the motion; the reference is the exact
//! transmittance (`coif_shading::shadow::quality`) of every drawn render
//! hair at its real shadow radius, averaged over 16 rays on a 2 mm disk
//! (the footprint reference of `shading/SHADOWS.md`), at every vertex of
//! a few hundred evenly spaced hairs; the maps are compared there. Beside
//! each row, the paired change of the error against k = 1: per sampled
//! hair, the mean of `|T_k - T_ref| - |T_1 - T_ref|` over its vertices,
//! then the mean over the hairs and its standard error (hairs as the
//! independent units: the vertices of one hair share its shadow). With
//! `PER_HAIR_CSV`, k = 1's mean absolute error per sampled hair is written
//! there (`hair,vertices,mean_abs_error`), to pair two builds of the map
//! (two versions of the code) hair by hair.

use coif_frame::{motion, FramePipeline, FrameSettings, HairScene};
use coif_geometry::scene::GrowOptions;
use coif_shading::shadow::quality::{error_of_map, reference_transmittance, Footprint};
use glam::Vec3;
use std::time::Instant;

fn main() {
    let hairs_sampled: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(6);
    let scene = HairScene::procedural(&GrowOptions {
        strand_count: 2048,
        curl: 0.15,
        ..GrowOptions::default()
    })
    .unwrap();
    // The motion's frames before the map is measured (30: 3 segments per
    // span; the demo's last frame, 90, has 2).
    let frames: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(30);
    let run = |k: usize| {
        let settings = FrameSettings {
            shadow_thinning: k,
            ..FrameSettings::default()
        };
        let mut p = FramePipeline::new(&scene, settings, 1.5).unwrap();
        let pivot = p.pivot();
        for f in 0..frames {
            p.simulate(1.0 / 30.0, motion::turn_and_nod(f as f32 / 30.0, pivot));
        }
        p.render();
        p
    };
    let full = run(1);
    let points: Vec<Vec3> = full
        .shaded_vertices()
        .iter()
        .map(|v| Vec3::from(v.position))
        .collect();
    let (_, verts) = full.render_vertices();
    let strands = points.len() / verts;
    let stride = (strands / hairs_sampled).max(1);
    let map = full.shadow_map().unwrap();
    let settings = map.settings().clone();
    let light = -full.settings().light.to_light;
    let start = Instant::now();
    let reference = reference_transmittance(
        &settings,
        light,
        &points,
        verts,
        stride,
        Footprint {
            rays: 16,
            radius: 2e-3,
        },
    );
    println!(
        "{strands} hairs x {verts} vertices; reference at {} vertices of every {stride}-th hair ({:.1} s)",
        reference.len(),
        start.elapsed().as_secs_f64()
    );
    println!(
        "| k | hairs in the map | mean abs error | RMS | max | bias | mean |T_k - T_1| | paired change of the mean abs error (+- standard error over the hairs) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    // |T_map - T_ref| per sampled vertex, grouped by hair (the reference's
    // order: every stride-th hair, its finite vertices).
    let abs_errors = |m: &coif_shading::shadow::OpacityShadowMap| -> Vec<Vec<f64>> {
        let mut exact = reference.iter();
        points
            .chunks_exact(verts)
            .step_by(stride)
            .map(|hair| {
                hair.iter()
                    .filter(|p| p.is_finite())
                    .zip(&mut exact)
                    .map(|(p, t)| f64::from((m.transmittance(*p) - t).abs()))
                    .collect()
            })
            .collect()
    };
    let base_errors = abs_errors(map);
    if let Some(path) = std::env::args().nth(3) {
        let mut csv = String::from("hair,vertices,mean_abs_error\n");
        for (i, e) in base_errors
            .iter()
            .enumerate()
            .filter(|(_, e)| !e.is_empty())
        {
            let mean = e.iter().sum::<f64>() / e.len() as f64;
            csv += &format!("{},{},{mean:.9}\n", i * stride, e.len());
        }
        std::fs::write(&path, csv).expect("write the per-hair CSV");
    }
    let base = error_of_map(map, &points, verts, stride, &reference);
    for k in [1usize, 2, 4, 8, 16, 32] {
        let p = run(k);
        assert_eq!(p.shaded_vertices().len(), points.len(), "same hair");
        let m = p.shadow_map().unwrap();
        let e = error_of_map(m, &points, verts, stride, &reference);
        // Difference from the full map at every drawn vertex.
        let diff: f64 = points
            .iter()
            .map(|&q| (m.transmittance(q) - map.transmittance(q)).abs() as f64)
            .sum::<f64>()
            / points.len() as f64;
        // Per hair, the mean change of the absolute error.
        let changes: Vec<f64> = abs_errors(m)
            .iter()
            .zip(&base_errors)
            .filter(|(a, _)| !a.is_empty())
            .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x - y).sum::<f64>() / a.len() as f64)
            .collect();
        // (No standard error from a single hair: NaN.)
        let h = changes.len() as f64;
        let mean = changes.iter().sum::<f64>() / h;
        let var = changes.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (h - 1.0);
        println!(
            "| {k} | {} | {:.4} | {:.4} | {:.3} | {:+.4} | {:.4} | {:+.4} +- {:.4} |",
            strands.div_ceil(k),
            e.mean_abs,
            e.rms,
            e.max_abs,
            e.bias,
            diff,
            mean,
            (var / h).sqrt()
        );
    }
    println!(
        "(k = 1 is the reference pipeline's map: mean abs {:.4}; mean reference T {:.3})",
        base.mean_abs, base.mean_reference
    );
}
