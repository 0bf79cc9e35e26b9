//! `Groom::resampled`: exact on strands already evenly spaced at the
//! requested count; otherwise every sample sits at its share of the arc
//! length within 0.1 % of the strand's length; any vertex counts in one
//! groom; bad requests refused.

use coif_base::rng::SplitMix64;
use coif_geometry::groom::{Error, Groom};
use glam::Vec3;

/// The arc-length position of `p` on `strand` (it lies on a segment).
fn arc_position(strand: &[Vec3], p: Vec3) -> f32 {
    let mut walked = 0.0f32;
    let mut best = (f32::INFINITY, 0.0f32);
    for w in strand.windows(2) {
        let d = w[1] - w[0];
        let len = d.length();
        let t = if len > 0.0 {
            ((p - w[0]).dot(d) / (len * len)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let off = (w[0] + d * t).distance(p);
        if off < best.0 {
            best = (off, walked + t * len);
        }
        walked += len;
    }
    assert!(best.0 < 1e-5, "{p} is {} off the strand", best.0);
    best.1
}

fn length(strand: &[Vec3]) -> f32 {
    strand.windows(2).map(|w| w[0].distance(w[1])).sum()
}

#[test]
fn evenly_spaced_strands_come_back_as_they_are() {
    // Arcs of circles, 32 points evenly spaced, in centimetres.
    let mut points = Vec::new();
    for s in 0..20 {
        let r = 5.0 + s as f32;
        points.extend((0..32).map(|i| {
            let a = i as f32 * 0.05;
            Vec3::new(r * a.cos(), r * a.sin(), s as f32)
        }));
    }
    let groom = Groom::from_strands(points.clone(), &[32; 20]).unwrap();
    let out = groom.resampled(32, 0.01).unwrap();
    let worst = out
        .iter()
        .zip(&points)
        .map(|(a, b)| a.distance(*b * 0.01))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-7, "{worst} m");
}

#[test]
fn any_counts_resample_to_their_arc_length_shares() {
    let mut rng = SplitMix64::new(5);
    let mut points = Vec::new();
    let mut counts = Vec::new();
    for _ in 0..50 {
        // Helices sampled at random parameters: uneven spacing.
        let n = 2 + (rng.range(0.0, 200.0) as usize);
        let mut ts: Vec<f32> = (0..n).map(|_| rng.range(0.0, 1.0)).collect();
        ts[0] = 0.0;
        ts[n - 1] = 1.0;
        ts.sort_by(f32::total_cmp);
        points.extend(
            ts.iter()
                .map(|t| Vec3::new((6.0 * t).cos() * 2.0, -20.0 * t, (6.0 * t).sin() * 2.0)),
        );
        counts.push(n);
    }
    let groom = Groom::from_strands(points, &counts).unwrap();
    for verts in [2, 7, 32] {
        let out = groom.resampled(verts, 1.0).unwrap();
        assert_eq!(out.len(), 50 * verts);
        for (i, resampled) in out.chunks(verts).enumerate() {
            let strand = groom.strand(i);
            let total = length(strand);
            assert_eq!(resampled[0], strand[0]);
            assert_eq!(resampled[verts - 1], strand[strand.len() - 1]);
            for (k, p) in resampled.iter().enumerate() {
                let want = total * k as f32 / (verts - 1) as f32;
                let got = arc_position(strand, *p);
                assert!(
                    (got - want).abs() <= 1e-3 * total,
                    "strand {i} sample {k}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn bad_requests_are_refused() {
    let groom = Groom::from_strands(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[2, 1]).unwrap();
    assert!(matches!(
        groom.resampled(1, 1.0),
        Err(Error::BadResample(_))
    ));
    assert!(matches!(
        groom.resampled(4, 0.0),
        Err(Error::BadResample(_))
    ));
    assert!(matches!(
        groom.resampled(4, f32::NAN),
        Err(Error::BadResample(_))
    ));
    assert!(matches!(
        groom.resampled(usize::MAX, 1.0),
        Err(Error::BadResample(_))
    ));
    assert!(matches!(
        groom.resampled(4, 1e38),
        Err(Error::NonFinite { .. })
    ));
    // The one-point strand is its point, four times.
    let out = groom.resampled(4, 2.0).unwrap();
    assert_eq!(&out[4..], &[Vec3::Y * 2.0; 4]);
}

#[test]
fn resampling_refuses_sizes_that_would_not_fit_in_memory() {
    use coif_geometry::groom::Groom;
    use glam::Vec3;
    // A 2-point groom asked for 2^28 points grew to 3 GB before.
    let groom = Groom::from_strands(vec![Vec3::ZERO, Vec3::X], &[2]).unwrap();
    assert!(groom.resampled(1 << 28, 1.0).is_err());
    assert!(groom.resampled((1 << 16) + 1, 1.0).is_err());
    assert_eq!(groom.resampled(1 << 16, 1.0).unwrap().len(), 1 << 16);
}
