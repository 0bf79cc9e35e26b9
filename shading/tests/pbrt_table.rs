//! The far-field lookup tables: error against the directly evaluated far
//! field at resolutions 32 to 256, the parameterisation against Nalu's,
//! SIMD batch against scalar lookups, and constructor validation.

use coif_base::SplitMix64;
use coif_shading::pbrt::{quality, FarField, Parameterisation, Params, Table};
use coif_shading::{Error, RgbBuffer, ShadingSamples};
use glam::Vec3;

/// Relative RMS error over random directions, default material (pbrt-v3's
/// defaults): bilinear interpolation error falls about fourfold per
/// doubling, and the target of 1% is met from 128 on.
#[test]
fn table_error_falls_with_resolution_and_meets_one_percent() {
    let p = Params::default();
    let errors: Vec<f32> = [32, 64, 128, 256]
        .iter()
        .map(|&r| quality::table_error(&p, r, 2000, 3).unwrap())
        .collect();
    for w in errors.windows(2) {
        assert!(w[1] < 0.5 * w[0], "{errors:?}");
    }
    assert!(errors[2] < 0.01, "128: {errors:?}");
    assert!(errors[3] < 0.003, "256: {errors:?}");
}

/// Uniform angles beat Nalu's sin theta / cos phi axes at the same size:
/// cos phi is flat near phi = 0 and pi, where the R and TT lobes sit.
#[test]
fn angle_axes_beat_nalu_axes() {
    let p = Params::default();
    for res in [64, 128] {
        let angles =
            quality::table_error_with_axes(&p, res, Parameterisation::Angles, 2000, 4).unwrap();
        let nalu =
            quality::table_error_with_axes(&p, res, Parameterisation::Nalu, 2000, 4).unwrap();
        assert!(angles < 0.25 * nalu, "{res}: angles {angles} nalu {nalu}");
    }
}

/// At the grid nodes the table holds the far field itself: a lookup there
/// equals direct evaluation up to the coordinate polynomial's rounding.
#[test]
fn table_reproduces_the_far_field_at_grid_nodes() {
    let p = Params::default();
    let res = 33;
    let table = Table::new(&p, res).unwrap();
    let ff = FarField::new(&p, coif_shading::pbrt::recommended_order(&p)).unwrap();
    let node = |k: usize| {
        -std::f32::consts::FRAC_PI_2 + std::f32::consts::PI * k as f32 / (res - 1) as f32
    };
    for (i, o, f) in [
        (16, 16, 0),
        (10, 20, 8),
        (20, 12, 32),
        (1, 30, 16),
        (25, 5, 31),
    ] {
        let (ti, to) = (node(i), node(o));
        let phi = std::f32::consts::PI * f as f32 / (res - 1) as f32;
        let got = table.lookup(ti.sin(), to.sin(), phi.cos());
        let want = ff.eval_angles(ti.sin(), to.sin(), phi);
        let tol = 2e-3 * want.max_element().max(1e-3);
        assert!(
            (got - want).abs().max_element() <= tol,
            "{i} {o} {f}: {got} {want}"
        );
    }
}

fn batch(n: usize, seed: u64) -> ShadingSamples {
    let mut rng = SplitMix64::new(seed);
    let mut s = ShadingSamples::with_capacity(n);
    for k in 0..n {
        let t = rng.unit_vector();
        let (wi, wo) = match k % 7 {
            // Along the fibre and grazing configurations.
            0 => (t, rng.unit_vector()),
            1 => (rng.unit_vector(), -t),
            _ => (rng.unit_vector(), rng.unit_vector()),
        };
        s.push(t, wi, wo);
    }
    s
}

#[test]
fn simd_batch_equals_scalar_lookups() {
    let p = Params::default();
    for axes in [Parameterisation::Angles, Parameterisation::Nalu] {
        let table = Table::with_axes(&p, 64, axes).unwrap();
        // 1003 samples: a partial last block exercises the padding.
        let samples = batch(1003, 21);
        let (mut simd, mut scalar) = (RgbBuffer::default(), RgbBuffer::default());
        table.scattering_batch(&samples, &mut simd);
        coif_shading::pbrt::table::scalar::scattering_batch(&table, &samples, &mut scalar);
        assert_eq!(simd.len(), 1003);
        for k in 0..samples.len() {
            let (a, b) = (simd.get(k), scalar.get(k));
            // Same operations in the same order (explicit mul_add on both
            // sides): bit-identical results.
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "{axes:?} {k}: {a} {b}"
            );
            assert!(a.is_finite() && a.min_element() >= 0.0);
            let (t, wi, wo) = samples.get(k);
            assert_eq!(b, table.scattering(t, wi, wo));
        }
    }
}

#[test]
fn nan_sample_stays_in_its_lane() {
    let table = Table::new(&Params::default(), 32).unwrap();
    let mut samples = batch(16, 5);
    let (t, mut wi, wo) = samples.get(3);
    wi.y = f32::NAN;
    samples.set(3, t, wi, wo).unwrap();
    let mut out = RgbBuffer::default();
    table.scattering_batch(&samples, &mut out);
    for k in 0..16 {
        let v = out.get(k);
        if k == 3 {
            assert!(v.is_nan(), "{v}");
        } else {
            assert!(v.is_finite(), "{k}: {v}");
        }
    }
    let (t, wi, wo) = samples.get(3);
    assert!(table.scattering(t, wi, wo).is_nan());
}

#[test]
fn constructors_validate() {
    let p = Params::default();
    assert_eq!(Table::new(&p, 1).unwrap_err(), Error::InvalidResolution(1));
    let bad = Params {
        beta_m: 0.0,
        ..Params::default()
    };
    assert!(matches!(
        Table::new(&bad, 32),
        Err(Error::InvalidParameter { name: "beta_m", .. })
    ));
    let bad = Params {
        sigma_a: Vec3::new(0.1, f32::NAN, 0.0),
        ..Params::default()
    };
    assert!(Table::new(&bad, 32).is_err());
    assert!(FarField::new(&p, 0).is_err());
    assert!(!format!("{}", Error::InvalidResolution(1)).is_empty());
}

/// The table reflects the same energy as the far field it samples: the
/// sphere integral of a 128 table is within 1% of the far field's, for a
/// white and an absorbing material.
#[test]
fn table_integrates_like_the_far_field() {
    use std::f32::consts::PI;
    let white = Params {
        sigma_a: Vec3::ZERO,
        ..Params::default()
    };
    for p in [white, Params::default()] {
        let table = Table::new(&p, 128).unwrap();
        let ff = FarField::new(&p, coif_shading::pbrt::recommended_order(&p)).unwrap();
        for theta_o in [-0.8f32, 0.1, 1.0] {
            let wo = Vec3::new(theta_o.sin(), theta_o.cos(), 0.0);
            let (n_t, n_p) = (160, 90);
            let (mut a, mut b) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
            for i in 0..n_t {
                let s = -1.0 + (i as f32 + 0.5) * 2.0 / n_t as f32;
                let c = (1.0 - s * s).sqrt();
                for j in 0..n_p {
                    let phi = (j as f32 + 0.5) * 2.0 * PI / n_p as f32;
                    let wi = Vec3::new(s, c * phi.cos(), c * phi.sin());
                    a += table.scattering(Vec3::X, wi, wo).as_dvec3();
                    b += ff.eval(Vec3::X, wi, wo).as_dvec3();
                }
            }
            let rel = ((a - b) / b).abs().max_element();
            assert!(rel < 0.01, "theta_o {theta_o}: table {a} far field {b}");
        }
    }
}
