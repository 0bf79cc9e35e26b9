//! The frame pipeline end to end on the built-in head, at 128 x 128: the
//! picture is deterministic and shows hair on a head, and the side of the
//! hair away from the light is darker than the lit side.

mod common;

use coif_frame::{
    motion, FramePipeline, FrameSettings, HairScene, ShadingModel, HAIR_AMBIENT_ALBEDO,
};
use coif_render::RgbImage;
use glam::Vec3;

fn scene() -> HairScene {
    common::small_hair_scene()
}

/// Builds a pipeline and runs `frames` frames of the built-in motion.
fn run(settings: FrameSettings, frames: usize) -> (FramePipeline, RgbImage) {
    let mut p = FramePipeline::new(&scene(), settings, 1.5).unwrap();
    let pivot = p.pivot();
    for f in 0..frames {
        p.frame(1.0 / 30.0, motion::turn_and_nod(f as f32 / 30.0, pivot));
    }
    let img = p.image();
    (p, img)
}

#[test]
fn the_default_render_is_deterministic_and_shows_brown_hair_on_a_head() {
    let (p, a) = run(FrameSettings::small(128), 4);
    let (_, b) = run(FrameSettings::small(128), 4);
    assert_eq!(a.data, b.data, "two runs give the same bytes");
    let stats = p.stats();
    assert!(
        stats.hairs > 500 && stats.segments > 10 * stats.hairs,
        "{stats:?}"
    );
    assert!(stats.head_pixels > 200, "{stats:?}");

    // The same frames with invisible hair: background and head only.
    let (_, bare) = run(
        FrameSettings {
            hair_opacity: 0.0,
            ..FrameSettings::small(128)
        },
        4,
    );
    let mut hair_pixels = 0;
    let mut sum = [0f64; 3];
    for (px, bg) in a.data.chunks_exact(3).zip(bare.data.chunks_exact(3)) {
        let differs = px.iter().zip(bg).any(|(x, y)| x.abs_diff(*y) > 12);
        if differs {
            hair_pixels += 1;
            for c in 0..3 {
                sum[c] += px[c] as f64;
            }
        }
    }
    let fraction = hair_pixels as f64 / (128.0 * 128.0);
    assert!(
        fraction > 0.12 && fraction < 0.7,
        "hair covers {:.1} % of the picture",
        fraction * 100.0
    );
    let mean = sum.map(|s| s / hair_pixels as f64);
    // Brown hair: red over green over blue, neither black nor white.
    assert!(
        mean[0] > mean[1] && mean[1] > mean[2] && mean[0] > 60.0 && mean[0] < 240.0,
        "mean hair colour {mean:?}"
    );
}

/// Mean luminance of the direct light in the vertex colours of hair in the
/// head's shadow (the ray toward the light meets the head sphere) and of
/// the other hair, and the share of vertices in the shadow.
fn shadowed_and_lit(p: &FramePipeline) -> (f32, f32, f32) {
    let vertices = p.shaded_vertices();
    let to_light = p.settings().light.to_light;
    let head = &p.head_spheres()[0];
    let ambient = HAIR_AMBIENT_ALBEDO * p.settings().light.ambient;
    let (mut shadowed, mut lit) = ((0.0, 0), (0.0, 0));
    for v in vertices {
        // |p + s l - c| = r for some s > 0, with p outside the sphere.
        let m = Vec3::from(v.position) - head.center;
        let (b, c) = (
            m.dot(to_light),
            m.length_squared() - head.radius * head.radius,
        );
        let in_shadow = c > 0.0 && b < 0.0 && b * b > c;
        // The direct light's share: the colour minus the constant ambient term.
        let y = (Vec3::from(v.color) - ambient).dot(Vec3::new(0.2126, 0.7152, 0.0722));
        if in_shadow {
            shadowed = (shadowed.0 + y, shadowed.1 + 1);
        } else {
            lit = (lit.0 + y, lit.1 + 1);
        }
    }
    assert!(shadowed.1 > 0 && lit.1 > 0);
    (
        shadowed.0 / shadowed.1 as f32,
        lit.0 / lit.1 as f32,
        shadowed.1 as f32 / vertices.len() as f32,
    )
}

#[test]
fn hair_in_the_heads_shadow_is_darker_for_every_model() {
    for model in ShadingModel::ALL {
        let (p, _) = run(
            FrameSettings {
                shading: model,
                ..FrameSettings::small(96)
            },
            1,
        );
        let (shadowed, lit, share) = shadowed_and_lit(&p);
        // A guard that the scene puts enough hair behind the head for the
        // comparison below to mean something (thousands of vertices at 5 %);
        // how much depends on how the hair drapes, not on the shading.
        assert!(
            share > 0.05,
            "{model}: {share} of the hair is behind the head"
        );
        assert!(lit > 0.0, "{model}: lit hair gets direct light ({lit})");
        assert!(
            shadowed.abs() < 0.02 * lit,
            "{model}: hair in the head's shadow {shadowed}, lit hair {lit}"
        );
    }
}

#[test]
fn the_head_is_lambert_lit_brighter_toward_the_light() {
    // Without hair (and its shadow), the head's pixels toward the light
    // (upper left) are brighter than those away from it (lower right).
    let (p, img) = run(
        FrameSettings {
            hair_opacity: 0.0,
            shadows: false,
            ..FrameSettings::small(128)
        },
        1,
    );
    let camera = p.camera();
    let to_light = p.settings().light.to_light;
    // Screen direction of the light: project a point toward it from the
    // head's centre (the split between the halves compared below).
    let centre = p.head_spheres()[0].center;
    let a = camera.project(centre, 1e-3).unwrap();
    let b = camera.project(centre + to_light * 0.05, 1e-3).unwrap();
    let dir = (b - a).truncate().normalize();
    let (mut toward, mut away) = ((0.0f64, 0), (0.0f64, 0));
    let fb = p.framebuffer();
    for y in 0..128 {
        for x in 0..128 {
            if fb.depth(fb.index(x, y)).is_infinite() {
                continue;
            }
            let px = img.pixel(x, y);
            let l = px.iter().map(|&c| c as f64).sum::<f64>();
            let s = (glam::Vec2::new(x as f32, y as f32) - a.truncate()).dot(dir);
            if s > 5.0 {
                toward = (toward.0 + l, toward.1 + 1);
            } else if s < -5.0 {
                away = (away.0 + l, away.1 + 1);
            }
        }
    }
    assert!(toward.1 > 50 && away.1 > 50, "{toward:?} {away:?}");
    assert!(
        toward.0 / toward.1 as f64 > 1.3 * away.0 / away.1 as f64,
        "{toward:?} {away:?}"
    );
}

#[test]
fn bad_frame_times_and_poses_are_ignored_not_propagated() {
    let (mut p, _) = run(FrameSettings::small(64), 2);
    let nan_pose = glam::Affine3A::from_translation(Vec3::splat(f32::NAN));
    for (dt, pose, steps) in [
        (f32::NAN, glam::Affine3A::IDENTITY, 0),
        (-1.0, glam::Affine3A::IDENTITY, 0),
        (1.0 / 30.0, nan_pose, 2),
    ] {
        let stats = p.frame(dt, pose);
        assert_eq!(stats.substeps, steps, "dt {dt}");
        assert!(stats.hairs > 0);
        let v = p.shaded_vertices();
        assert!(v.iter().all(|v| v.color.iter().all(|c| c.is_finite())));
        assert!(v.iter().all(|v| v.position.iter().all(|c| c.is_finite())));
        assert!(p.strands().restored_strands() == 0, "no strand blew up");
    }
}

/// Culling the hair hidden behind the head changes no byte of the
/// picture, and does cull: the same frames with and without it, from the
/// default view (hair on the far side behind the head) and from the side.
#[test]
fn culling_hair_behind_the_head_keeps_every_byte() {
    for view in [None, Some(Vec3::X)] {
        let settings = |occlusion_culling| FrameSettings {
            occlusion_culling,
            view_direction: view,
            ..FrameSettings::small(128)
        };
        let (on, a) = run(settings(true), 3);
        let (off, b) = run(settings(false), 3);
        assert!(a.data == b.data, "view {view:?}: the pictures differ");
        let (s_on, s_off) = (on.stats(), off.stats());
        assert_eq!(s_on.segments, s_off.segments);
        assert_eq!(s_off.hidden_segments, 0);
        assert!(
            s_on.hidden_segments > s_on.segments / 20 && s_on.hidden_segments < s_on.segments,
            "view {view:?}: {} of {} segments culled",
            s_on.hidden_segments,
            s_on.segments
        );
    }
}

#[test]
fn a_settle_or_buffers_out_of_bounds_are_refused_before_any_work() {
    use coif_frame::Error;
    use coif_geometry::scene::GrowOptions;
    // An infinite settle used to loop without end.
    for settle in [f32::INFINITY, f32::NAN, -1.0, 601.0] {
        let got = FramePipeline::new(&scene(), FrameSettings::small(64), settle);
        assert!(
            matches!(
                got,
                Err(Error::Setting {
                    name: "settle_seconds",
                    ..
                })
            ),
            "settle {settle}"
        );
    }
    // A density and a span count each within range that together ask for
    // tens of gigabytes of render vertices (it aborted out of memory).
    let big = HairScene::procedural(&GrowOptions::default()).unwrap();
    let settings = FrameSettings {
        max_segments_per_span: 256,
        render_hairs_per_cm2: 1300.0,
        ..FrameSettings::small(64)
    };
    let got = FramePipeline::new(&big, settings, 0.0);
    assert!(
        matches!(got, Err(Error::Setting { name, .. }) if name.contains("max_segments_per_span")),
        "{:?}",
        got.err()
    );
    // Growth options that would allocate without bound are refused.
    let huge = GrowOptions {
        strand_count: 1 << 40,
        ..Default::default()
    };
    assert!(matches!(
        HairScene::procedural(&huge),
        Err(Error::Geometry(_))
    ));
}
