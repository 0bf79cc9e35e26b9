//! Error measurements for time-against-error reports: chord error of the
//! refinement level, fit error against control count and smoothing, and
//! what distance-LOD thinning of the interpolated hair costs on screen.
//! Reference values come from direct (closed-form) curve evaluation and
//! from the full set of render hairs.

use crate::bspline::{evaluate, refine};
use crate::culling::distance_lod;
use crate::fit::fit;
use crate::interpolation::{Interpolation, RenderHairs};
use crate::vertex::HairWidth;
use crate::Error;
use coif_base::rng::SplitMix64;
use coif_base::LANES;
use glam::Vec3;

/// Sub-samples per refined segment when measuring chord error.
pub const CHORD_SAMPLES_PER_SEGMENT: usize = 32;

/// Measured chord error of `refine(control, N)`: the largest distance
/// between the curve `C(u)` and the refined polyline's linear interpolation
/// at the same parameter, over [`CHORD_SAMPLES_PER_SEGMENT`] samples per
/// segment. This is what [`crate::level::chord_error_bound`] bounds. 0 for
/// fewer than two control points.
pub fn chord_error(control: &[Vec3], segments_per_span: usize) -> f32 {
    if control.len() < 2 {
        return 0.0;
    }
    let n = segments_per_span.max(1);
    let mut poly = Vec::new();
    refine(control, n, &mut poly);
    let mut worst = 0.0f32;
    for (s, w) in poly.windows(2).enumerate() {
        for m in 1..CHORD_SAMPLES_PER_SEGMENT {
            let f = m as f32 / CHORD_SAMPLES_PER_SEGMENT as f32;
            let u = (s as f32 + f) / n as f32;
            let err = (evaluate(control, u) - w[0].lerp(w[1], f)).length();
            worst = worst.max(err);
        }
    }
    worst
}

/// Root-mean-square and largest distance between a fitted curve and the
/// points it is compared with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitError {
    /// Root-mean-square distance, metres.
    pub rms: f32,
    /// Largest distance, metres.
    pub max: f32,
}

/// Fits `n_control` controls with `smoothing` to `samples` (see
/// [`crate::fit`]) and measures the fitted curve, at the samples' uniform
/// parameters, against `truth` (same length as `samples`; pass `samples`
/// itself for the residual, or the noise-free points to measure how much
/// noise the fit removed).
///
/// # Errors
///
/// [`Error::CountMismatch`] if `truth` and `samples` differ in length, and
/// as [`crate::fit`] does.
pub fn fit_error(
    truth: &[Vec3],
    samples: &[Vec3],
    n_control: usize,
    smoothing: f32,
) -> Result<FitError, Error> {
    if truth.len() != samples.len() {
        return Err(Error::CountMismatch {
            what: "truth points (one per sample)",
            expected: samples.len(),
            got: truth.len(),
        });
    }
    let ctrl = fit(samples, n_control, smoothing)?;
    let p = samples.len();
    let (mut sum, mut max) = (0.0f64, 0.0f32);
    for (i, t) in truth.iter().enumerate() {
        let u = if p > 1 {
            i as f32 * (n_control - 1) as f32 / (p - 1) as f32
        } else {
            0.0
        };
        let d = (evaluate(&ctrl, u) - *t).length();
        sum += (d as f64) * (d as f64);
        max = max.max(d);
    }
    Ok(FitError {
        rms: (sum / p.max(1) as f64).sqrt() as f32,
        max,
    })
}

/// `n` points of a helix around +Y (a curly strand): radius `radius`,
/// `turns` turns over height `height`, starting at `(radius, 0, 0)`.
pub fn helix(n: usize, radius: f32, height: f32, turns: f32) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let s = if n > 1 {
                i as f32 / (n - 1) as f32
            } else {
                0.0
            };
            let a = std::f32::consts::TAU * turns * s;
            Vec3::new(radius * a.cos(), -height * s, radius * a.sin())
        })
        .collect()
}

/// `points` plus independent noise uniform in `[-amplitude, amplitude]` per
/// coordinate, reproducibly from `seed`.
pub fn with_noise(points: &[Vec3], amplitude: f32, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    points
        .iter()
        .map(|p| {
            *p + Vec3::new(
                rng.range(-amplitude, amplitude),
                rng.range(-amplitude, amplitude),
                rng.range(-amplitude, amplitude),
            )
        })
        .collect()
}

/// Longest piece (pixels) a projected hair segment is cut into by
/// [`optical_depth`].
pub const OPTICAL_DEPTH_PIECE_PX: f32 = 0.25;

/// Per-pixel optical depth of the drawn render hairs on a `grid[0] x
/// grid[1]` pixel grid: `tau(pixel) = sum over hair segments of
/// width_px x length_px inside the pixel / pixel area (1 px^2)`, i.e. the
/// projected area of the hair in the pixel, the quantity the coverage (and
/// for thin hair the opacity `1 - exp(-tau)`) of a pixel follows.
///
/// Hairs are those of the first `groups_drawn` groups that `hairs` holds
/// (written by [`crate::interpolate`]), `width` root to tip times
/// `width_factor` (from [`crate::distance_lod`]), as
/// [`crate::write_render_vertices`] draws them. `project` maps a point (the
/// hairs' coordinates) to `[x_px, y_px, pixels per metre there]`, `None`
/// behind the eye. Each projected segment is cut into pieces of at most
/// [`OPTICAL_DEPTH_PIECE_PX`] (at most 4096), each deposited whole in the
/// pixel of its midpoint with the width interpolated there. Segments
/// with an unprojectable or non-finite end are skipped. `out` is resized to
/// the grid and overwritten (row-major, `y * grid[0] + x`).
#[allow(clippy::too_many_arguments)]
pub fn optical_depth(
    interpolation: &Interpolation,
    hairs: &RenderHairs,
    groups_drawn: usize,
    width: HairWidth,
    width_factor: f32,
    grid: [usize; 2],
    project: impl Fn(Vec3) -> Option<[f32; 3]>,
    out: &mut Vec<f64>,
) {
    let [gw, gh] = grid;
    out.clear();
    out.resize(gw * gh, 0.0);
    let verts = hairs.verts_per_hair();
    if verts < 2 {
        return;
    }
    let inv = 1.0 / (verts - 1) as f32;
    let width_at =
        |r: usize| (width.root + (width.tip - width.root) * r as f32 * inv) * width_factor;
    let groups = interpolation.groups();
    for (g, group) in groups.iter().enumerate().take(groups_drawn) {
        if !hairs.is_group_written(g) {
            continue;
        }
        for lane in 0..(group.hairs as usize).min(LANES) {
            let mut prev = project(hairs.position(g, lane, 0));
            for r in 1..verts {
                let next = project(hairs.position(g, lane, r));
                if let (Some(a), Some(b)) = (prev, next) {
                    let wa = width_at(r - 1) * a[2];
                    let wb = width_at(r) * b[2];
                    deposit(out, grid, a, b, wa, wb);
                }
                prev = next;
            }
        }
    }
}

/// Adds segment `a -> b` (pixels; widths `wa`, `wb` pixels) to `out`.
fn deposit(out: &mut [f64], grid: [usize; 2], a: [f32; 3], b: [f32; 3], wa: f32, wb: f32) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let length = (dx * dx + dy * dy).sqrt();
    if !(length.is_finite() && wa.is_finite() && wb.is_finite()) {
        return;
    }
    let pieces = ((length / OPTICAL_DEPTH_PIECE_PX).ceil() as usize).clamp(1, 4096);
    let piece = length / pieces as f32;
    for i in 0..pieces {
        let f = (i as f32 + 0.5) / pieces as f32;
        let (x, y) = (a[0] + dx * f, a[1] + dy * f);
        if x < 0.0 || y < 0.0 {
            continue;
        }
        let (px, py) = (x as usize, y as usize);
        if px < grid[0] && py < grid[1] {
            out[py * grid[0] + px] += ((wa + (wb - wa) * f) * piece) as f64;
        }
    }
}

/// Relative RMS difference `sqrt(sum (a - r)^2 / sum r^2)` of `a` against
/// `reference` (same length; 0 if both are all zero, infinite if only the
/// reference is).
pub fn relative_rms_difference(a: &[f64], reference: &[f64]) -> f64 {
    let (mut err, mut norm) = (0.0f64, 0.0f64);
    for (x, r) in a.iter().zip(reference) {
        err += (x - r) * (x - r);
        norm += r * r;
    }
    if err == 0.0 {
        0.0
    } else {
        (err / norm).sqrt()
    }
}

/// What drawing only the fraction `fraction` of the render hairs costs on
/// screen: the relative RMS difference ([`relative_rms_difference`]) of the
/// per-pixel [`optical_depth`] of the thinned, width-compensated set
/// against that of every hair at its own width.
///
/// The thinned set is what [`crate::distance_lod`] draws for that fraction
/// (the shuffled prefix of whole groups, widened by `hair_count /
/// hairs_drawn`), so the expected optical depth of every pixel is kept and
/// the error is the noise of the sparser sample of hairs: 0 for
/// `fraction >= 1`, growing as hairs are dropped (for independent hairs
/// about `sqrt(1 / fraction - 1)` times the relative spread of one pixel's
/// depth). `hairs` must hold every group (an [`crate::interpolate`] with all
/// groups drawn); `width`, `grid` and `project` as in [`optical_depth`].
pub fn thinning_error(
    interpolation: &Interpolation,
    hairs: &RenderHairs,
    width: HairWidth,
    fraction: f32,
    grid: [usize; 2],
    project: impl Fn(Vec3) -> Option<[f32; 3]>,
) -> f64 {
    let all = interpolation.group_count();
    let mut full = Vec::new();
    optical_depth(
        interpolation,
        hairs,
        all,
        width,
        1.0,
        grid,
        &project,
        &mut full,
    );
    // distance_lod draws clamp(width_px, min_fraction, 1) of the hair.
    let lod = distance_lod(interpolation, fraction, fraction);
    let mut thinned = Vec::new();
    optical_depth(
        interpolation,
        hairs,
        lod.groups_drawn,
        width,
        lod.width_factor,
        grid,
        &project,
        &mut thinned,
    );
    relative_rms_difference(&thinned, &full)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{interpolate, refine_strands, RefinedGuides};
    use coif_kernels::Strands;

    /// A 10 x 10 grid of straight guides, 1 cm apart, hanging 10 cm down
    /// from the plane y = 0, with 150 render hairs per cm^2 between them,
    /// every hair interpolated; and the orthographic view along -z of the
    /// patch (10 cm -> 32 px) in the hairs' coordinates (relative to the
    /// guides' origin).
    fn hanging_patch() -> (
        Interpolation,
        RenderHairs,
        impl Fn(Vec3) -> Option<[f32; 3]> + Copy,
    ) {
        let n = 10;
        let roots: Vec<Vec3> = (0..n * n)
            .map(|i| Vec3::new((i % n) as f32 * 0.01, 0.0, (i / n) as f32 * 0.01))
            .collect();
        let points: Vec<Vec3> = roots
            .iter()
            .flat_map(|r| (0..8).map(move |v| *r - Vec3::Y * (0.1 * v as f32 / 7.0)))
            .collect();
        let mut triangles = Vec::new();
        for z in 0..n - 1 {
            for x in 0..n - 1 {
                let i = (z * n + x) as u32;
                let n = n as u32;
                triangles.push([i, i + 1, i + n]);
                triangles.push([i + 1, i + n + 1, i + n]);
            }
        }
        let strands = Strands::from_polylines(&points, 8).unwrap();
        let interp = Interpolation::new(&roots, &triangles, 150.0, 3).unwrap();
        let mut guides = RefinedGuides::new(strands.blocks(), 2).unwrap();
        refine_strands(strands.blocks(), None, &mut guides).unwrap();
        let mut hairs = RenderHairs::new(&interp, &guides);
        let written =
            interpolate(&interp, &guides, None, interp.group_count(), &mut hairs).unwrap();
        assert_eq!(written, interp.group_count());
        let origin = strands.origin().as_vec3();
        let front_view = move |p: Vec3| {
            let (p, k) = (p + origin, 320.0);
            Some([p.x * k + 1.0, -p.y * k, k])
        };
        (interp, hairs, front_view)
    }

    #[test]
    fn optical_depth_is_the_projected_area_of_the_hair() {
        let (interp, hairs, front_view) = hanging_patch();
        let width = HairWidth {
            root: 1e-4,
            tip: 1e-4,
        };
        let mut tau = Vec::new();
        let all = interp.group_count();
        optical_depth(
            &interp,
            &hairs,
            all,
            width,
            1.0,
            [32, 32],
            front_view,
            &mut tau,
        );
        // Every hair is 10 cm long, fully inside the grid: area per hair
        // (1e-4 m x 0.1 m) x 320^2 px^2 / m^2 = 1.024 px^2.
        let expected = interp.hair_count() as f64 * 1.024;
        let total: f64 = tau.iter().sum();
        assert!(
            (total - expected).abs() < 1e-3 * expected,
            "{total} vs {expected}"
        );
        // Doubling the width factor doubles every pixel.
        let mut wide = Vec::new();
        optical_depth(
            &interp,
            &hairs,
            all,
            width,
            2.0,
            [32, 32],
            front_view,
            &mut wide,
        );
        for (a, b) in tau.iter().zip(&wide) {
            assert!((2.0 * a - b).abs() <= 1e-9 * b.abs().max(1.0));
        }
    }

    #[test]
    fn thinning_error_is_zero_for_the_full_set_and_grows_as_hairs_are_dropped() {
        let (interp, hairs, front_view) = hanging_patch();
        let width = HairWidth::default();
        let e: Vec<f64> = [1.0, 0.5, 0.25, 0.125]
            .iter()
            .map(|&f| thinning_error(&interp, &hairs, width, f, [32, 32], front_view))
            .collect();
        assert_eq!(e[0], 0.0);
        assert!(e[1] > 0.0, "{e:?}");
        assert!(e[1] < e[2] && e[2] < e[3], "{e:?}");
        // Width compensation keeps the total (expected) coverage: the
        // error is noise, well under the 88 % of hairs dropped at 1/8.
        assert!(e[3] < 0.88, "{e:?}");
    }

    #[test]
    fn relative_rms_difference_of_known_vectors() {
        assert_eq!(relative_rms_difference(&[1.0, 2.0], &[1.0, 2.0]), 0.0);
        let d = relative_rms_difference(&[0.0, 4.0], &[3.0, 4.0]);
        assert!((d - 3.0 / 5.0).abs() < 1e-12);
        assert_eq!(relative_rms_difference(&[0.0], &[0.0]), 0.0);
        assert!(relative_rms_difference(&[1.0], &[0.0]).is_infinite());
    }
}
