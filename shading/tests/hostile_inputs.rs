//! Every public batch entry point of coif-shading driven with hostile sizes
//! and values (empty, mismatched lengths, NaN, infinities, indices past the
//! end): none panics, and each refuses what it must with the right error.
//! Property tests (proptest): generated inputs find the cases hand-written
//! ones miss.

use coif_base::tasks::Serial;
use coif_shading::kajiya_kay::{self, KajiyaKay};
use coif_shading::marschner::{self, Lut};
use coif_shading::pbrt::{self, FarField, Table};
use coif_shading::shadow::{self, BuildScratch, OpacityShadowMap, ShadowSettings};
use coif_shading::{Error, RgbBuffer, ShadingSamples};
use glam::Vec3;
use proptest::prelude::*;
use std::sync::OnceLock;

/// Any `f32`, with NaN, the infinities, zero and extremes well represented.
fn hostile_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => -2.0f32..2.0,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(0.0f32),
        1 => Just(f32::MAX),
        1 => Just(f32::MIN_POSITIVE),
        1 => any::<f32>(),
    ]
}

fn hostile_vec3() -> impl Strategy<Value = Vec3> {
    (hostile_f32(), hostile_f32(), hostile_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Samples of hostile directions, `0 ..= 40` of them.
fn hostile_samples() -> impl Strategy<Value = ShadingSamples> {
    prop::collection::vec((hostile_vec3(), hostile_vec3(), hostile_vec3()), 0..=40).prop_map(|v| {
        let mut s = ShadingSamples::default();
        for (t, wi, wo) in v {
            s.push(t, wi, wo);
        }
        s
    })
}

/// An output buffer whose public channels have unrelated lengths.
fn ragged_rgb() -> impl Strategy<Value = RgbBuffer> {
    (0usize..50, 0usize..50, 0usize..50).prop_map(|(r, g, b)| RgbBuffer {
        r: vec![7.0; r],
        g: vec![7.0; g],
        b: vec![7.0; b],
    })
}

fn lut() -> &'static Lut {
    static LUT: OnceLock<Lut> = OnceLock::new();
    LUT.get_or_init(|| Lut::new(&marschner::Params::default(), 16))
}

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Table::new(&pbrt::Params::default(), 16).unwrap())
}

fn far_field() -> &'static FarField {
    static FF: OnceLock<FarField> = OnceLock::new();
    FF.get_or_init(|| FarField::new(&pbrt::Params::default(), 8).unwrap())
}

/// A small built shadow map and the hair it was built from.
fn shadow_map() -> &'static (OpacityShadowMap, Vec<Vec3>) {
    static MAP: OnceLock<(OpacityShadowMap, Vec<Vec3>)> = OnceLock::new();
    MAP.get_or_init(|| {
        let pts: Vec<Vec3> = (0..16)
            .flat_map(|s| {
                (0..6).map(move |v| Vec3::new(0.01 * s as f32, -0.02 * v as f32, 0.003 * v as f32))
            })
            .collect();
        let settings = ShadowSettings {
            resolution: 16,
            layers: 8,
            ..Default::default()
        };
        let mut map = OpacityShadowMap::new(settings).unwrap();
        map.build(Vec3::NEG_Y, &pts, 6);
        (map, pts)
    })
}

/// Every batch path gives one value per sample in all three channels.
fn assert_sized(out: &RgbBuffer, n: usize) {
    assert_eq!((out.r.len(), out.g.len(), out.b.len()), (n, n, n));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Samples from columns: accepted exactly when the nine lengths agree.
    #[test]
    fn from_columns_needs_equal_lengths(lens in prop::array::uniform9(0usize..6)) {
        let col = |i: usize| vec![0.5f32; lens[i]];
        let made = ShadingSamples::from_columns(
            [col(0), col(1), col(2)],
            [col(3), col(4), col(5)],
            [col(6), col(7), col(8)],
        );
        if lens.iter().all(|&l| l == lens[0]) {
            let s = made.unwrap();
            prop_assert_eq!(s.len(), lens[0]);
            prop_assert!(s.t().iter().chain(&s.wi()).chain(&s.wo()).all(|a| a.len() == lens[0]));
        } else {
            let is_mismatch = matches!(made, Err(Error::CountMismatch { expected, .. }) if expected == lens[0]);
            prop_assert!(is_mismatch);
        }
    }

    /// Every ShadingSamples batch path, SIMD and scalar, on hostile samples
    /// and a ragged output: no panic, one value per sample in each channel,
    /// and the SIMD and scalar twins agree where they are finite.
    #[test]
    fn batches_never_panic(samples in hostile_samples(), out0 in ragged_rgb(),
                           kk in (hostile_vec3(), hostile_f32(), hostile_f32())) {
        let n = samples.len();
        let mut model = KajiyaKay {
            diffuse: kk.0,
            ..KajiyaKay::default()
        };
        model.primary.exponent = kk.1;
        model.secondary.shift = kk.2;
        let mut a = out0.clone();
        let mut b = out0.clone();
        model.shade_batch(&samples, &mut a);
        kajiya_kay::scalar::shade_batch(&model, &samples, &mut b);
        assert_sized(&a, n);
        assert_sized(&b, n);

        let mut a = out0.clone();
        lut().scattering_batch(&samples, &mut a);
        assert_sized(&a, n);
        let mut b = out0.clone();
        marschner::lut::scalar::scattering_batch(lut(), &samples, &mut b);
        assert_sized(&b, n);

        let mut a = out0.clone();
        table().scattering_batch(&samples, &mut a);
        assert_sized(&a, n);
        let mut b = out0.clone();
        pbrt::table::scalar::scattering_batch(table(), &samples, &mut b);
        assert_sized(&b, n);

        let mut a = out0.clone();
        far_field().scattering_batch(&samples, &mut a);
        assert_sized(&a, n);
        let mut a = out0.clone();
        pbrt::scattering_batch_monte_carlo(&pbrt::Params::default(), &samples, 2, 7, &mut a);
        assert_sized(&a, n);
        let mut a = out0;
        marschner::scattering_batch(&marschner::Params::default(), &samples, &mut a);
        assert_sized(&a, n);
    }

    /// Sample access by index: past the end is `None` / `IndexOutOfRange`,
    /// never a panic, and a refused `set` changes nothing.
    #[test]
    fn sample_indices_past_the_end_are_refused(samples in hostile_samples(), i in 0usize..64,
                                               v in hostile_vec3()) {
        let mut s = samples.clone();
        let n = s.len();
        let set = s.set(i, v, v, v);
        if i < n {
            prop_assert!(set.is_ok());
            let got = s.try_get(i).unwrap();
            prop_assert_eq!(got.0.to_array().map(f32::to_bits), v.to_array().map(f32::to_bits));
        } else {
            prop_assert_eq!(set, Err(Error::IndexOutOfRange { index: i, len: n }));
            prop_assert!(s.try_get(i).is_none());
        }
        // Blocks load and store at any start, padded or clipped.
        let _ = s.load_block(i);
        let _ = s.load_block(usize::MAX);
        let mut out = RgbBuffer { r: vec![0.0; 5], g: vec![0.0; 9], b: vec![] };
        out.store_block(i, coif_base::Vec3Lanes::splat(Vec3::ONE));
        out.store_block(usize::MAX, coif_base::Vec3Lanes::splat(Vec3::ONE));
    }

    /// Shadow lookups: accepted exactly when there is one output per point;
    /// refused calls write nothing.
    #[test]
    fn transmittance_needs_one_output_per_point(
        points in prop::collection::vec(hostile_vec3(), 0..30),
        out_len in 0usize..32,
    ) {
        let (map, _) = shadow_map();
        for simd in [true, false] {
            let mut out = vec![7.0f32; out_len];
            let r = if simd {
                map.transmittance_batch(&points, &mut out)
            } else {
                shadow::scalar::transmittance_batch(map, &points, &mut out)
            };
            if out_len == points.len() {
                prop_assert!(r.is_ok());
                // NaN points may give NaN; finite ones a transmittance in [0, 1].
                for (t, p) in out.iter().zip(&points) {
                    if p.is_finite() {
                        prop_assert!((0.0..=1.0).contains(t), "{} at {}", t, p);
                    }
                }
            } else {
                prop_assert_eq!(r, Err(Error::CountMismatch {
                    what: "transmittances (one per point)",
                    expected: points.len(),
                    got: out_len,
                }));
                prop_assert!(out.iter().all(|&t| t == 7.0));
            }
        }
    }

    /// The far field's azimuthal terms: one output per angle.
    #[test]
    fn azimuthal_needs_one_output_per_phi(phis in prop::collection::vec(hostile_f32(), 0..10),
                                          out_len in 0usize..12, sin_o in hostile_f32()) {
        let mut out = vec![[Vec3::ONE; 4]; out_len];
        let r = far_field().azimuthal(sin_o, (1.0 - sin_o * sin_o).max(0.0).sqrt(), &phis, &mut out);
        if out_len == phis.len() {
            prop_assert!(r.is_ok());
        } else {
            let is_mismatch = matches!(r, Err(Error::CountMismatch { .. }));
            prop_assert!(is_mismatch);
            prop_assert!(out.iter().all(|o| *o == [Vec3::ONE; 4]));
        }
    }

    /// Shadow maps built from hostile hair: any point count (partial strands
    /// included), any vertex count, NaN and infinite points, any light.
    #[test]
    fn shadow_builds_never_panic(points in prop::collection::vec(hostile_vec3(), 0..40),
                                 verts in 0usize..6, light in hostile_vec3(), tasks in 0usize..4) {
        let settings = ShadowSettings { resolution: 8, layers: 4, ..Default::default() };
        let mut map = OpacityShadowMap::new(settings.clone()).unwrap();
        map.build(light, &points, verts);
        let _ = map.transmittance(Vec3::ZERO);
        let mut scratch = BuildScratch::new(&settings, tasks).unwrap();
        prop_assert!(map.build_tasks(&Serial, &mut scratch, light, &points, verts).is_ok());
        let _ = map.transmittance(Vec3::ZERO);
    }
}

/// Scratch made for other settings is refused (and the map left empty).
#[test]
fn mismatched_build_scratch_is_refused() {
    let settings = ShadowSettings {
        resolution: 8,
        layers: 4,
        ..Default::default()
    };
    let other = ShadowSettings {
        resolution: 16,
        ..settings.clone()
    };
    let (_, pts) = shadow_map();
    let mut map = OpacityShadowMap::new(settings).unwrap();
    let mut scratch = BuildScratch::new(&other, 2).unwrap();
    let r = map.build_tasks(&Serial, &mut scratch, Vec3::NEG_Y, pts, 6);
    assert!(matches!(r, Err(Error::CountMismatch { .. })), "{r:?}");
    assert!(!map.is_ready());
    assert_eq!(map.transmittance(Vec3::ZERO), 1.0);
}

/// Sizes no machine can hold are errors, not capacity-overflow panics.
#[test]
fn huge_counts_are_errors() {
    let settings = ShadowSettings {
        resolution: 8,
        layers: 4,
        ..Default::default()
    };
    for tasks in [usize::MAX, usize::MAX / 2, 1 << 60] {
        assert!(matches!(
            BuildScratch::new(&settings, tasks),
            Err(Error::InvalidShadowSetting { name: "tasks", .. })
        ));
    }
    // Lut resolutions are clamped (documented), never an allocation failure.
    let _ = Lut::new(&marschner::Params::default(), 0);
    assert!(matches!(
        Table::new(&pbrt::Params::default(), 1),
        Err(Error::InvalidResolution(1))
    ));
    assert!(FarField::new(&pbrt::Params::default(), 0).is_err());
}

/// Material parameters that are NaN or out of range: errors or
/// sanitised values, never a panic.
#[test]
fn hostile_parameters_never_panic() {
    for bad in [f32::NAN, f32::INFINITY, -1.0, 0.0, 1e30] {
        let p = pbrt::Params {
            eta: bad,
            ..Default::default()
        };
        assert!(p.validate().is_err() || bad == 1e30);
        let _ = pbrt::scattering_local(&p, bad, Vec3::X, Vec3::Y);
        let m = marschner::Params {
            eta: bad,
            alpha_r: bad,
            beta_r: bad,
            ..Default::default()
        };
        let _ = marschner::scattering(&m, Vec3::X, Vec3::Y, Vec3::Z);
        let _ = Lut::new(&m, 4).scattering(Vec3::X, Vec3::Y, Vec3::Z);
        let s = ShadowSettings {
            density: bad,
            hair_radius: bad,
            ..Default::default()
        };
        assert!(OpacityShadowMap::new(s).is_err() || bad == 1e30);
    }
}

/// `RgbBuffer::get` and `set` panic past the end as documented; their
/// forms `try_get` and `try_set` answer for any index.
#[test]
fn rgb_buffer_has_non_panicking_accessors() {
    let mut b = coif_shading::RgbBuffer::zeros(3);
    assert_eq!(b.try_get(2), Some(glam::Vec3::ZERO));
    assert_eq!(b.try_get(3), None);
    assert!(b.try_set(1, glam::Vec3::ONE).is_ok());
    assert_eq!(b.get(1), glam::Vec3::ONE);
    assert!(b.try_set(usize::MAX, glam::Vec3::ONE).is_err());
    assert!(std::panic::catch_unwind(|| b.get(3)).is_err());
}

#[test]
fn sizes_that_would_not_fit_in_memory_are_refused() {
    // Each bound alone passed: 8192^2 texels x 64 RGBA groups is 64 GiB.
    let huge = ShadowSettings {
        resolution: shadow::MAX_RESOLUTION,
        layers: shadow::MAX_LAYERS,
        ..ShadowSettings::default()
    };
    assert!(huge.validate().is_err());
    assert!(OpacityShadowMap::new(huge).is_err());
    let largest = ShadowSettings {
        resolution: 2048,
        layers: 64,
        ..ShadowSettings::default()
    };
    assert!(largest.validate().is_ok(), "2048^2 x 16 groups is the cap");
    // A table of 2^20 nodes per axis, a quadrature of 2^30 nodes.
    let p = pbrt::Params::default();
    assert!(matches!(
        Table::new(&p, 1 << 20),
        Err(Error::InvalidResolution(_))
    ));
    assert!(matches!(
        Table::new(&p, pbrt::MAX_TABLE_RESOLUTION + 1),
        Err(Error::InvalidResolution(_))
    ));
    assert!(matches!(
        FarField::new(&p, 1 << 30),
        Err(Error::InvalidQuadratureOrder(_))
    ));
    assert!(FarField::new(&p, pbrt::MAX_FAR_FIELD_ORDER).is_ok());
}
