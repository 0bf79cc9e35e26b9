//! Kajiya-Kay and Scheuermann's shifted highlights: the formulas at
//! hand-checked configurations, SIMD = scalar, and robustness.

mod common;

use coif_base::SplitMix64;
use coif_shading::kajiya_kay::{Highlight, KajiyaKay};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::Vec3;

use common::fibre_direction as dir;

#[test]
fn diffuse_is_kd_times_sine_to_the_tangent() {
    let kk = KajiyaKay::plain(Vec3::new(0.5, 0.25, 0.125), Vec3::ZERO, 10.0);
    for theta in [-1.4f32, -0.7, 0.0, 0.3, 1.2] {
        let s = kk.shade(Vec3::X, dir(theta, 0.4), dir(0.2, 2.0));
        let want = Vec3::new(0.5, 0.25, 0.125) * theta.cos();
        assert!((s - want).abs().max_element() < 1e-6, "{s} vs {want}");
    }
}

#[test]
fn specular_peaks_on_the_mirror_cone_with_height_ks() {
    let kk = KajiyaKay::plain(Vec3::ZERO, Vec3::ONE, 50.0);
    let theta_i = 0.5f32;
    let wi = dir(theta_i, 0.0);
    // On the cone t . wo = -t . wi the specular is K_s for any azimuth.
    for phi in [0.3f32, 1.5, 3.0] {
        let s = kk.shade(Vec3::X, wi, dir(-theta_i, phi));
        assert!((s.x - 1.0).abs() < 1e-4, "{s}");
    }
    // Scanning theta_o, the maximum is at theta_o = -theta_i.
    let best = (0..=1000)
        .map(|k| -1.5 + 3.0 * k as f32 / 1000.0)
        .max_by(|a, b| {
            let f = |t: f32| kk.shade(Vec3::X, wi, dir(t, 1.0)).x;
            f(*a).total_cmp(&f(*b))
        })
        .unwrap();
    assert!((best + theta_i).abs() < 0.004, "peak at {best}");
    // The value off the cone follows cos(theta_i + theta_o)^p... with both
    // vectors away from the fibre: (s_i s_o - c_i c_o) = cos(a_i + a_o - pi).
    let theta_o = -0.2f32;
    let s = kk.shade(Vec3::X, wi, dir(theta_o, 1.0)).x;
    let base = (theta_i.cos() * theta_o.cos() - theta_i.sin() * theta_o.sin()).powf(50.0);
    assert!((s - base).abs() < 1e-5 * base.max(1e-3), "{s} vs {base}");
}

#[test]
fn shifted_highlight_moves_the_peak_by_the_tilt_angle() {
    // A tangent tilted by atan(shift) toward the (camera-facing) normal moves
    // the mirror cone: for wi, wo in the plane of t and n the peak satisfies
    // theta_o' = -theta_i' about the tilted tangent.
    let shift = 0.2f32;
    let tilt = shift.atan();
    let kk = KajiyaKay {
        diffuse: Vec3::ZERO,
        primary: Highlight {
            color: Vec3::ONE,
            exponent: 200.0,
            shift,
        },
        secondary: Highlight {
            color: Vec3::ZERO,
            exponent: 1.0,
            shift: 0.0,
        },
    };
    let theta_i = 0.4f32;
    let wi = dir(theta_i, 0.0);
    let best = (0..=3000)
        .map(|k| -1.5 + 3.0 * k as f32 / 3000.0)
        .max_by(|a, b| {
            let f = |t: f32| kk.shade(Vec3::X, wi, dir(t, 0.0)).x;
            f(*a).total_cmp(&f(*b))
        })
        .unwrap();
    // With phi = 0, n = +Y and t' = (X + shift Y) / sqrt(1 + shift^2), so for
    // w = (sin theta, cos theta, 0): t' . w = sin(theta + tilt), i.e.
    // theta' = theta + tilt, and the peak theta_o' = -theta_i' is at
    // theta_o = -theta_i - 2 tilt.
    let want = -theta_i - 2.0 * tilt;
    assert!((best - want).abs() < 0.005, "peak {best} want {want}");
}

fn random_samples(n: usize, seed: u64) -> ShadingSamples {
    let mut rng = SplitMix64::new(seed);
    let mut s = ShadingSamples::with_capacity(n);
    for _ in 0..n {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    // Adversarial: along the fibre, opposite, grazing, non-unit, tiny.
    let t = Vec3::new(0.0, 0.6, 0.8);
    let perp = Vec3::X;
    for (wi, wo) in [
        (t, t),
        (t, -t),
        (-t, perp),
        (perp, t),
        (perp, -perp),
        (perp, perp),
        ((t + 1e-7 * perp).normalize(), -t),
        (1e-12 * perp, t),
    ] {
        s.push(t, wi, wo);
    }
    s
}

#[test]
fn simd_batch_matches_scalar() {
    let kk = KajiyaKay::default();
    let samples = random_samples(4003, 11);
    let (mut a, mut b) = (RgbBuffer::default(), RgbBuffer::default());
    kk.shade_batch(&samples, &mut a);
    coif_shading::kajiya_kay::scalar::shade_batch(&kk, &samples, &mut b);
    assert_eq!(a.len(), samples.len());
    // Same algorithm and order; wide's ln/exp polynomials vs libm: 2e-5 relative.
    for i in 0..samples.len() {
        let (x, y) = (a.get(i), b.get(i));
        assert!(x.is_finite() && x.min_element() >= 0.0, "{i}: {x}");
        let tol = 2e-5 * y.abs().max_element().max(1e-3);
        assert!((x - y).abs().max_element() <= tol, "{i}: {x} vs {y}");
    }
}

#[test]
fn bad_samples_stay_in_their_lane() {
    let kk = KajiyaKay::default();
    let mut samples = random_samples(16, 5);
    let (t, mut wi, wo) = samples.get(3);
    wi.y = f32::NAN;
    samples.set(3, t, wi, wo).unwrap();
    let (mut t, wi, wo) = samples.get(9);
    t.x = f32::INFINITY;
    samples.set(9, t, wi, wo).unwrap();
    let (t, wi, _) = samples.get(12);
    samples.set(12, t, wi, Vec3::ZERO).unwrap();
    let mut out = RgbBuffer::default();
    kk.shade_batch(&samples, &mut out);
    for i in 0..16 {
        let v = out.get(i);
        match i {
            3 | 9 => assert!(v.is_nan(), "{i}: {v}"),
            12 => assert_eq!(v, Vec3::ZERO),
            _ => {
                let (t, wi, wo) = samples.get(i);
                let want = kk.shade(t, wi, wo);
                assert!((v - want).abs().max_element() < 1e-4, "{i}");
            }
        }
    }
}
