//! The same bytes at 8 and 16 lanes: a strand's result must not depend on
//! how many strands share its instruction.
//!
//! Each test computes one result, writes its bytes to
//! `<target>/lanes-equivalence/<name>-lanes<N>.bin` (N = [`LANES`] of this
//! build) and, when the other width's file is there, compares the two byte
//! for byte. CI runs this file in the default (8-lane) build with the
//! workspace's tests, then again with `--features lanes16`
//! (`.ci/run`), so the second run compares. Run alone, a test checks its
//! own width's result and says that the other is missing.
//!
//! - the mohawk (2,226 strands; skipped without `../shared`) after 60 steps
//!   with spheres, a capsule, a signed distance field, wind with
//!   turbulence and drag, Coulomb friction, the hair grid's volume and
//!   friction and local shape constraints, its roots shaken (positions);
//! - every shading model on 1,000 random samples (Kajiya-Kay, the
//!   Marschner table, the pbrt table, dual scattering on both).

use coif::base::SplitMix64;
use coif::geometry::scene::scalp_spheres;
use coif::groom;
use coif::kernels::{step_colliders, Capsule, Colliders, Sdf, SimParams, Sphere, Strands, LANES};
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

/// Writes this width's bytes and compares them with the other width's.
fn check(name: &str, bytes: &[u8]) {
    let dir = folder();
    std::fs::create_dir_all(&dir).expect("the lanes-equivalence folder");
    let file = |lanes: usize| dir.join(format!("{name}-lanes{lanes}.bin"));
    std::fs::write(file(LANES), bytes).expect("writing this width's bytes");
    let other = if LANES == 8 { 16 } else { 8 };
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
        Err(_) => eprintln!(
            "{name}: no {other}-lane result in {} to compare with",
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
        // Sleeping is decided per block: with it on, a block of sixteen
        // strands sleeps later than its two blocks of eight would.
        sleep_speed: 0.0,
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
