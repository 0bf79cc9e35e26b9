//! The C calls of LOD and shading give exactly what the Rust API gives: the
//! same strands refined (`coif_refine` = `refine_strands`), the same render
//! vertices (`coif_hairs_write_vertices` = refine + interpolate +
//! `write_render_vertices`) and the same colours (`coif_shade_*` =
//! `shade_batch` / `scattering_batch`), bit for bit; failed calls write
//! nothing.

use coif_capi::*;
use coif_kernels::{SimParams, Strands};
use coif_lod::{HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex};
use coif_shading::kajiya_kay::KajiyaKay;
use coif_shading::marschner::{self, Lut};
use coif_shading::pbrt::{self, Table};
use coif_shading::{RgbBuffer, ShadingSamples};
use glam::Vec3;
use std::ptr;

const GRID: usize = 5; // 5 x 5 = 25 guides: not a multiple of 8
const VERTS: usize = 8;

/// Wavy guides on a 5 x 5 grid of roots 1 cm apart, far from the origin
/// (so the local origin matters), and the grid's triangles.
fn guides() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    for j in 0..GRID {
        for i in 0..GRID {
            let root = Vec3::new(100.0 + 0.01 * i as f32, 1.7, -40.0 + 0.01 * j as f32);
            for v in 0..VERTS {
                let t = v as f32;
                pts.push(root + Vec3::new(0.003 * (t + i as f32).sin(), -0.015 * t, 0.002 * t));
            }
        }
    }
    let mut tris = Vec::new();
    for j in 0..GRID - 1 {
        for i in 0..GRID - 1 {
            let k = (j * GRID + i) as u32;
            let g = GRID as u32;
            tris.push([k, k + 1, k + g]);
            tris.push([k + 1, k + g + 1, k + g]);
        }
    }
    (pts, tris)
}

fn flat(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// A C set and its Rust twin, stepped a few frames so they are not at rest.
fn stepped_pair() -> (*mut CoifStrands, Strands) {
    let (pts, _) = guides();
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let mut c: *mut CoifStrands = ptr::null_mut();
    let xyz = flat(&pts);
    let p = coif_sim_params_default();
    // SAFETY: `xyz` holds 3 floats per point; `c` is live after success.
    unsafe {
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), pts.len(), VERTS, &mut c),
            CoifStatus::COIF_OK
        );
        for _ in 0..10 {
            assert_eq!(coif_step(c, &p, ptr::null(), 0), CoifStatus::COIF_OK);
            coif_kernels::step(&mut rust, &SimParams::default(), &[]);
        }
    }
    (c, rust)
}

#[test]
fn c_refine_matches_rust_refine_bit_for_bit() {
    let (c, rust) = stepped_pair();
    let origin = rust.origin();
    // Coarse, finer (the scratch grows), coarse again (it does not shrink).
    for n in [3usize, 7, 2] {
        // SAFETY: `c` is live; the buffers hold `bound` points.
        unsafe {
            let bound = coif_refine_bound(c, n);
            assert_eq!(bound, 25 * coif_lod::refined_len(VERTS, n));
            let mut xyz = vec![f32::NAN; 3 * bound];
            let mut tan = vec![f32::NAN; 3 * bound];
            assert_eq!(
                coif_refine(c, n, xyz.as_mut_ptr(), tan.as_mut_ptr(), bound),
                CoifStatus::COIF_OK
            );
            let mut guides = RefinedGuides::new(rust.blocks(), n).unwrap();
            coif_lod::refine_strands(rust.blocks(), None, &mut guides).unwrap();
            let r = guides.verts_per_strand();
            let mut want_xyz = Vec::new();
            let mut want_tan = Vec::new();
            for i in 0..25 {
                for k in 0..r {
                    want_xyz.push((origin + guides.position(i, k).as_dvec3()).as_vec3());
                    want_tan.push(guides.tangent(i, k));
                }
            }
            assert!(same_bits(&xyz, &flat(&want_xyz)), "positions at N = {n}");
            assert!(same_bits(&tan, &flat(&want_tan)), "tangents at N = {n}");
            // Tangents optional; a buffer one point short is refused untouched.
            let mut again = vec![0.0f32; 3 * bound];
            assert_eq!(
                coif_refine(c, n, again.as_mut_ptr(), ptr::null_mut(), bound),
                CoifStatus::COIF_OK
            );
            assert!(same_bits(&again, &xyz));
            let mut short = vec![-1.0f32; 3 * bound];
            assert_eq!(
                coif_refine(c, n, short.as_mut_ptr(), ptr::null_mut(), bound - 1),
                CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL
            );
            assert!(short.iter().all(|&x| x == -1.0));
        }
    }
    // SAFETY: `c` is live, then freed once.
    unsafe {
        assert_eq!(coif_refine_bound(c, 0), 0);
        assert_eq!(coif_refine_bound(c, 257), 0);
        let mut x = [0.0f32; 3];
        assert_eq!(
            coif_refine(c, 0, x.as_mut_ptr(), ptr::null_mut(), 1),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        coif_strands_free(c);
    }
}

#[test]
fn c_render_vertices_match_rust_bit_for_bit() {
    let (c, rust) = stepped_pair();
    let (pts, tris) = guides();
    let settings = CoifHairSettings {
        hairs_per_cm2: 60.0,
        max_segments_per_span: 6,
        ..coif_hair_settings_default()
    };
    let roots: Vec<Vec3> = pts.iter().step_by(VERTS).copied().collect();
    let interp = Interpolation::new(&roots, &tris, 60.0, settings.seed).unwrap();
    let mut guides = RefinedGuides::new(rust.blocks(), 6).unwrap();
    let mut hairs = RenderHairs::new(&interp, &guides);
    let width = HairWidth::default();
    let mut h: *mut CoifHairs = ptr::null_mut();
    // SAFETY: every buffer holds what its count says; handles live until freed.
    unsafe {
        assert_eq!(
            coif_hairs_new(c, tris.as_ptr().cast(), tris.len(), &settings, &mut h),
            CoifStatus::COIF_OK
        );
        assert_eq!(coif_hairs_hair_count(h), interp.hair_count());
        assert_eq!(coif_hairs_group_count(h), interp.group_count());
        assert!(interp.hair_count() > 50, "{} hairs", interp.hair_count());
        let mut origin = [0.0f64; 3];
        assert_eq!(
            coif_strands_origin(c, origin.as_mut_ptr()),
            CoifStatus::COIF_OK
        );
        assert_eq!(origin, rust.origin().to_array());

        let mut groups = 0usize;
        let mut factor = 0.0f32;
        assert_eq!(
            coif_hairs_distance_lod(h, 0.4, 0.1, &mut groups, &mut factor),
            CoifStatus::COIF_OK
        );
        let d = coif_lod::distance_lod(&interp, 0.4, 0.1);
        assert_eq!((groups, factor), (d.groups_drawn, d.width_factor));
        assert!(groups < interp.group_count());

        for (n, drawn, wf) in [(6, usize::MAX, 1.0), (2, groups, factor), (4, 1, 1.5)] {
            let bound = coif_hairs_vertex_bound(h, n, drawn);
            let mut out = vec![CoifRenderVertex::default(); bound + 3];
            let mut written = 0usize;
            assert_eq!(
                coif_hairs_write_vertices(
                    h,
                    c,
                    n,
                    drawn,
                    wf,
                    out.as_mut_ptr(),
                    out.len(),
                    &mut written
                ),
                CoifStatus::COIF_OK
            );
            assert_eq!(written, bound);
            let g = drawn.min(interp.group_count());
            guides.set_segments_per_span(n).unwrap();
            coif_lod::refine_strands(rust.blocks(), None, &mut guides).unwrap();
            coif_lod::interpolate(&interp, &guides, None, g, &mut hairs).unwrap();
            let mut want = vec![RenderVertex::default(); bound];
            let count =
                coif_lod::write_render_vertices(&interp, &hairs, g, width, wf, &mut want).unwrap();
            assert_eq!(count, bound);
            let got: &[u8] = std::slice::from_raw_parts(out.as_ptr().cast(), 32 * bound);
            assert_eq!(
                got,
                coif_lod::vertex_bytes(&want),
                "N = {n}, groups {drawn}"
            );
            assert!(out[bound..]
                .iter()
                .all(|v| *v == CoifRenderVertex::default()));
        }

        // Refused: too small, a level above the settings' maximum, a set of
        // another shape, a bad width factor; nothing written.
        let bound = coif_hairs_vertex_bound(h, 6, usize::MAX);
        let mut out = vec![CoifRenderVertex::default(); bound];
        let mut written = 77usize;
        let (other, _) = stepped_pair();
        let mut d: *mut CoifStrands = ptr::null_mut();
        let xyz = flat(&pts[..VERTS * 24]);
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), 24 * VERTS, VERTS, &mut d),
            CoifStatus::COIF_OK
        );
        // The same call with one argument wrong each time (`out` holds
        // `cap` vertices or is NULL).
        let mut write = |guides, n, wf, out, cap| {
            coif_hairs_write_vertices(h, guides, n, usize::MAX, wf, out, cap, &mut written)
        };
        let buf = out.as_mut_ptr();
        let statuses = [
            write(c, 6, 1.0, buf, bound - 1),
            write(c, 7, 1.0, buf, bound),
            write(d, 6, 1.0, buf, bound),
            write(c, 6, 0.0, buf, bound),
            write(c, 6, f32::NAN, buf, bound),
            write(c, 6, 1.0, ptr::null_mut(), bound),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_COUNT_MISMATCH,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_NULL,
            ]
        );
        assert!(out.iter().all(|v| *v == CoifRenderVertex::default()));
        assert_eq!(written, 77);
        assert_eq!(coif_hairs_vertex_bound(h, 7, usize::MAX), 0);

        // Construction refuses bad triangles and settings, leaving NULL.
        let mut bad: *mut CoifHairs = ptr::null_mut();
        let out_of_range = [[0u32, 1, 25]];
        let nan_density = CoifHairSettings {
            hairs_per_cm2: f32::NAN,
            ..settings
        };
        let zero_level = CoifHairSettings {
            max_segments_per_span: 0,
            ..settings
        };
        let statuses = [
            coif_hairs_new(c, out_of_range.as_ptr().cast(), 1, &settings, &mut bad),
            coif_hairs_new(c, tris.as_ptr().cast(), 0, &settings, &mut bad),
            coif_hairs_new(c, tris.as_ptr().cast(), tris.len(), &nan_density, &mut bad),
            coif_hairs_new(c, tris.as_ptr().cast(), tris.len(), &zero_level, &mut bad),
            coif_hairs_new(c, ptr::null(), tris.len(), &settings, &mut bad),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NULL,
            ]
        );
        assert!(bad.is_null());
        coif_hairs_free(h);
        coif_strands_free(c);
        coif_strands_free(d);
        coif_strands_free(other);
    }
}

/// 21 vertices (two full SIMD blocks and a padded one) with varied tangents.
fn vertices() -> Vec<CoifRenderVertex> {
    (0..21)
        .map(|k| {
            let a = k as f32 * 0.37;
            CoifRenderVertex {
                position: [0.01 * a.cos(), 0.02 * k as f32, 0.01 * a.sin()],
                width: 80e-6,
                tangent: Vec3::new(a.sin(), -1.0, 0.3 * a.cos())
                    .normalize()
                    .to_array(),
                strand_parameter: k as f32 / 20.0,
            }
        })
        .collect()
}

/// The Rust samples of `vertices` lit from `light`, seen from `eye`.
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

#[test]
fn c_shading_matches_rust_batches_bit_for_bit() {
    let verts = vertices();
    let (light, eye) = (Vec3::new(0.3, 1.0, 0.8), Vec3::new(0.2, 0.3, 1.5));
    let s = samples(&verts, light, eye);
    let n = verts.len();
    let mut got = vec![0.0f32; 3 * n];

    let kk = CoifKajiyaKay {
        primary_exponent: 60.0,
        ..coif_kajiya_kay_default()
    };
    let rust_kk = KajiyaKay {
        primary: coif_shading::kajiya_kay::Highlight {
            exponent: 60.0,
            ..KajiyaKay::default().primary
        },
        ..KajiyaKay::default()
    };
    let mut want = RgbBuffer::default();
    rust_kk.shade_batch(&s, &mut want);
    let (l, e) = (light.to_array(), eye.to_array());
    // SAFETY: every buffer holds what its count says.
    unsafe {
        assert_eq!(
            coif_shade_kajiya_kay(
                &kk,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                got.as_mut_ptr(),
                n
            ),
            CoifStatus::COIF_OK
        );
    }
    assert!(same_bits(&got, &rgb_flat(&want)), "Kajiya-Kay");
    assert!(got.iter().any(|&c| c > 0.0));

    let params = coif_marschner_params_default();
    let rust_lut = Lut::new(&marschner::Params::default(), 32);
    rust_lut.scattering_batch(&s, &mut want);
    let mut lut: *mut CoifMarschnerLut = ptr::null_mut();
    // SAFETY: as above; `lut` is live until freed.
    unsafe {
        assert_eq!(
            coif_marschner_lut_new(&params, 32, &mut lut),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_shade_marschner_lut(
                lut,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                got.as_mut_ptr(),
                n
            ),
            CoifStatus::COIF_OK
        );
        assert!(same_bits(&got, &rgb_flat(&want)), "Marschner tables");

        let pbrt_params = coif_pbrt_params_default();
        let rust_table = Table::new(&pbrt::Params::default(), 16).unwrap();
        rust_table.scattering_batch(&s, &mut want);
        let mut table: *mut CoifPbrtTable = ptr::null_mut();
        assert_eq!(
            coif_pbrt_table_new(&pbrt_params, 16, &mut table),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_shade_pbrt_table(
                table,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                got.as_mut_ptr(),
                n
            ),
            CoifStatus::COIF_OK
        );
        assert!(same_bits(&got, &rgb_flat(&want)), "pbrt tables");
        assert!(got.iter().any(|&c| c > 0.0));
        let mut bad_table: *mut CoifPbrtTable = ptr::null_mut();
        let rough = CoifPbrtParams {
            beta_m: 0.0,
            ..pbrt_params
        };
        let nan_eta = CoifPbrtParams {
            eta: f32::NAN,
            ..pbrt_params
        };
        assert_eq!(
            coif_pbrt_table_new(&rough, 16, &mut bad_table),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_pbrt_table_new(&nan_eta, 16, &mut bad_table),
            CoifStatus::COIF_ERROR_NON_FINITE
        );
        assert_eq!(
            coif_pbrt_table_new(&pbrt_params, 1, &mut bad_table),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(bad_table.is_null());
        coif_pbrt_table_free(table);

        // Refused, nothing written: too small, NaN vertex, zero light, bad
        // material, bad table settings.
        let mut out = vec![-1.0f32; 3 * n];
        let mut nan_vertex = verts.clone();
        nan_vertex[9].tangent[1] = f32::NAN;
        let zero = [0.0f32; 3];
        let bad_kk = CoifKajiyaKay {
            secondary_exponent: -1.0,
            ..kk
        };
        let statuses = [
            coif_shade_kajiya_kay(
                &kk,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                out.as_mut_ptr(),
                n - 1,
            ),
            coif_shade_kajiya_kay(
                &kk,
                nan_vertex.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                out.as_mut_ptr(),
                n,
            ),
            coif_shade_kajiya_kay(
                &kk,
                verts.as_ptr(),
                n,
                zero.as_ptr(),
                e.as_ptr(),
                out.as_mut_ptr(),
                n,
            ),
            coif_shade_kajiya_kay(
                &bad_kk,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                out.as_mut_ptr(),
                n,
            ),
            coif_shade_marschner_lut(
                lut,
                verts.as_ptr(),
                n,
                l.as_ptr(),
                ptr::null(),
                out.as_mut_ptr(),
                n,
            ),
            coif_shade_marschner_lut(
                ptr::null(),
                verts.as_ptr(),
                n,
                l.as_ptr(),
                e.as_ptr(),
                out.as_mut_ptr(),
                n,
            ),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
                CoifStatus::COIF_ERROR_NON_FINITE,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_NULL,
                CoifStatus::COIF_ERROR_NULL,
            ]
        );
        assert!(out.iter().all(|&x| x == -1.0));
        let mut bad: *mut CoifMarschnerLut = ptr::null_mut();
        let low_eta = CoifMarschnerParams { eta: 0.9, ..params };
        let nan_absorption = CoifMarschnerParams {
            absorption: [0.1, f32::NAN, 0.1],
            ..params
        };
        assert_eq!(
            coif_marschner_lut_new(&low_eta, 32, &mut bad),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            coif_marschner_lut_new(&nan_absorption, 32, &mut bad),
            CoifStatus::COIF_ERROR_NON_FINITE
        );
        assert_eq!(
            coif_marschner_lut_new(&params, 1, &mut bad),
            CoifStatus::COIF_ERROR_INVALID_ARGUMENT
        );
        assert!(bad.is_null());
        coif_marschner_lut_free(lut);
    }
}

#[test]
fn status_codes_outside_the_enum_have_a_message() {
    use std::ffi::CStr;
    // SAFETY: the messages are static NUL-terminated strings.
    let msg = |code| {
        unsafe { CStr::from_ptr(coif_status_message_code(code)) }
            .to_str()
            .unwrap()
    };
    assert_eq!(msg(-1), "unknown status");
    assert_eq!(msg(8), "unknown status");
    assert_eq!(msg(i32::MAX), "unknown status");
    // SAFETY: as above.
    let direct = unsafe { CStr::from_ptr(coif_status_message(CoifStatus::COIF_ERROR_BAD_DATA)) };
    assert_eq!(msg(7), direct.to_str().unwrap());
    assert_ne!(msg(0), "unknown status");
}
