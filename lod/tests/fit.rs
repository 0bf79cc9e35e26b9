//! P-spline fits: recovery of known control points, noise removal on a
//! helix, the batch `Fitter` against per-strand `fit`, bad inputs, and
//! resampling authored strands of any vertex count.

use coif_base::SplitMix64;
use coif_lod::{self as lod, quality, Error, Fitter, Resampler};
use glam::Vec3;

fn random_controls(rng: &mut SplitMix64, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            Vec3::new(
                rng.range(-0.02, 0.02),
                -0.03 * i as f32,
                rng.range(-0.02, 0.02),
            )
        })
        .collect()
}

fn size(points: &[Vec3]) -> f32 {
    let lo = points.iter().fold(Vec3::INFINITY, |m, p| m.min(*p));
    let hi = points.iter().fold(Vec3::NEG_INFINITY, |m, p| m.max(*p));
    (hi - lo).length()
}

#[test]
fn fit_recovers_controls_of_a_refined_curve() {
    let mut rng = SplitMix64::new(11);
    let mut curve = Vec::new();
    for &(n, segs) in &[(2usize, 5usize), (3, 4), (8, 4), (12, 6), (20, 3), (9, 1)] {
        let ctrl = random_controls(&mut rng, n);
        // refine samples the curve at u = k / N: uniform parameter from
        // the first point to the last, which is what fit assumes.
        lod::refine(&ctrl, segs, &mut curve);
        let got = lod::fit(&curve, n, 0.0).unwrap();
        let tol = 1e-4 * size(&ctrl);
        for (a, b) in got.iter().zip(&ctrl) {
            assert!(
                (*a - *b).length() < tol,
                "n {n} N {segs}: {a} vs {b} (tol {tol})"
            );
        }
    }
}

#[test]
fn smoothing_removes_most_of_the_noise_on_a_helix() {
    // A 20 cm curl of 1.5 cm radius, 600 samples, +-2 mm noise per axis.
    let truth = quality::helix(600, 0.015, 0.2, 3.0);
    let noisy = quality::with_noise(&truth, 0.002, 5);
    let noise_rms = (truth
        .iter()
        .zip(&noisy)
        .map(|(a, b)| (*a - *b).length_squared() as f64)
        .sum::<f64>()
        / truth.len() as f64)
        .sqrt() as f32;
    let plain = quality::fit_error(&truth, &noisy, 60, 0.0).unwrap();
    let smooth = quality::fit_error(&truth, &noisy, 60, 1.0).unwrap();
    // "Most of the noise": the smoothed curve is within a third of the noise level of the truth.
    assert!(
        smooth.rms < noise_rms / 3.0,
        "smoothed rms {} vs noise rms {noise_rms}",
        smooth.rms
    );
    assert!(
        smooth.rms < plain.rms,
        "smoothing must beat plain least squares here"
    );
}

#[test]
fn fitter_batch_equals_per_strand_fit() {
    let mut rng = SplitMix64::new(12);
    let (p, n, lambda) = (64usize, 12usize, 0.05f32);
    // 150 strands: more than one internal chunk of right-hand sides.
    let mut all = Vec::new();
    for _ in 0..150 {
        let ctrl = random_controls(&mut rng, 10);
        let pts: Vec<Vec3> = (0..p)
            .map(|i| lod::bspline::evaluate(&ctrl, i as f32 * 9.0 / (p - 1) as f32))
            .collect();
        all.extend(quality::with_noise(&pts, 0.001, rng.next_u64()));
    }
    let mut fitter = Fitter::new(p, n, lambda).unwrap();
    let mut batch = vec![Vec3::ZERO; 150 * n];
    fitter.fit_into(&all, &mut batch).unwrap();
    for s in 0..150 {
        let single = lod::fit(&all[s * p..(s + 1) * p], n, lambda).unwrap();
        for (a, b) in batch[s * n..(s + 1) * n].iter().zip(&single) {
            assert!((*a - *b).length() < 1e-6, "strand {s}: {a} vs {b}");
        }
    }
}

#[test]
fn a_non_finite_strand_does_not_spread_in_a_batch() {
    let ctrl: Vec<Vec3> = (0..5)
        .map(|i| Vec3::new(0.0, -(i as f32), 0.1 * i as f32))
        .collect();
    let mut pts = Vec::new();
    lod::refine(&ctrl, 4, &mut pts);
    let p = pts.len();
    let mut all = [pts.clone(), pts.clone(), pts.clone()].concat();
    all[p + 3].y = f32::NAN;
    let mut fitter = Fitter::new(p, 5, 0.0).unwrap();
    let mut out = vec![Vec3::ZERO; 15];
    fitter.fit_into(&all, &mut out).unwrap();
    assert!(out[5..10].iter().any(|c| !c.is_finite()));
    for s in [0, 2] {
        for (a, b) in out[s * 5..s * 5 + 5].iter().zip(&ctrl) {
            assert!((*a - *b).length() < 1e-4, "strand {s}: {a} vs {b}");
        }
    }
}

#[test]
fn bad_inputs_return_errors() {
    let pts: Vec<Vec3> = (0..10).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
    assert!(matches!(
        lod::fit(&pts, 1, 0.0),
        Err(Error::TooFewControlPoints { .. })
    ));
    assert!(matches!(
        lod::fit(&pts, 0, 0.0),
        Err(Error::TooFewControlPoints { .. })
    ));
    assert!(matches!(
        lod::fit(&pts, 11, 0.0),
        Err(Error::MoreControlsThanPoints { .. })
    ));
    assert!(lod::fit(&[], 2, 0.0).is_err());
    assert!(lod::fit(&pts[..1], 2, 0.0).is_err());
    for bad in [-1.0, f32::NAN, f32::INFINITY] {
        assert!(
            matches!(lod::fit(&pts, 4, bad), Err(Error::InvalidParameter { .. })),
            "{bad}"
        );
    }
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut p = pts.clone();
        p[4].z = bad;
        assert_eq!(lod::fit(&p, 4, 0.0), Err(Error::NonFinite { index: 4 }));
    }
    // Display is human-readable.
    assert!(lod::fit(&pts, 1, 0.0)
        .unwrap_err()
        .to_string()
        .contains("at least 2"));
    let mut f = Fitter::new(10, 4, 0.0).unwrap();
    let mut out = vec![Vec3::ZERO; 4];
    assert!(matches!(
        f.fit_into(&pts[..9], &mut out),
        Err(Error::CountMismatch { .. })
    ));
    assert!(matches!(
        f.fit_into(&pts, &mut out[..3]),
        Err(Error::CountMismatch { .. })
    ));
    // n_control == points.len() is allowed and interpolates.
    let exact = lod::fit(&pts, 10, 0.0).unwrap();
    assert_eq!(exact.len(), 10);
}

#[test]
fn resampler_turns_any_vertex_count_into_v_vertices_on_the_same_curve() {
    let target = random_controls(&mut SplitMix64::new(13), 10);
    let mut dense = Vec::new();
    let mut refined = Vec::new();
    let mut resampler = Resampler::new(128, 10, 0.0).unwrap();
    for &authored in &[7usize, 31, 100, 257] {
        // An authored strand: `authored` points along the target curve.
        dense.clear();
        dense.extend(
            (0..authored)
                .map(|i| lod::bspline::evaluate(&target, i as f32 * 9.0 / (authored - 1) as f32)),
        );
        let mut out = vec![Vec3::ZERO; 10];
        resampler.resample_into(&dense, &mut out).unwrap();
        assert_eq!(out[0], dense[0], "root stays exactly on the scalp");
        // The resampled strand's curve stays close to the authored polyline.
        lod::refine(&out, 8, &mut refined);
        let tol = 0.02 * size(&target);
        for q in &refined {
            let d = dense
                .windows(2)
                .map(|w| point_segment_distance(*q, w[0], w[1]))
                .fold(f32::INFINITY, f32::min);
            assert!(
                d < tol,
                "authored {authored}: {q} is {d} from the strand (tol {tol})"
            );
        }
        // And its control points are spread evenly along it.
        let seg: Vec<f32> = out.windows(2).map(|w| (w[1] - w[0]).length()).collect();
        let mean = seg.iter().sum::<f32>() / seg.len() as f32;
        assert!(seg.iter().all(|s| (s - mean).abs() < 0.5 * mean), "{seg:?}");
    }
    let mut out = vec![Vec3::ZERO; 10];
    assert!(resampler.resample_into(&[], &mut out).is_err());
    assert!(resampler
        .resample_into(&[Vec3::NAN, Vec3::ZERO], &mut out)
        .is_err());
    resampler.resample_into(&[Vec3::ONE], &mut out).unwrap();
    assert!(out.iter().all(|p| (*p - Vec3::ONE).length() < 1e-6));
}

fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + t * ab)).length()
}
