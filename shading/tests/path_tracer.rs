//! The path tracer through explicit fibres: white furnace, one fibre against
//! the far field, determinism, geometry statistics and refused input.

use coif_base::SplitMix64;
use coif_shading::path_tracer::{
    orthographic_rays, tuft, DirectionalLight, FibreScene, PathTracer, TuftParams,
};
use coif_shading::pbrt::{self, local_directions, recommended_order, FarField, Params};
use coif_shading::Error;
use glam::Vec3;
use std::time::Instant;

fn white() -> Params {
    Params {
        sigma_a: Vec3::ZERO,
        ..Params::default()
    }
}

fn tuft_params(volume_fraction: f32, seed: u64) -> TuftParams {
    TuftParams {
        length: 400.0,
        width: 60.0,
        thickness: 24.0,
        radius: 1.0,
        volume_fraction,
        seed,
    }
}

/// White furnace: sigma_a = 0, environment 1, no light, max depth 10,000.
/// Every path that escapes carries radiance 1 (white weights are 1 to
/// 4e-5), so the patch mean must be 1; a path that stops (zero pdf,
/// non-finite weight, depth limit) pulls it below. Four tufts (volume
/// fractions 0.1, 0.25, 0.4 at 24 r thick, and 0.45 at 80 r), three
/// view directions (across the fibres from the slab's face, oblique, and
/// 30 degrees off the fibre axis), 48 rays x 48 paths each.
#[test]
fn white_furnace_through_a_tuft() {
    let tracer = PathTracer::new(&white(), None, Vec3::ONE, 10_000).unwrap();
    let views = [
        Vec3::Z,
        Vec3::new(0.0, 0.6, 0.8),
        Vec3::new(0.866, 0.0, 0.5),
    ];
    let mut paths = 0usize;
    let mut scatterings = 0.0f64;
    let start = Instant::now();
    for (k, (f, thickness)) in [(0.1f32, 24.0f32), (0.25, 24.0), (0.4, 24.0), (0.45, 80.0)]
        .into_iter()
        .enumerate()
    {
        let t = tuft(&TuftParams {
            thickness,
            ..tuft_params(f, 7 + k as u64)
        })
        .unwrap();
        for (v, from) in views.iter().enumerate() {
            let rays = t.camera_rays(*from, 10.0, 48, 100 + v as u64).unwrap();
            let est = tracer.estimate_threaded(&t.scene, &rays, 48, 5, 2).unwrap();
            let n = est.len() as f64;
            let mean = est.iter().map(|e| e.mean.as_dvec3()).sum::<glam::DVec3>() / n;
            // Standard error of the patch mean: rays are independent.
            let se = (est
                .iter()
                .map(|e| e.standard_error.as_dvec3().powf(2.0))
                .sum::<glam::DVec3>())
            .map(f64::sqrt)
                / n;
            let ms = est.iter().map(|e| e.mean_scatterings as f64).sum::<f64>() / n;
            let mx = est.iter().map(|e| e.max_scatterings).max().unwrap();
            println!(
                "furnace f {f} D {thickness} ({} fibres, {} overlaps) view {from}: {mean:.6} +- {se:.6}, \
                 scatterings mean {ms:.1} max {mx}",
                t.fibre_count, t.overlaps
            );
            assert!(
                (mean - glam::DVec3::ONE).abs().max_element() < 0.01,
                "{mean}"
            );
            assert!(se.max_element() < 0.002, "{se}");
            assert!(mx < 10_000, "no path reached the depth limit");
            paths += rays.len() * 48;
            scatterings += ms * rays.len() as f64 * 48.0;
        }
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "furnace: {paths} paths, {:.1} scatterings per path, {:.0} paths/s ({:.0} scatterings/s) on 2 threads",
        scatterings / paths as f64,
        paths as f64 / secs,
        scatterings / secs
    );
}

/// The same furnace with absorbing (default, brown) fibres is below 1 and
/// darker the denser the tuft (more scattering, more absorption).
#[test]
fn absorbing_tuft_is_darker_when_denser() {
    let tracer = PathTracer::new(&Params::default(), None, Vec3::ONE, 10_000).unwrap();
    let mut last = f32::INFINITY;
    for (k, f) in [0.05f32, 0.2, 0.4].into_iter().enumerate() {
        let t = tuft(&tuft_params(f, 3 + k as u64)).unwrap();
        let rays = t.camera_rays(Vec3::Z, 10.0, 32, 1).unwrap();
        let est = tracer.estimate(&t.scene, &rays, 32, 9).unwrap();
        let mean = est.iter().map(|e| e.mean.y).sum::<f32>() / est.len() as f32;
        println!("absorbing f {f}: green {mean}");
        assert!(mean < last && mean < 1.0 && mean > 0.0);
        last = mean;
    }
}

fn fibre_setup() -> (Vec3, FibreScene) {
    let t = Vec3::new(0.3, 1.0, 0.2).normalize();
    let scene = FibreScene::from_segments(&[(-2000.0 * t, 2000.0 * t)], 1.0).unwrap();
    (t, scene)
}

/// Rays toward `-wo` hitting the fibre along `t` at offsets `offsets`
/// (in units of r across its projected width).
fn rays_across(t: Vec3, wo: Vec3, offsets: impl Iterator<Item = f32>) -> Vec<(Vec3, Vec3)> {
    let d = -wo;
    let side = t.cross(d).normalize();
    offsets
        .map(|o| (side * o - d * 30.0 + t * 3.0, d))
        .collect()
}

/// One fibre, directional light, first scattering only, no environment: the
/// radiance averaged over rays spread uniformly (stratified, jittered)
/// across the fibre's width equals `FarField::eval(t, wi, wo) * E`.
#[test]
fn single_fibre_first_bounce_is_the_far_field() {
    let params = Params::default();
    let far = FarField::new(&params, 4 * recommended_order(&params)).unwrap();
    let (t, scene) = fibre_setup();
    let e = Vec3::new(1.0, 0.8, 0.6);
    let mut rng = SplitMix64::new(2);
    let n = 4096;
    for _ in 0..6 {
        let wi = rng.unit_vector();
        let wo = rng.unit_vector();
        if wo.dot(t).abs() > 0.9 || wi.dot(t).abs() > 0.95 {
            continue;
        }
        let light = DirectionalLight {
            to_light: wi,
            irradiance: e,
        };
        let tracer = PathTracer::new(&params, Some(light), Vec3::ZERO, 1).unwrap();
        let offsets: Vec<f32> = (0..n)
            .map(|k| -1.0 + 2.0 * (k as f32 + rng.next_f32()) / n as f32)
            .collect();
        let rays = rays_across(t, wo, offsets.iter().copied());
        let est = tracer.estimate(&scene, &rays, 1, 4).unwrap();
        let values: Vec<glam::DVec3> = est.iter().map(|e| e.mean.as_dvec3()).collect();
        let mean = values.iter().sum::<glam::DVec3>() / n as f64;
        // Error bars as for independent uniform h (stratification only
        // makes the real error smaller).
        let var = values
            .iter()
            .map(|v| (*v - mean) * (*v - mean))
            .sum::<glam::DVec3>()
            / (n as f64 - 1.0);
        let se = (var / n as f64).map(f64::sqrt);
        let reference = (far.eval(t, wi, wo) * e).as_dvec3();
        println!("wi {wi} wo {wo}: traced {mean:.5} +- {se:.6}, far field {reference:.5}");
        for c in 0..3 {
            assert!(
                (mean[c] - reference[c]).abs() < 4.0 * se[c] + 1e-4 * reference[c].max(1e-3),
                "channel {c}: {mean} vs {reference}"
            );
        }
    }
}

/// Pointwise: a ray at offset `h` across the fibre gives
/// `scattering_local(h, wo, wi) E` in the frame of `local_directions`
/// (the sign of `h` matters here, unlike in the h-average).
#[test]
fn single_fibre_radiance_at_each_offset_is_the_local_model() {
    let params = Params::default();
    let lobes = pbrt::Lobes::new(&params);
    let (t, scene) = fibre_setup();
    let wi = Vec3::new(0.2, -0.5, 0.8).normalize();
    let wo = Vec3::new(-0.6, 0.1, 0.7).normalize();
    let e = Vec3::ONE;
    let tracer = PathTracer::new(
        &params,
        Some(DirectionalLight {
            to_light: wi,
            irradiance: e,
        }),
        Vec3::ZERO,
        1,
    )
    .unwrap();
    let (wo_l, wi_l) = local_directions(t, wi, wo);
    let mut asymmetric = 0;
    for k in 0..39 {
        let off = -0.95 + 0.05 * k as f32;
        let ray = rays_across(t, wo, std::iter::once(off))[0];
        let hit = scene.intersect(ray.0, ray.1, f32::INFINITY).unwrap();
        let got = tracer.radiance(&scene, ray.0, ray.1, &mut SplitMix64::new(k));
        let want = pbrt::scattering_local_with(&lobes, &params, hit.h, wo_l, wi_l) * e;
        let mirror = pbrt::scattering_local_with(&lobes, &params, -hit.h, wo_l, wi_l) * e;
        assert!(
            (got - want).abs().max_element() <= 1e-4 * want.max_element() + 1e-7,
            "offset {off} h {}: {got} vs {want}",
            hit.h
        );
        assert!((hit.h.abs() - off.abs()).abs() < 1e-3);
        if (mirror - want).abs().max_element() > 0.05 * want.max_element() {
            asymmetric += 1;
        }
    }
    assert!(asymmetric > 10, "the configuration tells h from -h");
}

/// A single straight fibre scatters every path exactly once whatever the
/// depth limit: the continuation never hits the fibre it left (no
/// self-intersection) and never stays stuck inside it.
#[test]
fn single_fibre_is_scattered_once() {
    let (t, scene) = fibre_setup();
    let tracer = PathTracer::new(&white(), None, Vec3::ONE, 1000).unwrap();
    let wo = Vec3::new(-0.6, 0.1, 0.7).normalize();
    let rays = rays_across(t, wo, (0..64).map(|k| -0.99 + 1.98 * k as f32 / 63.0));
    for e in tracer.estimate(&scene, &rays, 64, 1).unwrap() {
        assert_eq!(e.max_scatterings, 1);
        assert_eq!(e.mean_scatterings, 1.0);
        assert!(
            (e.mean - Vec3::ONE).abs().max_element() < 1e-4,
            "{:?}",
            e.mean
        );
    }
}

/// A second fibre between the hit and the light blocks the direct light.
#[test]
fn shadow_rays_are_blocked_by_fibres() {
    let scene = FibreScene::from_segments(
        &[
            (Vec3::new(-100.0, 0.0, 0.0), Vec3::new(100.0, 0.0, 0.0)),
            (Vec3::new(-100.0, 0.0, 5.0), Vec3::new(100.0, 0.0, 5.0)),
        ],
        1.0,
    )
    .unwrap();
    let light = DirectionalLight {
        to_light: Vec3::Z,
        irradiance: Vec3::ONE,
    };
    let tracer = PathTracer::new(&Params::default(), Some(light), Vec3::ZERO, 1).unwrap();
    // Camera below, looking up at the lower fibre's centre: its light is
    // blocked by the upper fibre. The upper fibre seen from the side is lit.
    let up = tracer.radiance(
        &scene,
        Vec3::new(0.0, 0.0, -10.0),
        Vec3::Z,
        &mut SplitMix64::new(1),
    );
    assert_eq!(up, Vec3::ZERO);
    let side = tracer.radiance(
        &scene,
        Vec3::new(0.0, -10.0, 5.3),
        Vec3::Y,
        &mut SplitMix64::new(1),
    );
    assert!(side.max_element() > 0.0);
}

/// Mean crossings of rays through the slab's thickness equal the expected
/// `2 r n / W` (fibre centres per unit area `n / (W D)` times the strip
/// width 2 r times the thickness D), within 3 % (the count of fibres in
/// the strip fluctuates; 600 r wide, about 2 % relative standard deviation
/// at f = 0.1), and the BVH count equals brute force.
#[test]
fn tuft_crossings_match_the_density() {
    for f in [0.1f32, 0.3] {
        let p = TuftParams {
            width: 600.0,
            ..tuft_params(f, 11)
        };
        let t = tuft(&p).unwrap();
        let mut rng = SplitMix64::new(2);
        let mut sum = 0usize;
        let n = 4000;
        for _ in 0..n {
            let o = Vec3::new(rng.range(-100.0, 100.0), rng.range(-280.0, 280.0), 50.0);
            let c = t.scene.crossings(o, -Vec3::Z, f32::INFINITY);
            assert_eq!(c, t.scene.crossings_brute_force(o, -Vec3::Z, f32::INFINITY));
            sum += c;
        }
        let mean = sum as f64 / n as f64;
        let expected = 2.0 * p.radius as f64 * t.fibre_count as f64 / p.width as f64;
        println!("f {f}: crossings {mean:.3}, expected {expected:.3}");
        assert!((mean / expected - 1.0).abs() < 0.03, "{mean} vs {expected}");
    }
}

/// Same seed, same bytes; any thread count, same bytes.
#[test]
fn estimates_are_deterministic() {
    let t = tuft(&tuft_params(0.3, 5)).unwrap();
    let light = DirectionalLight {
        to_light: Vec3::new(0.3, 0.4, 1.0),
        irradiance: Vec3::splat(2.0),
    };
    let tracer = PathTracer::new(&Params::default(), Some(light), Vec3::splat(0.2), 64).unwrap();
    let rays = t.camera_rays(Vec3::new(0.2, 0.3, 1.0), 8.0, 23, 3).unwrap();
    let bytes = |v: Vec<coif_shading::path_tracer::RadianceEstimate>| {
        v.iter()
            .flat_map(|e| {
                e.mean
                    .to_array()
                    .into_iter()
                    .chain(e.standard_error.to_array())
                    .chain([e.mean_scatterings])
                    .map(f32::to_bits)
            })
            .collect::<Vec<u32>>()
    };
    let a = bytes(tracer.estimate(&t.scene, &rays, 16, 99).unwrap());
    assert_eq!(a, bytes(tracer.estimate(&t.scene, &rays, 16, 99).unwrap()));
    for threads in [0, 2, 3, 7, 100] {
        let b = tracer
            .estimate_threaded(&t.scene, &rays, 16, 99, threads)
            .unwrap();
        assert_eq!(a, bytes(b), "{threads} threads");
    }
    assert_ne!(a, bytes(tracer.estimate(&t.scene, &rays, 16, 100).unwrap()));
    // Same tuft from the same seed.
    let t2 = tuft(&tuft_params(0.3, 5)).unwrap();
    assert_eq!(t.fibre_count, t2.fibre_count);
    assert_eq!(t.scene.segment(17), t2.scene.segment(17));
}

#[test]
fn bad_input_is_refused() {
    fn p(name: &'static str) -> impl Fn(Error) -> bool {
        move |e: Error| matches!(e, Error::InvalidParameter { name: n, .. } if n == name)
    }
    let ok = [Vec3::ZERO, Vec3::X];
    assert!(FibreScene::from_strands(&ok, &[2], 0.1).is_ok());
    assert!(p("points")(
        FibreScene::from_strands(&[Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0)], &[2], 0.1)
            .unwrap_err()
    ));
    assert!(p("points")(
        FibreScene::from_segments(&[(Vec3::ZERO, Vec3::splat(f32::INFINITY))], 0.1).unwrap_err()
    ));
    for r in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(p("radius")(
            FibreScene::from_strands(&ok, &[2], r).unwrap_err()
        ));
    }
    assert!(p("segments")(
        FibreScene::from_strands(&[], &[], 0.1).unwrap_err()
    ));
    assert!(p("segments")(
        FibreScene::from_segments(&[], 0.1).unwrap_err()
    ));
    assert!(p("segments")(
        FibreScene::from_strands(&[Vec3::ONE, Vec3::ONE], &[2], 0.1).unwrap_err()
    ));
    assert!(matches!(
        FibreScene::from_strands(&ok, &[3], 0.1),
        Err(Error::CountMismatch { .. })
    ));
    assert!(matches!(
        FibreScene::from_strands(&ok, &[usize::MAX, 2], 0.1),
        Err(Error::CountMismatch { .. })
    ));

    let params = Params::default();
    let light = |to_light, irradiance| {
        Some(DirectionalLight {
            to_light,
            irradiance,
        })
    };
    assert!(p("to_light")(
        PathTracer::new(&params, light(Vec3::ZERO, Vec3::ONE), Vec3::ZERO, 4).unwrap_err()
    ));
    assert!(p("to_light")(
        PathTracer::new(&params, light(Vec3::NAN, Vec3::ONE), Vec3::ZERO, 4).unwrap_err()
    ));
    assert!(p("irradiance")(
        PathTracer::new(&params, light(Vec3::Z, Vec3::splat(-1.0)), Vec3::ZERO, 4).unwrap_err()
    ));
    assert!(p("environment")(
        PathTracer::new(&params, None, Vec3::new(0.0, f32::NAN, 0.0), 4).unwrap_err()
    ));
    assert!(p("max_depth")(
        PathTracer::new(&params, None, Vec3::ZERO, usize::MAX).unwrap_err()
    ));
    let bad_material = Params {
        beta_m: f32::NAN,
        ..Params::default()
    };
    assert!(p("beta_m")(
        PathTracer::new(&bad_material, None, Vec3::ZERO, 4).unwrap_err()
    ));

    let tracer = PathTracer::new(&params, None, Vec3::ONE, 4).unwrap();
    let scene = FibreScene::from_strands(&ok, &[2], 0.1).unwrap();
    assert!(p("paths_per_ray")(
        tracer
            .estimate(&scene, &[(Vec3::Y, -Vec3::Y)], 0, 1)
            .unwrap_err()
    ));
    assert!(tracer.estimate(&scene, &[], 4, 1).unwrap().is_empty());
    // Non-finite or huge rays: NaN or a value, never a panic.
    let mut rng = SplitMix64::new(1);
    assert!(tracer
        .radiance(&scene, Vec3::NAN, Vec3::X, &mut rng)
        .is_nan());
    assert!(tracer
        .radiance(&scene, Vec3::Y, Vec3::ZERO, &mut rng)
        .is_nan());
    let _ = tracer.radiance(&scene, Vec3::splat(3e38), -Vec3::ONE, &mut rng);
    let huge = FibreScene::from_segments(
        &[(Vec3::new(-1e38, 0.0, 0.0), Vec3::new(1e38, 1e38, 0.0))],
        3e38,
    )
    .unwrap();
    assert!(p("segment length")(
        FibreScene::from_segments(
            &[(Vec3::new(-1e38, 0.0, 0.0), Vec3::new(1e38, 3e38, 0.0))],
            1.0
        )
        .unwrap_err()
    ));
    let _ = tracer.radiance(&huge, Vec3::new(0.0, 1e38, 0.0), -Vec3::Y, &mut rng);
    let _ = huge.crossings(Vec3::ZERO, Vec3::X, f32::INFINITY);

    for (name, tp) in [
        (
            "radius",
            TuftParams {
                radius: 0.0,
                ..tuft_params(0.2, 1)
            },
        ),
        (
            "length",
            TuftParams {
                length: f32::NAN,
                ..tuft_params(0.2, 1)
            },
        ),
        ("volume_fraction", tuft_params(0.0, 1)),
        ("volume_fraction", tuft_params(0.9, 1)),
        (
            "fibre_count",
            TuftParams {
                radius: 1e-4,
                ..tuft_params(0.5, 1)
            },
        ),
    ] {
        assert!(p(name)(tuft(&tp).unwrap_err()), "{name}");
    }
    assert!(p("from")(
        orthographic_rays(Vec3::ZERO, Vec3::ZERO, 1.0, 1.0, 4, 1).unwrap_err()
    ));
    assert!(p("window")(
        orthographic_rays(Vec3::ZERO, Vec3::Z, 1.0, -1.0, 4, 1).unwrap_err()
    ));
}

/// Speed on one thread (`cargo test --release -p coif-shading --test
/// path_tracer -- --ignored --nocapture`): the white furnace and a lit
/// brown tuft (f = 0.4, 24 r thick), 64 rays x 256 paths each.
#[test]
#[ignore]
fn speed_on_one_thread() {
    let t = tuft(&tuft_params(0.4, 1)).unwrap();
    let rays = t
        .camera_rays(Vec3::new(0.0, 0.6, 0.8), 10.0, 64, 1)
        .unwrap();
    let light = DirectionalLight {
        to_light: Vec3::new(0.3, -0.4, 0.8),
        irradiance: Vec3::ONE,
    };
    for (name, params, light, env) in [
        ("white furnace", white(), None, Vec3::ONE),
        (
            "brown, light + env 0.2",
            Params::default(),
            Some(light),
            Vec3::splat(0.2),
        ),
    ] {
        let tracer = PathTracer::new(&params, light, env, 10_000).unwrap();
        let start = Instant::now();
        let est = tracer.estimate(&t.scene, &rays, 256, 1).unwrap();
        let secs = start.elapsed().as_secs_f64();
        let paths = (rays.len() * 256) as f64;
        let scat = est.iter().map(|e| e.mean_scatterings as f64).sum::<f64>() * 256.0;
        println!(
            "{name}: {:.0} paths/s, {:.0} scatterings/s, {:.1} scatterings/path",
            paths / secs,
            scat / secs,
            scat / paths
        );
    }
}
