//! Penalised least-squares B-spline fits (P-splines, Eilers & Marx 1996,
//! "Flexible smoothing with B-splines and penalties"), solved with
//! faer's Cholesky factorisation.
//!
//! For `p` points `y_i` taken as samples at uniform parameter
//! `u_i = i (n - 1) / (p - 1)` of the curve of [`crate::refine`] with `n`
//! control points `c`, minimise
//!
//! ```text
//! |B c - y|^2 + lambda |D2 c|^2   ->   (B^T B + lambda D2^T D2) c = B^T y
//! ```
//!
//! where row `i` of `B` holds the four span weights at `u_i` with the phantom
//! ends folded in (`P_{-1} = 2 P_0 - P_1` adds `2 b0` to `c_0` and `-b0` to
//! `c_1`; likewise at the tip), and `D2` has rows `[1 -2 1]`. The matrix
//! depends only on `(p, n, lambda)`: a [`Fitter`] factors it once and then
//! solves all strands' x, y and z right-hand sides together. Arithmetic is in
//! f64; inputs and outputs are f32.

use crate::Error;
use faer::linalg::solvers::{Llt, Solve};
use faer::{Mat, Side};
use glam::Vec3;

/// Strands per faer solve in [`Fitter::fit_into`] (3 right-hand sides each).
const STRANDS_PER_SOLVE: usize = 64;

/// Penalised least-squares fit (faer): `n_control` control points whose
/// [`crate::refine`] curve passes closest to `points`, taken as samples at
/// uniform parameter from the first to the last, with second-difference
/// penalty `smoothing` (`lambda`; 0 = plain least squares).
///
/// # Errors
///
/// [`Error::TooFewControlPoints`] on `n_control < 2`,
/// [`Error::MoreControlsThanPoints`] on `n_control > points.len()`,
/// [`Error::NonFinite`] on non-finite input, [`Error::InvalidParameter`] on
/// `smoothing < 0` or NaN or infinite, [`Error::SingularFit`] if the normal
/// matrix is not positive definite.
pub fn fit(points: &[Vec3], n_control: usize, smoothing: f32) -> Result<Vec<Vec3>, Error> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFinite { index });
    }
    let mut fitter = Fitter::new(points.len(), n_control, smoothing)?;
    let mut out = vec![Vec3::ZERO; n_control];
    fitter.fit_into(points, &mut out)?;
    Ok(out)
}

/// Row `i` of the folded basis matrix: weights on controls `first .. first + 4`
/// (entries past `n - 1` are zero).
#[derive(Clone, Copy, Debug)]
struct BasisRow {
    first: usize,
    w: [f64; 4],
}

/// A factored P-spline system for one `(point count, control count, lambda)`:
/// build once, then fit any number of strands.
#[derive(Clone, Debug)]
pub struct Fitter {
    n_points: usize,
    n_control: usize,
    smoothing: f32,
    rows: Vec<BasisRow>,
    llt: Llt<f64>,
    /// Right-hand sides: column `3 s + axis` for strand `s` of a chunk.
    rhs: Mat<f64>,
}

impl Fitter {
    /// Builds `B^T B + lambda D2^T D2` and factors it (faer `Llt`).
    ///
    /// # Errors
    ///
    /// As [`fit`] does (with `n_points` for the number of points), and
    /// [`Error::SingularFit`] if the matrix is not positive definite.
    ///
    /// # Panics
    ///
    /// Only as an allocation does: the fitter holds dense `n_points x
    /// n_control` and `n_control x n_control` matrices.
    pub fn new(n_points: usize, n_control: usize, smoothing: f32) -> Result<Fitter, Error> {
        if n_control < 2 {
            return Err(Error::TooFewControlPoints { n_control });
        }
        if n_control > n_points {
            return Err(Error::MoreControlsThanPoints {
                n_control,
                points: n_points,
            });
        }
        if !(smoothing.is_finite() && smoothing >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "smoothing",
                value: smoothing as f64,
                expected: "finite and >= 0",
            });
        }
        let rows: Vec<BasisRow> = (0..n_points)
            .map(|i| basis_row(i, n_points, n_control))
            .collect();
        let n = n_control;
        let mut a = Mat::<f64>::zeros(n, n);
        for row in &rows {
            for (k, &wk) in row.w.iter().enumerate() {
                for (m, &wm) in row.w.iter().enumerate() {
                    if row.first + k < n && row.first + m < n {
                        a[(row.first + k, row.first + m)] += wk * wm;
                    }
                }
            }
        }
        let lambda = smoothing as f64;
        for i in 0..n.saturating_sub(2) {
            let d = [1.0, -2.0, 1.0];
            for k in 0..3 {
                for m in 0..3 {
                    a[(i + k, i + m)] += lambda * d[k] * d[m];
                }
            }
        }
        let llt = Llt::new(a.as_ref(), Side::Lower).map_err(|e| match e {
            faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                Error::SingularFit { pivot: index }
            }
        })?;
        Ok(Fitter {
            n_points,
            n_control,
            smoothing,
            rows,
            llt,
            rhs: Mat::zeros(n, 3 * STRANDS_PER_SOLVE),
        })
    }

    /// Samples per strand the fitter was built for.
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// Control points per fitted strand.
    pub fn n_control(&self) -> usize {
        self.n_control
    }

    /// The second-difference penalty `lambda` (0 = plain least squares).
    pub fn smoothing(&self) -> f32 {
        self.smoothing
    }

    /// Fits every strand of `points` (`n_points` per strand, strand after
    /// strand) and writes `n_control` control points per strand into `out`.
    ///
    /// A strand with a
    /// non-finite point gets non-finite control points; the other strands
    /// are unaffected (each right-hand side is solved independently).
    /// Allocates nothing.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] (and nothing written) if `points` is not a
    /// whole number of strands or `out` has not `n_control` points per strand.
    pub fn fit_into(&mut self, points: &[Vec3], out: &mut [Vec3]) -> Result<(), Error> {
        let (p, n) = (self.n_points, self.n_control);
        if !points.len().is_multiple_of(p) {
            return Err(Error::CountMismatch {
                what: "points (a whole number of strands)",
                expected: points.len().div_ceil(p) * p,
                got: points.len(),
            });
        }
        let strands = points.len() / p;
        if out.len() != strands * n {
            return Err(Error::CountMismatch {
                what: "output control points",
                expected: strands * n,
                got: out.len(),
            });
        }
        for (chunk, (pts, res)) in points
            .chunks(p * STRANDS_PER_SOLVE)
            .zip(out.chunks_mut(n * STRANDS_PER_SOLVE))
            .enumerate()
        {
            let _ = chunk;
            let count = pts.len() / p;
            for s in 0..count {
                let strand = &pts[s * p..(s + 1) * p];
                for axis in 0..3 {
                    let col = self.rhs.col_as_slice_mut(3 * s + axis);
                    col.fill(0.0);
                    for (row, y) in self.rows.iter().zip(strand) {
                        let y = y[axis] as f64;
                        let end = (row.first + 4).min(n);
                        for (c, w) in col[row.first..end].iter_mut().zip(row.w) {
                            *c += w * y;
                        }
                    }
                }
            }
            let rhs = self.rhs.as_mut().subcols_mut(0, 3 * count);
            self.llt.solve_in_place(rhs);
            for s in 0..count {
                for k in 0..n {
                    res[s * n + k] = Vec3::new(
                        self.rhs[(k, 3 * s)] as f32,
                        self.rhs[(k, 3 * s + 1)] as f32,
                        self.rhs[(k, 3 * s + 2)] as f32,
                    );
                }
            }
        }
        Ok(())
    }

    /// [`Fitter::fit_into`] into a new vector.
    ///
    /// # Errors
    ///
    /// As [`Fitter::fit_into`].
    pub fn fit(&mut self, points: &[Vec3]) -> Result<Vec<Vec3>, Error> {
        let mut out = vec![Vec3::ZERO; points.len() / self.n_points.max(1) * self.n_control];
        self.fit_into(points, &mut out)?;
        Ok(out)
    }
}

/// Folded basis row of sample `i` of `p` for `n` controls.
fn basis_row(i: usize, p: usize, n: usize) -> BasisRow {
    let u = if p > 1 {
        i as f64 * (n - 1) as f64 / (p - 1) as f64
    } else {
        0.0
    };
    let j = (u.floor() as usize).min(n - 2);
    let t = u - j as f64;
    let s = 1.0 - t;
    let b = [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ];
    // Dense weights on controls j-1 ..= j+2 with phantoms folded in.
    let mut dense = [0.0f64; 6]; // index c - (j - 1) + 1, covers j-2 ..= j+3 safely
    let mut add = |c: isize, w: f64| {
        let idx = c - (j as isize - 1) + 1;
        dense[idx as usize] += w;
    };
    for (k, &w) in b.iter().enumerate() {
        let c = j as isize - 1 + k as isize;
        if c < 0 {
            add(0, 2.0 * w);
            add(1, -w);
        } else if c >= n as isize {
            add(n as isize - 1, 2.0 * w);
            add(n as isize - 2, -w);
        } else {
            add(c, w);
        }
    }
    let first = j.saturating_sub(1);
    let offset = (first as isize - (j as isize - 1) + 1) as usize;
    let mut w = [0.0; 4];
    w.copy_from_slice(&dense[offset..offset + 4]);
    BasisRow { first, w }
}

/// Resamples polylines of any vertex count to `n_vertices` control points:
/// `n_samples` arc-length-uniform points along the polyline, then a P-spline
/// [`Fitter`] (`n_samples` -> `n_vertices`, `smoothing`). Use it to load an
/// authored groom into a simulation of `V = n_vertices` vertices per strand.
#[derive(Clone, Debug)]
pub struct Resampler {
    fitter: Fitter,
    samples: Vec<Vec3>,
}

impl Resampler {
    /// A resampler to `n_vertices` points through `n_samples` arc-length samples.
    ///
    /// # Errors
    ///
    /// As [`Fitter::new`] (`n_vertices >= 2`, `n_samples >= n_vertices`).
    ///
    /// # Panics
    ///
    /// As [`Fitter::new`], only if its matrices cannot be allocated.
    pub fn new(n_samples: usize, n_vertices: usize, smoothing: f32) -> Result<Resampler, Error> {
        Ok(Resampler {
            fitter: Fitter::new(n_samples, n_vertices, smoothing)?,
            samples: vec![Vec3::ZERO; n_samples],
        })
    }

    /// Vertices per resampled strand.
    pub fn n_vertices(&self) -> usize {
        self.fitter.n_control()
    }

    /// Fits one strand (any number of points, root first) into `out`
    /// (`n_vertices` points). A one-point or zero-length strand gives copies
    /// of its root.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] on an empty strand or an `out` of another
    /// length than `n_vertices`, [`Error::NonFinite`] on a non-finite point;
    /// nothing is written then.
    pub fn resample_into(&mut self, strand: &[Vec3], out: &mut [Vec3]) -> Result<(), Error> {
        if strand.is_empty() {
            return Err(Error::CountMismatch {
                what: "strand points (at least)",
                expected: 1,
                got: 0,
            });
        }
        if let Some(index) = strand.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        arc_length_samples(strand, &mut self.samples);
        self.fitter.fit_into(&self.samples, out)?;
        // The fit passes through the samples' ends only approximately when
        // smoothing > 0; the roots must stay exactly on the scalp.
        out[0] = strand[0];
        Ok(())
    }

    /// Resamples many strands: `strands` yields each strand's points; `out`
    /// receives `n_vertices` points per strand, strand after strand.
    ///
    /// # Errors
    ///
    /// As [`Resampler::resample_into`], at the first strand that fails
    /// (`out` then holds the strands before it).
    pub fn resample_all<'a>(
        &mut self,
        strands: impl IntoIterator<Item = &'a [Vec3]>,
        out: &mut Vec<Vec3>,
    ) -> Result<(), Error> {
        out.clear();
        let v = self.n_vertices();
        for s in strands {
            let start = out.len();
            out.resize(start + v, Vec3::ZERO);
            self.resample_into(s, &mut out[start..])?;
        }
        Ok(())
    }
}

pub use coif_base::polyline::arc_length_samples;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folded_rows_reproduce_refine_weights() {
        // Row weights times controls equal the curve evaluated directly.
        let ctrl: Vec<Vec3> = (0..5)
            .map(|i| Vec3::new(i as f32, (i * i) as f32 * 0.3, (i as f32).sin()))
            .collect();
        let p = 13;
        for i in 0..p {
            let row = basis_row(i, p, ctrl.len());
            let mut sum = Vec3::ZERO;
            for k in 0..4 {
                if row.first + k < ctrl.len() {
                    sum += ctrl[row.first + k] * row.w[k] as f32;
                }
            }
            let u = i as f32 * 4.0 / 12.0;
            let direct = crate::bspline::evaluate(&ctrl, u);
            assert!((sum - direct).length() < 1e-5, "{i}: {sum} {direct}");
        }
    }

    #[test]
    fn arc_length_samples_are_even() {
        let strand = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 3.0, 0.0)];
        let mut out = [Vec3::ZERO; 5];
        arc_length_samples(&strand, &mut out);
        for w in out.windows(2) {
            assert!(((w[1] - w[0]).length() - 1.0).abs() < 1e-6);
        }
        assert_eq!(out[4], strand[2]);
    }
}
