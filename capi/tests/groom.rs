//! Grooms through the C interface: the shared TressFX grooms load from
//! memory as `coif_geometry::groom::load` reads them, make the same strands
//! as the Rust resampling, and corrupted bytes (truncated, lying counts, an
//! unknown format, a NaN) are refused with `*out` left NULL. Tests needing
//! the shared grooms skip, saying so, when the folder is absent.

use coif_capi::*;
use coif_geometry::groom;
use coif_kernels::Strands;
use glam::Vec3;
use std::ptr;

/// Loads `bytes` through C: the status and the handle (NULL on error).
fn load(bytes: &[u8]) -> (CoifStatus, *mut CoifGroom) {
    let mut g: *mut CoifGroom = ptr::dangling_mut();
    // SAFETY: `bytes` is readable for its length; `g` is writable.
    let st = unsafe { coif_groom_load(bytes.as_ptr(), bytes.len(), &mut g) };
    (st, g)
}

#[test]
fn shared_grooms_load_as_in_rust() {
    for name in ["sintel_lite.tfx", "ratboy_mohawk.tfx"] {
        let Some(path) = coif_testkit::groom_path(name) else {
            return;
        };
        let bytes = std::fs::read(&path).expect("read the groom");
        let rust = groom::load(&bytes).expect("Rust loads it");
        let (st, g) = load(&bytes);
        assert_eq!(st, CoifStatus::COIF_OK, "{name}");
        // SAFETY: `g` is live until freed; buffers hold what the counts say.
        unsafe {
            assert_eq!(coif_groom_strand_count(g), rust.strand_count());
            assert_eq!(coif_groom_vertex_count(g), rust.vertex_count());
            for s in [0, rust.strand_count() / 2, rust.strand_count() - 1] {
                let n = coif_groom_strand_vertex_count(g, s);
                assert_eq!(n, rust.strand(s).len());
                let mut xyz = vec![0.0f32; 3 * n];
                assert_eq!(
                    coif_groom_strand_points(g, s, xyz.as_mut_ptr(), n),
                    CoifStatus::COIF_OK
                );
                let want: Vec<f32> = rust.strand(s).iter().flat_map(|p| p.to_array()).collect();
                assert_eq!(xyz, want);
                let mut short = vec![-1.0f32; 3 * n];
                assert_eq!(
                    coif_groom_strand_points(g, s, short.as_mut_ptr(), n - 1),
                    CoifStatus::COIF_ERROR_BUFFER_TOO_SMALL
                );
                assert!(short.iter().all(|&x| x == -1.0));
            }
            let past = rust.strand_count();
            assert_eq!(coif_groom_strand_vertex_count(g, past), 0);
            let mut xyz = [0.0f32; 3];
            assert_eq!(
                coif_groom_strand_points(g, past, xyz.as_mut_ptr(), 1),
                CoifStatus::COIF_ERROR_INVALID_ARGUMENT
            );

            // Strands from every 7th strand, 12 vertices, centimetres to metres.
            let (stride, verts) = (7, 12);
            let guides = coif_groom_guide_count(g, stride);
            assert_eq!(guides, rust.strand_count().div_ceil(stride));
            let mut s: *mut CoifStrands = ptr::null_mut();
            assert_eq!(
                coif_strands_from_groom(g, stride, verts, 0.01, &mut s),
                CoifStatus::COIF_OK
            );
            assert_eq!(coif_strands_strand_count(s), guides);
            assert_eq!(coif_strands_verts_per_strand(s), verts);
            let mut want = Vec::new();
            let mut buf = vec![Vec3::ZERO; verts];
            for k in (0..rust.strand_count()).step_by(stride) {
                let scaled: Vec<Vec3> = rust.strand(k).iter().map(|p| *p * 0.01).collect();
                coif_lod::arc_length_samples(&scaled, &mut buf);
                want.extend_from_slice(&buf);
            }
            let rust_strands = Strands::from_polylines(&want, verts).unwrap();
            let mut got = vec![0.0f32; 3 * guides * verts];
            assert_eq!(
                coif_strands_positions(s, got.as_mut_ptr(), guides * verts),
                CoifStatus::COIF_OK
            );
            let want_xyz: Vec<f32> = rust_strands
                .positions()
                .iter()
                .flat_map(|p| p.to_array())
                .collect();
            assert_eq!(got, want_xyz);
            // Metres: a scalp-sized groom, not one a hundred times larger.
            let (lo, hi) = got.chunks(3).fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), p| (lo.min(Vec3::from_slice(p)), hi.max(Vec3::from_slice(p))),
            );
            assert!(
                (hi - lo).max_element() < 2.0,
                "{name}: extent {:?}",
                hi - lo
            );
            // The strands outlive the groom.
            coif_groom_free(g);
            let p = coif_sim_params_default();
            assert_eq!(coif_step(s, &p, ptr::null(), 0), CoifStatus::COIF_OK);

            // Bad arguments leave *out NULL.
            let (_, g) = load(&bytes);
            for (stride, verts, scale, want) in [
                (0, 12, 0.01, CoifStatus::COIF_ERROR_INVALID_ARGUMENT),
                (1, 1, 0.01, CoifStatus::COIF_ERROR_INVALID_ARGUMENT),
                (1, 12, 0.0, CoifStatus::COIF_ERROR_INVALID_ARGUMENT),
                (1, 12, f32::NAN, CoifStatus::COIF_ERROR_NON_FINITE),
                (1, 12, 1e38, CoifStatus::COIF_ERROR_NON_FINITE),
            ] {
                let mut bad: *mut CoifStrands = ptr::dangling_mut();
                assert_eq!(
                    coif_strands_from_groom(g, stride, verts, scale, &mut bad),
                    want
                );
                assert!(bad.is_null());
            }
            coif_groom_free(g);
            coif_strands_free(s);
        }
    }
}

fn tfx_header(strands: u32, verts: u32, offset: u32) -> Vec<u8> {
    let mut b = vec![0u8; 160];
    b[0..4].copy_from_slice(&4.0f32.to_le_bytes());
    b[4..8].copy_from_slice(&strands.to_le_bytes());
    b[8..12].copy_from_slice(&verts.to_le_bytes());
    b[12..16].copy_from_slice(&offset.to_le_bytes());
    b
}

#[test]
fn corrupted_grooms_are_refused() {
    // A good little file: 2 strands of 3 points.
    let mut good = tfx_header(2, 3, 160);
    for k in 0..6 {
        for c in [k as f32, 1.0, 2.0, 0.0] {
            good.extend_from_slice(&c.to_le_bytes());
        }
    }
    let (st, g) = load(&good);
    assert_eq!(st, CoifStatus::COIF_OK);
    // SAFETY: `g` is live, then freed.
    unsafe {
        assert_eq!(coif_groom_vertex_count(g), 6);
        coif_groom_free(g);
    }
    let mut lying_strands = good.clone();
    lying_strands[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    let mut lying_verts = good.clone();
    lying_verts[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    let mut lying_offset = good.clone();
    lying_offset[12..16].copy_from_slice(&(u32::MAX - 8).to_le_bytes());
    let mut nan = good.clone();
    nan[160 + 16 + 4..160 + 16 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    let mut cyhair_lying = b"HAIR".to_vec();
    cyhair_lying.extend_from_slice(&u32::MAX.to_le_bytes());
    cyhair_lying.extend_from_slice(&u32::MAX.to_le_bytes());
    cyhair_lying.resize(128, 0);
    let cases: Vec<(&str, &[u8], CoifStatus)> = vec![
        (
            "truncated",
            &good[..good.len() - 1],
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        ("header only", &good[..160], CoifStatus::COIF_ERROR_BAD_DATA),
        (
            "half a header",
            &good[..80],
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        ("empty", &[], CoifStatus::COIF_ERROR_BAD_DATA),
        (
            "strand count lies",
            &lying_strands,
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        (
            "vertex count lies",
            &lying_verts,
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        (
            "offset lies",
            &lying_offset,
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        (
            "cyHair counts lie",
            &cyhair_lying,
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        (
            "unknown format",
            &[7u8; 300],
            CoifStatus::COIF_ERROR_BAD_DATA,
        ),
        ("NaN coordinate", &nan, CoifStatus::COIF_ERROR_NON_FINITE),
    ];
    for (what, bytes, want) in cases {
        let (st, g) = load(bytes);
        assert_eq!(st, want, "{what}");
        assert!(g.is_null(), "{what}: *out not NULL");
    }
    // Every truncation of the good file is refused, never a crash.
    for len in 0..good.len() {
        let (st, g) = load(&good[..len]);
        assert_ne!(st, CoifStatus::COIF_OK, "truncated to {len}");
        assert!(g.is_null());
    }
    // NULL pointers.
    let mut g: *mut CoifGroom = ptr::null_mut();
    // SAFETY: NULL on purpose; `g` writable.
    unsafe {
        assert_eq!(
            coif_groom_load(ptr::null(), 10, &mut g),
            CoifStatus::COIF_ERROR_NULL
        );
        assert_eq!(
            coif_groom_load(good.as_ptr(), good.len(), ptr::null_mut()),
            CoifStatus::COIF_ERROR_NULL
        );
        assert_eq!(coif_groom_strand_count(ptr::null()), 0);
        assert_eq!(coif_groom_guide_count(ptr::null(), 1), 0);
        coif_groom_free(ptr::null_mut());
    }
}
