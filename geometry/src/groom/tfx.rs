//! AMD TressFX 4 `.tfx` groom files (little-endian; layout in
//! `shared/data/grooms/README.md`): a 160-byte header (f32 version, u32
//! strand count, u32 vertices per strand, u32 byte offset of the positions,
//! further offsets, reserved words), then `f32 x, y, z, w` per vertex, strand
//! after strand, root first (`w = 0` marks a pinned vertex).
//!
//! Every count and offset is checked against the input's length before
//! anything is allocated from it.

use super::{Error, Groom};
use glam::Vec3;

/// Size of the fixed header.
pub const HEADER_BYTES: usize = 160;

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

fn f32_at(bytes: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(bytes, at))
}

/// True if `bytes` looks like a `.tfx` file (a header whose version is 4.x).
pub fn sniff(bytes: &[u8]) -> bool {
    bytes.len() >= HEADER_BYTES && (4.0..5.0).contains(&f32_at(bytes, 0))
}

/// Parses a `.tfx` file. Errors, never panics, on truncation, lying counts
/// or offsets, and non-finite coordinates.
///
/// # Errors
///
/// [`Error`] on truncation, lying counts, non-finite points; never panics.
pub fn parse(bytes: &[u8]) -> Result<Groom, Error> {
    if bytes.len() < HEADER_BYTES {
        return Err(Error::Truncated {
            needed: HEADER_BYTES as u64,
            available: bytes.len() as u64,
        });
    }
    if !sniff(bytes) {
        return Err(Error::BadHeader(
            "not a TressFX 4 file (version is not 4.x)",
        ));
    }
    let strands = u32_at(bytes, 4) as u64;
    let verts = u32_at(bytes, 8) as u64;
    let offset = u32_at(bytes, 12) as u64;
    if strands == 0 {
        return Err(Error::BadHeader("zero strands"));
    }
    if verts < 2 {
        return Err(Error::BadHeader("fewer than 2 vertices per strand"));
    }
    if offset < HEADER_BYTES as u64 {
        return Err(Error::BadHeader("positions overlap the header"));
    }
    // (2^32 - 1)^2 * 16 does not fit in u64 (found by `cargo fuzz`): saturate,
    // then compare with the input before allocating anything.
    let needed = strands
        .saturating_mul(verts)
        .saturating_mul(16)
        .saturating_add(offset);
    if needed > bytes.len() as u64 {
        return Err(Error::Truncated {
            needed,
            available: bytes.len() as u64,
        });
    }
    let count = (strands * verts) as usize;
    let data = &bytes[offset as usize..offset as usize + count * 16];
    let mut points = Vec::with_capacity(count);
    for (index, rec) in data.chunks_exact(16).enumerate() {
        let p = Vec3::new(f32_at(rec, 0), f32_at(rec, 4), f32_at(rec, 8));
        if !p.is_finite() {
            return Err(Error::NonFinite { index });
        }
        points.push(p);
    }
    Groom::from_strands(points, &vec![verts as usize; strands as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(strands: u32, verts: u32, points: &[[f32; 4]]) -> Vec<u8> {
        let mut b = vec![0u8; HEADER_BYTES];
        b[0..4].copy_from_slice(&4.0f32.to_le_bytes());
        b[4..8].copy_from_slice(&strands.to_le_bytes());
        b[8..12].copy_from_slice(&verts.to_le_bytes());
        b[12..16].copy_from_slice(&(HEADER_BYTES as u32).to_le_bytes());
        for p in points {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b
    }

    #[test]
    fn reads_a_small_file() {
        let pts = [
            [0.0, 1.0, 2.0, 0.0],
            [0.0, 0.5, 2.0, 1.0],
            [1.0, 1.0, 2.0, 0.0],
            [1.0, 0.5, 2.0, 1.0],
        ];
        let g = parse(&file(2, 2, &pts)).unwrap();
        assert_eq!(g.strand_count(), 2);
        assert_eq!(g.vertex_count(), 4);
        assert_eq!(
            g.strand(1),
            &[Vec3::new(1.0, 1.0, 2.0), Vec3::new(1.0, 0.5, 2.0)]
        );
        let (scaled, v) = g.uniform_points(0.01).unwrap();
        assert_eq!(v, 2);
        assert!((scaled[1].y - 0.005).abs() < 1e-7);
    }

    #[test]
    fn rejects_hostile_input() {
        let pts = [[0.0; 4]; 4];
        let good = file(2, 2, &pts);
        for n in [0, 10, HEADER_BYTES - 1, good.len() - 1] {
            assert!(
                matches!(parse(&good[..n]), Err(Error::Truncated { .. })),
                "cut at {n}"
            );
        }
        // A header that claims 4 billion strands must not allocate for them.
        let liar = file(u32::MAX, u32::MAX, &pts);
        assert!(matches!(parse(&liar), Err(Error::Truncated { .. })));
        assert!(matches!(parse(&file(0, 2, &[])), Err(Error::BadHeader(_))));
        assert!(matches!(
            parse(&file(1, 1, &pts[..1])),
            Err(Error::BadHeader(_))
        ));
        let mut nan = pts;
        nan[3][1] = f32::NAN;
        assert_eq!(parse(&file(2, 2, &nan)), Err(Error::NonFinite { index: 3 }));
        let mut bad_offset = good.clone();
        bad_offset[12..16].copy_from_slice(&4u32.to_le_bytes());
        assert!(matches!(parse(&bad_offset), Err(Error::BadHeader(_))));
        let mut far_offset = good.clone();
        far_offset[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(matches!(parse(&far_offset), Err(Error::Truncated { .. })));
        let mut not_tfx = good;
        not_tfx[0..4].copy_from_slice(b"HAIR");
        assert!(parse(&not_tfx).is_err());
    }
}
