//! The same bytes at 8 and 16 lanes: a strand's result must not depend on
//! how many strands share its instruction.
//!
//! Each test computes one result and writes its bytes to
//! `<target>/lanes-equivalence/<name>-lanes<N>.bin` (N = [`LANES`] of this
//! build); a 16-lane build then compares them with the 8-lane file byte
//! for byte. CI runs this file in the default (8-lane) build with the
//! workspace's tests, then again with `--features lanes16` (`.ci/run`).
//! By hand: `cargo test --release -p coif --test lanes_equivalence`, then
//! the same with `--features lanes16`.
//!
//! - the mohawk (2,226 strands; skipped without `../shared`) after 60
//!   steps with spheres, a capsule, a signed distance field, wind with
//!   turbulence and drag, Coulomb friction, the hair grid's volume and
//!   friction and local shape constraints, its roots shaken (positions);
//! - 300 hanging strands that fall asleep (sleep is decided per group of
//!   eight strands), then are woken group by group by a sphere swept
//!   through them and by one moved root;
//! - every shading model on 1,000 random samples (Kajiya-Kay, the
//!   Marschner table, the pbrt table, dual scattering on both);
//! - LOD render vertices of Sintel's 228 guides after a second of her
//!   head's turn: refinement at 1 and 4 segments per span, interpolation
//!   of every group and of a quarter (the distance LOD's prefix);
//! - the default scene (Sintel on her bust, 96 x 96, three frames of the
//!   demo's turn and gust: simulation with the body's field and the hair
//!   grid, LOD, the fused prepare with dual scattering, the opacity shadow
//!   map and the raster), from the shadow map of every drawn group and of
//!   every third: the picture, every shaded vertex and every shadow texel
//!   (the fused pass puts two interpolation groups in a block at 16 lanes,
//!   one at 8).

use coif::base::SplitMix64;
use coif::frame::style::StyleScene;
use coif::frame::{motion, FramePipeline, FrameSettings, HairScene};
use coif::geometry::scene::scalp_spheres;
use coif::groom;
use coif::kernels::{
    self, step_colliders, Capsule, Colliders, Sdf, SimParams, Sphere, Strands, LANES,
};
use coif::lod::{
    interpolate, refine_strands, refined_len, write_render_vertices, HairWidth, Interpolation,
    RefinedGuides, RenderHairs, RenderVertex,
};
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::{marschner, pbrt, RgbBuffer, ShadingSamples};
use coif_testkit::groom_path;
use glam::Vec3;
use std::path::PathBuf;

/// `<target>/lanes-equivalence`, from the test binary's own path
/// (`<target>/<profile>/deps/<binary>`).
fn folder() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let target = exe
        .ancestors()
        .nth(3)
        .expect("<target>/<profile>/deps/<binary>");
    target.join("lanes-equivalence")
}

/// Writes this width's bytes; a 16-lane build also compares them with the
/// 8-lane build's (the run before it: an 8-lane run only writes, so that a
/// stale 16-lane file never fails it).
fn check(name: &str, bytes: &[u8]) {
    let dir = folder();
    std::fs::create_dir_all(&dir).expect("the lanes-equivalence folder");
    let file = |lanes: usize| dir.join(format!("{name}-lanes{lanes}.bin"));
    std::fs::write(file(LANES), bytes).expect("writing this width's bytes");
    if LANES == 8 {
        eprintln!(
            "{name}: {} bytes written for the 16-lane run to compare",
            bytes.len()
        );
        return;
    }
    let other = 8;
    match std::fs::read(file(other)) {
        Ok(theirs) => {
            assert_eq!(
                theirs.len(),
                bytes.len(),
                "{name}: lengths at {other} and {LANES} lanes"
            );
            if let Some(at) = theirs.iter().zip(bytes).position(|(a, b)| a != b) {
                panic!(
                    "{name}: byte {at} of {} differs between {other} and {LANES} lanes",
                    bytes.len()
                );
            }
            eprintln!(
                "{name}: {} bytes, the same at {other} and {LANES} lanes",
                bytes.len()
            );
        }
        Err(_) => panic!(
            "{name}: no 8-lane result in {}: run the 8-lane build of this test first",
            dir.display()
        ),
    }
}

fn floats(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

#[test]
fn the_mohawk_in_a_full_world_steps_to_the_same_bytes() {
    let Some(path) = groom_path("ratboy_mohawk.tfx") else {
        eprintln!("skipped: ratboy_mohawk.tfx not found (../shared/data/grooms)");
        return;
    };
    let g = groom::load(&std::fs::read(path).unwrap()).unwrap();
    let (pts, v) = g.uniform_points(0.01).unwrap();
    assert_eq!(pts.len() / v, 2226);
    let spheres = scalp_spheres(&pts, v, 2, 0.08);
    let head = &spheres[0];
    let capsules = [Capsule {
        a: head.center + Vec3::new(-0.2, -0.05, 0.1),
        b: head.center + Vec3::new(0.2, -0.05, 0.1),
        radius: 0.04,
    }];
    let (mesh_points, triangles) = coif_testkit::meshes::icosphere(3, 0.9 * head.radius);
    let mesh_points: Vec<Vec3> = mesh_points.iter().map(|p| *p + head.center).collect();
    let sdf = Sdf::from_mesh(&mesh_points, &triangles, 0.004).unwrap();
    let sdfs = [sdf];
    let params = SimParams {
        local_shape_stiffness: 1.0,
        wind: Vec3::new(2.0, 0.0, 1.0),
        drag: 0.5,
        turbulence: 0.5,
        volume_stiffness: 1.0,
        hair_friction: 1.0,
        ..SimParams::default()
    };
    let mut s = Strands::from_polylines(&pts, v).unwrap();
    let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
    let mut moved = roots.clone();
    for i in 0..60 {
        let off = Vec3::X * 0.05 * (i as f32 * 0.2).sin();
        for (m, r) in moved.iter_mut().zip(&roots) {
            *m = *r + off;
        }
        s.set_roots(&moved).unwrap();
        let shaken: Vec<Sphere> = spheres
            .iter()
            .map(|c| Sphere {
                center: c.center + off,
                radius: c.radius,
            })
            .collect();
        let colliders = Colliders {
            spheres: &shaken,
            capsules: &capsules,
            sdfs: &sdfs,
        };
        step_colliders(&mut s, &params, &colliders);
    }
    let positions = s.positions();
    assert!(positions.iter().all(|p| p.is_finite()));
    check(
        "mohawk_world",
        &floats(positions.iter().flat_map(|p| p.to_array())),
    );
}

#[test]
fn every_shading_model_gives_the_same_bytes() {
    let mut rng = SplitMix64::new(41);
    let mut samples = ShadingSamples::default();
    let (mut fibres, mut direct) = (Vec::new(), Vec::new());
    for _ in 0..1000 {
        samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        fibres.push(rng.range(0.0, 60.0));
        direct.push(rng.next_f32());
    }
    let pbrt_params = pbrt::Params {
        sigma_a: pbrt::sigma_a_from_concentration(0.4, 0.1),
        ..pbrt::Params::default()
    };
    let table = pbrt::Table::new(&pbrt_params, 32).unwrap();
    let lut = marschner::Lut::new(
        &marschner::Params {
            absorption: pbrt_params.sigma_a * 0.5,
            ..marschner::Params::default()
        },
        64,
    );
    let settings = DualScatteringSettings {
        resolution: 32,
        ..DualScatteringSettings::default()
    };
    let mut bytes = Vec::new();
    let mut out = RgbBuffer::default();
    let mut push = |out: &RgbBuffer| {
        bytes.extend(floats((0..out.len()).flat_map(|i| out.get(i).to_array())));
    };
    KajiyaKay::default().shade_batch(&samples, &mut out);
    push(&out);
    let mut single = RgbBuffer::default();
    lut.scattering_batch(&samples, &mut single);
    push(&single);
    let ds = DualScattering::from_marschner(&lut, settings).unwrap();
    ds.shade_batch(&samples, &single, &fibres, &direct, &mut out)
        .unwrap();
    push(&out);
    table.scattering_batch(&samples, &mut single);
    push(&single);
    let ds = DualScattering::from_pbrt(&table, settings).unwrap();
    ds.shade_batch(&samples, &single, &fibres, &direct, &mut out)
        .unwrap();
    push(&out);
    check("shading_models", &bytes);
}

#[test]
fn lod_render_vertices_are_the_same_bytes() {
    let scene = StyleScene::sintel().unwrap();
    let mut strands = scene.strands().unwrap();
    let params = SimParams {
        local_shape_stiffness: coif::frame::style::SCENE_STIFFNESS,
        ..SimParams::default()
    };
    let mut field = scene.field.clone();
    for i in 0..60 {
        let pose = scene.pose((i + 1) as f32 * params.dt);
        strands.set_head_pose(pose).unwrap();
        if let Some(f) = field.as_mut() {
            f.set_transform(pose).unwrap();
        }
        let colliders = Colliders {
            sdfs: field.as_slice(),
            ..Colliders::default()
        };
        step_colliders(&mut strands, &params, &colliders);
    }
    let v = scene.verts;
    let roots: Vec<Vec3> = scene.guides.iter().step_by(v).copied().collect();
    let center = coif::geometry::scene::fit_sphere(&roots).unwrap().center;
    let triangles = coif::geometry::triangulate::scalp_triangles(&roots, center);
    let interpolation = Interpolation::new(&roots, &triangles, 20.0, 7).unwrap();
    let mut refined = RefinedGuides::new(strands.blocks(), 4).unwrap();
    let mut hairs = RenderHairs::new(&interpolation, &refined);
    let mut vertices =
        vec![RenderVertex::default(); interpolation.hair_count() * refined_len(v, 4)];
    let mut bytes = Vec::new();
    for segments in [1, 4] {
        for groups in [interpolation.group_count(), interpolation.group_count() / 4] {
            refined.set_segments_per_span(segments).unwrap();
            refine_strands(strands.blocks(), None, &mut refined).unwrap();
            interpolate(&interpolation, &refined, None, groups, &mut hairs).unwrap();
            let n = write_render_vertices(
                &interpolation,
                &hairs,
                groups,
                HairWidth::default(),
                1.0,
                &mut vertices,
            )
            .unwrap();
            assert!(n > 0);
            bytes.extend_from_slice(wide::bytemuck::cast_slice(&vertices[..n]));
        }
    }
    check("lod_render_vertices", &bytes);
}

#[test]
fn the_default_scenes_picture_is_the_same_bytes() {
    // The fused prepare fills a block with one interpolation group per
    // eight lanes (two at 16), and its shadow map takes every `thinning`-th
    // drawn group, blocks of them split into tasks at group boundaries:
    // the picture, every shaded vertex and every shadow texel must not
    // depend on how many groups share a block. Thinning 3 makes blocks of
    // groups that are not neighbours in the drawn list.
    for thinning in [1, 3] {
        let scene = HairScene::sintel().unwrap();
        let mut settings = FrameSettings::small(96).with_body_simulation();
        settings.shadow_thinning = thinning;
        let mut p = FramePipeline::new(&scene, settings, 0.1).unwrap();
        let pivot = p.pivot();
        for f in 0..3 {
            let t = 1.6 + 0.2 * f as f32;
            p.set_wind(motion::gust(t, motion::GUST_WIND));
            p.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
            p.frame_with(
                1.0 / 15.0,
                motion::turn(t, pivot),
                &coif::base::tasks::Serial,
            );
        }
        assert!(p.stats().segments > 1000, "{:?}", p.stats());
        let image = p.image();
        let name = format!("sintel_thinning{thinning}");
        check(&format!("{name}_picture"), &image.data);
        let shaded = p.shaded_vertices().iter().flat_map(|v| {
            v.position
                .into_iter()
                .chain(v.color)
                .chain([v.width, v.strand_parameter])
        });
        check(&format!("{name}_shaded_vertices"), &floats(shaded));
        let map = p.shadow_map().expect("shadows are on");
        let (n, layers) = (map.settings().resolution, map.settings().layers);
        let opacities =
            (0..n * n * layers).map(|k| map.stored_opacity(k % n, (k / n) % n, k / (n * n)));
        check(&format!("{name}_shadow_map"), &floats(opacities));
    }
}

#[test]
fn sleeping_hair_sleeps_and_wakes_the_same_way() {
    // 300 strands (not a whole number of blocks at either width) of 16
    // vertices, 2 cm apart, hanging from a 20 x 15 grid of roots 3 cm apart.
    let verts = 16;
    let pts: Vec<Vec3> = (0..300)
        .flat_map(|k| {
            let root = Vec3::new(0.03 * (k % 20) as f32, 0.0, 0.03 * (k / 20) as f32);
            (0..verts).map(move |v| root - Vec3::Y * (0.02 * v as f32))
        })
        .collect();
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    let mut roots: Vec<Vec3> = pts.iter().step_by(verts).copied().collect();
    let params = SimParams::default();
    let (mut slept, mut woken) = (0, false);
    for i in 0..360 {
        // 4 s at rest, then a 4 cm sphere swept along x through the hair
        // for 1 s, one root nudged, and 1 s at rest.
        let center = if (240..300).contains(&i) {
            Vec3::new(-0.1 + 0.012 * (i - 240) as f32, -0.15, 0.2)
        } else {
            Vec3::new(-0.1, -0.15, 0.2)
        };
        if i == 300 {
            roots[123].x += 1e-3;
            s.set_roots(&roots).unwrap();
        }
        let asleep = s.sleeping_strands();
        let sphere = [Sphere {
            center,
            radius: 0.04,
        }];
        kernels::step(&mut s, &params, &sphere);
        woken |= i >= 240 && s.sleeping_strands() < asleep;
        slept = slept.max(s.sleeping_strands());
    }
    assert!(slept >= 200, "only {slept} of 300 strands fell asleep");
    assert!(woken, "nothing woke a sleeping strand");
    let positions = s.positions();
    assert!(positions.iter().all(|p| p.is_finite()));
    check(
        "sleeping_hair",
        &floats(positions.iter().flat_map(|p| p.to_array())),
    );
}

#[test]
fn a_shadow_map_built_in_tasks_from_lane_rows_is_the_same_bytes() {
    // 301 curly strands (not a whole number of blocks at either width) in
    // lane layout, one vertex not finite, built as 7 tasks: the tasks
    // split the hair at groups of eight lanes, so the same strands fall in
    // each task's partial map at 8 and 16 lanes.
    use coif::shading::shadow::{
        to_lane_rows, BuildScratch, LaneRows, OpacityShadowMap, ShadowMode, ShadowSettings,
    };
    let verts = 16;
    let mut rng = SplitMix64::new(11);
    let mut pts = Vec::with_capacity(301 * verts);
    for _ in 0..301 {
        let root = Vec3::new(rng.range(-0.1, 0.1), 0.0, rng.range(-0.1, 0.1));
        let phase = rng.range(0.0, std::f32::consts::TAU);
        for r in 0..verts {
            let a = phase + 0.8 * r as f32;
            pts.push(root + Vec3::new(0.01 * a.cos(), -0.01 * r as f32, 0.01 * a.sin()));
        }
    }
    pts[40] = Vec3::NAN;
    let mut rows = Vec::new();
    let strands = to_lane_rows(&pts, verts, Vec3::splat(1.0e30), &mut rows);
    let hair = LaneRows {
        rows: &rows,
        verts,
        strands,
    };
    let settings = ShadowSettings {
        resolution: 64,
        mode: ShadowMode::Deep,
        ..Default::default()
    };
    let mut scratch = BuildScratch::new(&settings, 7).unwrap();
    let mut map = OpacityShadowMap::new(settings.clone()).unwrap();
    let light = Vec3::new(1.0, -0.5, 0.3);
    map.build_lanes(&coif::base::tasks::Serial, &mut scratch, light, &hair)
        .unwrap();
    let (n, layers) = (settings.resolution, settings.layers);
    let opacities: Vec<f32> = (0..n * n * layers)
        .map(|k| map.stored_opacity(k % n, (k / n) % n, k / (n * n)))
        .collect();
    assert!(opacities.iter().filter(|o| **o != 0.0).count() > 1000);
    check("shadow_map_lane_rows_7_tasks", &floats(opacities));
}
