//! The default scene: Sintel on her bust, from the files shipped in
//! `assets/sintel`. It builds, the bust reads with its triangle count, no
//! guide vertex ends inside the bust beyond 2 mm (the exact distance to the
//! mesh) over the demo's motion (a head turn, then a gust), the hair rests
//! at its groom in calm air and comes back to it after the gust, the
//! picture has the same bytes on any thread count, and bad or missing
//! files give an error that says what is wrong.

use coif_base::tasks::{Rayon, Serial};
use coif_frame::style::{groom_distance_percentile, kinked_share};
use coif_frame::{motion, Error, FramePipeline, FrameSettings, HairScene};
use coif_geometry::mesh::{MeshError, TriangleMesh};
use coif_testkit::meshes::brute;
use glam::Vec3;

const BUST: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../assets/sintel/sintel_bust.obj"
);
const GROOM: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../assets/sintel/sintel_lite.tfx"
);

/// The demo's settings for a scene with a body, at `size` pixels.
fn settings(size: usize) -> FrameSettings {
    FrameSettings::small(size).with_body_simulation()
}

#[test]
fn the_scene_builds_from_the_shipped_files() {
    let bust = TriangleMesh::from_obj(&std::fs::read(BUST).unwrap(), 0.01).unwrap();
    assert_eq!(bust.positions().len(), 3046);
    assert_eq!(bust.triangles().len(), 5952);
    let (lo, hi) = bust.bounds();
    assert!(hi.y - lo.y > 0.4 && hi.y - lo.y < 0.45, "{lo} {hi}: metres");

    let scene = HairScene::sintel().unwrap();
    assert_eq!(scene.guide_count(), 228);
    assert_eq!(scene.verts_per_strand, 32);
    let body = scene.body.as_ref().expect("Sintel has a body");
    assert_eq!(
        body.mesh(),
        &bust,
        "the compiled-in bust is the shipped file"
    );
    assert!(scene.triangles.len() > 300, "{}", scene.triangles.len());
    assert!(scene.rig.is_empty(), "the bust's field, no spheres");
    assert!(scene.ribbons.is_empty());
    // The head sphere lies inside the bust, about the roots' centre.
    let head = &scene.head[0];
    assert!(head.radius > 0.05 && head.radius < 0.11, "{}", head.radius);
    assert!(body.field().distance(head.center) <= -head.radius + 1e-4);
    // Two eyes in the eye openings of the mesh, one each side, in front
    // of the head; not the mouth, not the cuts.
    let eyes = body.eyes();
    assert_eq!(eyes.len(), 2, "{eyes:?}");
    assert_eq!(body.irises().len(), 2);
    assert!(eyes[0].center.x * eyes[1].center.x < 0.0, "{eyes:?}");
    for e in eyes {
        assert!(e.center.z > head.center.z && e.center.y > 0.3, "{e:?}");
        assert!(e.radius > 0.01 && e.radius < 0.03, "{e:?}");
    }
    // The same scene from the files on disk.
    let from_files = HairScene::from_files(
        &std::fs::read(GROOM).unwrap(),
        &std::fs::read(BUST).unwrap(),
        0.01,
        usize::MAX,
        32,
    )
    .unwrap();
    assert_eq!(from_files.guides, scene.guides);
    assert_eq!(from_files.triangles, scene.triangles);
}

/// Exact depth of world point `p` inside the rest mesh posed by `pose`
/// (positive inside; the sign by the winding number, as the field's).
fn exact_depth(mesh: &(Vec<Vec3>, Vec<[u32; 3]>), pose: &glam::Affine3A, p: Vec3) -> f32 {
    let q = pose.inverse().transform_point3(p);
    let (d, w) = brute(mesh, q);
    if w >= 0.5 {
        d as f32
    } else {
        -(d as f32)
    }
}

#[test]
fn no_guide_vertex_ends_inside_the_bust_over_the_default_motion() {
    let scene = HairScene::sintel().unwrap();
    let body = scene.body.clone().unwrap();
    let mesh = (
        body.mesh().positions().to_vec(),
        body.mesh().triangles().to_vec(),
    );
    let mut p = FramePipeline::new(&scene, settings(64), 1.5).unwrap();
    // The same motion without the gust, to see what the wind does.
    let mut still = FramePipeline::new(&scene, settings(64), 1.5).unwrap();
    let pivot = p.pivot();
    let fps = 30.0;
    let (mut worst, mut checked, mut blown, mut root_stretch) = (0.0f32, 0, 0.0f32, 0.0f32);
    for f in 0..96 {
        let t = f as f32 / fps;
        p.set_wind(motion::gust(t, motion::GUST_WIND));
        p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
        let pose = motion::turn(t, pivot);
        p.simulate(1.0 / fps, pose);
        still.simulate(1.0 / fps, pose);
        let positions = p.strands().positions();
        assert!(positions.iter().all(|x| x.is_finite()), "frame {f}");
        // Roots kept on the scalp: the root segments (whose roots start
        // inside the mesh for 5 strands) are not stretched beyond 3 % (the
        // strain limit allows 1 %; 2.1 % measured). Segments further out,
        // in contact with the bust, stretch more where the field's push
        // wins over the strain limit (kernels/README.md).
        for (k, w) in positions.windows(2).enumerate() {
            if k % scene.verts_per_strand < 2 {
                let rest = scene.guides[k].distance(scene.guides[k + 1]);
                root_stretch = root_stretch.max(w[0].distance(w[1]) / rest - 1.0);
            }
        }
        if f % 4 == 3 {
            let field = p.body_field().unwrap();
            for x in &positions {
                // The field (4 mm cells, within about a millimetre of the
                // exact distance near the surface) picks the vertices near
                // it; the brute force gives their exact depth.
                if field.distance(*x) < 0.004 {
                    worst = worst.max(exact_depth(&mesh, &pose, *x));
                    checked += 1;
                }
            }
        }
        // How far the gust moves the hair: the 99th percentile over the
        // vertices of the distance to the windless run.
        let mut apart: Vec<f32> = positions
            .iter()
            .zip(still.strands().positions())
            .map(|(a, b)| a.distance(b))
            .collect();
        apart.sort_by(f32::total_cmp);
        blown = blown.max(apart[apart.len() * 99 / 100]);
    }
    assert!(
        checked > 1000,
        "vertices near the surface checked: {checked}"
    );
    assert!(
        worst <= 2e-3,
        "deepest guide vertex {worst} m inside the bust"
    );
    eprintln!("deepest {worst} m, root segments stretched {root_stretch}, gust {blown} m");
    assert!(
        root_stretch < 0.03,
        "a root segment stretched by {root_stretch}"
    );
    // The gust reaches the hair: a hundredth of the vertices (the free
    // ends) move by more than 5 mm from the calm run (measured: 93 mm at
    // its peak).
    assert!(blown > 5e-3, "the gust moved the hair by {blown} m");
}

#[test]
fn the_hair_rests_at_its_groom_in_calm_air_and_returns_after_the_gust() {
    // The demo's motion at the default local shape: calm air while the
    // head turns (0-2 s), the gust and its turbulence (1.6-3 s), calm
    // again. Measured: 1.0 mm from the groom (p95) settled, 0.5 % of the
    // interior vertices kinked; the gust moves the vertices 81 mm (p95)
    // from where they rested; 3 s after it they are back within 2.0 mm
    // (most of the hair asleep by then: 0.5 mm when it could not sleep).
    // With the gust's turbulence held on at rest (as the scene had it
    // before), the hair kept blowing: 16 mm from its groom after 3 s at
    // rest (`examples/style.rs -- --body --turbulence 1.5 0.7`).
    let scene = HairScene::sintel().unwrap();
    let verts = scene.verts_per_strand;
    let mut p = FramePipeline::new(&scene, settings(64), 1.5).unwrap();
    let pivot = p.pivot();
    let rested = p.strands().positions();
    let settled = groom_distance_percentile(&rested, &scene.guides, verts, 0.95);
    let kinked = kinked_share(&rested, &scene.guides, verts, 30.0);
    let fps = 30.0;
    let mut blown = 0.0f32;
    for f in 0..180 {
        let t = f as f32 / fps;
        p.set_wind(motion::gust(t, motion::GUST_WIND));
        p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
        p.simulate(1.0 / fps, motion::turn(t, pivot));
        if (1.6..3.0).contains(&t) {
            let now = p.strands().positions();
            blown = blown.max(groom_distance_percentile(&now, &rested, verts, 0.95));
        }
    }
    let back = groom_distance_percentile(&p.strands().positions(), &rested, verts, 0.95);
    eprintln!("settled {settled} m from the groom, {kinked} kinked; gust {blown} m; back {back} m");
    assert!(settled < 3e-3, "settled {settled} m from the groom");
    assert!(kinked < 0.01, "{kinked} of the vertices kinked at rest");
    assert!(blown > 0.02, "the gust moved the hair {blown} m (p95)");
    assert!(
        back < 3e-3,
        "3 s after the gust, {back} m from where it rested"
    );
}

#[test]
fn the_picture_is_the_same_bytes_on_any_thread_count() {
    let scene = HairScene::sintel().unwrap();
    let run = |executor: &dyn coif_base::tasks::Executor| {
        let mut p = FramePipeline::new(&scene, settings(96), 0.1).unwrap();
        let pivot = p.pivot();
        for f in 0..3 {
            let t = 1.6 + 0.2 * f as f32;
            p.set_wind(motion::gust(t, motion::GUST_WIND));
            p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
            p.frame_with(1.0 / 15.0, motion::turn(t, pivot), executor);
        }
        assert!(p.stats().body_pixels > 500, "{:?}", p.stats());
        assert!(p.stats().segments > 1000, "{:?}", p.stats());
        p.image().data
    };
    let serial = run(&Serial);
    let pool = Rayon::new(2).unwrap();
    assert!(run(&pool) == serial, "2 threads: the picture differs");
}

#[test]
fn bad_or_missing_files_give_a_clear_error() {
    let groom = std::fs::read(GROOM).unwrap();
    let bust = std::fs::read(BUST).unwrap();
    let message = |r: Result<HairScene, Error>| r.unwrap_err().to_string();
    // A truncated groom, a garbage mesh, a mesh without triangles.
    let m = message(HairScene::from_files(&groom[..100], &bust, 0.01, 228, 32));
    assert!(m.starts_with("groom:"), "{m}");
    let m = message(HairScene::from_files(
        &groom,
        b"v 1 2\nf 1 2 3\n",
        0.01,
        228,
        32,
    ));
    assert!(m.starts_with("body mesh:"), "{m}");
    let e =
        HairScene::from_files(&groom, b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", 0.01, 228, 32).unwrap_err();
    assert!(matches!(e, Error::Mesh(MeshError::Empty)), "{e}");
    let m = message(HairScene::from_files(&groom, &bust, f32::NAN, 228, 32));
    assert!(m.contains("scale"), "{m}");
    // A mesh that is not the groom's body: the roots' centre is outside.
    let far = b"v 10 0 0\nv 11 0 0\nv 10 1 0\nv 10 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
    let m = message(HairScene::from_files(&groom, far, 0.01, 228, 32));
    assert!(m.contains("not inside the body mesh"), "{m}");
    // The bust read at a scale that makes its field absurdly large.
    let m = message(HairScene::from_files(&groom, &bust, 10.0, 228, 32));
    assert!(m.starts_with("simulation:") || m.contains("body"), "{m}");
}
