//! Test scenes: a tuft (a slab of parallel straight fibres) and
//! orthographic bundles of camera rays aimed at it.

use super::fibres::FibreScene;
use crate::Error;
use coif_base::rng::SplitMix64;
use glam::Vec3;
use std::f32::consts::PI;

/// Most fibres a tuft may have.
pub const MAX_TUFT_FIBRES: usize = 4_000_000;

/// Candidate positions tried per fibre before an overlap is accepted.
pub const PLACEMENT_ATTEMPTS: usize = 64;

/// A slab of parallel fibres along x, centred at the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TuftParams {
    /// Fibre length (along x); the fibres run from `-length/2` to `length/2`.
    pub length: f32,
    /// Extent of the fibre centres along y.
    pub width: f32,
    /// Extent of the fibre centres along z.
    pub thickness: f32,
    /// Fibre radius.
    pub radius: f32,
    /// Fibre cross-section area over the cross-section's area:
    /// `n pi r^2 / (width thickness)`, in (0, 0.6].
    pub volume_fraction: f32,
    /// Placement seed.
    pub seed: u64,
}

/// A tuft built into a scene.
#[derive(Clone, Debug)]
pub struct Tuft {
    /// The fibres (one segment each).
    pub scene: FibreScene,
    /// What it was built from.
    pub params: TuftParams,
    /// Number of fibres, `round(volume_fraction width thickness / (pi r^2))`
    /// (at least 1).
    pub fibre_count: usize,
    /// Fibres placed overlapping another (closer than `2 r`) after
    /// [`PLACEMENT_ATTEMPTS`] rejected candidates; 0 below a volume
    /// fraction of about 0.4.
    pub overlaps: usize,
}

/// A tuft: `fibre_count` straight fibres along x, their centres uniform
/// (seeded) in `[-width/2, width/2] x [-thickness/2, thickness/2]` (y, z),
/// kept at least `2 r` apart by rejection on a grid of cells `2 r` wide
/// (up to [`PLACEMENT_ATTEMPTS`] candidates per fibre, then the last one
/// is kept and counted in [`Tuft::overlaps`]).
///
/// # Errors
///
/// [`Error::InvalidParameter`] if a length is not finite and positive, the
/// volume fraction is outside (0, 0.6], or the count exceeds
/// [`MAX_TUFT_FIBRES`] (`"fibre_count"`).
pub fn tuft(params: &TuftParams) -> Result<Tuft, Error> {
    let p = *params;
    for (name, v) in [
        ("length", p.length),
        ("width", p.width),
        ("thickness", p.thickness),
        ("radius", p.radius),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::InvalidParameter { name, value: v });
        }
    }
    if !(p.volume_fraction > 0.0 && p.volume_fraction <= 0.6) {
        return Err(Error::InvalidParameter {
            name: "volume_fraction",
            value: p.volume_fraction,
        });
    }
    let r = p.radius;
    let n = (p.volume_fraction as f64 * p.width as f64 * p.thickness as f64
        / (PI as f64 * r as f64 * r as f64))
        .round()
        .max(1.0);
    if n.is_nan() || n > MAX_TUFT_FIBRES as f64 {
        return Err(Error::InvalidParameter {
            name: "fibre_count",
            value: n as f32,
        });
    }
    let n = n as usize;
    // Grid of cells 2r wide over the cross-section (bounded: n is bounded
    // and the cell count is capped at 4n + 1 by widening the cells).
    let mut cell = 2.0 * r;
    let cells_for =
        |c: f32| ((p.width / c).ceil() as f64 + 1.0) * ((p.thickness / c).ceil() as f64 + 1.0);
    while cells_for(cell) > (4 * n + 16) as f64 {
        cell *= 2.0;
    }
    let gw = (p.width / cell).ceil() as usize + 1;
    let gh = (p.thickness / cell).ceil() as usize + 1;
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); gw * gh];
    let mut centres: Vec<(f32, f32)> = Vec::with_capacity(n);
    let mut rng = SplitMix64::new(p.seed);
    let mut overlaps = 0usize;
    let min_d2 = 4.0 * r * r;
    let cell_of = |y: f32, z: f32| {
        let i = (((y + 0.5 * p.width) / cell) as usize).min(gw - 1);
        let j = (((z + 0.5 * p.thickness) / cell) as usize).min(gh - 1);
        (i, j)
    };
    for _ in 0..n {
        let mut placed = None;
        for attempt in 0..PLACEMENT_ATTEMPTS {
            let y = rng.range(-0.5 * p.width, 0.5 * p.width);
            let z = rng.range(-0.5 * p.thickness, 0.5 * p.thickness);
            let (ci, cj) = cell_of(y, z);
            let clear = (ci.saturating_sub(1)..(ci + 2).min(gw)).all(|i| {
                (cj.saturating_sub(1)..(cj + 2).min(gh)).all(|j| {
                    grid[i * gh + j].iter().all(|&k| {
                        let (yk, zk) = centres[k as usize];
                        (yk - y) * (yk - y) + (zk - z) * (zk - z) >= min_d2
                    })
                })
            });
            if clear || attempt + 1 == PLACEMENT_ATTEMPTS {
                if !clear {
                    overlaps += 1;
                }
                placed = Some((y, z, ci, cj));
                break;
            }
        }
        if let Some((y, z, ci, cj)) = placed {
            grid[ci * gh + cj].push(centres.len() as u32);
            centres.push((y, z));
        }
    }
    let half = 0.5 * p.length;
    let segments: Vec<(Vec3, Vec3)> = centres
        .iter()
        .map(|&(y, z)| (Vec3::new(-half, y, z), Vec3::new(half, y, z)))
        .collect();
    let scene = FibreScene::from_segments(&segments, r)?;
    Ok(Tuft {
        scene,
        params: p,
        fibre_count: centres.len(),
        overlaps,
    })
}

/// `count` parallel rays toward `target` from the direction `from` (the
/// direction from the target toward the camera, normalised): origins at
/// `target + distance from + a e1 + b e2` with `(a, b)` uniform (seeded) in
/// the square `[-window/2, window/2]^2` of the plane normal to `from`
/// (`e1, e2` its orthonormal pair), directions `-from`. Average the
/// radiance of these rays to get a patch's mean.
///
/// # Errors
///
/// [`Error::InvalidParameter`] for a zero or non-finite `from` (`"from"`),
/// or a non-finite `target`, `distance` or `window` (or negative window).
pub fn orthographic_rays(
    target: Vec3,
    from: Vec3,
    distance: f32,
    window: f32,
    count: usize,
    seed: u64,
) -> Result<Vec<(Vec3, Vec3)>, Error> {
    let bad = |name, value| Err(Error::InvalidParameter { name, value });
    let Some(w) = from.try_normalize() else {
        return bad("from", from.length());
    };
    if !target.is_finite() {
        return bad("target", f32::NAN);
    }
    if !distance.is_finite() {
        return bad("distance", distance);
    }
    if !(window.is_finite() && window >= 0.0) {
        return bad("window", window);
    }
    let (e1, e2) = w.any_orthonormal_pair();
    let mut rng = SplitMix64::new(seed);
    Ok((0..count)
        .map(|_| {
            let a = (rng.next_f32() - 0.5) * window;
            let b = (rng.next_f32() - 0.5) * window;
            (target + w * distance + e1 * a + e2 * b, -w)
        })
        .collect())
}

impl Tuft {
    /// The tuft's centre (the origin).
    pub fn centre(&self) -> Vec3 {
        Vec3::ZERO
    }

    /// [`orthographic_rays`] aimed at the tuft's centre from `from`,
    /// starting outside the tuft's bounding sphere.
    ///
    /// # Errors
    ///
    /// As [`orthographic_rays`].
    pub fn camera_rays(
        &self,
        from: Vec3,
        window: f32,
        count: usize,
        seed: u64,
    ) -> Result<Vec<(Vec3, Vec3)>, Error> {
        let (lo, hi) = self.scene.bounds();
        let distance = 0.5 * (hi - lo).length() + 4.0 * self.params.radius;
        orthographic_rays(self.centre(), from, distance, window, count, seed)
    }
}
