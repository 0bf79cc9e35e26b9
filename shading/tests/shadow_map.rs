//! Opacity shadow maps: settings, the analytic slab, the exact reference,
//! SIMD against scalar, bad input.

use coif_base::{SplitMix64, Vec3Lanes, LANES};
use coif_shading::shadow::{exact_transmittance, OpacityShadowMap, ShadowMode, ShadowSettings};
use coif_shading::Error;
use glam::Vec3;

const RADIUS: f32 = 0.0004;
const SPACING: f32 = 4.0 * RADIUS;
const LAYER_GAP: f32 = 0.01;
const LAYERS: usize = 6;
const VERTS: usize = 11;

/// `LAYERS` layers of straight hairs along x, perpendicular to a light
/// shining along +z: layer m at z = m * LAYER_GAP, hairs at y = j * SPACING,
/// x in [-0.05, 0.05]. A ray toward the light from behind layer m crosses
/// m + 1 layers; each covers the fraction 2 r / SPACING = 1/2 of the plane.
fn slab() -> Vec<Vec3> {
    let mut pts = Vec::new();
    for m in 0..LAYERS {
        for j in -25..=25 {
            for v in 0..VERTS {
                let x = -0.05 + 0.1 * v as f32 / (VERTS - 1) as f32;
                pts.push(Vec3::new(x, j as f32 * SPACING, m as f32 * LAYER_GAP));
            }
        }
    }
    pts
}

fn settings(layers: usize, mode: ShadowMode, resolution: usize) -> ShadowSettings {
    ShadowSettings {
        resolution,
        layers,
        mode,
        hair_radius: RADIUS,
        ..Default::default()
    }
}

/// The opacity of one hair, `1 - exp(-k)`: the map's `T = exp(-alpha sigma)`.
fn opacity(s: &ShadowSettings) -> f32 {
    1.0 - (-s.density).exp()
}

#[test]
fn settings_are_validated() {
    assert!(ShadowSettings::default().validate().is_ok());
    assert!(ShadowSettings::deep().validate().is_ok());
    let bad = [
        ShadowSettings {
            resolution: 1,
            ..Default::default()
        },
        ShadowSettings {
            resolution: 100_000,
            ..Default::default()
        },
        ShadowSettings {
            layers: 0,
            ..Default::default()
        },
        ShadowSettings {
            layers: 1000,
            ..Default::default()
        },
        ShadowSettings {
            density: -1.0,
            ..Default::default()
        },
        ShadowSettings {
            density: f32::NAN,
            ..Default::default()
        },
        ShadowSettings {
            hair_radius: 0.0,
            ..Default::default()
        },
        ShadowSettings {
            hair_radius: f32::INFINITY,
            ..Default::default()
        },
    ];
    for s in bad {
        let e = OpacityShadowMap::new(s.clone()).unwrap_err();
        assert!(
            matches!(e, Error::InvalidShadowSetting { .. }),
            "{s:?}: {e}"
        );
        assert!(!e.to_string().is_empty());
    }
}

#[test]
fn slab_between_layers_matches_the_analytic_opacity() {
    // Texels of 3.3 mm span two hair spacings, so the texel average of the
    // coverage is 1/2 per layer and T = exp(-alpha sigma) with sigma = 1/2
    // per layer in front; 16 slices put no hair between the lookup
    // depth (halfway between layers) and the plane behind it, so OSM is exact
    // there up to the splat's resolution.
    let pts = slab();
    let s = settings(16, ShadowMode::Slices, 32);
    let mut map = OpacityShadowMap::new(s.clone()).unwrap();
    map.build(Vec3::Z, &pts, VERTS);
    for m in 0..LAYERS - 1 {
        let z = (m as f32 + 0.5) * LAYER_GAP;
        let expected = (-opacity(&s) * 0.5 * (m + 1) as f32).exp();
        for (x, y) in [(0.0, 0.0), (0.013, -0.007), (-0.021, 0.011)] {
            let t = map.transmittance(Vec3::new(x, y, z));
            assert!(
                (t - expected).abs() < 0.02 * expected,
                "behind {} layers at ({x}, {y}): T = {t}, analytic {expected}",
                m + 1
            );
        }
    }
    // In front of the first layer: lit.
    assert_eq!(map.transmittance(Vec3::new(0.0, 0.0, -0.01)), 1.0);
    // Outside the footprint: lit.
    assert_eq!(map.transmittance(Vec3::new(0.5, 0.0, 0.03)), 1.0);
}

#[test]
fn slab_behind_everything_holds_all_layers_in_both_modes() {
    let pts = slab();
    let expected = (-opacity(&settings(1, ShadowMode::Slices, 32)) * 0.5 * LAYERS as f32).exp();
    for mode in [ShadowMode::Slices, ShadowMode::Deep] {
        for layers in [1, 3, 4, 16] {
            let mut map = OpacityShadowMap::new(settings(layers, mode, 32)).unwrap();
            map.build(Vec3::Z, &pts, VERTS);
            let t = map.transmittance(Vec3::new(0.004, 0.003, 1.0));
            assert!(
                (t - expected).abs() < 0.02 * expected,
                "{mode:?} {layers}: T = {t}, analytic {expected}"
            );
        }
    }
}

#[test]
fn exact_reference_counts_the_hairs_in_front() {
    let pts = slab();
    let s = settings(16, ShadowMode::Slices, 32);
    for m in 0..LAYERS {
        let z = (m as f32 + 0.5) * LAYER_GAP;
        // Right behind a column of hairs (y = 3 spacings), between joints.
        let p = Vec3::new(0.0037, 3.0 * SPACING, z);
        let t = exact_transmittance(&s, Vec3::Z, &pts, VERTS, p);
        let expected = (-s.density * (m + 1) as f32).exp();
        assert!(
            (t - expected).abs() < 1e-6,
            "behind {} hairs: {t} vs {expected}",
            m + 1
        );
        // Halfway between columns: the ray passes every hair.
        let gap = Vec3::new(0.0037, 3.5 * SPACING, z);
        assert_eq!(exact_transmittance(&s, Vec3::Z, &pts, VERTS, gap), 1.0);
    }
    // A point on a hair does not count its own segment.
    let on = Vec3::new(0.0037, 0.0, 0.0);
    assert_eq!(exact_transmittance(&s, Vec3::Z, &pts, VERTS, on), 1.0);
    // Lit from the other side (-z), the point on layer 0 sees 5 layers.
    let t = exact_transmittance(&s, -Vec3::Z, &pts, VERTS, on);
    assert!((t - (-s.density * 5.0).exp()).abs() < 1e-6, "{t}");
}

/// A blob of random curly strands around the origin.
fn random_hair(strands: usize, verts: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::with_capacity(strands * verts);
    for _ in 0..strands {
        let mut p = rng.unit_vector() * 0.1;
        let d = rng.unit_vector();
        for v in 0..verts {
            pts.push(p);
            let wiggle = rng.unit_vector() * 0.3;
            p += (d + wiggle).normalize() * 0.01 * (1.0 + v as f32 * 0.0);
        }
    }
    pts
}

#[test]
fn transmittance_is_in_unit_range_and_falls_along_the_light() {
    let pts = random_hair(600, 16, 7);
    let light = Vec3::new(0.3, -1.0, 0.2).normalize();
    for mode in [ShadowMode::Slices, ShadowMode::Deep] {
        let mut map = OpacityShadowMap::new(settings(
            if mode == ShadowMode::Deep { 3 } else { 16 },
            mode,
            128,
        ))
        .unwrap();
        map.build(light, &pts, 16);
        let mut rng = SplitMix64::new(3);
        let mut darkest = 1.0f32;
        for _ in 0..200 {
            let start = rng.unit_vector() * 0.08 - light * 0.3;
            let mut prev = 1.0f32;
            for k in 0..120 {
                let t = map.transmittance(start + light * (k as f32 * 0.005));
                assert!((0.0..=1.0).contains(&t), "{mode:?}: T = {t}");
                assert!(
                    t <= prev + 1e-5,
                    "{mode:?}: T rose from {prev} to {t} along the light"
                );
                prev = t;
            }
            darkest = darkest.min(prev);
        }
        assert!(
            darkest < 0.5,
            "{mode:?}: the hair casts almost no shadow ({darkest})"
        );
    }
}

#[test]
fn simd_batch_equals_scalar() {
    let pts = random_hair(300, 12, 11);
    let light = Vec3::new(-0.4, 0.2, 1.0).normalize();
    let mut rng = SplitMix64::new(5);
    // Points inside, around and outside the hair, plus non-finite ones;
    // 1003 is not a multiple of 8.
    let mut queries: Vec<Vec3> = (0..1003)
        .map(|_| rng.unit_vector() * rng.range(0.0, 0.3))
        .collect();
    queries[17] = Vec3::new(f32::NAN, 0.0, 0.0);
    queries[500] = Vec3::new(0.0, f32::INFINITY, 0.0);
    queries[1002] = Vec3::splat(f32::NAN);
    for (mode, layers) in [
        (ShadowMode::Slices, 16),
        (ShadowMode::Slices, 5),
        (ShadowMode::Deep, 3),
    ] {
        let mut map = OpacityShadowMap::new(settings(layers, mode, 64)).unwrap();
        map.build(light, &pts, 12);
        let mut simd = vec![0.0; queries.len()];
        let mut scalar = vec![0.0; queries.len()];
        map.transmittance_batch(&queries, &mut simd).unwrap();
        coif_shading::shadow::scalar::transmittance_batch(&map, &queries, &mut scalar).unwrap();
        let mut shadowed = 0;
        for (i, (a, b)) in simd.iter().zip(&scalar).enumerate() {
            assert!(
                (a - b).abs() <= 1e-6,
                "{mode:?} point {i}: SIMD {a} scalar {b}"
            );
            shadowed += (*b < 0.99) as usize;
        }
        assert!(
            shadowed > 50,
            "{mode:?}: only {shadowed} shadowed points: a vacuous comparison"
        );
        for i in [17, 500, 1002] {
            assert_eq!(simd[i], 1.0);
            assert_eq!(scalar[i], 1.0);
        }
    }
}

#[test]
fn empty_and_broken_input_is_lit_and_does_not_panic() {
    let mut map = OpacityShadowMap::new(ShadowSettings::default()).unwrap();
    let probe = [Vec3::ZERO, Vec3::ONE];
    let mut out = [0.0; 2];
    // Never built, empty, one vertex per strand, zero light, all NaN.
    map.transmittance_batch(&probe, &mut out).unwrap();
    assert_eq!(out, [1.0, 1.0]);
    map.build(Vec3::Z, &[], 16);
    assert_eq!(map.transmittance(Vec3::ZERO), 1.0);
    map.build(Vec3::Z, &[Vec3::ZERO; 8], 1);
    assert_eq!(map.transmittance(Vec3::ZERO), 1.0);
    map.build(Vec3::ZERO, &slab(), VERTS);
    assert!(!map.is_ready());
    map.build(Vec3::Z, &[Vec3::NAN; 22], VERTS);
    map.transmittance_batch(&probe, &mut out).unwrap();
    assert_eq!(out, [1.0, 1.0]);

    // A NaN vertex removes its two segments and nothing else: the slab with
    // one broken vertex still shadows as before away from it.
    let mut pts = slab();
    let mut clean = OpacityShadowMap::new(settings(16, ShadowMode::Slices, 32)).unwrap();
    clean.build(Vec3::Z, &pts, VERTS);
    pts[5] = Vec3::NAN;
    pts[VERTS * 40 + 3] = Vec3::new(f32::INFINITY, 0.0, 0.0);
    let mut broken = OpacityShadowMap::new(settings(16, ShadowMode::Slices, 32)).unwrap();
    broken.build(Vec3::Z, &pts, VERTS);
    let far = Vec3::new(0.03, -0.02, 0.035);
    assert!((clean.transmittance(far) - broken.transmittance(far)).abs() < 1e-6);
    assert!(broken.transmittance(far) < 0.5);
    // Shorter output than input: refused, nothing written.
    let mut short = [7.0; 1];
    assert_eq!(
        broken.transmittance_batch(&[far, far], &mut short),
        Err(coif_shading::Error::CountMismatch {
            what: "transmittances (one per point)",
            expected: 2,
            got: 1
        })
    );
    assert_eq!(short[0], 7.0);
}

#[test]
fn the_map_holds_the_hair_shadow_area() {
    // Behind the last plane every texel holds its average count of segments
    // in front; summed over texels times the texel area, that is the area of
    // the hair's shadow: per strand 2 r * (projected length) + pi r^2 (its
    // round start). The light (0.6, 0, 0.8) is tilted along the hairs (x),
    // so a 0.1 m hair projects to 0.1 * sqrt(1 - 0.6^2) = 0.08 m.
    let pts = slab();
    let strands = pts.len() / VERTS;
    let cap = std::f32::consts::PI * RADIUS * RADIUS;
    let expected = strands as f32 * (2.0 * RADIUS * 0.08 + cap);
    for (mode, layers) in [(ShadowMode::Slices, 16), (ShadowMode::Deep, 3)] {
        let mut map = OpacityShadowMap::new(settings(layers, mode, 48)).unwrap();
        map.build(Vec3::new(0.6, 0.0, 0.8), &pts, VERTS);
        let h = map.placement().texel as f64;
        let mut total = 0.0f64;
        for y in 0..48 {
            for x in 0..48 {
                total += map.stored_opacity(x, y, layers - 1) as f64;
            }
        }
        let area = (total * h * h) as f32;
        assert!(
            (area - expected).abs() < 1e-3 * expected,
            "{mode:?}: deposited {area} m^2, expected {expected} m^2"
        );
    }
}

#[test]
fn hairs_through_are_the_count_far_behind_and_simd_equals_scalar() {
    let pts = random_hair(300, 12, 11);
    let light = Vec3::new(-0.4, 0.2, 1.0).normalize();
    let mut rng = SplitMix64::new(6);
    let queries: Vec<Vec3> = (0..800)
        .map(|_| rng.unit_vector() * rng.range(0.0, 0.3))
        .collect();
    for (mode, layers) in [
        (ShadowMode::Slices, 16),
        (ShadowMode::Slices, 5),
        (ShadowMode::Deep, 3),
    ] {
        let mut map = OpacityShadowMap::new(settings(layers, mode, 64)).unwrap();
        map.build(light, &pts, 12);
        let mut behind_some = 0;
        for block in queries.chunks_exact(LANES) {
            let mut p = Vec3Lanes::splat(block[0]);
            for (l, &q) in block.iter().enumerate() {
                p.set_lane(l, q);
            }
            let (front, through) = map.hairs_in_front_and_through_simd(p);
            let (front, through) = (front.to_array(), through.to_array());
            assert_eq!(front, map.hairs_in_front_simd(p).to_array());
            for (l, &q) in block.iter().enumerate() {
                // The scalar twin, and the count at a point far behind
                // the hair on the same light ray: the last plane's.
                let (f, t) = map.hairs_in_front_and_through(q);
                let far = map.hairs_in_front(q + light * 10.0);
                assert!(
                    (f - front[l]).abs() <= 1e-5 * (1.0 + f),
                    "{mode:?}: {f} vs {}",
                    front[l]
                );
                assert!(
                    (t - through[l]).abs() <= 1e-5 * (1.0 + t),
                    "{mode:?}: {t} vs {}",
                    through[l]
                );
                assert!(
                    (t - far).abs() <= 1e-4 * (1.0 + t),
                    "{mode:?}: through {t}, far behind {far}"
                );
                assert!(t >= f - 1e-4, "{mode:?}: through {t} < in front {f}");
                behind_some += (t > f + 0.05) as usize;
            }
        }
        assert!(
            behind_some > 50,
            "{mode:?}: {behind_some} points with hair behind"
        );
    }
}
