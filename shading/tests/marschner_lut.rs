//! Marschner's factored lookup tables: error against the direct model at
//! resolutions 32..256 for Nalu's layout and coif's, SIMD = scalar, and
//! robustness.

use coif_base::SplitMix64;
use coif_shading::marschner::lut::{MAX_RESOLUTION, MIN_RESOLUTION};
use coif_shading::marschner::{accuracy, scattering, Lut, LutLayout, Params};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::Vec3;

const SAMPLES: usize = 20_000;
const SEED: u64 = 1;

#[test]
fn error_against_direct_shrinks_with_resolution() {
    let p = Params::default();
    let mut previous = [f64::INFINITY; 4];
    for res in [32, 64, 128, 256] {
        let mut errors = [0.0; 4];
        for (k, layout) in LutLayout::ALL.into_iter().enumerate() {
            errors[k] = accuracy::lut_relative_rms_error(&p, res, layout, SAMPLES, SEED);
            assert!(
                errors[k] < previous[k],
                "{layout:?} at {res}: {} !< {}",
                errors[k],
                previous[k]
            );
            eprintln!(
                "resolution {res:4} {layout:?}: relative RMS {:.4}",
                errors[k]
            );
        }
        // coif's angular layout beats Nalu's at every resolution.
        assert!(errors[2] < errors[0], "{errors:?}");
        if res >= 128 {
            // Indexing phi linearly halves the error of cos phi indexing once
            // theta is no longer the bottleneck (the glints sit near phi = 0).
            assert!(errors[2] < errors[3], "{errors:?}");
        }
        previous = errors;
    }
}

#[test]
fn angular_table_at_128_stays_within_four_percent_over_seeds() {
    // The target is 1 % relative RMS at 128 x 128. It is NOT met
    // robustly: the error is heavy-tailed (a few samples near the TRT glints
    // and caustic dominate it) and measures 0.9-2.1 % with 20,000 samples and
    // 1.7-3.2 % with 400,000, depending on the seed. What holds over seeds is
    // the bound below (measured worst 2.0 % at 100,000 samples).
    let p = Params::default();
    for seed in [1, 2, 3] {
        let e = accuracy::lut_relative_rms_error(&p, 128, LutLayout::Angular, 100_000, seed);
        assert!(e < 0.04, "seed {seed}: {e}");
        let nalu = accuracy::lut_relative_rms_error(&p, 128, LutLayout::Nalu, 20_000, seed);
        assert!(e < nalu / 5.0, "seed {seed}: angular {e} vs Nalu {nalu}");
    }
}

#[test]
fn lookups_at_table_nodes_reproduce_the_direct_model() {
    // Where every coordinate lands on a texel (angular layout): theta_i and
    // theta_o on the grid, phi on the grid, and cos theta_d on a grid line,
    // the bilinear lookup returns the tabulated direct values. Choose
    // theta_i = -theta_o so that theta_h = 0 and cos theta_d = cos theta_o; with
    // res - 1 = 90, the grids hold 2 deg steps in theta and phi.
    let p = Params::default();
    let lut = Lut::new(&p, 91);
    let t = Vec3::X;
    for (to_deg, phi_deg) in [(0.0f32, 0.0f32), (0.0, 180.0), (0.0, 40.0), (0.0, 90.0)] {
        let (to, phi) = (to_deg.to_radians(), phi_deg.to_radians());
        let wi = Vec3::new((-to).sin(), (-to).cos(), 0.0);
        let wo = Vec3::new(to.sin(), to.cos() * phi.cos(), to.cos() * phi.sin());
        let a = lut.scattering(t, wi, wo);
        let b = scattering(&p, t, wi, wo);
        assert!(
            (a - b).abs().max_element() < 2e-3 * b.max_element(),
            "{to_deg} {phi_deg}: {a} vs {b}"
        );
    }
}

fn samples(n: usize, seed: u64) -> ShadingSamples {
    let mut rng = SplitMix64::new(seed);
    let mut s = ShadingSamples::with_capacity(n + 16);
    for _ in 0..n {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    let t = Vec3::new(0.0, 0.6, 0.8);
    let (x, b) = (Vec3::X, t.cross(Vec3::X));
    for (wi, wo) in [
        (t, t),
        (t, -t),
        (-t, x),
        (x, -x),
        (x, b),
        ((t + 1e-7 * x).normalize(), (-t + 1e-7 * b).normalize()),
        (5.0 * x, 0.1 * t),
        (1e15 * x, 1e-15 * b),
    ] {
        s.push(t, wi, wo);
    }
    s
}

#[test]
fn simd_batch_matches_scalar_for_every_layout() {
    let p = Params::default();
    let s = samples(5001, 4);
    for layout in LutLayout::ALL {
        let lut = Lut::with_layout(&p, 64, layout);
        let (mut a, mut b) = (RgbBuffer::default(), RgbBuffer::default());
        lut.scattering_batch(&s, &mut a);
        coif_shading::marschner::lut::scalar::scattering_batch(&lut, &s, &mut b);
        let mut worst = 0.0f32;
        for i in 0..s.len() {
            let (x, y) = (a.get(i), b.get(i));
            assert!(
                x.is_finite() && x.min_element() >= 0.0,
                "{layout:?} {i}: {x}"
            );
            // Same arithmetic except wide's asin/acos polynomials (~1e-7
            // relative in angle) moving the bilinear weights: measured
            // worst 1.2e-5 relative, Nalu's layout (no inverse trigonometry)
            // bit-identical.
            let tol = 1e-4 * y.max_element().max(1e-2);
            worst = worst.max((x - y).abs().max_element() / y.max_element().max(1e-2));
            assert!(
                (x - y).abs().max_element() <= tol,
                "{layout:?} {i}: {x} vs {y}"
            );
        }
        eprintln!("{layout:?}: worst relative SIMD-scalar difference {worst:e}");
    }
}

#[test]
fn scalar_lookup_is_finite_and_non_negative_everywhere() {
    let s = samples(20_000, 8);
    for layout in LutLayout::ALL {
        let lut = Lut::with_layout(&Params::default(), 32, layout);
        for i in 0..s.len() {
            let (t, wi, wo) = s.get(i);
            let v = lut.scattering(t, wi, wo);
            assert!(
                v.is_finite() && v.min_element() >= 0.0,
                "{layout:?} {i}: {v}"
            );
        }
    }
}

#[test]
fn bad_samples_stay_in_their_lane_and_resolution_is_clamped() {
    assert_eq!(Lut::new(&Params::default(), 0).resolution(), MIN_RESOLUTION);
    assert_eq!(
        Lut::new(&Params::default(), 1 << 40).resolution(),
        MAX_RESOLUTION
    );
    let weird = Params {
        eta: f32::NAN,
        beta_r: 0.0,
        eccentricity: -1.0,
        ..Params::default()
    };
    let _ = Lut::new(&weird, 4); // must not panic
    let lut = Lut::new(&Params::default(), 32);
    let mut s = samples(16, 2);
    let (t, wi, mut wo) = s.get(2);
    wo.z = f32::NAN;
    s.set(2, t, wi, wo).unwrap();
    let (mut t, wi, wo) = s.get(10);
    t.y = f32::NEG_INFINITY;
    s.set(10, t, wi, wo).unwrap();
    let (t, _, wo) = s.get(5);
    s.set(5, t, Vec3::ZERO, wo).unwrap();
    let mut out = RgbBuffer::default();
    lut.scattering_batch(&s, &mut out);
    for i in 0..16 {
        let v = out.get(i);
        let (t, wi, wo) = s.get(i);
        match i {
            2 | 10 => assert!(v.is_nan() && lut.scattering(t, wi, wo).is_nan(), "{i}"),
            5 => assert_eq!(v, Vec3::ZERO),
            _ => assert!(
                (v - lut.scattering(t, wi, wo)).abs().max_element()
                    < 1e-3 * v.max_element().max(1e-2)
            ),
        }
    }
}
