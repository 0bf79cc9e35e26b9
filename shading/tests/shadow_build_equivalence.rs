//! The SIMD shadow map build (`OpacityShadowMap::build`) makes the same map
//! as its scalar reference (`build_scalar`) bit for bit: every stored
//! opacity compared with `==` on the bits, and lookups (which also read the
//! deep mode's depth map) equal, for slices and deep layers, several light
//! directions, NaN vertices, a partial trailing strand, hair far from the
//! origin and resolutions whose texel count is not a multiple of 16.
//!
//! The same cases for the lane-layout build (`build_lanes`, the fused
//! prepare pass's): SIMD and scalar twin bit for bit (one task), and
//! against `build` on the same strands the same placement and first depths
//! bit for bit, opacities and lookups to float rounding (its deposits add
//! up in another order), lanes that are not hair never read.

mod common;

use coif_base::tasks::Serial;
use coif_base::SplitMix64;
use coif_shading::shadow::{BuildScratch, LaneRows, OpacityShadowMap, ShadowMode, ShadowSettings};
use glam::Vec3;

/// Random wavy strands around `centre`: `strands` strands of `verts`
/// vertices, segments of `step` metres (long ones span many texels, so
/// segments with more than eight samples are covered).
fn hair(strands: usize, verts: usize, step: f32, centre: Vec3, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::with_capacity(strands * verts);
    for _ in 0..strands {
        let mut p = centre + rng.unit_vector() * 0.1;
        let d = rng.unit_vector();
        for _ in 0..verts {
            pts.push(p);
            p += (d + rng.unit_vector() * 0.5).normalize() * step * rng.range(0.2, 1.5);
        }
    }
    pts
}

fn lights() -> [Vec3; 4] {
    [
        Vec3::new(1.0, -0.5, 0.3),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(-0.2, 1.0, 0.05),
        Vec3::new(0.577, 0.577, 0.577),
    ]
}

fn settings(mode: ShadowMode, layers: usize, resolution: usize) -> ShadowSettings {
    ShadowSettings {
        mode,
        layers,
        resolution,
        ..Default::default()
    }
}

/// Builds with both paths and asserts the maps are identical; returns the
/// number of texel planes holding opacity (so callers can check that the
/// case was not empty).
fn assert_same(s: &ShadowSettings, light: Vec3, pts: &[Vec3], verts: usize, what: &str) -> usize {
    let mut simd = OpacityShadowMap::new(s.clone()).unwrap();
    let mut scalar = OpacityShadowMap::new(s.clone()).unwrap();
    simd.build(light, pts, verts);
    coif_shading::shadow::scalar::build(&mut scalar, light, pts, verts);
    assert_eq!(simd.is_ready(), scalar.is_ready(), "{what}: readiness");
    assert_eq!(simd.placement(), scalar.placement(), "{what}: placement");
    let n = s.resolution;
    let mut filled = 0;
    for y in 0..n {
        for x in 0..n {
            for l in 0..s.layers {
                let (a, b) = (simd.stored_opacity(x, y, l), scalar.stored_opacity(x, y, l));
                assert!(
                    a.to_bits() == b.to_bits(),
                    "{what}: texel ({x}, {y}) plane {l}: simd {a} scalar {b}"
                );
                filled += usize::from(a > 0.0);
            }
        }
    }
    // The deep mode's depth map is private: lookups read it, so equal
    // lookups at every vertex (and beside them) check it too.
    for p in pts.iter().flat_map(|p| [*p, *p + Vec3::splat(0.003)]) {
        let (a, b) = (simd.transmittance(p), scalar.transmittance(p));
        assert!(
            a.to_bits() == b.to_bits(),
            "{what}: lookup at {p}: {a} vs {b}"
        );
    }
    assert_lanes(s, light, pts, verts, &simd, what);
    filled
}

/// The lane-layout builds of the same strands: SIMD (one task) and scalar
/// bit for bit; against `points_map` (the `build` of `pts`) the same
/// readiness, placement and first depths, opacities within 1e-5 relative
/// (1e-5 absolute below 1) and lookups within 1e-5.
fn assert_lanes(
    s: &ShadowSettings,
    light: Vec3,
    pts: &[Vec3],
    verts: usize,
    points_map: &OpacityShadowMap,
    what: &str,
) {
    let (rows, strands) = common::lane_rows(pts, verts);
    let hair = LaneRows {
        rows: &rows,
        verts,
        strands,
    };
    let mut simd = OpacityShadowMap::new(s.clone()).unwrap();
    let mut scalar = OpacityShadowMap::new(s.clone()).unwrap();
    let mut scratch = BuildScratch::new(s, 1).unwrap();
    simd.build_lanes(&Serial, &mut scratch, light, &hair)
        .unwrap();
    coif_shading::shadow::scalar::build_lanes(&mut scalar, light, &hair);
    assert_eq!(
        common::stored_bits(&simd),
        common::stored_bits(&scalar),
        "{what}: lanes, simd against scalar"
    );
    assert_eq!(
        simd.is_ready(),
        points_map.is_ready(),
        "{what}: lanes readiness"
    );
    assert_eq!(
        simd.is_ready(),
        scalar.is_ready(),
        "{what}: lanes readiness"
    );
    if !simd.is_ready() {
        return;
    }
    assert_eq!(
        simd.placement(),
        points_map.placement(),
        "{what}: lanes placement"
    );
    let n = s.resolution;
    for y in 0..n {
        for x in 0..n {
            let z = [&simd, &scalar, points_map].map(|m| m.first_depth(x, y).map(f32::to_bits));
            assert!(
                z[0] == z[1] && z[0] == z[2],
                "{what}: first depth ({x}, {y}): {z:?}"
            );
            for l in 0..s.layers {
                let (a, b) = (
                    simd.stored_opacity(x, y, l),
                    points_map.stored_opacity(x, y, l),
                );
                assert!(
                    (a - b).abs() <= 1e-5 * b.abs().max(1.0),
                    "{what}: lanes texel ({x}, {y}) plane {l}: {a} vs {b}"
                );
            }
        }
    }
    for p in pts.iter().flat_map(|p| [*p, *p + Vec3::splat(0.003)]) {
        let (a, b) = (simd.transmittance(p), points_map.transmittance(p));
        assert!(
            (a - b).abs() <= 1e-5,
            "{what}: lanes lookup at {p}: {a} vs {b}"
        );
    }
}

#[test]
fn simd_build_equals_scalar_build_bit_for_bit() {
    let pts = hair(150, 12, 0.02, Vec3::ZERO, 7);
    for (mode, layers) in [
        (ShadowMode::Slices, 16),
        (ShadowMode::Slices, 6),
        (ShadowMode::Deep, 3),
        (ShadowMode::Deep, 5),
    ] {
        // 64^2 = 4096 texels (a multiple of 16); 61^2 = 3721 (not: the
        // prefix sum's scalar tail runs).
        for resolution in [64, 61] {
            for light in lights() {
                let s = settings(mode, layers, resolution);
                let what = format!("{mode:?} {layers} at {resolution}^2, light {light}");
                let filled = assert_same(&s, light, &pts, 12, &what);
                assert!(filled > 1000, "{what}: only {filled} planes filled");
            }
        }
    }
}

#[test]
fn simd_build_equals_scalar_with_nan_vertices_partial_strands_and_far_hair() {
    let mut pts = hair(101, 9, 0.015, Vec3::ZERO, 11);
    // NaN and infinite vertices: at a root, mid-strand, at a tip.
    pts[0] = Vec3::NAN;
    pts[9 * 5 + 4].y = f32::NAN;
    pts[9 * 17 + 8] = Vec3::INFINITY;
    // A partial trailing strand (ignored by both).
    pts.extend_from_slice(&[Vec3::ZERO, Vec3::new(0.05, 0.0, 0.0), Vec3::ONE]);
    // Hair a kilometre from the origin (coarse f32 positions).
    let far = hair(80, 9, 0.015, Vec3::new(1000.0, -700.0, 300.0), 13);
    // Strands of 20 vertices (19 segments: chunks of 8, 8 and 3 in the
    // SIMD segment setup) broken at vertex 7 (the last of the first chunk:
    // segment 8, the next chunk's first, starts a new piece and gets the
    // cap), at vertex 8 and at vertex 16.
    let mut long = hair(60, 20, 0.015, Vec3::ZERO, 17);
    for (strand, vertex) in [(3, 7), (10, 8), (11, 16), (12, 7), (12, 9)] {
        long[strand * 20 + vertex].x = f32::NAN;
    }
    for (mode, layers) in [(ShadowMode::Slices, 16), (ShadowMode::Deep, 3)] {
        for light in lights() {
            let s = settings(mode, layers, 48);
            for (name, p, verts) in [
                ("nan/partial", &pts, 9),
                ("far", &far, 9),
                ("long broken", &long, 20),
            ] {
                let what = format!("{name} {mode:?} light {light}");
                let filled = assert_same(&s, light, p, verts, &what);
                assert!(filled > 300, "{what}: only {filled} planes filled");
            }
        }
    }
}

#[test]
fn simd_build_equals_scalar_on_degenerate_input() {
    let s = settings(ShadowMode::Deep, 3, 16);
    let one_point = [Vec3::new(0.1, 0.2, 0.3); 4];
    let all_nan = [Vec3::NAN; 8];
    let huge = [
        Vec3::splat(3.0e38),
        Vec3::splat(-3.0e38),
        Vec3::ZERO,
        Vec3::X,
    ];
    for (name, p, verts) in [
        ("one point", &one_point[..], 2),
        ("all NaN", &all_nan[..], 4),
        ("overflowing", &huge[..], 2),
        ("one vertex per strand", &one_point[..], 1),
    ] {
        for light in [Vec3::Z, Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)] {
            assert_same(&s, light, p, verts, name);
        }
    }
}
