//! Cem Yuksel's cyHair `.hair` files (little-endian): a 128-byte header
//! ("HAIR", u32 hair count, u32 point count, u32 flags, u32 default segment
//! count, f32 default thickness, f32 default transparency, f32 x 3 default
//! colour, 88 bytes of text), then the arrays whose flags are set, in this
//! order: u16 segments per hair (SEGMENTS = 1), f32 xyz points (POINTS = 2),
//! f32 thickness (THICKNESS = 4), f32 transparency (TRANSPARENCY = 8), f32 rgb
//! colours (COLORS = 16). A hair has segments + 1 points; without the
//! segments array every hair has the default count.
//!
//! Every count is checked against the input's length before anything is
//! allocated from it; thickness, transparency and colour are validated for
//! size and skipped (coif's `Groom` keeps positions only).

use super::{Error, Groom};
use glam::Vec3;

/// Size of the cyHair header in bytes.
pub const HEADER_BYTES: usize = 128;
/// Header flag bit: the file has a segment count per strand.
pub const SEGMENTS: u32 = 1;
/// Header flag bit: the file has points.
pub const POINTS: u32 = 2;
/// Header flag bit: the file has a thickness per point.
pub const THICKNESS: u32 = 4;
/// Header flag bit: the file has a transparency per point.
pub const TRANSPARENCY: u32 = 8;
/// Header flag bit: the file has a colour per point.
pub const COLORS: u32 = 16;

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(b, at))
}

/// True if `bytes` starts with cyHair's signature.
pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"HAIR")
}

/// Parses a cyHair file. Errors, never panics, on truncation, lying counts,
/// a missing points array, segments that do not add up, non-finite points.
///
/// # Errors
///
/// [`Error`] as listed above; never panics.
pub fn parse(bytes: &[u8]) -> Result<Groom, Error> {
    let available = bytes.len() as u64;
    if bytes.len() < HEADER_BYTES {
        return Err(Error::Truncated {
            needed: HEADER_BYTES as u64,
            available,
        });
    }
    if !sniff(bytes) {
        return Err(Error::BadHeader("not a cyHair file (no HAIR signature)"));
    }
    let hairs = u32_at(bytes, 4) as u64;
    let points = u32_at(bytes, 8) as u64;
    let flags = u32_at(bytes, 12);
    let default_segments = u32_at(bytes, 16) as u64;
    if hairs == 0 {
        return Err(Error::BadHeader("zero hairs"));
    }
    if flags & POINTS == 0 {
        return Err(Error::BadHeader("no points array"));
    }
    // Sizes of the arrays present, in file order; u32 counts times 12 fit in u64.
    let seg_bytes = if flags & SEGMENTS != 0 { hairs * 2 } else { 0 };
    let per_point = 12
        + 4 * (flags & THICKNESS != 0) as u64
        + 4 * (flags & TRANSPARENCY != 0) as u64
        + 12 * (flags & COLORS != 0) as u64;
    let needed = HEADER_BYTES as u64 + seg_bytes + points * per_point;
    if needed > available {
        return Err(Error::Truncated { needed, available });
    }
    // Per-hair point counts, from the segments array or the default.
    // Without a segments array `hairs` is not bounded by the input's size; every
    // hair has at least one point, so `points` bounds it (the loop stops there).
    let mut counts = Vec::with_capacity(hairs.min(points) as usize);
    let mut total = 0u64;
    for h in 0..hairs as usize {
        let segments = if flags & SEGMENTS != 0 {
            let at = HEADER_BYTES + 2 * h;
            u16::from_le_bytes([bytes[at], bytes[at + 1]]) as u64
        } else {
            default_segments
        };
        total += segments + 1;
        if total > points {
            return Err(Error::BadHeader(
                "segments add up to more points than the file has",
            ));
        }
        counts.push(segments as usize + 1);
    }
    if total != points {
        return Err(Error::BadHeader(
            "segments add up to fewer points than the file has",
        ));
    }
    let start = HEADER_BYTES + seg_bytes as usize;
    let data = &bytes[start..start + points as usize * 12];
    let mut pts = Vec::with_capacity(points as usize);
    for (index, rec) in data.chunks_exact(12).enumerate() {
        let p = Vec3::new(f32_at(rec, 0), f32_at(rec, 4), f32_at(rec, 8));
        if !p.is_finite() {
            return Err(Error::NonFinite { index });
        }
        pts.push(p);
    }
    Groom::from_strands(pts, &counts)
}

/// Writes `groom` as a cyHair file with the segments and points arrays and
/// `info` (up to 88 bytes of it) in the header. Errors if a strand has more
/// than 65,536 points (segment counts are u16) or the groom more than 2^32 - 1.
///
/// # Errors
///
/// [`Error`] as listed above.
pub fn write(groom: &Groom, info: &str) -> Result<Vec<u8>, Error> {
    let hairs =
        u32::try_from(groom.strand_count()).map_err(|_| Error::Unwritable("too many hairs"))?;
    let points =
        u32::try_from(groom.vertex_count()).map_err(|_| Error::Unwritable("too many points"))?;
    let mut out = Vec::with_capacity(HEADER_BYTES + 2 * hairs as usize + 12 * points as usize);
    out.extend_from_slice(b"HAIR");
    out.extend_from_slice(&hairs.to_le_bytes());
    out.extend_from_slice(&points.to_le_bytes());
    out.extend_from_slice(&(SEGMENTS | POINTS).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes()); // default segments (unused: the array is present)
    for default in [1.0f32, 0.0, 0.5, 0.4, 0.3] {
        // thickness, transparency, colour
        out.extend_from_slice(&default.to_le_bytes());
    }
    let mut text = [0u8; 88];
    let n = info.len().min(88);
    text[..n].copy_from_slice(&info.as_bytes()[..n]);
    out.extend_from_slice(&text);
    debug_assert_eq!(out.len(), HEADER_BYTES);
    for i in 0..groom.strand_count() {
        let segments = u16::try_from(groom.strand(i).len() - 1)
            .map_err(|_| Error::Unwritable("a strand has more than 65,536 points"))?;
        out.extend_from_slice(&segments.to_le_bytes());
    }
    for p in groom.points() {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Groom {
        let pts = vec![
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(0.1, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 0.2, 0.3),
        ];
        Groom::from_strands(pts, &[3, 2]).unwrap()
    }

    #[test]
    fn round_trips_a_groom_with_uneven_strands() {
        let g = sample();
        let bytes = write(&g, "coif test").unwrap();
        assert_eq!(bytes.len(), HEADER_BYTES + 2 * 2 + 12 * 5);
        let back = parse(&bytes).unwrap();
        assert_eq!(back, g);
        assert_eq!(super::super::load(&bytes).unwrap(), g);
    }

    #[test]
    fn default_segments_and_extra_arrays_are_understood() {
        // Two hairs of default 1 segment (2 points), with thickness and colour arrays.
        let mut b = Vec::new();
        b.extend_from_slice(b"HAIR");
        b.extend_from_slice(&2u32.to_le_bytes());
        b.extend_from_slice(&4u32.to_le_bytes());
        b.extend_from_slice(&(POINTS | THICKNESS | COLORS).to_le_bytes());
        b.extend_from_slice(&1u32.to_le_bytes());
        b.resize(HEADER_BYTES, 0);
        for k in 0..12 {
            b.extend_from_slice(&(k as f32).to_le_bytes());
        }
        b.extend_from_slice(&[0u8; 4 * 4 + 12 * 4]);
        let g = parse(&b).unwrap();
        assert_eq!(g.strand_count(), 2);
        assert_eq!(
            g.strand(1),
            &[Vec3::new(6.0, 7.0, 8.0), Vec3::new(9.0, 10.0, 11.0)]
        );
        // One byte short of the colour array.
        assert!(matches!(
            parse(&b[..b.len() - 1]),
            Err(Error::Truncated { .. })
        ));
    }

    #[test]
    fn rejects_hostile_headers() {
        let good = write(&sample(), "").unwrap();
        let with = |at: usize, v: u32| {
            let mut b = good.clone();
            b[at..at + 4].copy_from_slice(&v.to_le_bytes());
            b
        };
        // Counts that lie: no allocation follows, just an error.
        assert!(matches!(
            parse(&with(4, u32::MAX)),
            Err(Error::Truncated { .. })
        ));
        assert!(matches!(
            parse(&with(8, u32::MAX)),
            Err(Error::Truncated { .. })
        ));
        assert!(
            matches!(parse(&with(8, 4)), Err(Error::BadHeader(_))),
            "segments exceed points"
        );
        assert!(matches!(parse(&with(4, 0)), Err(Error::BadHeader(_))));
        assert!(
            matches!(parse(&with(12, SEGMENTS)), Err(Error::BadHeader(_))),
            "no points array"
        );
        for n in [0, 3, 100, good.len() - 1] {
            assert!(parse(&good[..n]).is_err(), "truncated at {n}");
        }
        let mut nan = good.clone();
        let at = HEADER_BYTES + 4 + 12 * 2 + 4;
        nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(parse(&nan), Err(Error::NonFinite { index: 2 }));
        assert_eq!(
            super::super::load(b"NOPE and more bytes"),
            Err(Error::UnknownFormat)
        );
        let long = Groom::from_strands(vec![Vec3::ZERO; 70_000], &[70_000]).unwrap();
        assert!(matches!(write(&long, ""), Err(Error::Unwritable(_))));
    }
}
