//! The per-element SIMD entry points a fused per-vertex pass calls
//! (no batch buffers): each `_simd` lane equals its one-element scalar twin
//! (Kajiya-Kay `shade` / `shade_simd`, Marschner `Lut::scattering` /
//! `scattering_simd`, pbrt `Table::scattering` / `scattering_simd`, shadow
//! `transmittance` / `transmittance_simd`), with one light direction splatted
//! over the lanes as a frame has, and a bad lane (NaN, zero length) stays
//! in its lane.

use coif_base::{SplitMix64, Vec3Lanes, LANES};
use coif_shading::kajiya_kay::KajiyaKay;
use coif_shading::shadow::{OpacityShadowMap, ShadowSettings};
use coif_shading::{marschner, pbrt};
use glam::Vec3;

/// Blocks of eight (tangent, view) pairs, the light shared by all lanes;
/// block 0 lane 3 has a NaN tangent and lane 5 a zero view direction.
fn blocks(count: usize, seed: u64) -> (Vec3, Vec<(Vec3Lanes, Vec3Lanes)>) {
    let mut rng = SplitMix64::new(seed);
    let wi = rng.unit_vector();
    let mut out = Vec::new();
    for b in 0..count {
        let (mut t, mut wo) = (Vec3Lanes::ZERO, Vec3Lanes::ZERO);
        for l in 0..LANES {
            t.set_lane(l, rng.unit_vector());
            wo.set_lane(l, rng.unit_vector());
        }
        if b == 0 {
            t.set_lane(3, Vec3::new(f32::NAN, 0.0, 1.0));
            wo.set_lane(5, Vec3::ZERO);
        }
        out.push((t, wo));
    }
    (wi, out)
}

/// Every lane of `x8` against `one` at the same inputs: equal within
/// `rel` of the larger of the value and `floor` (NaN where the scalar is
/// NaN).
fn check_model(
    what: &str,
    rel: f32,
    floor: f32,
    one: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
    x8: impl Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes,
) {
    let (wi, blocks) = blocks(256, 7);
    let mut compared = 0;
    for (b, (t, wo)) in blocks.iter().enumerate() {
        let got = x8(*t, Vec3Lanes::splat(wi), *wo);
        for l in 0..LANES {
            let want = one(t.lane(l), wi, wo.lane(l));
            let g = got.lane(l);
            if want.is_nan() {
                assert!(g.is_nan(), "{what} block {b} lane {l}: {g} vs NaN");
                continue;
            }
            let tol = rel * want.abs().max_element().max(floor);
            assert!(
                (g - want).abs().max_element() <= tol,
                "{what} block {b} lane {l}: {g} vs {want}"
            );
            compared += 1;
        }
    }
    assert!(compared > 2000, "{what}: {compared} lanes compared");
}

#[test]
fn kajiya_kay_x8_equals_shade_per_lane() {
    let kk = KajiyaKay::default();
    // The same operations in the same order; sqrt and the power series are
    // correctly rounded per lane, so only fused-vs-unfused contractions differ.
    check_model(
        "kajiya-kay",
        1e-5,
        1e-3,
        |t, wi, wo| kk.shade(t, wi, wo),
        |t, wi, wo| kk.shade_simd(t, wi, wo),
    );
    let (_, b) = blocks(1, 7);
    let out = kk.shade_simd(b[0].0, Vec3Lanes::splat(Vec3::Y), b[0].1);
    assert!(out.lane(3).is_nan(), "NaN tangent gives NaN");
    assert_eq!(out.lane(5), Vec3::ZERO, "zero view direction gives zero");
    assert!(out.lane(0).is_finite() && out.lane(4).is_finite());
}

#[test]
fn marschner_lut_x8_equals_scattering_per_lane() {
    let lut = marschner::Lut::new(&marschner::Params::default(), 64);
    // wide's asin/acos polynomials against libm's (about 1e-7 in angle).
    check_model(
        "marschner lut",
        1e-4,
        1e-2,
        |t, wi, wo| lut.scattering(t, wi, wo),
        |t, wi, wo| lut.scattering_simd(t, wi, wo),
    );
}

#[test]
fn pbrt_table_x8_equals_scattering_per_lane() {
    let table = pbrt::Table::new(&pbrt::Params::default(), 32).unwrap();
    check_model(
        "pbrt table",
        1e-4,
        1e-2,
        |t, wi, wo| table.scattering(t, wi, wo),
        |t, wi, wo| table.scattering_simd(t, wi, wo),
    );
}

/// A small head of hair: 512 strands of 16 vertices falling from a sphere.
fn hair() -> Vec<Vec3> {
    let mut rng = SplitMix64::new(3);
    let mut pts = Vec::new();
    for _ in 0..512 {
        let root = rng.unit_vector() * 0.1;
        let dir = (root.normalize() + Vec3::new(0.0, -1.0, 0.0)).normalize();
        for v in 0..16 {
            pts.push(root + dir * (0.01 * v as f32));
        }
    }
    pts
}

#[test]
fn transmittance_x8_equals_transmittance_per_lane() {
    let pts = hair();
    for settings in [ShadowSettings::default(), ShadowSettings::deep()] {
        let mut map = OpacityShadowMap::new(ShadowSettings {
            resolution: 64,
            density: 2.0,
            ..settings
        })
        .unwrap();
        let light = Vec3::new(0.3, -1.0, 0.2).normalize();
        let unbuilt = map.transmittance_simd(Vec3Lanes::splat(pts[0]));
        assert_eq!(unbuilt.to_array(), [1.0; LANES], "no build: lit");
        map.build(light, &pts, 16);
        let mut shadowed = 0;
        for (k, chunk) in pts.chunks_exact(LANES).enumerate() {
            let mut p = Vec3Lanes::ZERO;
            for (l, q) in chunk.iter().enumerate() {
                p.set_lane(l, *q);
            }
            if k == 5 {
                p.set_lane(2, Vec3::new(0.0, f32::INFINITY, 0.0));
                p.set_lane(6, Vec3::NAN);
            }
            let got = map.transmittance_simd(p).to_array();
            for (l, g) in got.iter().enumerate() {
                let want = map.transmittance(p.lane(l));
                assert!((g - want).abs() <= 1e-6, "{k} lane {l}: {g} vs {want}");
                shadowed += usize::from(want < 0.9);
            }
            if k == 5 {
                assert_eq!((got[2], got[6]), (1.0, 1.0), "non-finite lanes are lit");
            }
        }
        assert!(shadowed > 500, "the test hair shadows itself ({shadowed})");
    }
}
