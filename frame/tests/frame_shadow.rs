//! Hair self-shadowing with the opacity shadow map: hair deeper from the
//! light is darker than hair at the lit surface.

mod common;

use coif_frame::{FramePipeline, FrameSettings, PrepareMode, ShadingModel};
use glam::{Affine3A, Vec3};

fn pipeline(settings: FrameSettings) -> FramePipeline {
    let scene = common::small_hair_scene();
    let mut p = FramePipeline::new(&scene, settings, 0.5).unwrap();
    p.frame(1.0 / 30.0, Affine3A::IDENTITY);
    p
}

#[test]
fn hair_deeper_from_the_light_is_in_shadow_and_darker() {
    // The reference pipeline keeps every vertex's transmittance.
    let p = pipeline(FrameSettings {
        prepare: PrepareMode::Reference,
        ..FrameSettings::small(96)
    });
    assert!(p.has_shadow_map());
    let (vertices, _) = p.render_vertices();
    let t = p.vertex_transmittance();
    let to_light = p.settings().light.to_light;
    // Depth along the light (larger = farther from the light).
    let depth: Vec<f32> = vertices
        .iter()
        .map(|v| -Vec3::from(v.position).dot(to_light))
        .collect();
    let mut sorted = depth.clone();
    sorted.sort_by(f32::total_cmp);
    let (near, far) = (sorted[sorted.len() / 4], sorted[3 * sorted.len() / 4]);
    let mean = |keep: &dyn Fn(f32) -> bool| {
        let (s, n) = depth
            .iter()
            .zip(t)
            .filter(|(d, _)| keep(**d))
            .fold((0.0, 0), |(s, n), (_, t)| (s + t, n + 1));
        s / n as f32
    };
    let (lit, deep) = (mean(&|d| d < near), mean(&|d| d > far));
    assert!(t.iter().all(|t| (0.0..=1.0).contains(t)));
    assert!(
        lit > 0.5,
        "the quarter nearest the light gets most of the light: {lit}"
    );
    assert!(
        deep < 0.5 * lit,
        "the farthest quarter is in the hair's shadow: {deep} vs {lit}"
    );
}

#[test]
fn the_shadow_map_only_darkens_single_scattering_and_darkens_on_the_whole() {
    // Per vertex, for single scattering (a transmittance in [0, 1] times
    // the same light). With dual scattering (the physical models'
    // default) light crossing the hair in front is scattered on, spread
    // in angle, so a vertex behind a red-transmitting fibre may get more
    // light toward some views than it would unshadowed: only the sum
    // must fall.
    for multiple in [false, true] {
        for model in ShadingModel::ALL {
            let with = pipeline(FrameSettings {
                shading: model,
                multiple_scattering: multiple,
                ..FrameSettings::small(64)
            });
            let without = pipeline(FrameSettings {
                shading: model,
                multiple_scattering: multiple,
                shadows: false,
                ..FrameSettings::small(64)
            });
            assert!(!without.has_shadow_map());
            let (a, b) = (with.shaded_vertices(), without.shaded_vertices());
            assert_eq!(a.len(), b.len());
            let (mut sum_a, mut sum_b) = (0.0f64, 0.0f64);
            for k in 0..a.len() {
                let (ca, cb) = (Vec3::from(a[k].color), Vec3::from(b[k].color));
                assert!(
                    multiple || ca.cmple(cb + Vec3::splat(1e-6)).all(),
                    "{model}: vertex {k} {ca} > {cb}"
                );
                sum_a += ca.element_sum() as f64;
                sum_b += cb.element_sum() as f64;
            }
            assert!(
                sum_a < 0.9 * sum_b,
                "{model} (multiple scattering {multiple}): shadowed {sum_a} vs unshadowed {sum_b}"
            );
        }
    }
}
