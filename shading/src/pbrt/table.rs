//! The far-field pbrt model baked into two 2D lookup tables.
//!
//! pbrt-v3's model separates exactly: `M_p` depends on (theta_i, theta_o)
//! only (the cuticle tilt shifts theta_o, so it stays inside that pair) and
//! the h-averaged `A_p N_p` on (phi, theta_o) only (pbrt evaluates
//! refraction and Fresnel at theta_o). So the far field is
//! `sum_{p<3} M_p(theta_i, theta_o) N_p(phi, theta_o) + R_3(theta_i, theta_o)`
//! with `R_3 = M_3 A_3 / (2 pi)` averaged over h. The only error of the
//! tables is bilinear interpolation.
//!
//! * M table, `res x res` cells of 6 channels over (theta_i, theta_o):
//!   `M_0, M_1, M_2` and `R_3` (RGB).
//! * N table, `res x res` cells of 9 channels over (phi, theta_o):
//!   `N_0, N_1, N_2` (RGB, colour baked in: rebuild when the material changes).
//!
//! Axes ([`Parameterisation`]): `Angles` samples theta and phi uniformly
//! (phi in [0, pi]: the far field is even in phi); `Nalu` samples sin theta
//! and cos phi uniformly as NVIDIA's Nalu demo did, which is coarse where
//! the lobes are narrow, near phi = 0 and pi and at grazing theta. PBRT.md
//! compares both.
//!
//! [`Table::scattering`] (one sample) and [`Table::scattering_simd`] (eight
//! lanes) run the same steps; [`Table::scattering_batch`] (SIMD) and
//! [`scalar::scattering_batch`] look up a whole batch.

pub mod scalar;

use super::far_field::{combine, recommended_order, world_angles, FarField};
use super::fast_acos::{acos, acos_simd};
use super::params::Params;
use crate::{Error, RgbBuffer, ShadingSamples};
use coif_base::lanes::F32Lanes;
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;
use std::f32::consts::PI;
use wide::f32x8;

/// How the table axes map angles to grid coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Parameterisation {
    /// Uniform in theta_i, theta_o in [-pi/2, pi/2] and phi in [0, pi].
    #[default]
    Angles,
    /// Uniform in sin theta in [-1, 1] and cos phi in [-1, 1] (Nalu).
    Nalu,
}

/// Channels used in an M cell (`M_0, M_1, M_2, R_3 rgb`), stored in one
/// `f32x8` (two channels of padding; eight channels whatever the lane
/// width) so that the SIMD path loads a corner
/// with one aligned load.
const M_CH: usize = 6;
/// Channels used in an N cell (`N_0, N_1, N_2` rgb), stored in two `f32x8`.
const N_CH: usize = 9;

/// Largest [`Table`] resolution accepted (nodes per axis): the tables
/// hold about 100 bytes per node pair (100 MB at 1024), and their build is
/// a quadrature per node pair.
pub const MAX_TABLE_RESOLUTION: usize = 1024;

/// The far-field pbrt model in two `res x res` tables with bilinear lookup.
#[derive(Clone, Debug)]
pub struct Table {
    res: usize,
    axes: Parameterisation,
    /// `m[i_theta_i * res + i_theta_o]`.
    m: Vec<[f32x8; 1]>,
    /// `n[i_phi * res + i_theta_o]`.
    n: Vec<[f32x8; 2]>,
}

impl Table {
    /// Tables of `resolution x resolution` cells with [`Parameterisation::Angles`],
    /// built from the far field at its [`recommended_order`].
    ///
    /// # Errors
    ///
    /// As [`Table::with_axes`].
    pub fn new(params: &Params, resolution: usize) -> Result<Table, Error> {
        Table::with_axes(params, resolution, Parameterisation::Angles)
    }

    /// Tables with the chosen axes. Errors on invalid `params` or a
    /// resolution below 2.
    ///
    /// # Errors
    ///
    /// As [`Params::validate`], and [`Error::InvalidResolution`] below 2
    /// or above [`MAX_TABLE_RESOLUTION`].
    pub fn with_axes(
        params: &Params,
        resolution: usize,
        axes: Parameterisation,
    ) -> Result<Table, Error> {
        params.validate()?;
        let ff = FarField::new(params, recommended_order(params))?;
        Table::from_far_field(&ff, resolution, axes)
    }

    /// Tables sampled from a prepared far field (its quadrature order is used).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidResolution`] below 2 or above
    /// [`MAX_TABLE_RESOLUTION`].
    pub fn from_far_field(
        ff: &FarField,
        resolution: usize,
        axes: Parameterisation,
    ) -> Result<Table, Error> {
        let res = resolution;
        if !(2..=MAX_TABLE_RESOLUTION).contains(&res) {
            return Err(Error::InvalidResolution(res));
        }
        // Grid node k of an axis, as (sin theta, cos theta) or phi.
        let step = 1.0 / (res - 1) as f64;
        let theta_node = |k: usize| -> (f32, f32) {
            let u = k as f64 * step;
            let s = match axes {
                Parameterisation::Angles => (std::f64::consts::PI * (u - 0.5)).sin(),
                Parameterisation::Nalu => 2.0 * u - 1.0,
            };
            let s = s.clamp(-1.0, 1.0);
            (s as f32, (1.0 - s * s).max(0.0).sqrt() as f32)
        };
        let phis: Vec<f32> = (0..res)
            .map(|k| {
                let u = k as f64 * step;
                (match axes {
                    Parameterisation::Angles => std::f64::consts::PI * u,
                    Parameterisation::Nalu => (1.0 - 2.0 * u).clamp(-1.0, 1.0).acos(),
                }) as f32
            })
            .collect();

        let mut m = vec![[f32x8::ZERO; 1]; res * res];
        let mut n = vec![[f32x8::ZERO; 2]; res * res];
        let mut row = vec![[Vec3::ZERO; 4]; res];
        for j in 0..res {
            let (sin_o, cos_o) = theta_node(j);
            ff.azimuthal(sin_o, cos_o, &phis, &mut row)?;
            for (k, terms) in row.iter().enumerate() {
                let mut cell = [0.0f32; 16];
                for p in 0..3 {
                    cell[3 * p..3 * p + 3].copy_from_slice(&terms[p].to_array());
                }
                n[k * res + j] = cells(cell);
            }
            let residual = row[0][3];
            for i in 0..res {
                let (sin_i, cos_i) = theta_node(i);
                let mp = ff.longitudinal(sin_i, cos_i, sin_o, cos_o);
                let r3 = residual * mp[3];
                m[i * res + j] = [f32x8::new([
                    mp[0], mp[1], mp[2], r3.x, r3.y, r3.z, 0.0, 0.0,
                ])];
            }
        }
        Ok(Table { res, axes, m, n })
    }

    /// Texels per table side.
    pub fn resolution(&self) -> usize {
        self.res
    }

    /// How the table axes are parameterised.
    pub fn parameterisation(&self) -> Parameterisation {
        self.axes
    }

    /// Grid coordinates in [0, res - 1] of theta_i, theta_o and phi.
    #[inline]
    fn coords(&self, sin_i: f32, sin_o: f32, cos_phi: f32) -> (f32, f32, f32) {
        let scale = (self.res - 1) as f32;
        match self.axes {
            Parameterisation::Angles => (
                scale - acos(sin_i) * (scale / PI),
                scale - acos(sin_o) * (scale / PI),
                acos(cos_phi) * (scale / PI),
            ),
            Parameterisation::Nalu => {
                let half = 0.5 * scale;
                (
                    sin_i.mul_add(half, half),
                    sin_o.mul_add(half, half),
                    (-cos_phi).mul_add(half, half),
                )
            }
        }
    }

    /// Scalar lookup: the far field for unit tangent `t`, unit `wi` toward
    /// the light and unit `wo` toward the viewer. NaN input gives NaN.
    #[inline]
    pub fn scattering(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (sin_i, sin_o, cos_phi) = world_angles(t, wi, wo);
        self.lookup(sin_i, sin_o, cos_phi)
    }

    /// Scalar lookup from `sin theta_i`, `sin theta_o` and `cos phi`.
    #[inline]
    pub fn lookup(&self, sin_i: f32, sin_o: f32, cos_phi: f32) -> Vec3 {
        let (ui, uo, uphi) = self.coords(sin_i, sin_o, cos_phi);
        if ui.is_nan() || uo.is_nan() || uphi.is_nan() {
            return Vec3::NAN;
        }
        let (ci, fi) = split(ui, self.res);
        let (co, fo) = split(uo, self.res);
        let (cp, fp) = split(uphi, self.res);
        let res = self.res;
        let m = bilerp::<1, M_CH>(&self.m, ci * res + co, res, fi, fo);
        let n = bilerp::<2, N_CH>(&self.n, cp * res + co, res, fp, fo);
        combine_cells(&m, &n)
    }

    /// SIMD batch ([`coif_base::lanes::F32Lanes`], [`coif_base::LANES`] samples per step): the same
    /// coordinates, bilinear weights and sums as [`Table::scattering`],
    /// with per-lane table fetches. `out` is resized to the batch.
    pub fn scattering_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        out.resize(samples.len());
        let mut start = 0;
        while start < samples.len() {
            let (t, wi, wo) = samples.load_block(start);
            out.store_block(start, self.scattering_simd(t, wi, wo));
            start += LANES;
        }
    }

    /// Eight lookups at once.
    #[inline]
    pub fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        let sin_i = wi.dot(t);
        let sin_o = wo.dot(t);
        let pi_ = wi - t * sin_i;
        let po = wo - t * sin_o;
        let len2 = pi_.length_squared() * po.length_squared();
        let cos_phi = pi_.dot(po) / len2.max(F32Lanes::splat(1e-30)).sqrt();
        let one = F32Lanes::ONE;
        let clamp1 = |x: F32Lanes| {
            let x = x.simd_gt(one).bitselect(one, x);
            x.simd_lt(-one).bitselect(-one, x)
        };
        let (sin_i, sin_o) = (clamp1(sin_i), clamp1(sin_o));

        let scale = (self.res - 1) as f32;
        let (ui, uo, uphi) = match self.axes {
            Parameterisation::Angles => {
                let k = F32Lanes::splat(scale / PI);
                let s = F32Lanes::splat(scale);
                (
                    s - acos_simd(sin_i) * k,
                    s - acos_simd(sin_o) * k,
                    acos_simd(cos_phi) * k,
                )
            }
            Parameterisation::Nalu => {
                let half = F32Lanes::splat(0.5 * scale);
                (
                    sin_i.mul_add(half, half),
                    sin_o.mul_add(half, half),
                    (-cos_phi).mul_add(half, half),
                )
            }
        };
        let invalid = ui.is_nan() | uo.is_nan() | uphi.is_nan();
        let (ci, fi) = split_simd(ui, self.res);
        let (co, fo) = split_simd(uo, self.res);
        let (cp, fp) = split_simd(uphi, self.res);

        let (fi, fo, fp) = (fi.to_array(), fo.to_array(), fp.to_array());
        let res = self.res;
        let mut out = [[0.0f32; LANES]; 3];
        for l in 0..LANES {
            let m = lerp_cells(&self.m, ci[l] * res + co[l], res, fi[l], fo[l]);
            let n = lerp_cells(&self.n, cp[l] * res + co[l], res, fp[l], fo[l]);
            let v = combine_cells(m[0].as_array(), &concat(&n));
            out[0][l] = v.x;
            out[1][l] = v.y;
            out[2][l] = v.z;
        }
        let sum = Vec3Lanes::new(
            F32Lanes::new(out[0]),
            F32Lanes::new(out[1]),
            F32Lanes::new(out[2]),
        );
        Vec3Lanes::select(invalid, Vec3Lanes::splat(Vec3::NAN), sum)
    }
}

/// Sixteen floats as two vectors.
fn cells(c: [f32; 16]) -> [f32x8; 2] {
    let (a, b) = c.split_at(8);
    [
        f32x8::new(a.try_into().expect("8")),
        f32x8::new(b.try_into().expect("8")),
    ]
}

/// Two vectors as sixteen floats.
#[inline]
fn concat(v: &[f32x8; 2]) -> [f32; 16] {
    let mut out = [0.0; 16];
    out[..8].copy_from_slice(v[0].as_array());
    out[8..].copy_from_slice(v[1].as_array());
    out
}

/// `N_0 M_0 + N_1 M_1 + N_2 M_2 + R_3` from interpolated cell channels.
#[inline]
fn combine_cells(m: &[f32], n: &[f32]) -> Vec3 {
    let mp = [m[0], m[1], m[2], 1.0];
    let terms = [
        Vec3::new(n[0], n[1], n[2]),
        Vec3::new(n[3], n[4], n[5]),
        Vec3::new(n[6], n[7], n[8]),
        Vec3::new(m[3], m[4], m[5]),
    ];
    combine(&mp, &terms)
}

/// Cell index and fraction of a grid coordinate, clamped into the grid.
#[inline]
fn split(u: f32, res: usize) -> (usize, f32) {
    let top = (res - 2) as f32;
    let u = u.clamp(0.0, (res - 1) as f32);
    let c = u.floor().min(top);
    (c as usize, u - c)
}

/// [`split`] for a block of lanes (NaN lanes get cell 0; the caller masks them).
#[inline]
fn split_simd(u: F32Lanes, res: usize) -> ([usize; LANES], F32Lanes) {
    let zero = F32Lanes::ZERO;
    let last = F32Lanes::splat((res - 1) as f32);
    let top = F32Lanes::splat((res - 2) as f32);
    let u = u.simd_lt(zero).bitselect(zero, u);
    let u = u.simd_gt(last).bitselect(last, u);
    let c = u.floor();
    let c = c.simd_gt(top).bitselect(top, c);
    let ca = c.to_array();
    let cells = std::array::from_fn(|l| if ca[l] >= 0.0 { ca[l] as usize } else { 0 });
    (cells, u - c)
}

/// Bilinear blend, channel by channel in scalar code, of the cells `base`,
/// `base + 1`, `base + res`, `base + res + 1` with fractions `fa` (first
/// axis) and `fb` (second): `lo = c00 + (c01 - c00) fb`, `hi = c10 +
/// (c11 - c10) fb`, `lo + (hi - lo) fa`, each step one fused multiply-add.
#[inline]
fn bilerp<const V: usize, const C: usize>(
    t: &[[f32x8; V]],
    base: usize,
    res: usize,
    fa: f32,
    fb: f32,
) -> [f32; C] {
    let [c00, c01, c10, c11] = [base, base + 1, base + res, base + res + 1].map(|k| &t[k]);
    std::array::from_fn(|c| {
        let ch = |cell: &[f32x8; V]| cell[c / 8].as_array()[c % 8];
        let lo = (ch(c01) - ch(c00)).mul_add(fb, ch(c00));
        let hi = (ch(c11) - ch(c10)).mul_add(fb, ch(c10));
        (hi - lo).mul_add(fa, lo)
    })
}

/// [`bilerp`] with the channels of a cell in SIMD lanes: the same
/// operations per channel, eight channels per instruction, one aligned load
/// per corner vector.
#[inline]
fn lerp_cells<const V: usize>(
    t: &[[f32x8; V]],
    base: usize,
    res: usize,
    fa: f32,
    fb: f32,
) -> [f32x8; V] {
    let (fa, fb) = (f32x8::splat(fa), f32x8::splat(fb));
    let (c00, c01, c10, c11) = (&t[base], &t[base + 1], &t[base + res], &t[base + res + 1]);
    std::array::from_fn(|v| {
        let lo = (c01[v] - c00[v]).mul_add(fb, c00[v]);
        let hi = (c11[v] - c10[v]).mul_add(fb, c10[v]);
        (hi - lo).mul_add(fa, lo)
    })
}
