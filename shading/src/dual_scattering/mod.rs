//! Dual scattering: multiple scattering in hair at the cost of a few
//! lookups per shading point (Zinke, Yuksel, Weber and Keyser 2008, "Dual
//! scattering approximation for fast multiple scattering in hair", ACM
//! TOG 27(3); the equations cited below are that paper's).
//!
//! Light reaching a point inside hair has crossed `n` fibres on its way
//! from the light. The paper splits what arrives into a **global** part,
//! forward scattered through those fibres, and a **local** part, scattered
//! back by the fibres around the point:
//!
//! * global (eqs. 6-8): of the light entering the hair, the fraction
//!   `T_f = a_f(theta)^n` is still travelling forward after `n` crossings
//!   (`a_f` the fibre's forward-scattering attenuation, [`FibreAverages`]),
//!   spread in longitude by `sigma_f^2 = n beta_f^2`; its direction is
//!   spread over the forward azimuths, so the fibre at the point scatters it
//!   with its forward-azimuth average broadened by `sigma_f^2`:
//!   `f_G = g_amp g(theta_h - mu_g, v_g + sigma_f^2) / cos^2 theta_d`;
//! * local (eqs. 9-14): light bounced back and forth between the point's
//!   neighbours, `f_back = 2 A_b g(theta_h - delta_b, sigma_b^2) / (pi
//!   cos^2 theta_d)` with `A_b = A_1 + A_3` (one and three backward
//!   bounces), `A_1 = a_b a_f^2 / (1 - a_f^2)` and `A_3 = a_b^3 a_f^2 /
//!   (1 - a_f^2)^3`; the shift is `delta_b = alpha_b (1 - 2 a_b^2 / (1 -
//!   a_f^2)^2) + alpha_f (2 (1 - a_f^2)^2 + 4 a_f^2 a_b^2) / (1 - a_f^2)^3`
//!   and the width `sigma_b = (1 + d_b a_f^2) (a_b sqrt(2 beta_f^2 +
//!   beta_b^2) + a_b^3 sqrt(2 beta_f^2 + 3 beta_b^2)) / (a_b + a_b^3 (2
//!   beta_f + 3 beta_b))`.
//!
//! With the direct fraction `D` (the light reaching the point through no
//! fibre: a shadow map's transmittance) and the model's single scattering
//! `S`, the shading function is (section 5, "F")
//!
//! `F = D (S + d_b f_back c) + max(T_f - D, 0) d_f (f_G + pi d_b f_back^G) c`
//!
//! where `f_back^G` is `f_back` with the width `sigma_b^2 + sigma_f^2`, `d_f`
//! and `d_b` the density factors of forward and backward scattering (0.7
//! in the paper, [`DEFAULT_FORWARD_DENSITY`] and [`DEFAULT_BACKWARD_DENSITY`]
//! here by measurement;
//! [`DualScatteringSettings`]) and `c = cos theta_i` for a
//! model whose `S` already carries the cosine of the lighting integral
//! (pbrt-v3's far field), 1 for one that does not (Marschner's `S`: the
//! caller multiplies). With `n = 0` and `D = 1` (nothing in front) `F` is
//! single scattering plus the local backscatter.
//!
//! Differences from the paper, measured against the path tracer through
//! explicit fibres ([`crate::path_tracer`], [`accuracy`];
//! `shading/MULTIPLE_SCATTERING.md` has the figures): `T_f = a_f^n` without
//! the paper's extra `d_f` (`d_f` weighs the scattered light once, in `F`);
//! one global Gaussian per fibre instead of one per lobe (so any model
//! serves, pbrt-v3's included); the widths `beta_f`, `delta_b`, `sigma_b`
//! and the global mean and variance luminance-weighted to one channel
//! (their channels differ by a few per cent), the attenuations and
//! amplitudes per channel. Like the paper, the global term is the fibre's
//! average over the forward azimuths, the same for every view: the
//! fibre's profile filtered by a box of width pi instead (light arriving
//! from every forward azimuth) tripled the error on views through the
//! hair from behind, and was dropped.
//!
//! A known limit: the local backscatter is the paper's slab, truncated at
//! the `m` fibres on the light's line behind the point. In a lone wisp of
//! sparse hair (volume fraction 0.005, Sintel's crown clipped to a 6 mm
//! ball, less than the 12.6 mm light travels between fibres there) the
//! path tracer's light scattered back to a fibre does not follow that
//! count (it comes from the neighbours in every direction, and near the
//! wisp's edge half of them are missing), and the backscatter there is
//! about twice the tracer's for blond hair per fibre behind
//! (`MULTIPLE_SCATTERING.md`, "Sintel's crown: the diagnosis"); seeing
//! such an edge needs the hair over the hemisphere behind the point,
//! which a shadow map does not give. With the hair of two free paths round
//! the point (a 24 mm ball of the crown) the count on the line matches the
//! hemisphere's and dual scattering is 4.6 times closer to the tracer than
//! single scattering.
//!
//! The averages are tabulated once per material over `theta_i`
//! ([`DualScattering::new`]) and refined four times linearly. Everything
//! that depends only on `theta_i` (the local backscatter's Gaussian, the
//! amplitudes with the densities and the constants, the widths in the
//! units of a base-2 exponential) is folded into a 16-float record per
//! refined node; a lookup takes the nearest record, then two arccosines,
//! six exponentials `2^-q` (a degree-4 polynomial, 2.9e-6 relative, and the
//! exponent bits), two divisions and three square roots. NaN in any input
//! but `single` reaches every channel of the result through the
//! arithmetic (the clamps keep it), without a mask.
//! [`DualScattering::shade`] (one sample), [`DualScattering::shade_simd`]
//! (eight lanes) and the batches [`DualScattering::shade_batch`] /
//! [`scalar::shade_batch`] run the same operations in the same order (the
//! arccosine and exponential are shared polynomials), so they agree to
//! the bit (tested).

pub mod accuracy;
mod averages;
mod fast_exp;
pub mod scalar;

pub use averages::FibreAverages;

use crate::pbrt::fast_acos::{acos, acos_simd};
use crate::{marschner, pbrt, Error, RgbBuffer, ShadingSamples};
use coif_base::lanes::{from_groups, F32Group, GROUP_LANES};
use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::{Vec3Lanes, LANES};
use fast_exp::{exp2_neg, exp2_neg_simd};
use glam::Vec3;
use std::f32::consts::PI;

/// The forward density factor `d_f` of [`DualScatteringSettings::default`]:
/// fitted against the path tracer on tufts of blond and brown hair (volume
/// fractions 0.05-0.3, two lights, four views; `shading/MULTIPLE_SCATTERING.md`)
/// on a grid of steps of 0.05, the pair `(d_f, d_b)` with the smallest
/// combined relative RMS error of the two colours, then checked on tufts,
/// a light and views left out of the fit and on a region of Sintel's hair.
/// The paper's 0.7 quintuples the error on blond hair there.
pub const DEFAULT_FORWARD_DENSITY: f32 = 0.4;

/// The backward density factor `d_b` of [`DualScatteringSettings::default`]
/// (fitted with [`DEFAULT_FORWARD_DENSITY`]).
pub const DEFAULT_BACKWARD_DENSITY: f32 = 0.35;

/// Quality and density settings of [`DualScattering`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualScatteringSettings {
    /// Density factor of forward scattering `d_f` in (0, 1] (0.7 in the
    /// paper; [`DEFAULT_FORWARD_DENSITY`] by measurement).
    pub forward_density: f32,
    /// Density factor of backward scattering `d_b` in [0, 1] (0.7 in the
    /// paper; [`DEFAULT_BACKWARD_DENSITY`] by measurement).
    pub backward_density: f32,
    /// Table entries over `theta_i` in [-pi/2, pi/2], at least 2.
    pub resolution: usize,
}

impl Default for DualScatteringSettings {
    /// Densities [`DEFAULT_FORWARD_DENSITY`] and
    /// [`DEFAULT_BACKWARD_DENSITY`], 64 entries.
    fn default() -> Self {
        DualScatteringSettings {
            forward_density: DEFAULT_FORWARD_DENSITY,
            backward_density: DEFAULT_BACKWARD_DENSITY,
            resolution: 64,
        }
    }
}

impl DualScatteringSettings {
    /// Checks the ranges.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] for a density out of range,
    /// [`Error::InvalidResolution`] below 2 (or above 4096).
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name, value| Err(Error::InvalidParameter { name, value });
        if !(self.forward_density > 0.0 && self.forward_density <= 1.0) {
            return bad("forward_density", self.forward_density);
        }
        if !(self.backward_density >= 0.0 && self.backward_density <= 1.0) {
            return bad("backward_density", self.backward_density);
        }
        if !(2..=4096).contains(&self.resolution) {
            return Err(Error::InvalidResolution(self.resolution));
        }
        Ok(())
    }
}

/// Channels of the averages' record (the quantities of the module docs, one
/// node; refined linearly between nodes, then turned into a [`fast`] record).
mod ch {
    /// `ln a_f`, RGB.
    pub const LN_AF: usize = 0;
    /// `A_b`, RGB.
    pub const AB: usize = 3;
    /// The global amplitude `g_amp` (the scattered light's one Gaussian
    /// has `g_amp + 2 d_b A_b`), RGB.
    pub const G_AMP: usize = 6;
    /// `beta_f^2` (luminance-weighted).
    pub const BETA_F2: usize = 9;
    /// `delta_b`.
    pub const DELTA_B: usize = 10;
    /// `sigma_b^2`.
    pub const SIGMA_B2: usize = 11;
    /// Its mean (the moment-matched `mu_g` and `delta_b`).
    pub const G_MEAN: usize = 12;
    /// Its variance before the spread (moment-matched from `v_g` and
    /// `sigma_b^2`).
    pub const G_VAR: usize = 13;
}

/// Channels of a lookup record (two `F32Lanes`): the averages' record with
/// everything that does not depend on the sample's hair counts folded in,
/// per `theta_i`. With `s = acos(sin theta_i) + acos(sin theta_o)` (so
/// `theta_h = pi/2 - s/2`), `c_2 = 1 + cos theta_i cos theta_o + sin
/// theta_i sin theta_o` (`2 cos^2 theta_d`) and `2^-q` the exponentials:
///
/// * `T_f = 2^-(n NL_AF)`, the layers behind `1 - 2^-(2 m NL_AF)` (per
///   channel);
/// * the local backscatter `BACK 2^-(y^2) layers c / c_2` with `y = s
///   B_SLOPE + B_SHIFT`;
/// * the scattered light `(G_AMP + BACK RHO layers) 2^-(x^2 w) sqrt(w) c /
///   c_2` with `x = s / 2 + G_SHIFT` and `1 / w = G_VAR + n BETA_F2`.
mod fast {
    /// `-log2 a_f`, RGB (at least [`super::MIN_RATE`]).
    pub const NL_AF: usize = 0;
    /// The local backscatter's amplitude `A_b d_b (4 / pi) / sqrt(2 pi
    /// sigma_b^2)`, RGB.
    pub const BACK: usize = 3;
    /// The global amplitude `g_amp K`, `K = 2 d_f / sqrt(2 pi log2(e) / 2)`,
    /// RGB.
    pub const G_AMP: usize = 6;
    /// `K pi / 2 sqrt(2 pi sigma_b^2)`: `BACK RHO` is the scattered
    /// backscatter's amplitude `2 d_b A_b K`.
    pub const RHO: usize = 9;
    /// `k / 2`, `k = sqrt(log2(e) / (2 sigma_b^2))`.
    pub const B_SLOPE: usize = 10;
    /// `(delta_b - pi / 2) k`.
    pub const B_SHIFT: usize = 11;
    /// `mean - pi / 2` of the scattered light's Gaussian.
    pub const G_SHIFT: usize = 12;
    /// Its variance before the spread over `log2(e) / 2`.
    pub const G_VAR: usize = 13;
    /// `beta_f^2` over `log2(e) / 2` (at least [`super::MIN_RATE`]).
    pub const BETA_F2: usize = 14;
}

/// Records per interval of the computed nodes: lookups take the nearest
/// record (at 64 nodes, every 0.7 degrees: `a_f^n` at `n = 20` moves by at
/// most 2 % between records) instead of blending two.
const REFINE: usize = 4;

/// Smallest variance of a Gaussian lobe (radians^2; 0.6 degrees).
const MIN_VARIANCE: f32 = 1e-4;
/// [`MIN_VARIANCE`] over `log2(e) / 2` (the scale of [`fast::G_VAR`]).
const MIN_VARIANCE_G: f32 = MIN_VARIANCE / HALF_LOG2_E;
/// Smallest `cos^2 theta_d` (Marschner's `MIN_COS_THETA_D` squared).
const MIN_COS2_D: f32 = marschner::MIN_COS_THETA_D * marschner::MIN_COS_THETA_D;
/// Smallest `a_f` whose logarithm is stored (`ln` of it is about -23).
const MIN_AF: f32 = 1e-10;
/// Smallest rate of an exponential `2^-(n r)` or spread per fibre, so
/// that an infinite `n` gives `2^-inf` (0) or an infinite variance, not NaN.
const MIN_RATE: f32 = 1e-30;
/// `log2(e) / 2`: `exp(-x^2 / (2 v)) = 2^-(x^2 HALF_LOG2_E / v)`.
const HALF_LOG2_E: f32 = 0.5 * std::f32::consts::LOG2_E;
/// Largest `a_f^2` in the backscatter sums (their denominators `1 - a_f^2`
/// vanish for a lossless fibre).
const MAX_AF2: f32 = 0.99;

/// Dual scattering tables of one material, built once.
#[derive(Clone, Debug)]
pub struct DualScattering {
    settings: DualScatteringSettings,
    /// Whether the model's `S` includes `cos theta_i` (pbrt: yes).
    includes_cosine: bool,
    /// The averages at the table's nodes.
    averages: Vec<FibreAverages>,
    /// One 16-float record per refined node ([`fast`]).
    /// Sixteen floats each, as two `f32x8` (64 bytes) at every lane width.
    records: Vec<[F32Group; 2]>,
    /// `(records - 1) / pi`: records per radian of `theta_i`.
    index_scale: f32,
    /// `records - 1/2`: the lookup rounds `(theta_i + pi/2) index_scale`
    /// to the nearest record as the truncation of this minus
    /// `acos(sin theta_i) index_scale`.
    index_top: f32,
}

impl DualScattering {
    /// Tables for the fibre whose scattering function, for unit directions
    /// (`t` tangent, `wi` toward the light, `wo` toward the viewer), is
    /// `scattering(t, wi, wo)`; `includes_cosine` says whether it carries
    /// the `cos theta_i` of the lighting integral (it is divided out for
    /// the averages). About `resolution x 9,216` evaluations.
    ///
    /// # Errors
    ///
    /// As [`DualScatteringSettings::validate`].
    pub fn new(
        scattering: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
        includes_cosine: bool,
        settings: DualScatteringSettings,
    ) -> Result<DualScattering, Error> {
        settings.validate()?;
        let res = settings.resolution;
        // Without the cosine; nodes kept off the poles, where it is 0.
        let f = |t: Vec3, wi: Vec3, wo: Vec3| {
            let v = scattering(t, wi, wo);
            if includes_cosine {
                v / (1.0 - wi.x * wi.x).max(1e-12).sqrt()
            } else {
                v
            }
        };
        let step = std::f64::consts::PI / (res - 1) as f64;
        let edge = std::f64::consts::FRAC_PI_2 - 0.25 * step;
        let nodes = pbrt::gauss_legendre(averages::THETA_NODES);
        let averages: Vec<FibreAverages> = (0..res)
            .map(|k| {
                let theta = (-std::f64::consts::FRAC_PI_2 + k as f64 * step).clamp(-edge, edge);
                let mut a = averages::fibre_averages(&f, &nodes, theta);
                bound_attenuations(&mut a);
                a
            })
            .collect();
        let d_b = settings.backward_density;
        let coarse: Vec<[f32; 16]> = averages.iter().map(|a| record(a, d_b)).collect();
        // Nearest-node lookups on a grid REFINE times finer, linear
        // between the computed nodes.
        let mut records = Vec::with_capacity((res - 1) * REFINE + 1);
        for pair in coarse.windows(2) {
            for j in 0..REFINE {
                let f = j as f32 / REFINE as f32;
                let r = std::array::from_fn(|c| (pair[1][c] - pair[0][c]).mul_add(f, pair[0][c]));
                records.push(pack(fast_record(&r, &settings)));
            }
        }
        records.push(pack(fast_record(&coarse[res - 1], &settings)));
        let last = records.len() - 1;
        Ok(DualScattering {
            settings,
            includes_cosine,
            averages,
            records,
            index_scale: last as f32 / PI,
            index_top: last as f32 + 0.5,
        })
    }

    /// Tables for a Marschner lookup table's model (`S` without the cosine).
    ///
    /// # Errors
    ///
    /// As [`DualScatteringSettings::validate`].
    pub fn from_marschner(
        lut: &marschner::Lut,
        settings: DualScatteringSettings,
    ) -> Result<DualScattering, Error> {
        DualScattering::new(|t, wi, wo| lut.scattering(t, wi, wo), false, settings)
    }

    /// Tables for pbrt-v3's far field in a lookup table (with the cosine).
    ///
    /// # Errors
    ///
    /// As [`DualScatteringSettings::validate`].
    pub fn from_pbrt(
        table: &pbrt::Table,
        settings: DualScatteringSettings,
    ) -> Result<DualScattering, Error> {
        DualScattering::new(|t, wi, wo| table.scattering(t, wi, wo), true, settings)
    }

    /// The settings the tables were built with.
    pub fn settings(&self) -> DualScatteringSettings {
        self.settings
    }

    /// Whether the model's `S` (and so [`DualScattering::shade`]'s result)
    /// includes `cos theta_i`.
    pub fn includes_cosine(&self) -> bool {
        self.includes_cosine
    }

    /// The fibre averages at the table's nodes, `theta_i` from -pi/2 to pi/2.
    pub fn averages(&self) -> &[FibreAverages] {
        &self.averages
    }

    /// Bytes of the lookup records.
    pub fn size_bytes(&self) -> usize {
        self.records.len() * std::mem::size_of::<[F32Group; 2]>()
    }

    /// The shading function `F` for one sample: `single` is the model's
    /// single scattering `S(t, wi, wo)`, `fibres` the number of fibres
    /// between the point and the light (`n`, clamped to >= 0), `direct`
    /// the fraction of the light reaching it unscattered (`D`, clamped to
    /// [0, 1]). Directions are unit (as the models' table lookups take
    /// them); NaN in gives NaN out.
    #[inline]
    pub fn shade(
        &self,
        single: Vec3,
        t: Vec3,
        wi: Vec3,
        wo: Vec3,
        fibres: f32,
        direct: f32,
    ) -> Vec3 {
        self.shade_layered(single, t, wi, wo, fibres, f32::INFINITY, direct)
    }

    /// [`DualScattering::shade`] for a point with `behind` fibres between
    /// it and the far side of the hair along the light (the paper's hair
    /// is infinitely deep behind the point: `behind` = infinity). The
    /// local backscatter is the paper's series over the layers behind the
    /// point, light going `k` layers in and `k` back: with `m` layers it
    /// stops at `k = m`, `A_1 (1 - a_f^(2m))` (and the same factor on
    /// `A_3`, per channel), so a fibre with no hair
    /// behind it gets no backscatter. A deep opacity map gives `behind` as
    /// its last plane's hair count minus the point's.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn shade_layered(
        &self,
        single: Vec3,
        t: Vec3,
        wi: Vec3,
        wo: Vec3,
        fibres: f32,
        behind: f32,
        direct: f32,
    ) -> Vec3 {
        // Unclamped: the arccosine clamps, and NaN stays NaN through it
        // (every clamp below that could replace a NaN sample's value has
        // the value second, where `maxps` / `minps` keep it, or is on a
        // path that also goes through one that keeps it).
        let sin_i = wi.dot(t);
        let sin_o = wo.dot(t);
        let acos_i = acos(sin_i);
        let acos_o = acos(sin_o);
        // The nearest record: theta_i + pi/2 = pi - acos_i, in steps of
        // pi / last; NaN goes to record 0.
        let top = self.index_top;
        let u = minps(maxps(acos_i.mul_add(-self.index_scale, top), 0.0), top);
        let k = (u as usize).min(self.records.len() - 1);
        let rec = &self.records[k];
        let r = |c: usize| rec[c / 8].as_array()[c % 8];

        let n = maxps(0.0, fibres);
        let m = maxps(0.0, behind);
        let d = minps(1.0, maxps(0.0, direct));
        let s = acos_i + acos_o;
        let cos_i = maxps((-sin_i).mul_add(sin_i, 1.0), 0.0).sqrt();
        let cos_o = maxps((-sin_o).mul_add(sin_o, 1.0), 0.0).sqrt();
        let c2 = cos_i.mul_add(cos_o, sin_i.mul_add(sin_o, 1.0));
        let inv2 = 1.0 / maxps(c2, 2.0 * MIN_COS2_D);
        let inv2c = if self.includes_cosine {
            inv2 * cos_i
        } else {
            inv2
        };

        let t_f = [0, 1, 2].map(|c| exp2_neg(n * r(fast::NL_AF + c)));
        let m2 = m + m;
        let layers = [0, 1, 2].map(|c| 1.0 - exp2_neg(m2 * r(fast::NL_AF + c)));
        let y = s.mul_add(r(fast::B_SLOPE), r(fast::B_SHIFT));
        let e_b = exp2_neg(y * y);
        let w = 1.0 / maxps(n.mul_add(r(fast::BETA_F2), r(fast::G_VAR)), MIN_VARIANCE_G);
        let x = s.mul_add(0.5, r(fast::G_SHIFT));
        let e_g = exp2_neg(x * x * w);
        let s_b = e_b * inv2c;
        let s_g = e_g * w.sqrt() * inv2c;
        let single = single.to_array();
        let out: [f32; 3] = std::array::from_fn(|c| {
            let back = r(fast::BACK + c) * layers[c];
            let local = back.mul_add(s_b, single[c]);
            let far = back.mul_add(r(fast::RHO), r(fast::G_AMP + c)) * s_g;
            let scattered = maxps(0.0, t_f[c] - d);
            local.mul_add(d, scattered * far)
        });
        Vec3::from_array(out)
    }

    /// [`DualScattering::shade`] for eight samples: the same steps, lane by
    /// lane (the record fetches per lane, the rest in `F32Lanes`).
    #[inline]
    pub fn shade_simd(
        &self,
        single: Vec3Lanes,
        t: Vec3Lanes,
        wi: Vec3Lanes,
        wo: Vec3Lanes,
        fibres: F32Lanes,
        direct: F32Lanes,
    ) -> Vec3Lanes {
        let deep = F32Lanes::splat(f32::INFINITY);
        self.shade_layered_simd(single, t, wi, wo, fibres, deep, direct)
    }

    /// [`DualScattering::shade_layered`] for eight samples.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn shade_layered_simd(
        &self,
        single: Vec3Lanes,
        t: Vec3Lanes,
        wi: Vec3Lanes,
        wo: Vec3Lanes,
        fibres: F32Lanes,
        behind: F32Lanes,
        direct: F32Lanes,
    ) -> Vec3Lanes {
        let one = F32Lanes::ONE;
        let zero = F32Lanes::ZERO;
        // As the scalar twin, operation for operation.
        let sin_i = wi.dot(t);
        let sin_o = wo.dot(t);
        let acos_i = acos_simd(sin_i);
        let acos_o = acos_simd(sin_o);
        let top = F32Lanes::splat(self.index_top);
        let u = acos_i
            .mul_add(F32Lanes::splat(-self.index_scale), top)
            .fast_max(zero)
            .fast_min(top);
        // Byte offsets of the records (64 bytes each), in [0, 64 last].
        let k: I32Lanes = u.fast_trunc_int();
        let offsets: [i32; LANES] = (k << 6_i32).to_array();
        let base = self.records.as_ptr().cast::<u8>();
        // Per group of eight lanes: the eight records' halves as rows, two
        // 8 x 8 transposes into channels (two groups in a 16-lane build).
        let mut channels = [[[F32Group::ZERO; 8]; 2]; LANES / GROUP_LANES];
        for (k, group) in channels.iter_mut().enumerate() {
            let mut rows = [[F32Group::ZERO; 8]; 2];
            for (j, &offset) in offsets[k * GROUP_LANES..][..GROUP_LANES].iter().enumerate() {
                // SAFETY: u is in [0, last + 1/2] (a NaN is replaced by 0 by
                // the `fast_max`), so its truncation is a record index in
                // [0, last], last < len, and a record is 64 bytes.
                let rec = unsafe { &*base.add(offset as u32 as usize).cast::<[F32Group; 2]>() };
                rows[0][j] = rec[0];
                rows[1][j] = rec[1];
            }
            *group = [F32Group::transpose(rows[0]), F32Group::transpose(rows[1])];
        }
        let r = |c: usize| from_groups(std::array::from_fn(|k| channels[k][c / 8][c % 8]));

        let n = zero.fast_max(fibres);
        let m = zero.fast_max(behind);
        let d = one.fast_min(zero.fast_max(direct));
        let s = acos_i + acos_o;
        let cos_i = sin_i.mul_neg_add(sin_i, one).fast_max(zero).sqrt();
        let cos_o = sin_o.mul_neg_add(sin_o, one).fast_max(zero).sqrt();
        let c2 = cos_i.mul_add(cos_o, sin_i.mul_add(sin_o, one));
        let inv2 = one / c2.fast_max(F32Lanes::splat(2.0 * MIN_COS2_D));
        let inv2c = if self.includes_cosine {
            inv2 * cos_i
        } else {
            inv2
        };

        let t_f = [
            exp2_neg_simd(n * r(fast::NL_AF)),
            exp2_neg_simd(n * r(fast::NL_AF + 1)),
            exp2_neg_simd(n * r(fast::NL_AF + 2)),
        ];
        let m2 = m + m;
        let layers = [
            one - exp2_neg_simd(m2 * r(fast::NL_AF)),
            one - exp2_neg_simd(m2 * r(fast::NL_AF + 1)),
            one - exp2_neg_simd(m2 * r(fast::NL_AF + 2)),
        ];
        let y = s.mul_add(r(fast::B_SLOPE), r(fast::B_SHIFT));
        let e_b = exp2_neg_simd(y * y);
        let w = one
            / n.mul_add(r(fast::BETA_F2), r(fast::G_VAR))
                .fast_max(F32Lanes::splat(MIN_VARIANCE_G));
        let x = s.mul_add(F32Lanes::splat(0.5), r(fast::G_SHIFT));
        let e_g = exp2_neg_simd(x * x * w);
        let s_b = e_b * inv2c;
        let s_g = e_g * w.sqrt() * inv2c;
        let channel = |c: usize, single: F32Lanes| {
            let back = r(fast::BACK + c) * layers[c];
            let local = back.mul_add(s_b, single);
            let far = back.mul_add(r(fast::RHO), r(fast::G_AMP + c)) * s_g;
            let scattered = zero.fast_max(t_f[c] - d);
            local.mul_add(d, scattered * far)
        };
        Vec3Lanes::new(
            channel(0, single.x),
            channel(1, single.y),
            channel(2, single.z),
        )
    }

    /// `F` for a batch (SIMD, eight samples per step): `single[k]` the
    /// model's scattering of sample `k`, `fibres[k]` and `direct[k]` as in
    /// [`DualScattering::shade`]. `out` is resized to the batch
    /// (allocation-free once it has the capacity).
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] unless `single`, `fibres` and `direct` have
    /// one entry per sample (nothing is written).
    pub fn shade_batch(
        &self,
        samples: &ShadingSamples,
        single: &RgbBuffer,
        fibres: &[f32],
        direct: &[f32],
        out: &mut RgbBuffer,
    ) -> Result<(), Error> {
        check_lengths(samples, single, fibres, direct)?;
        out.resize(samples.len());
        let mut start = 0;
        while start < samples.len() {
            let (t, wi, wo) = samples.load_block(start);
            let s = single.load_block(start);
            let n = load_padded(fibres, start);
            let d = load_padded(direct, start);
            out.store_block(start, self.shade_simd(s, t, wi, wo, n, d));
            start += LANES;
        }
        Ok(())
    }
}

/// The checks of the batch calls.
fn check_lengths(
    samples: &ShadingSamples,
    single: &RgbBuffer,
    fibres: &[f32],
    direct: &[f32],
) -> Result<(), Error> {
    let n = samples.len();
    for (what, got) in [
        (
            "single-scattering values (one per sample)",
            single.r.len().min(single.g.len()).min(single.b.len()),
        ),
        ("fibre counts (one per sample)", fibres.len()),
        ("direct fractions (one per sample)", direct.len()),
    ] {
        if got != n {
            return Err(Error::CountMismatch {
                what,
                expected: n,
                got,
            });
        }
    }
    Ok(())
}

/// Eight values from `start`, zero-padded past the end.
#[inline]
fn load_padded(a: &[f32], start: usize) -> F32Lanes {
    let mut v = [0.0f32; LANES];
    for (l, x) in a.iter().skip(start).take(LANES).enumerate() {
        v[l] = *x;
    }
    F32Lanes::new(v)
}

/// `1 / sqrt(2 pi)`.
const INV_SQRT_2PI: f32 = 0.398_942_3;

/// Keeps the attenuations physical: each in [0, 1] and their sum at most 1
/// in every channel. A model that is not energy conserving (Marschner's
/// lobes send out more than the fibre intercepts at most angles, up to
/// about 1.3 times) is scaled down by one factor for all three channels
/// there, so its colour is kept.
fn bound_attenuations(a: &mut FibreAverages) {
    let (f, b) = (a.a_f.max(Vec3::ZERO), a.a_b.max(Vec3::ZERO));
    let most = (f + b).max_element();
    let s = if most > 1.0 { 1.0 / most } else { 1.0 };
    a.a_f = (f * s).min(Vec3::ONE);
    a.a_b = (b * s).min(Vec3::ONE);
}

/// The lookup record of one node: the per-channel `ln a_f`, `A_b` and
/// global amplitude, and the one-channel widths and shifts (see the module
/// docs for the formulas).
fn record(a: &FibreAverages, d_b: f32) -> [f32; 16] {
    let lum = averages::LUMINANCE.as_vec3();
    let mut ab = Vec3::ZERO;
    let mut delta = Vec3::ZERO;
    let mut sigma = Vec3::ZERO;
    for c in 0..3 {
        let (af, bb) = (a.a_f[c], a.a_b[c]);
        let af2 = (af * af).min(MAX_AF2);
        let q = 1.0 - af2;
        let (bf, bbw) = (a.beta_f[c], a.beta_b[c]);
        let ab3 = bb * bb * bb;
        ab[c] = bb * af2 / q + ab3 * af2 / (q * q * q);
        delta[c] = a.alpha_b[c] * (1.0 - 2.0 * bb * bb / (q * q))
            + a.alpha_f[c] * (2.0 * q * q + 4.0 * af2 * bb * bb) / (q * q * q);
        let den = bb + ab3 * (2.0 * bf + 3.0 * bbw);
        sigma[c] = if den > 1e-12 {
            (1.0 + d_b * af2)
                * (bb * (2.0 * bf * bf + bbw * bbw).sqrt()
                    + ab3 * (2.0 * bf * bf + 3.0 * bbw * bbw).sqrt())
                / den
        } else {
            0.0
        };
    }
    // One-channel widths and shifts: weighted by luminance times the
    // channel's share (A_b for the backscatter, a_f for the forward width).
    let weighted = |v: Vec3, w: Vec3| {
        let w = w * lum;
        let s = w.x + w.y + w.z;
        if s > 1e-20 {
            v.dot(w) / s
        } else {
            v.dot(lum)
        }
    };
    let beta_f2 = weighted(a.beta_f * a.beta_f, a.a_f);
    let delta_b = weighted(delta, ab);
    let sigma_b = weighted(sigma, ab);
    // The scattered light's two terms, the global `g_amp g(theta_h - mu_g,
    // v_g + s)` and the backscatter `2 d_b A_b g(theta_h - delta_b,
    // sigma_b^2 + s)` (both over cos^2 theta_d), as one Gaussian with their
    // summed amplitude and their (luminance-weighted) mean and variance:
    // the first two moments of the pair for every spread s.
    let back_amp = ab * (2.0 * d_b);
    let (w1, w2) = (a.g_amplitude.dot(lum), back_amp.dot(lum));
    let sigma_b2 = sigma_b * sigma_b;
    let (mean, var) = if w1 + w2 > 1e-20 {
        let mean = (w1 * a.g_mean + w2 * delta_b) / (w1 + w2);
        let second = (w1 * (a.g_variance + a.g_mean * a.g_mean)
            + w2 * (sigma_b2 + delta_b * delta_b))
            / (w1 + w2);
        (mean, (second - mean * mean).max(0.0))
    } else {
        (a.g_mean, a.g_variance)
    };
    let mut r = [0.0f32; 16];
    for c in 0..3 {
        r[ch::LN_AF + c] = a.a_f[c].max(MIN_AF).ln();
        r[ch::AB + c] = ab[c];
        r[ch::G_AMP + c] = a.g_amplitude[c];
    }
    r[ch::BETA_F2] = beta_f2;
    r[ch::DELTA_B] = delta_b;
    r[ch::SIGMA_B2] = sigma_b2;
    r[ch::G_MEAN] = mean;
    r[ch::G_VAR] = var;
    r
}

/// The lookup record ([`fast`]) of an averages' record ([`ch`]).
fn fast_record(a: &[f32; 16], settings: &DualScatteringSettings) -> [f32; 16] {
    let (d_f, d_b) = (settings.forward_density, settings.backward_density);
    let sigma_b2 = a[ch::SIGMA_B2].max(MIN_VARIANCE);
    // 1 / sqrt(2 pi sigma_b^2): the backscatter's Gaussian's peak.
    let peak_b = INV_SQRT_2PI / sigma_b2.sqrt();
    let k_b = (HALF_LOG2_E / sigma_b2).sqrt();
    // The scattered light's Gaussian is 2^-(x^2 w) sqrt(w) / sqrt(2 pi
    // HALF_LOG2_E) with w = HALF_LOG2_E / v, and 1 / cos^2 theta_d = 2 / c_2.
    let k_far = 2.0 * d_f * INV_SQRT_2PI / HALF_LOG2_E.sqrt();
    let mut r = [0.0f32; 16];
    for c in 0..3 {
        r[fast::NL_AF + c] = (-a[ch::LN_AF + c] * std::f32::consts::LOG2_E).max(MIN_RATE);
        r[fast::BACK + c] = a[ch::AB + c] * (d_b * (4.0 / PI) * peak_b);
        r[fast::G_AMP + c] = a[ch::G_AMP + c] * k_far;
    }
    r[fast::RHO] = k_far * (0.5 * PI) / peak_b;
    r[fast::B_SLOPE] = 0.5 * k_b;
    r[fast::B_SHIFT] = (a[ch::DELTA_B] - 0.5 * PI) * k_b;
    r[fast::G_SHIFT] = a[ch::G_MEAN] - 0.5 * PI;
    r[fast::G_VAR] = a[ch::G_VAR] / HALF_LOG2_E;
    r[fast::BETA_F2] = (a[ch::BETA_F2] / HALF_LOG2_E).max(MIN_RATE);
    r
}

/// `if a > b { a } else { b }`: `maxps(a, b)` as [`F32Lanes::fast_max`] gives
/// it (NaN in either gives `b`).
#[inline(always)]
fn maxps(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// `if a < b { a } else { b }`: `minps(a, b)` (NaN in either gives `b`).
#[inline(always)]
fn minps(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// Sixteen floats as two vectors.
fn pack(r: [f32; 16]) -> [F32Group; 2] {
    [
        F32Group::new(std::array::from_fn(|c| r[c])),
        F32Group::new(std::array::from_fn(|c| r[8 + c])),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use coif_base::rng::SplitMix64;

    /// `F` by the module docs' formulas, in `f64` with `libm`'s
    /// exponential, from the averages' record `r` ([`ch`]).
    fn reference(
        ds: &DualScattering,
        r: &[f32; 16],
        single: Vec3,
        sin_i: f32,
        sin_o: f32,
        [n, m, d]: [f64; 3],
    ) -> [f64; 3] {
        let g = |x: f64, v: f64| {
            let v = v.max(MIN_VARIANCE as f64);
            (-x * x / (2.0 * v)).exp() / (2.0 * std::f64::consts::PI * v).sqrt()
        };
        let r = r.map(f64::from);
        let (si, so) = (sin_i as f64, sin_o as f64);
        let theta_h = 0.5 * (si.asin() + so.asin());
        let (ci, co) = ((1.0 - si * si).sqrt(), (1.0 - so * so).sqrt());
        let inv_cos2_d = 1.0 / (0.5 * (1.0 + ci * co + si * so)).max(MIN_COS2_D as f64);
        let c = if ds.includes_cosine { ci } else { 1.0 };
        let (d_f, d_b) = (
            ds.settings.forward_density as f64,
            ds.settings.backward_density as f64,
        );
        let g_b = g(theta_h - r[ch::DELTA_B], r[ch::SIGMA_B2]);
        let g_g = g(theta_h - r[ch::G_MEAN], r[ch::G_VAR] + n * r[ch::BETA_F2]);
        std::array::from_fn(|k| {
            let t_f = (n * r[ch::LN_AF + k]).exp();
            let layers = 1.0 - (2.0 * m * r[ch::LN_AF + k]).exp();
            let a_b = r[ch::AB + k] * layers;
            let back = a_b * 2.0 / std::f64::consts::PI * inv_cos2_d * g_b;
            let far = (r[ch::G_AMP + k] + 2.0 * d_b * a_b) * g_g * inv_cos2_d;
            (single[k] as f64 + back * d_b * c) * d + (t_f - d).max(0.0) * far * d_f * c
        })
    }

    #[test]
    fn fast_records_give_the_formulas() {
        let blond = crate::pbrt::sigma_a_from_concentration(0.3, 0.0);
        let table = pbrt::Table::new(
            &pbrt::Params {
                sigma_a: blond,
                ..pbrt::Params::default()
            },
            32,
        )
        .unwrap();
        let settings = DualScatteringSettings {
            resolution: 16,
            ..DualScatteringSettings::default()
        };
        let ds = DualScattering::from_pbrt(&table, settings).unwrap();
        let coarse: Vec<[f32; 16]> = ds
            .averages
            .iter()
            .map(|a| record(a, settings.backward_density))
            .collect();
        let mut rng = SplitMix64::new(21);
        let mut worst = 0.0f64;
        for _ in 0..2000 {
            let (t, wi, wo) = (rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
            let (n, m, d) = (rng.range(0.0, 40.0), rng.range(0.0, 30.0), rng.next_f32());
            let single = table.scattering(t, wi, wo);
            let got = ds.shade_layered(single, t, wi, wo, n, m, d);
            // The record the lookup takes, before its folding.
            let last = ds.records.len() - 1;
            let u = acos(wi.dot(t)).mul_add(-ds.index_scale, ds.index_top);
            let k = (u.max(0.0) as usize).min(last);
            let (node, j) = (k / REFINE, k % REFINE);
            let r: [f32; 16] = if node + 1 < coarse.len() {
                let f = j as f32 / REFINE as f32;
                std::array::from_fn(|c| {
                    (coarse[node + 1][c] - coarse[node][c]).mul_add(f, coarse[node][c])
                })
            } else {
                coarse[node]
            };
            let want = reference(
                &ds,
                &r,
                single,
                wi.dot(t),
                wo.dot(t),
                [n, m, d].map(f64::from),
            );
            for c in 0..3 {
                let err = (got[c] as f64 - want[c]).abs() / want[c].abs().max(1e-3);
                worst = worst.max(err);
            }
        }
        assert!(worst < 3e-5, "relative error {worst}");
    }
}
