//! Both shared TressFX grooms load, become guides with scalp triangles and
//! render a frame with hair and the bow's ribbons in it.

mod common;

use coif_testkit::groom_path;

use coif_frame::{FramePipeline, FrameSettings, HairScene};
use coif_geometry::groom;
use glam::Affine3A;

#[test]
fn both_shared_grooms_render_a_frame_with_hair() {
    for (name, max_guides) in [("ratboy_mohawk.tfx", 600), ("sintel_lite.tfx", 600)] {
        let Some(path) = groom_path(name) else {
            continue;
        };
        let g = groom::load(&std::fs::read(&path).unwrap()).unwrap();
        let scene = HairScene::from_groom(&g, max_guides, 16).unwrap();
        assert!(
            scene.guide_count() <= max_guides && scene.guide_count() > 100,
            "{name}: {}",
            scene.guide_count()
        );
        assert!(
            scene.triangles.len() > scene.guide_count() / 2,
            "{name}: {} triangles",
            scene.triangles.len()
        );
        // Metres: a head-sized groom.
        assert!(
            scene.extent > 0.05 && scene.extent < 1.0,
            "{name}: extent {} m",
            scene.extent
        );
        let settings = FrameSettings {
            render_hairs_per_cm2: 10.0,
            ..FrameSettings::small(96)
        };
        let mut p = FramePipeline::new(&scene, settings.clone(), 0.2).unwrap();
        let stats = p.frame(1.0 / 30.0, Affine3A::IDENTITY);
        assert!(stats.hairs > 100, "{name}: {stats:?}");
        let with_hair = p.image();
        let mut bare = FramePipeline::new(
            &scene,
            FrameSettings {
                hair_opacity: 0.0,
                ..settings
            },
            0.2,
        )
        .unwrap();
        bare.frame(1.0 / 30.0, Affine3A::IDENTITY);
        let bare = bare.image();
        let changed = with_hair
            .data
            .chunks_exact(3)
            .zip(bare.data.chunks_exact(3))
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 12))
            .count();
        assert!(
            changed > 96 * 96 / 20,
            "{name}: hair covers {changed} pixels"
        );
        assert!(p
            .shaded_vertices()
            .iter()
            .all(|v| v.color.iter().all(|c| c.is_finite())));
        // A loaded groom gets the bow too, drawn in the picture, and every
        // ribbon point stays out of the drawn head.
        assert_eq!(scene.ribbons.len(), 2, "{name}");
        assert!(stats.ribbon_pixels > 20, "{name}: {stats:?}");
        for i in 0..p.ribbons().len() {
            for q in p.ribbons().blended(i) {
                assert!(q.is_finite(), "{name}");
                for s in &scene.head {
                    assert!(
                        q.distance(s.center) > s.radius - 1e-3,
                        "{name}: {q} in {s:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_cyhair_groom_with_uneven_strands_is_resampled_into_guides() {
    // Strands of 3 to 9 points on a 10 cm sphere cap (centimetres), written
    // as cyHair and read back, as an exported groom would be.
    let mut points = Vec::new();
    let mut counts = Vec::new();
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    for i in 0..300 {
        let y = 1.0 - 1.2 * (i as f32 + 0.5) / 300.0;
        let r = (1.0 - y * y).sqrt();
        let n = glam::Vec3::new(
            r * (golden * i as f32).cos(),
            y,
            r * (golden * i as f32).sin(),
        );
        let count = 3 + i % 7;
        for v in 0..count {
            points.push(n * 10.0 + n * (12.0 * v as f32 / (count - 1) as f32));
        }
        counts.push(count);
    }
    let g = groom::Groom::from_strands(points, &counts).unwrap();
    let bytes = groom::cyhair::write(&g, "uneven").unwrap();
    let back = groom::load(&bytes).unwrap();
    let scene = HairScene::from_groom(&back, 1000, 8).unwrap();
    assert_eq!(scene.guide_count(), 300);
    assert_eq!(scene.verts_per_strand, 8);
    for (k, guide) in scene.guides.chunks_exact(8).enumerate() {
        let src = back.strand(k);
        // Same ends (metres) and evenly spaced points along the straight strand.
        assert!((guide[0] - src[0] * 0.01).length() < 1e-6);
        assert!((guide[7] - src[src.len() - 1] * 0.01).length() < 1e-5);
        for w in guide.windows(2) {
            assert!(((w[1] - w[0]).length() - 0.12 / 7.0).abs() < 1e-4);
        }
    }
    // The roots lie on a sphere: the drawn head is the fitted one, shrunk
    // to 97 % of the nearest root's distance so it stays under the roots.
    assert_eq!(scene.head.len(), 1);
    let head = &scene.head[0];
    assert!(head.center.length() < 1e-3, "{head:?}");
    assert!((head.radius - 0.097).abs() < 1e-3, "{head:?}");
    assert!(scene.triangles.len() > 400, "{}", scene.triangles.len());
}
