//! The C dual scattering calls give exactly what the Rust API gives:
//! `coif_shade_marschner_lut_dual` = `Lut::scattering_batch` then
//! `DualScattering::shade_batch`, `coif_shade_pbrt_table_dual` =
//! `Table::scattering_batch` then `DualScattering::shade_batch`, bit for
//! bit, serially and on an executor, with `behind` NULL (infinitely deep
//! hair); with `behind` given, `DualScattering::shade_layered` per vertex;
//! bad settings, NULL pointers and bad per-vertex inputs are refused with
//! a message and write nothing.

use coif_capi::*;
use coif_shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif_shading::marschner::{self, Lut};
use coif_shading::pbrt::{self, Table};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::Vec3;
use std::ffi::{c_void, CStr};
use std::ptr;

/// 101 vertices (twelve full SIMD blocks and a padded one, several tasks
/// on an executor) with varied tangents.
const N: usize = 101;

fn vertices() -> Vec<CoifRenderVertex> {
    (0..N)
        .map(|k| {
            let a = k as f32 * 0.37;
            CoifRenderVertex {
                position: [0.01 * a.cos(), 0.002 * k as f32, 0.01 * a.sin()],
                width: 80e-6,
                tangent: Vec3::new(a.sin(), -1.0, 0.3 * a.cos())
                    .normalize()
                    .to_array(),
                strand_parameter: k as f32 / (N - 1) as f32,
            }
        })
        .collect()
}

/// Fibre counts from 0 to about 60 and direct fractions that fall with
/// them, with the ends of both ranges (0 fibres, direct 0 and 1) included.
fn shadowing() -> (Vec<f32>, Vec<f32>) {
    let fibres: Vec<f32> = (0..N).map(|k| (k % 13) as f32 * 4.7).collect();
    let direct = fibres
        .iter()
        .enumerate()
        .map(|(k, n)| match k % 7 {
            0 => 1.0,
            1 => 0.0,
            _ => (-0.2 * n).exp(),
        })
        .collect();
    (fibres, direct)
}

/// Fibre counts behind each vertex: none (the far side of the hair), a
/// fraction of a fibre, and up to about 33 (where the backscatter series
/// is nearly the deep hair's).
fn behind() -> Vec<f32> {
    (0..N)
        .map(|k| match k % 5 {
            0 => 0.0,
            1 => 0.5,
            _ => (k % 11) as f32 * 3.3,
        })
        .collect()
}

/// The Rust samples of `vertices` lit from `light`, seen from `eye` (as
/// the C calls make them).
fn samples(verts: &[CoifRenderVertex], light: Vec3, eye: Vec3) -> ShadingSamples {
    let mut s = ShadingSamples::with_capacity(verts.len());
    for v in verts {
        let wo = (eye - Vec3::from_array(v.position)).normalize_or_zero();
        s.push(Vec3::from_array(v.tangent), light.normalize(), wo);
    }
    s
}

fn rgb_flat(rgb: &RgbBuffer) -> Vec<f32> {
    (0..rgb.len()).flat_map(|i| rgb.get(i).to_array()).collect()
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn last_error() -> String {
    // SAFETY: coif returns a NUL-terminated string valid until its next call.
    unsafe { CStr::from_ptr(coif_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// A `run` that calls the tasks on the calling thread, last first.
unsafe extern "C" fn backwards(
    _ctx: *mut c_void,
    count: usize,
    task: CoifTaskFn,
    task_ctx: *mut c_void,
) {
    for i in (0..count).rev() {
        // SAFETY: coif's task with coif's context, each index once.
        unsafe { task(task_ctx, i) };
    }
}

fn executor() -> CoifExecutor {
    CoifExecutor {
        ctx: ptr::null_mut(),
        threads: 4,
        run: Some(backwards),
    }
}

const LIGHT: [f32; 3] = [0.3, 1.0, 0.8];
const EYE: [f32; 3] = [0.2, 0.3, 1.5];

fn settings() -> CoifDualScatteringSettings {
    CoifDualScatteringSettings {
        resolution: 24,
        forward_density: 0.8,
        ..coif_dual_scattering_settings_default()
    }
}

fn rust_settings() -> DualScatteringSettings {
    DualScatteringSettings {
        resolution: 24,
        forward_density: 0.8,
        ..DualScatteringSettings::default()
    }
}

fn new_lut() -> *mut CoifMarschnerLut {
    let mut lut = ptr::null_mut();
    // SAFETY: readable parameters, writable out.
    let status = unsafe { coif_marschner_lut_new(&coif_marschner_params_default(), 32, &mut lut) };
    assert_eq!(status, CoifStatus::COIF_OK);
    lut
}

fn new_table() -> *mut CoifPbrtTable {
    let mut table = ptr::null_mut();
    // SAFETY: as above.
    let status = unsafe { coif_pbrt_table_new(&coif_pbrt_params_default(), 16, &mut table) };
    assert_eq!(status, CoifStatus::COIF_OK);
    table
}

#[test]
fn default_settings_are_the_rust_defaults() {
    let c = coif_dual_scattering_settings_default();
    let r = DualScatteringSettings::default();
    assert_eq!(
        (c.forward_density, c.backward_density, c.resolution),
        (r.forward_density, r.backward_density, r.resolution)
    );
}

#[test]
fn c_dual_scattering_matches_rust_bit_for_bit() {
    let verts = vertices();
    let (fibres, direct) = shadowing();
    let s = samples(&verts, Vec3::from_array(LIGHT), Vec3::from_array(EYE));
    let (mut single, mut want) = (RgbBuffer::default(), RgbBuffer::default());

    // Marschner: the Rust tables, then the Rust batch.
    let rust_lut = Lut::new(&marschner::Params::default(), 32);
    let rust_ds = DualScattering::from_marschner(&rust_lut, rust_settings()).unwrap();
    rust_lut.scattering_batch(&s, &mut single);
    rust_ds
        .shade_batch(&s, &single, &fibres, &direct, &mut want)
        .unwrap();
    let want_marschner = rgb_flat(&want);
    assert!(want_marschner.iter().all(|c| c.is_finite()));
    // Multiple scattering adds light where the direct fraction is below
    // the forward transmittance: not single * direct everywhere.
    let single_direct: Vec<f32> = (0..N)
        .flat_map(|k| (single.get(k) * direct[k]).to_array())
        .collect();
    assert!(!same_bits(&want_marschner, &single_direct));

    // pbrt.
    let rust_table = Table::new(&pbrt::Params::default(), 16).unwrap();
    let rust_ds = DualScattering::from_pbrt(&rust_table, rust_settings()).unwrap();
    rust_table.scattering_batch(&s, &mut single);
    rust_ds
        .shade_batch(&s, &single, &fibres, &direct, &mut want)
        .unwrap();
    let want_pbrt = rgb_flat(&want);
    assert!(want_pbrt.iter().all(|c| c.is_finite()));

    let (lut, table) = (new_lut(), new_table());
    let (mut ds_m, mut ds_p) = (ptr::null_mut(), ptr::null_mut());
    let exec = executor();
    // SAFETY: live handles; every buffer holds what its count says.
    unsafe {
        assert_eq!(
            coif_dual_scattering_from_marschner_lut(lut, &settings(), &mut ds_m),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_dual_scattering_from_pbrt_table(table, &settings(), &mut ds_p),
            CoifStatus::COIF_OK
        );
        for executor in [ptr::null(), &exec as *const CoifExecutor] {
            let mut got = vec![-1.0f32; 3 * (N + 3)];
            assert_eq!(
                coif_shade_marschner_lut_dual_with(
                    lut,
                    ds_m,
                    verts.as_ptr(),
                    N,
                    LIGHT.as_ptr(),
                    EYE.as_ptr(),
                    fibres.as_ptr(),
                    ptr::null(),
                    direct.as_ptr(),
                    got.as_mut_ptr(),
                    N + 3,
                    executor,
                ),
                CoifStatus::COIF_OK
            );
            assert!(same_bits(&got[..3 * N], &want_marschner), "Marschner");
            assert!(got[3 * N..].iter().all(|&c| c == -1.0), "past the count");
            assert_eq!(
                coif_shade_pbrt_table_dual_with(
                    table,
                    ds_p,
                    verts.as_ptr(),
                    N,
                    LIGHT.as_ptr(),
                    EYE.as_ptr(),
                    fibres.as_ptr(),
                    ptr::null(),
                    direct.as_ptr(),
                    got.as_mut_ptr(),
                    N,
                    executor,
                ),
                CoifStatus::COIF_OK
            );
            assert!(same_bits(&got[..3 * N], &want_pbrt), "pbrt");
        }
        // The calls without an executor are the NULL-executor calls.
        let mut got = vec![0.0f32; 3 * N];
        assert_eq!(
            coif_shade_marschner_lut_dual(
                lut,
                ds_m,
                verts.as_ptr(),
                N,
                LIGHT.as_ptr(),
                EYE.as_ptr(),
                fibres.as_ptr(),
                ptr::null(),
                direct.as_ptr(),
                got.as_mut_ptr(),
                N,
            ),
            CoifStatus::COIF_OK
        );
        assert!(same_bits(&got, &want_marschner));
        assert_eq!(
            coif_shade_pbrt_table_dual(
                table,
                ds_p,
                verts.as_ptr(),
                N,
                LIGHT.as_ptr(),
                EYE.as_ptr(),
                fibres.as_ptr(),
                ptr::null(),
                direct.as_ptr(),
                got.as_mut_ptr(),
                N,
            ),
            CoifStatus::COIF_OK
        );
        assert!(same_bits(&got, &want_pbrt));
        assert_eq!(last_error(), "");

        // The tables outlive the handles they were built from.
        coif_marschner_lut_free(lut);
        coif_pbrt_table_free(table);
        coif_dual_scattering_free(ds_m);
        coif_dual_scattering_free(ds_p);
        coif_dual_scattering_free(ptr::null_mut());
    }
}

#[test]
fn c_dual_scattering_with_behind_matches_shade_layered_bit_for_bit() {
    let verts = vertices();
    let (fibres, direct) = shadowing();
    let behind = behind();
    let s = samples(&verts, Vec3::from_array(LIGHT), Vec3::from_array(EYE));
    let mut single = RgbBuffer::default();
    // Per vertex: the model's single scattering, then `shade_layered`.
    let layered = |ds: &DualScattering, single: &RgbBuffer| -> Vec<f32> {
        (0..N)
            .flat_map(|k| {
                let (t, wi, wo) = s.get(k);
                ds.shade_layered(single.get(k), t, wi, wo, fibres[k], behind[k], direct[k])
                    .to_array()
            })
            .collect()
    };
    let deep = |ds: &DualScattering, single: &RgbBuffer| -> Vec<f32> {
        let mut out = RgbBuffer::default();
        ds.shade_batch(&s, single, &fibres, &direct, &mut out)
            .unwrap();
        rgb_flat(&out)
    };

    let rust_lut = Lut::new(&marschner::Params::default(), 32);
    let rust_ds = DualScattering::from_marschner(&rust_lut, rust_settings()).unwrap();
    rust_lut.scattering_batch(&s, &mut single);
    let want_marschner = layered(&rust_ds, &single);
    let deep_marschner = deep(&rust_ds, &single);
    let rust_table = Table::new(&pbrt::Params::default(), 16).unwrap();
    let rust_ds = DualScattering::from_pbrt(&rust_table, rust_settings()).unwrap();
    rust_table.scattering_batch(&s, &mut single);
    let want_pbrt = layered(&rust_ds, &single);
    let deep_pbrt = deep(&rust_ds, &single);
    for (layered, deep) in [(&want_marschner, &deep_marschner), (&want_pbrt, &deep_pbrt)] {
        assert!(layered.iter().all(|c| c.is_finite()));
        // The hair behind a vertex only adds backscatter: never more than
        // infinitely deep hair's, less where nothing is behind it.
        assert!(layered.iter().zip(deep).all(|(l, d)| l <= d));
        assert!((0..N)
            .filter(|k| behind[*k] == 0.0)
            .any(|k| (0..3).all(|c| layered[3 * k + c] < deep[3 * k + c])));
    }

    let (lut, table) = (new_lut(), new_table());
    let (mut ds_m, mut ds_p) = (ptr::null_mut(), ptr::null_mut());
    let exec = executor();
    // SAFETY: live handles; every buffer holds what its count says.
    unsafe {
        assert_eq!(
            coif_dual_scattering_from_marschner_lut(lut, &settings(), &mut ds_m),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_dual_scattering_from_pbrt_table(table, &settings(), &mut ds_p),
            CoifStatus::COIF_OK
        );
        let (v, l, e) = (verts.as_ptr(), LIGHT.as_ptr(), EYE.as_ptr());
        let (f, d) = (fibres.as_ptr(), direct.as_ptr());
        for executor in [ptr::null(), &exec as *const CoifExecutor] {
            for (b, want_m, want_p) in [
                (behind.as_ptr(), &want_marschner, &want_pbrt),
                (ptr::null(), &deep_marschner, &deep_pbrt),
            ] {
                let mut got = vec![-1.0f32; 3 * (N + 3)];
                let o = got.as_mut_ptr();
                assert_eq!(
                    coif_shade_marschner_lut_dual_with(
                        lut,
                        ds_m,
                        v,
                        N,
                        l,
                        e,
                        f,
                        b,
                        d,
                        o,
                        N + 3,
                        executor
                    ),
                    CoifStatus::COIF_OK
                );
                assert!(same_bits(&got[..3 * N], want_m), "Marschner");
                assert!(got[3 * N..].iter().all(|&c| c == -1.0), "past the count");
                assert_eq!(
                    coif_shade_pbrt_table_dual_with(
                        table, ds_p, v, N, l, e, f, b, d, o, N, executor
                    ),
                    CoifStatus::COIF_OK
                );
                assert!(same_bits(&got[..3 * N], want_p), "pbrt");
                // And without an executor argument.
                got.fill(-1.0);
                let o = got.as_mut_ptr();
                assert_eq!(
                    coif_shade_marschner_lut_dual(lut, ds_m, v, N, l, e, f, b, d, o, N),
                    CoifStatus::COIF_OK
                );
                assert!(same_bits(&got[..3 * N], want_m), "Marschner");
                assert_eq!(
                    coif_shade_pbrt_table_dual(table, ds_p, v, N, l, e, f, b, d, o, N),
                    CoifStatus::COIF_OK
                );
                assert!(same_bits(&got[..3 * N], want_p), "pbrt");
            }
        }
        assert_eq!(last_error(), "");
        coif_marschner_lut_free(lut);
        coif_pbrt_table_free(table);
        coif_dual_scattering_free(ds_m);
        coif_dual_scattering_free(ds_p);
    }
}

#[test]
fn bad_settings_are_refused_with_a_message() {
    let (lut, table) = (new_lut(), new_table());
    let ok = coif_dual_scattering_settings_default();
    let cases = [
        (
            CoifDualScatteringSettings {
                forward_density: 0.0,
                ..ok
            },
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            "forward_density",
        ),
        (
            CoifDualScatteringSettings {
                forward_density: 1.5,
                ..ok
            },
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            "forward_density",
        ),
        (
            CoifDualScatteringSettings {
                backward_density: -0.1,
                ..ok
            },
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            "backward_density",
        ),
        (
            CoifDualScatteringSettings {
                backward_density: f32::NAN,
                ..ok
            },
            CoifStatus::COIF_ERROR_NON_FINITE,
            "backward_density",
        ),
        (
            CoifDualScatteringSettings {
                resolution: 1,
                ..ok
            },
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            "resolution 1",
        ),
        (
            CoifDualScatteringSettings {
                resolution: 5000,
                ..ok
            },
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            "resolution 5000",
        ),
    ];
    // SAFETY: live handles, readable settings, writable out.
    unsafe {
        for (bad, status, named) in cases {
            let mut ds = ptr::dangling_mut::<CoifDualScattering>(); // not NULL before
            assert_eq!(
                coif_dual_scattering_from_marschner_lut(lut, &bad, &mut ds),
                status,
                "{bad:?}"
            );
            assert!(ds.is_null(), "*out NULL on error");
            assert!(last_error().contains(named), "{}", last_error());
            let mut ds = ptr::null_mut();
            assert_eq!(
                coif_dual_scattering_from_pbrt_table(table, &bad, &mut ds),
                status,
                "{bad:?}"
            );
            assert!(ds.is_null());
            assert!(last_error().contains(named), "{}", last_error());
        }
        coif_marschner_lut_free(lut);
        coif_pbrt_table_free(table);
    }
}

#[test]
fn null_pointers_are_refused() {
    let (lut, table) = (new_lut(), new_table());
    let ok = settings();
    // SAFETY: NULL or live handles and readable buffers.
    unsafe {
        let mut ds = ptr::null_mut();
        let builds = [
            coif_dual_scattering_from_marschner_lut(ptr::null(), &ok, &mut ds),
            coif_dual_scattering_from_marschner_lut(lut, ptr::null(), &mut ds),
            coif_dual_scattering_from_marschner_lut(lut, &ok, ptr::null_mut()),
            coif_dual_scattering_from_pbrt_table(ptr::null(), &ok, &mut ds),
            coif_dual_scattering_from_pbrt_table(table, ptr::null(), &mut ds),
            coif_dual_scattering_from_pbrt_table(table, &ok, ptr::null_mut()),
        ];
        assert_eq!(builds, [CoifStatus::COIF_ERROR_NULL; 6]);
        assert!(ds.is_null());
        assert!(!last_error().is_empty());

        let mut ds = ptr::null_mut();
        assert_eq!(
            coif_dual_scattering_from_marschner_lut(lut, &ok, &mut ds),
            CoifStatus::COIF_OK
        );
        let verts = vertices();
        let (fibres, direct) = shadowing();
        let behind = behind();
        let mut out = vec![-1.0f32; 3 * N];
        let (v, l, e, f, b, d, o) = (
            verts.as_ptr(),
            LIGHT.as_ptr(),
            EYE.as_ptr(),
            fibres.as_ptr(),
            behind.as_ptr(),
            direct.as_ptr(),
            out.as_mut_ptr(),
        );
        let null = ptr::null::<f32>();
        let shades = [
            coif_shade_marschner_lut_dual(ptr::null(), ds, v, N, l, e, f, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ptr::null(), v, N, l, e, f, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ds, ptr::null(), N, l, e, f, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ds, v, N, null, e, f, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ds, v, N, l, null, f, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ds, v, N, l, e, null, b, d, o, N),
            coif_shade_marschner_lut_dual(lut, ds, v, N, l, e, f, b, null, o, N),
            coif_shade_marschner_lut_dual(lut, ds, v, N, l, e, f, b, d, ptr::null_mut(), N),
            coif_shade_pbrt_table_dual(ptr::null(), ds, v, N, l, e, f, b, d, o, N),
            coif_shade_pbrt_table_dual(table, ptr::null(), v, N, l, e, f, b, d, o, N),
            // NULL fibres or fractions even with nothing to shade.
            coif_shade_marschner_lut_dual(lut, ds, v, 0, l, e, null, b, d, o, 0),
            coif_shade_marschner_lut_dual(lut, ds, v, 0, l, e, f, null, null, o, 0),
        ];
        assert_eq!(shades, [CoifStatus::COIF_ERROR_NULL; 12]);
        assert!(out.iter().all(|&c| c == -1.0), "nothing written");
        // NULL `behind` alone is not an error: infinitely deep hair.
        assert_eq!(
            coif_shade_marschner_lut_dual(lut, ds, v, N, l, e, f, null, d, o, N),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_shade_marschner_lut_dual(lut, ds, v, 0, l, e, f, null, d, o, 0),
            CoifStatus::COIF_OK
        );
        coif_dual_scattering_free(ds);
        coif_marschner_lut_free(lut);
        coif_pbrt_table_free(table);
    }
}

#[test]
fn bad_shading_inputs_are_refused_and_write_nothing() {
    let (lut, table) = (new_lut(), new_table());
    let verts = vertices();
    let (fibres, direct) = shadowing();
    // SAFETY: live handles; every buffer holds what its count says.
    unsafe {
        let (mut ds_m, mut ds_p) = (ptr::null_mut(), ptr::null_mut());
        assert_eq!(
            coif_dual_scattering_from_marschner_lut(lut, &settings(), &mut ds_m),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_dual_scattering_from_pbrt_table(table, &settings(), &mut ds_p),
            CoifStatus::COIF_OK
        );
        let mut out = vec![-1.0f32; 3 * N];
        let shade_m = |ds, fibres: &[f32], direct: &[f32], out: &mut [f32], capacity| {
            coif_shade_marschner_lut_dual(
                lut,
                ds,
                verts.as_ptr(),
                N,
                LIGHT.as_ptr(),
                EYE.as_ptr(),
                fibres.as_ptr(),
                ptr::null(),
                direct.as_ptr(),
                out.as_mut_ptr(),
                capacity,
            )
        };
        let with = |v: &[f32], k: usize, x: f32| {
            let mut v = v.to_vec();
            v[k] = x;
            v
        };
        let cases = [
            (
                shade_m(ds_m, &with(&fibres, 17, -1.0), &direct, &mut out, N),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                "fibres[17] = -1",
            ),
            (
                shade_m(ds_m, &with(&fibres, 100, f32::NAN), &direct, &mut out, N),
                CoifStatus::COIF_ERROR_NON_FINITE,
                "fibres[100] = NaN",
            ),
            (
                shade_m(ds_m, &with(&fibres, 3, f32::INFINITY), &direct, &mut out, N),
                CoifStatus::COIF_ERROR_NON_FINITE,
                "fibres[3] = inf",
            ),
            (
                shade_m(ds_m, &fibres, &with(&direct, 5, 1.5), &mut out, N),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                "direct[5] = 1.5",
            ),
            (
                shade_m(ds_m, &fibres, &with(&direct, 0, -0.25), &mut out, N),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                "direct[0] = -0.25",
            ),
            (
                shade_m(ds_m, &fibres, &with(&direct, 9, f32::NAN), &mut out, N),
                CoifStatus::COIF_ERROR_NON_FINITE,
                "direct[9] = NaN",
            ),
            (
                shade_m(ds_m, &fibres, &direct, &mut out, N - 1),
                CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
                "too small",
            ),
            (
                // Tables built for pbrt's cosine-weighted function.
                shade_m(ds_p, &fibres, &direct, &mut out, N),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                "built from pbrt tables, not Marschner tables",
            ),
            (
                coif_shade_pbrt_table_dual(
                    table,
                    ds_m,
                    verts.as_ptr(),
                    N,
                    LIGHT.as_ptr(),
                    EYE.as_ptr(),
                    fibres.as_ptr(),
                    ptr::null(),
                    direct.as_ptr(),
                    out.as_mut_ptr(),
                    N,
                ),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                "built from Marschner tables, not pbrt tables",
            ),
        ];
        for (status, want, message) in cases {
            assert_eq!(status, want, "{message}");
        }
        assert!(out.iter().all(|&c| c == -1.0), "nothing written");
        // The message of the last case.
        assert!(last_error().contains("built from Marschner tables"));
        // The message names the index (checked case by case).
        let bad = with(&fibres, 17, -1.0);
        shade_m(ds_m, &bad, &direct, &mut out, N);
        assert!(last_error().contains("fibres[17] = -1"), "{}", last_error());
        let bad = with(&direct, 5, 1.5);
        shade_m(ds_m, &fibres, &bad, &mut out, N);
        assert!(last_error().contains("direct[5] = 1.5"), "{}", last_error());
        let bad = with(&fibres, 100, f32::NAN);
        shade_m(ds_m, &bad, &direct, &mut out, N);
        assert!(
            last_error().contains("fibres[100] = NaN"),
            "{}",
            last_error()
        );
        assert!(out.iter().all(|&c| c == -1.0), "nothing written");

        // Counts behind are refused like the fibre counts, by both calls.
        let behind = behind();
        let shade_b = |pbrt: bool, behind: &[f32], out: &mut [f32]| {
            let (v, l, e) = (verts.as_ptr(), LIGHT.as_ptr(), EYE.as_ptr());
            let (f, b, d, o) = (
                fibres.as_ptr(),
                behind.as_ptr(),
                direct.as_ptr(),
                out.as_mut_ptr(),
            );
            if pbrt {
                coif_shade_pbrt_table_dual(table, ds_p, v, N, l, e, f, b, d, o, N)
            } else {
                coif_shade_marschner_lut_dual(lut, ds_m, v, N, l, e, f, b, d, o, N)
            }
        };
        for pbrt in [false, true] {
            let cases = [
                (
                    23,
                    -2.0,
                    CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                    "behind[23] = -2",
                ),
                (
                    100,
                    f32::NAN,
                    CoifStatus::COIF_ERROR_NON_FINITE,
                    "behind[100] = NaN",
                ),
                (
                    0,
                    f32::INFINITY,
                    CoifStatus::COIF_ERROR_NON_FINITE,
                    "behind[0] = inf",
                ),
                (
                    7,
                    f32::NEG_INFINITY,
                    CoifStatus::COIF_ERROR_NON_FINITE,
                    "behind[7] = -inf",
                ),
            ];
            for (k, x, want, message) in cases {
                assert_eq!(
                    shade_b(pbrt, &with(&behind, k, x), &mut out),
                    want,
                    "{message}"
                );
                assert!(last_error().contains(message), "{}", last_error());
                assert!(
                    last_error().contains("fibre count >= 0"),
                    "{}",
                    last_error()
                );
            }
            assert!(out.iter().all(|&c| c == -1.0), "nothing written");
            assert_eq!(shade_b(pbrt, &behind, &mut out), CoifStatus::COIF_OK);
            out.fill(-1.0);
        }
        coif_dual_scattering_free(ds_m);
        coif_dual_scattering_free(ds_p);
        coif_marschner_lut_free(lut);
        coif_pbrt_table_free(table);
    }
}
