//! The GPU buffers through the C interface are coif-gpu's, bit for bit:
//! `coif_gpu_pack_guides` = `coif_gpu::pack_guides` of the same stepped
//! strands, `coif_gpu_pack_hairs` = `coif_gpu::pack_hairs` of the same
//! interpolation (both placements), `coif_gpu_render_hair_count` =
//! `coif_gpu::render_hair_count`, `coif_gpu_hair_view_default` =
//! `HairView::default()`; a short buffer, NULL and misaligned pointers are
//! refused and nothing is written.

use coif_capi::*;
use coif_gpu::{GuideVertex, HairView, RenderHair};
use coif_kernels::{SimParams, Strands};
use coif_lod::Interpolation;
use glam::Vec3;
use std::ffi::CStr;
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

/// A C set and its Rust twin, stepped a few frames so they are not at rest.
fn stepped_pair() -> (*mut CoifStrands, Strands) {
    let (pts, _) = guides();
    let mut rust = Strands::from_polylines(&pts, VERTS).unwrap();
    let mut c: *mut CoifStrands = ptr::null_mut();
    let xyz: Vec<f32> = pts.iter().flat_map(|p| p.to_array()).collect();
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

/// The bytes of a slice of plain `#[repr(C)]` structs of `f32` and `u32`.
fn bytes<T: Copy>(v: &[T]) -> &[u8] {
    // SAFETY: the structs compared here have no padding (their sizes are
    // asserted to be the sum of their fields), so every byte is initialised.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast(), std::mem::size_of_val(v)) }
}

/// What the calling thread's last failed call said.
fn last_error() -> String {
    // SAFETY: `coif_last_error_message` never returns NULL.
    unsafe { CStr::from_ptr(coif_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn c_guides_are_coif_gpu_guides_bit_for_bit() {
    let (c, rust) = stepped_pair();
    let sentinel = CoifGpuGuideVertex {
        position: [7.0; 3],
        w: 7.0,
    };
    // SAFETY: `c` is live until freed; every buffer holds what its count says.
    unsafe {
        let n = coif_strands_point_count(c);
        assert_eq!(n, GRID * GRID * VERTS);
        let mut out = vec![sentinel; n + 3];
        let mut written = 0usize;
        assert_eq!(
            coif_gpu_pack_guides(c, out.as_mut_ptr(), out.len(), &mut written),
            CoifStatus::COIF_OK
        );
        assert_eq!(written, n);
        let mut want = vec![GuideVertex::default(); n];
        assert_eq!(coif_gpu::pack_guides(rust.blocks(), &mut want), Ok(n));
        assert_eq!(bytes(&out[..n]), bytes(&want));
        assert!(out[n..].iter().all(|g| *g == sentinel), "past the count");
        // Relative to the origin: the root of guide 0 is metres from it,
        // not a hundred.
        assert!(Vec3::from_array(out[0].position).length() < 1.0);

        // `written` is optional; an exact buffer is enough.
        let mut exact = vec![sentinel; n];
        assert_eq!(
            coif_gpu_pack_guides(c, exact.as_mut_ptr(), n, ptr::null_mut()),
            CoifStatus::COIF_OK
        );
        assert_eq!(bytes(&exact), bytes(&want));

        // Refused, nothing written: one entry short, NULL strands, NULL
        // buffer, a misaligned buffer, a misaligned count.
        let mut out = vec![sentinel; n];
        let mut written = 77usize;
        let buf = out.as_mut_ptr();
        let odd_buf = buf.cast::<u8>().add(1).cast::<CoifGpuGuideVertex>();
        let mut count_bytes = [0usize; 2];
        let odd_count = count_bytes.as_mut_ptr().cast::<u8>().add(1).cast::<usize>();
        assert_eq!(
            coif_gpu_pack_guides(c, buf, n - 1, &mut written),
            CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL
        );
        assert_eq!(last_error(), "the output buffer is too small");
        let statuses = [
            coif_gpu_pack_guides(ptr::null(), buf, n, &mut written),
            coif_gpu_pack_guides(c, ptr::null_mut(), n, &mut written),
            coif_gpu_pack_guides(c, odd_buf, n, &mut written),
            coif_gpu_pack_guides(c, buf, n, odd_count),
        ];
        assert_eq!(
            statuses,
            [
                CoifStatus::COIF_ERROR_NULL,
                CoifStatus::COIF_ERROR_NULL,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
            ]
        );
        assert!(out.iter().all(|g| *g == sentinel));
        assert_eq!(written, 77);
        assert_eq!(count_bytes, [0, 0]);
        coif_strands_free(c);
    }
}

#[test]
fn c_render_hairs_are_coif_gpu_render_hairs_bit_for_bit() {
    let (c, _) = stepped_pair();
    let (pts, tris) = guides();
    let roots: Vec<Vec3> = pts.iter().step_by(VERTS).copied().collect();
    let sentinel = CoifGpuRenderHair {
        guides: [9; 3],
        reserved: 9,
        weights: [9.0; 3],
        reserved_weight: 9.0,
    };
    for whole_groups in [0, 1] {
        let settings = CoifHairSettings {
            hairs_per_cm2: 60.0,
            whole_groups,
            ..coif_hair_settings_default()
        };
        let interp = if whole_groups == 1 {
            Interpolation::with_whole_groups(&roots, &tris, 60.0, settings.seed).unwrap()
        } else {
            Interpolation::new(&roots, &tris, 60.0, settings.seed).unwrap()
        };
        let mut h: *mut CoifHairs = ptr::null_mut();
        // SAFETY: every buffer holds what its count says; handles live until freed.
        unsafe {
            assert_eq!(
                coif_hairs_new(c, tris.as_ptr().cast(), tris.len(), &settings, &mut h),
                CoifStatus::COIF_OK
            );
            let n = coif_hairs_hair_count(h);
            assert_eq!(n, interp.hair_count());
            assert!(n > 50, "{n} hairs");
            let mut out = vec![sentinel; n + 2];
            let mut written = 0usize;
            assert_eq!(
                coif_gpu_pack_hairs(h, out.as_mut_ptr(), out.len(), &mut written),
                CoifStatus::COIF_OK
            );
            assert_eq!(written, n);
            let mut want = vec![RenderHair::default(); n];
            assert_eq!(coif_gpu::pack_hairs(&interp, &mut want), Ok(n));
            assert_eq!(
                bytes(&out[..n]),
                bytes(&want),
                "whole groups {whole_groups}"
            );
            assert!(out[n..].iter().all(|r| *r == sentinel), "past the count");
            assert!(out[..n].iter().all(|r| r.guides.iter().all(|&g| g < 25)));

            // The distance-LOD prefix: the view's `hairs`.
            let groups = coif_hairs_group_count(h);
            for drawn in [
                0,
                1,
                2,
                groups / 3,
                groups - 1,
                groups,
                groups + 5,
                usize::MAX,
            ] {
                assert_eq!(
                    coif_gpu_render_hair_count(h, drawn),
                    coif_gpu::render_hair_count(&interp, drawn),
                    "{drawn} groups"
                );
            }
            assert_eq!(coif_gpu_render_hair_count(h, usize::MAX), n);
            assert_eq!(coif_gpu_render_hair_count(ptr::null(), 3), 0);

            // Refused, nothing written: one entry short, NULL hairs, NULL
            // buffer, a misaligned buffer.
            let mut out = vec![sentinel; n];
            let mut written = 77usize;
            let buf = out.as_mut_ptr();
            let odd_buf = buf.cast::<u8>().add(2).cast::<CoifGpuRenderHair>();
            let statuses = [
                coif_gpu_pack_hairs(h, buf, n - 1, &mut written),
                coif_gpu_pack_hairs(h, buf, 0, &mut written),
                coif_gpu_pack_hairs(ptr::null(), buf, n, &mut written),
                coif_gpu_pack_hairs(h, ptr::null_mut(), n, &mut written),
                coif_gpu_pack_hairs(h, odd_buf, n, &mut written),
            ];
            assert_eq!(
                statuses,
                [
                    CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
                    CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL,
                    CoifStatus::COIF_ERROR_NULL,
                    CoifStatus::COIF_ERROR_NULL,
                    CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
                ]
            );
            assert!(out.iter().all(|r| *r == sentinel));
            assert_eq!(written, 77);
            coif_hairs_free(h);
        }
    }
    // SAFETY: `c` is live, freed once.
    unsafe { coif_strands_free(c) };
}

#[test]
fn c_hair_view_is_coif_gpu_hair_view() {
    let c = coif_gpu_hair_view_default();
    let rust = HairView::default();
    assert_eq!(bytes(&[c]), bytes(&[rust]));
    // A view filled field by field in C is the uniform coif-gpu's shaders
    // read: the same bytes as the Rust setters give.
    let mut rust = HairView::default();
    rust.set_level(VERTS, 4, 123);
    rust.width_factor = 1.5;
    let mut c = coif_gpu_hair_view_default();
    c.control_verts = VERTS as u32;
    c.segments_per_span = 4;
    c.hairs = 123;
    c.verts_per_hair = ((VERTS - 1) * 4 + 1) as u32;
    c.width_factor = 1.5;
    assert_eq!(bytes(&[c]), bytes(&[rust]));
}
