//! Dual scattering against the path tracer through explicit fibres
//! (`coif_shading::dual_scattering::accuracy`) on tufts of blond and brown
//! hair: the held-out set of `shading/MULTIPLE_SCATTERING.md` (not the
//! cases the density factors were fitted on), 300 rays of 256 paths per
//! view (about 10 s on two threads). The bounds are the goals: 15 %
//! relative RMS, and for blond at least twice as close as single
//! scattering with the exact shadow; the measured errors and the tracer's
//! noise are beside them.

use coif_shading::dual_scattering::accuracy::{first_hits, relative_rms, shade_hits};
use coif_shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif_shading::path_tracer::{tuft, DirectionalLight, PathTracer, TuftParams};
use coif_shading::pbrt;
use glam::Vec3;

/// Relative RMS errors of dual and single scattering against the tracer
/// over the cases, and the tracer's relative standard error.
fn errors(eumelanin: f32) -> (f64, f64, f64) {
    let params = pbrt::Params {
        sigma_a: pbrt::sigma_a_from_concentration(eumelanin, 0.0),
        ..pbrt::Params::default()
    };
    let table = pbrt::Table::new(&params, 64).unwrap();
    let ds = DualScattering::from_pbrt(&table, DualScatteringSettings::default()).unwrap();
    // `shade_hits` gives each hit the fibres behind it (`shade_layered`).
    let light = DirectionalLight {
        to_light: Vec3::new(-0.4, 0.5, 0.8).normalize(),
        irradiance: Vec3::ONE,
    };
    let tracer = PathTracer::new(&params, Some(light), Vec3::ZERO, 10_000).unwrap();
    let (mut dual, mut single, mut noise) = (Vec::new(), Vec::new(), Vec::new());
    for volume_fraction in [0.1, 0.25] {
        let tf = tuft(&TuftParams {
            length: 40.0,
            width: 40.0,
            thickness: 5.0,
            radius: 0.04,
            volume_fraction,
            seed: 1,
        })
        .unwrap();
        for view in [
            Vec3::new(0.4, -0.3, 1.0),
            Vec3::new(0.0, 1.0, 0.3),
            Vec3::new(-0.2, 0.3, -1.0),
        ] {
            let rays = tf.camera_rays(view, 1.5, 300, 3).unwrap();
            let estimates = tracer
                .estimate_threaded(&tf.scene, &rays, 256, 7, 2)
                .unwrap();
            let n = rays.len() as f32;
            let traced = estimates.iter().map(|e| e.mean).sum::<Vec3>() / n;
            let var = estimates
                .iter()
                .map(|e| e.standard_error * e.standard_error)
                .sum::<Vec3>();
            let hits = first_hits(&tf.scene, &rays, light.to_light);
            let (d, s) = shade_hits(&hits, &table, &ds, light.irradiance);
            dual.push((d, traced));
            single.push((s, traced));
            noise.push((
                traced + Vec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt()) / n,
                traced,
            ));
        }
    }
    (
        relative_rms(dual),
        relative_rms(single),
        relative_rms(noise),
    )
}

#[test]
fn blond_dual_scattering_is_within_15_percent_and_twice_as_close_as_single() {
    let (dual, single, noise) = errors(0.3);
    println!("blond: dual {dual:.3}, single {single:.3}, tracer noise {noise:.4}");
    assert!(noise < 0.03, "tracer noise {noise}");
    // Measured 0.088 (single 0.798), tracer noise 0.016.
    assert!(dual < 0.15, "dual scattering relative RMS {dual}");
    assert!(single > 2.0 * dual, "single {single} vs dual {dual}");
}

#[test]
fn brown_dual_scattering_is_within_15_percent_and_closer_than_single() {
    let (dual, single, noise) = errors(1.3);
    println!("brown: dual {dual:.3}, single {single:.3}, tracer noise {noise:.4}");
    assert!(noise < 0.03, "tracer noise {noise}");
    // Measured 0.095 (single 0.339), tracer noise 0.006.
    assert!(dual < 0.15, "dual scattering relative RMS {dual}");
    assert!(single > dual, "single {single} vs dual {dual}");
}
