//! Factored lookup tables for Marschner 2003 (NVIDIA Nalu, GPU Gems 2
//! chapter 23), with a scalar lookup and a `wide` SIMD batch lookup.
//!
//! S = M_R N_R + M_TT N_TT + M_TRT N_TRT, with
//! - table M, indexed by (0.5 + 0.5 sin theta_i, 0.5 + 0.5 sin theta_o),
//!   holding (M_R, M_TT, M_TRT, cos theta_d);
//! - table N, indexed by (cos theta_d, v), holding N_R (grey), N_TT (RGB) and
//!   N_TRT (RGB) with 1 / cos^2 theta_d folded in and the absorption baked,
//!   so it is rebuilt when the material changes.
//!
//! Both lookups are bilinear. The coordinates are the layout's choice
//! ([`LutLayout`]). Nalu's v = 0.5 + 0.5 cos phi squeezes the
//! neighbourhoods of phi = 0 and phi = pi into few texels (d cos phi / d phi
//! = 0 there), where the TRT glints (near +-phi_c, 15-25 deg at eta = 1.55)
//! and the TT forward peak live; and its sin theta axes squeeze grazing
//! angles (d sin theta / d theta = 0 at +-90 deg), where theta_i ~ -theta_o
//! puts theta_h at the M peaks and 1 / cos^2 theta_d makes S largest. That
//! grazing region dominates Nalu's error; the default [`LutLayout::Angular`]
//! indexes both axes linearly in angle and computes cos theta_d exactly.
//!
//! [`Lut::scattering`] (one sample) and [`Lut::scattering_simd`] (eight lanes)
//! run the same steps; [`Lut::scattering_batch`] (SIMD) and
//! [`scalar::scattering_batch`] look up a whole batch.

pub mod scalar;

use super::params::Sanitised;
use super::{longitudinal, n_terms, Params, MIN_COS_THETA_D};
use crate::{RgbBuffer, ShadingSamples};
use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::{Vec3Lanes, LANES};
use glam::{Vec3, Vec4};
use std::f64::consts::PI;

/// Smallest and largest table resolution [`Lut::new`] accepts (it clamps).
pub const MIN_RESOLUTION: usize = 2;
/// 1024 x 1024 texels take 48 MiB (16 bytes per M texel, 32 per N texel).
pub const MAX_RESOLUTION: usize = 1024;

/// How the angles index the two tables.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LutLayout {
    /// Nalu's: table M at (0.5 + 0.5 sin theta_i, 0.5 + 0.5 sin theta_o), cos theta_d
    /// read from table M, table N at (cos theta_d, 0.5 + 0.5 cos phi). No inverse
    /// trigonometry, but coarse near phi = 0 and pi and near grazing
    /// (|sin theta| -> 1), where 1 / cos^2 theta_d makes S largest.
    Nalu,
    /// Nalu's table M, table N at (cos theta_d, |phi| / pi) (one `acos`).
    LinearPhi,
    /// coif's: table M at (0.5 + theta_i / pi, 0.5 + theta_o / pi) (two `asin`),
    /// cos theta_d computed exactly as sqrt((1 + cos theta_i cos theta_o +
    /// sin theta_i sin theta_o) / 2) instead of interpolated, table N at
    /// (cos theta_d, |phi| / pi) (one `acos`).
    #[default]
    Angular,
    /// coif's angular table M with Nalu's 0.5 + 0.5 cos phi for table N: isolates
    /// the effect of the azimuth parameterisation.
    AngularCosPhi,
}

impl LutLayout {
    /// Every layout, for comparisons.
    pub const ALL: [LutLayout; 4] = [
        LutLayout::Nalu,
        LutLayout::LinearPhi,
        LutLayout::Angular,
        LutLayout::AngularCosPhi,
    ];

    /// Table M indexed by angle (asin at lookup) with exact cos theta_d.
    fn linear_theta(self) -> bool {
        matches!(self, LutLayout::Angular | LutLayout::AngularCosPhi)
    }

    /// Table N indexed by |phi| / pi (acos at lookup).
    fn linear_phi(self) -> bool {
        matches!(self, LutLayout::LinearPhi | LutLayout::Angular)
    }
}

/// The factored form in 2D lookup tables.
#[derive(Clone, Debug)]
pub struct Lut {
    resolution: usize,
    layout: LutLayout,
    /// (M_R, M_TT, M_TRT, cos theta_d) at [y * res + x], x from sin theta_i, y from sin theta_o.
    m: Vec<Vec4>,
    /// ((N_R, N_TT rgb), (N_TRT rgb, 0)) at [y * res + x], x from cos theta_d, y from v.
    n: Vec<[Vec4; 2]>,
}

/// Table entries below this are stored as zero: far-tail Gaussians and
/// strongly absorbed lobes would otherwise be subnormal floats, and every
/// multiply touching a subnormal takes a microcode assist (tens of times slower).
const FLUSH_TO_ZERO: f64 = 1e-12;

fn flushed(v: f64) -> f32 {
    if v.abs() < FLUSH_TO_ZERO {
        0.0
    } else {
        v as f32
    }
}

/// Zero-length inputs below this squared length give zero.
const MIN_LENGTH_SQUARED: f32 = 1e-30;
/// Below this cos theta_i cos theta_o, phi is undefined and taken as 0.
const MIN_COS_PRODUCT: f32 = 1e-12;

impl Lut {
    /// Tables of `resolution` x `resolution` texels each, with the default
    /// layout ([`LutLayout::LinearPhi`]). `resolution` is clamped to
    /// [`MIN_RESOLUTION`]..=[`MAX_RESOLUTION`] (2..=1024); NaN or
    /// out-of-range parameters are sanitised as [`super::scattering`] does.
    pub fn new(params: &Params, resolution: usize) -> Lut {
        Lut::with_layout(params, resolution, LutLayout::default())
    }

    /// Tables with an explicit azimuth layout (to compare Nalu's with coif's).
    pub fn with_layout(params: &Params, resolution: usize, layout: LutLayout) -> Lut {
        let res = resolution.clamp(MIN_RESOLUTION, MAX_RESOLUTION);
        let p = Sanitised::new(params);
        let step = 1.0 / (res - 1) as f64;
        let mut m = Vec::with_capacity(res * res);
        let theta_at = |u: f64| {
            if layout.linear_theta() {
                PI * (u - 0.5)
            } else {
                (2.0 * u - 1.0).clamp(-1.0, 1.0).asin()
            }
        };
        for y in 0..res {
            let theta_o = theta_at(y as f64 * step);
            for x in 0..res {
                let theta_i = theta_at(x as f64 * step);
                let mt = longitudinal::m_terms(&p, 0.5 * (theta_i + theta_o));
                let cos_d = (0.5 * (theta_o - theta_i)).cos();
                m.push(Vec4::new(
                    flushed(mt[0]),
                    flushed(mt[1]),
                    flushed(mt[2]),
                    cos_d as f32,
                ));
            }
        }
        let mut n = Vec::with_capacity(res * res);
        for y in 0..res {
            let v = y as f64 * step;
            let phi = if layout.linear_phi() {
                v * PI
            } else {
                (2.0 * v - 1.0).clamp(-1.0, 1.0).acos()
            };
            for x in 0..res {
                let cos_d = (x as f64 * step).max(MIN_COS_THETA_D as f64);
                let t = n_terms(&p, cos_d, phi);
                let k = 1.0 / (cos_d * cos_d);
                let f = |v: f64| flushed(v * k);
                n.push([
                    Vec4::new(f(t[0][0]), f(t[1][0]), f(t[1][1]), f(t[1][2])),
                    Vec4::new(f(t[2][0]), f(t[2][1]), f(t[2][2]), 0.0),
                ]);
            }
        }
        Lut {
            resolution: res,
            layout,
            m,
            n,
        }
    }

    /// Texels per side (after clamping).
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// The table layout (coordinates of both tables).
    pub fn layout(&self) -> LutLayout {
        self.layout
    }

    /// Bytes held by the two tables.
    pub fn size_bytes(&self) -> usize {
        self.m.len() * std::mem::size_of::<Vec4>() + self.n.len() * 2 * std::mem::size_of::<Vec4>()
    }

    /// Table M's texels for a GPU texture: `resolution` rows of
    /// `resolution` texels, texel `[y * resolution + x]` holding (M_R, M_TT,
    /// M_TRT, cos theta_d), x from theta_i and y from theta_o (by the
    /// layout's coordinate). A shader doing [`Lut::scattering`]'s bilinear
    /// lookups on these gives its results.
    pub fn table_m(&self) -> &[Vec4] {
        &self.m
    }

    /// Table N's texels for GPU textures, laid out as [`Lut::table_m`]:
    /// per texel `[(N_R, N_TT rgb), (N_TRT rgb, 0)]`, x from cos theta_d and
    /// y from the azimuth (by the layout's coordinate); two RGBA textures.
    pub fn table_n(&self) -> &[[Vec4; 2]] {
        &self.n
    }

    /// S from the tables (scalar lookup). Same robustness rules as
    /// [`super::scattering`]: non-unit directions are fine, zero length gives
    /// zero, non-finite components (or squared lengths overflowing f32) give NaN.
    pub fn scattering(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        if !(lt2 + li2 + lo2).is_finite() {
            return Vec3::NAN;
        }
        if lt2 < MIN_LENGTH_SQUARED || li2 < MIN_LENGTH_SQUARED || lo2 < MIN_LENGTH_SQUARED {
            return Vec3::ZERO;
        }
        let (rt, ri, ro) = (lt2.sqrt(), li2.sqrt(), lo2.sqrt());
        let sin_i = (wi.dot(t) / (ri * rt)).clamp(-1.0, 1.0);
        let sin_o = (wo.dot(t) / (ro * rt)).clamp(-1.0, 1.0);
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let cc = cos_i * cos_o;
        let cos_phi = if cc > MIN_COS_PRODUCT {
            ((wi.dot(wo) / (ri * ro) - sin_i * sin_o) / cc).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let inv_pi = std::f32::consts::FRAC_1_PI;
        let (ui, uo) = if self.layout.linear_theta() {
            (0.5 + sin_i.asin() * inv_pi, 0.5 + sin_o.asin() * inv_pi)
        } else {
            (0.5 + 0.5 * sin_i, 0.5 + 0.5 * sin_o)
        };
        let (mi, fx, fy) = self.coords(ui, uo);
        let m = self.bilinear_m(mi, fx, fy);
        let cos_d = if self.layout.linear_theta() {
            (0.5 * (1.0 + cc + sin_i * sin_o)).max(0.0).sqrt()
        } else {
            m.w
        };
        let v = if self.layout.linear_phi() {
            cos_phi.acos() * inv_pi
        } else {
            0.5 + 0.5 * cos_phi
        };
        let (ni, gx, gy) = self.coords(cos_d, v);
        combine(m, self.bilinear_n(ni, gx, gy))
    }

    /// Texel index of the lower corner and the bilinear weights for table
    /// coordinates (u, v) in [0, 1] (clamped; NaN lands on texel 0).
    #[inline(always)]
    fn coords(&self, u: f32, v: f32) -> (usize, f32, f32) {
        let scale = (self.resolution - 1) as f32;
        let last = (self.resolution - 2) as f32;
        let x = (u * scale).clamp(0.0, scale);
        let y = (v * scale).clamp(0.0, scale);
        let x0 = x.floor().clamp(0.0, last);
        let y0 = y.floor().clamp(0.0, last);
        (y0 as usize * self.resolution + x0 as usize, x - x0, y - y0)
    }

    #[inline(always)]
    fn bilinear_m(&self, i: usize, fx: f32, fy: f32) -> Vec4 {
        let r = self.resolution;
        let a = self.m[i].lerp(self.m[i + 1], fx);
        let b = self.m[i + r].lerp(self.m[i + r + 1], fx);
        a.lerp(b, fy)
    }

    #[inline(always)]
    fn bilinear_n(&self, i: usize, fx: f32, fy: f32) -> [Vec4; 2] {
        let r = self.resolution;
        let (c00, c10, c01, c11) = (
            &self.n[i],
            &self.n[i + 1],
            &self.n[i + r],
            &self.n[i + r + 1],
        );
        [0, 1].map(|k| {
            let a = c00[k].lerp(c10[k], fx);
            let b = c01[k].lerp(c11[k], fx);
            a.lerp(b, fy)
        })
    }

    /// SIMD batch lookup: eight samples at a time, the angle and index
    /// arithmetic in `F32Lanes`, texel fetches per lane (manual gathers) with the
    /// same bilinear arithmetic as the scalar path. `out` is resized to
    /// `samples.len()` (allocation-free once it has the capacity). Matches
    /// [`scalar::scattering_batch`] to float rounding (the `acos` of the
    /// LinearPhi layout is wide's polynomial in SIMD, libm's in scalar).
    pub fn scattering_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        crate::batch::shade_blocks(samples, out, |t, wi, wo| self.lookup_simd(t, wi, wo));
    }

    /// Eight lookups; the same steps as [`Lut::scattering`].
    #[inline(always)]
    pub fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        self.lookup_simd(t, wi, wo)
    }

    #[inline(always)]
    fn lookup_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        let one = F32Lanes::ONE;
        let zero = F32Lanes::ZERO;
        let half = F32Lanes::splat(0.5);
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        let non_finite = !(lt2 + li2 + lo2).is_finite();
        let tiny = F32Lanes::splat(MIN_LENGTH_SQUARED);
        let zero_len = lt2.simd_lt(tiny) | li2.simd_lt(tiny) | lo2.simd_lt(tiny);
        let (rt, ri, ro) = (lt2.sqrt(), li2.sqrt(), lo2.sqrt());
        let sin_i = (wi.dot(t) / (ri * rt)).max(-one).min(one);
        let sin_o = (wo.dot(t) / (ro * rt)).max(-one).min(one);
        let cos_i = (one - sin_i * sin_i).max(zero).sqrt();
        let cos_o = (one - sin_o * sin_o).max(zero).sqrt();
        let cc = cos_i * cos_o;
        let raw = ((wi.dot(wo) / (ri * ro) - sin_i * sin_o) / cc)
            .max(-one)
            .min(one);
        let cos_phi = cc
            .simd_gt(F32Lanes::splat(MIN_COS_PRODUCT))
            .select(raw, one);

        let inv_pi = F32Lanes::splat(std::f32::consts::FRAC_1_PI);
        let (ui, uo) = if self.layout.linear_theta() {
            (half + sin_i.asin() * inv_pi, half + sin_o.asin() * inv_pi)
        } else {
            (half + half * sin_i, half + half * sin_o)
        };
        let (mi, fx, fy) = self.coords_simd(ui, uo);
        let (mi, fx, fy) = (mi.to_array(), fx.to_array(), fy.to_array());
        let mut ms = [Vec4::ZERO; LANES];
        let mut table_cos_d = [0.0f32; LANES];
        for l in 0..LANES {
            ms[l] = self.bilinear_m(mi[l] as usize, fx[l], fy[l]);
            table_cos_d[l] = ms[l].w;
        }
        let cos_d = if self.layout.linear_theta() {
            (half * (one + cc + sin_i * sin_o)).max(zero).sqrt()
        } else {
            F32Lanes::new(table_cos_d)
        };
        let v = if self.layout.linear_phi() {
            cos_phi.acos() * inv_pi
        } else {
            half + half * cos_phi
        };
        let (ni, gx, gy) = self.coords_simd(cos_d, v);
        let (ni, gx, gy) = (ni.to_array(), gx.to_array(), gy.to_array());
        let mut rgb = [[0.0f32; LANES]; 3];
        for l in 0..LANES {
            let s = combine(ms[l], self.bilinear_n(ni[l] as usize, gx[l], gy[l]));
            rgb[0][l] = s.x;
            rgb[1][l] = s.y;
            rgb[2][l] = s.z;
        }
        let out = Vec3Lanes::new(
            F32Lanes::new(rgb[0]),
            F32Lanes::new(rgb[1]),
            F32Lanes::new(rgb[2]),
        );
        let out = Vec3Lanes::select(zero_len, Vec3Lanes::ZERO, out);
        Vec3Lanes::select(non_finite, Vec3Lanes::splat(Vec3::NAN), out)
    }

    /// SIMD twin of `coords`; the integer clamp keeps NaN lanes in bounds.
    #[inline(always)]
    fn coords_simd(&self, u: F32Lanes, v: F32Lanes) -> (I32Lanes, F32Lanes, F32Lanes) {
        let scale = F32Lanes::splat((self.resolution - 1) as f32);
        let last = F32Lanes::splat((self.resolution - 2) as f32);
        let zero = F32Lanes::ZERO;
        let x = (u * scale).max(zero).min(scale);
        let y = (v * scale).max(zero).min(scale);
        let x0 = x.floor().max(zero).min(last);
        let y0 = y.floor().max(zero).min(last);
        let last_i = I32Lanes::splat(self.resolution as i32 - 2);
        let xi = x0.trunc_int().max(I32Lanes::ZERO).min(last_i);
        let yi = y0.trunc_int().max(I32Lanes::ZERO).min(last_i);
        (
            yi * I32Lanes::splat(self.resolution as i32) + xi,
            x - x0,
            y - y0,
        )
    }
}

/// S = M_R N_R + M_TT N_TT + M_TRT N_TRT from the two texels' contents.
#[inline(always)]
fn combine(m: Vec4, n: [Vec4; 2]) -> Vec3 {
    let n_tt = Vec3::new(n[0].y, n[0].z, n[0].w);
    let n_trt = Vec3::new(n[1].x, n[1].y, n[1].z);
    (Vec3::splat(m.x * n[0].x) + n_tt * m.y + n_trt * m.z).max(Vec3::ZERO)
}
