//! Marschner 2003 evaluated directly: the paper's properties, the root
//! solvers, and robustness over every pair of directions.

mod common;

use coif_base::SplitMix64;
use coif_shading::marschner::{
    accuracy, azimuthal, fresnel, lobes, longitudinal, scattering, scattering_batch, Params,
    RootSolver,
};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::Vec3;
use std::f32::consts::PI;

use common::fibre_direction as dir;

#[test]
fn r_lobe_peaks_at_alpha_r_for_an_absorbing_fibre() {
    for alpha_deg in [-10.0f32, -7.5, -5.0] {
        let params = Params {
            absorption: Vec3::splat(50.0),
            alpha_r: alpha_deg.to_radians(),
            ..Params::default()
        };
        // theta_d = 0 (theta_i = theta_o = theta_h), fixed phi; scan theta_h.
        let phi = 0.6;
        let total = |th: f32| scattering(&params, Vec3::X, dir(th, 0.0), dir(th, phi)).x;
        let best = (0..=2000)
            .map(|k| (-30.0 + 60.0 * k as f32 / 2000.0).to_radians())
            .max_by(|a, b| total(*a).total_cmp(&total(*b)))
            .unwrap();
        assert!(
            (best - alpha_deg.to_radians()).abs() < 0.06f32.to_radians(),
            "alpha {alpha_deg}: peak at {} deg",
            best.to_degrees()
        );
        // The transmitted lobes are negligible there.
        let l = lobes(&params, Vec3::X, dir(best, 0.0), dir(best, phi));
        assert!(l.tt.x + l.trt.x < 1e-6 * l.r.x);
    }
}

#[test]
fn n_r_is_a_quarter_cos_half_phi_times_fresnel() {
    // Paper, section 4.2: for p = 0, h = -sin(phi/2), |dphi/dh| = 2 / cos gamma_i,
    // so N_R(phi) = cos(phi/2) / 4 * F(eta', eta'', gamma_i). Compare with
    // S_R cos^2 theta_d / M_R from the general root machinery.
    let params = Params::default();
    let eta = params.eta as f64;
    for theta_d_deg in [0.0f32, 20.0, 45.0] {
        for k in 0..12 {
            let phi = -PI + 2.0 * PI * (k as f32 + 0.5) / 12.0;
            let theta_h = 0.05f32;
            let td = theta_d_deg.to_radians();
            let l = accuracy::lobes_at_angles(&params, theta_h - td, theta_h + td, phi);
            let m_r = longitudinal::gaussian(
                params.beta_r as f64,
                theta_h as f64 - params.alpha_r as f64,
            );
            let cd = (td as f64).cos();
            let n_r = l.r.x as f64 * cd * cd / m_r;
            let (ep, epp) = fresnel::bravais(eta, (td as f64).sin(), cd);
            let want =
                (0.5 * phi as f64).cos() / 4.0 * fresnel::fresnel(ep, epp, -0.5 * phi as f64);
            assert!(
                (n_r - want).abs() < 1e-5 * want + 1e-7,
                "phi {phi}: {n_r} vs {want}"
            );
        }
    }
}

#[test]
fn scattering_is_symmetric_in_phi() {
    // Mirror wo across the plane of t and wi: phi -> -phi. Round fibre, and
    // the default elliptical one (major axis along the light's projection).
    let mut rng = SplitMix64::new(3);
    for ecc in [1.0f32, 0.85] {
        let params = Params {
            eccentricity: ecc,
            ..Params::default()
        };
        for _ in 0..300 {
            let ti = rng.range(-1.5, 1.5);
            let to = rng.range(-1.5, 1.5);
            let phi = rng.range(-PI, PI);
            let a = scattering(&params, Vec3::X, dir(ti, 0.0), dir(to, phi));
            let b = scattering(&params, Vec3::X, dir(ti, 0.0), dir(to, -phi));
            assert!(
                (a - b).abs().max_element() <= 2e-5 * a.max_element().max(1e-3),
                "{a} vs {b}"
            );
        }
    }
    // And N_TRT's roots on both sides: the solver finds mirrored roots.
    for k in 0..40 {
        let phi = -3.1 + 6.2 * k as f64 / 39.0;
        let mut a: Vec<f64> = azimuthal::roots_exact(2, phi, 1.55).as_slice().to_vec();
        let mut b: Vec<f64> = azimuthal::roots_exact(2, -phi, 1.55)
            .as_slice()
            .iter()
            .map(|h| -h)
            .collect();
        a.sort_by(f64::total_cmp);
        b.sort_by(f64::total_cmp);
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-9);
        }
    }
}

#[test]
fn eccentricity_changes_only_trt() {
    let round = Params {
        eccentricity: 1.0,
        ..Params::default()
    };
    let oval = Params {
        eccentricity: 0.85,
        ..Params::default()
    };
    let (wi, wo) = (dir(0.1, 0.0), dir(-0.2, 0.4));
    let a = lobes(&round, Vec3::X, wi, wo);
    let b = lobes(&oval, Vec3::X, wi, wo);
    assert_eq!(a.r, b.r);
    assert_eq!(a.tt, b.tt);
    assert!((a.trt - b.trt).abs().max_element() > 1e-4 * a.trt.max_element());
}

#[test]
fn absorption_colours_tt_and_trt_but_not_r() {
    let params = Params::default();
    let l = lobes(&params, Vec3::X, dir(0.1, 0.0), dir(-0.15, 2.8));
    assert_eq!(l.r.x, l.r.y);
    assert_eq!(l.r.y, l.r.z);
    // Absorption grows from red to blue, so transmitted light is reddest.
    assert!(l.tt.x > l.tt.y && l.tt.y > l.tt.z, "{}", l.tt);
}

#[test]
fn cubic_root_approximation_is_close_to_the_exact_roots() {
    // The paper's cubic matches phi(p, h) at h = 0 and h = +-1 but not in
    // between: measured max |h_cubic - h_exact| ~ 0.13 (near the TT cut-off
    // and the caustic, where phi is flat in h) and S differs by ~1.5% RMS.
    let e = accuracy::cubic_root_error(&Params::default(), 3000, 9);
    assert!(
        e.max_h_difference > 1e-4,
        "the cubic is an approximation: {e:?}"
    );
    assert!(e.max_h_difference < 0.25, "{e:?}");
    assert!(e.relative_rms > 1e-4 && e.relative_rms < 0.05, "{e:?}");
    assert!(e.root_count_mismatches * 100 < e.configurations, "{e:?}");
    // Both solvers give the same root for R (the cubic is exact for p = 0).
    for k in 0..20 {
        let phi = -3.0 + 6.0 * k as f64 / 19.0;
        let a = azimuthal::roots_exact(0, phi, 1.6);
        let b = azimuthal::roots_cubic(0, phi, 1.6);
        assert!((a.as_slice()[0] - b.as_slice()[0]).abs() < 1e-12);
    }
    let cubic = Params {
        roots: RootSolver::Cubic,
        ..Params::default()
    };
    assert!(scattering(&cubic, Vec3::X, Vec3::Y, dir(0.1, 2.0)).is_finite());
}

fn adversarial() -> Vec<(Vec3, Vec3, Vec3)> {
    let t = Vec3::new(0.0, 0.6, 0.8);
    let n = Vec3::X;
    let b = t.cross(n);
    let eps = 1e-7;
    let mut v = vec![];
    for (wi, wo) in [
        (t, t),
        (t, -t),
        (-t, t),
        (-t, n),
        (n, t),
        (n, -n),
        (n, n),
        (n, b),
        ((t + eps * n).normalize(), (-t + eps * b).normalize()),
        ((t + 0.01 * n).normalize(), (-t + 0.01 * b).normalize()),
        ((-t + 0.1 * n).normalize(), (t + 0.1 * n).normalize()),
        (3.0 * n, 0.01 * t + n),
        (1e15 * n, 1e-15 * t + 1e-16 * n),
    ] {
        v.push((t, wi, wo));
    }
    v
}

#[test]
fn finite_and_non_negative_for_every_pair_of_directions() {
    let mut rng = SplitMix64::new(21);
    let mut cases = adversarial();
    for _ in 0..20000 {
        cases.push((rng.unit_vector(), rng.unit_vector(), rng.unit_vector()));
    }
    for params in [
        Params::default(),
        Params {
            eccentricity: 0.85,
            eta: 1.9,
            absorption: Vec3::ZERO,
            ..Params::default()
        },
        Params {
            roots: RootSolver::Cubic,
            ..Params::default()
        },
    ] {
        for &(t, wi, wo) in &cases {
            let s = scattering(&params, t, wi, wo);
            assert!(
                s.is_finite() && s.min_element() >= 0.0,
                "{t} {wi} {wo}: {s}"
            );
        }
    }
}

#[test]
fn degenerate_input_gives_zero_or_nan_for_that_sample_only() {
    let p = Params::default();
    assert_eq!(scattering(&p, Vec3::ZERO, Vec3::Y, Vec3::Z), Vec3::ZERO);
    assert_eq!(scattering(&p, Vec3::X, Vec3::ZERO, Vec3::Z), Vec3::ZERO);
    assert!(scattering(&p, Vec3::X, Vec3::new(f32::NAN, 0.0, 1.0), Vec3::Z).is_nan());
    assert!(scattering(&p, Vec3::X, Vec3::Y, Vec3::new(0.0, f32::INFINITY, 1.0)).is_nan());
    // Non-unit directions give the same as unit ones.
    let a = scattering(&p, Vec3::X, dir(0.2, 0.0), dir(-0.1, 1.0));
    let b = scattering(&p, 2.0 * Vec3::X, 0.5 * dir(0.2, 0.0), 7.0 * dir(-0.1, 1.0));
    assert!((a - b).abs().max_element() < 1e-5 * a.max_element());
    // Batch: a NaN sample does not spread.
    let mut s = ShadingSamples::default();
    s.push(Vec3::X, Vec3::Y, Vec3::Z);
    s.push(Vec3::X, Vec3::NAN, Vec3::Z);
    s.push(Vec3::X, dir(0.3, 0.0), dir(-0.2, 2.0));
    let mut out = RgbBuffer::default();
    scattering_batch(&p, &s, &mut out);
    assert!(out.get(1).is_nan());
    assert_eq!(out.get(0), scattering(&p, Vec3::X, Vec3::Y, Vec3::Z));
    assert_eq!(
        out.get(2),
        scattering(&p, Vec3::X, dir(0.3, 0.0), dir(-0.2, 2.0))
    );
}
