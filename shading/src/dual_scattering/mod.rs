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
//! The averages are tabulated once per material over `theta_i`
//! ([`DualScattering::new`]) and refined four times linearly; a lookup
//! takes the nearest 16-float record, then six exponentials and three
//! divisions and square roots.
//! [`DualScattering::shade`] (one sample), [`DualScattering::shade_x8`]
//! (eight lanes) and the batches [`DualScattering::shade_batch`] /
//! [`scalar::shade_batch`] run the same operations in the same order (the
//! arccosine and exponential are shared polynomials), so they agree to
//! the bit (tested).

pub mod accuracy;
mod averages;
mod fast_exp;
pub mod scalar;

pub use averages::FibreAverages;

use crate::pbrt::fast_acos::{acos, acos_x8};
use crate::{marschner, pbrt, Error, RgbBuffer, ShadingSamples};
use coif_base::{Vec3x8, LANES};
use fast_exp::{exp_neg, exp_neg_x8};
use glam::Vec3;
use std::f32::consts::PI;
use wide::{f32x8, i32x8};

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

/// Channels of a table record (two `f32x8`).
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
    /// `ln a_f`, luminance-weighted (the depth factor of the backscatter).
    pub const LN_AF_LUM: usize = 14;
}

/// Records per interval of the computed nodes: lookups take the nearest
/// record (at 64 nodes, every 0.7 degrees: `a_f^n` at `n = 20` moves by at
/// most 2 % between records) instead of blending two.
const REFINE: usize = 4;

/// Smallest variance of a Gaussian lobe (radians^2; 0.6 degrees).
const MIN_VARIANCE: f32 = 1e-4;
/// Smallest `cos^2 theta_d` (Marschner's `MIN_COS_THETA_D` squared).
const MIN_COS2_D: f32 = marschner::MIN_COS_THETA_D * marschner::MIN_COS_THETA_D;
/// Smallest `a_f` whose logarithm is stored (`ln` of it is about -23).
const MIN_AF: f32 = 1e-10;
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
    /// One 16-float record per node ([`ch`]).
    records: Vec<[f32x8; 2]>,
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
                records.push(pack(std::array::from_fn(|c| {
                    (pair[1][c] - pair[0][c]).mul_add(f, pair[0][c])
                })));
            }
        }
        records.push(pack(coarse[res - 1]));
        Ok(DualScattering {
            settings,
            includes_cosine,
            averages,
            records,
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
        self.records.len() * std::mem::size_of::<[f32x8; 2]>()
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
    /// `A_3`, with `a_f` luminance-weighted), so a fibre with no hair
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
        // Unclamped: the arccosine clamps, and NaN stays NaN through it.
        let sin_i = wi.dot(t);
        let sin_o = wo.dot(t);
        let (theta_i, theta_o) = (0.5 * PI - acos(sin_i), 0.5 * PI - acos(sin_o));
        if theta_i.is_nan()
            || theta_o.is_nan()
            || fibres.is_nan()
            || behind.is_nan()
            || direct.is_nan()
        {
            return Vec3::NAN;
        }
        let last = self.records.len() - 1;
        let u = ((theta_i + 0.5 * PI) * (last as f32 / PI)).clamp(0.0, last as f32);
        let k = ((u + 0.5).floor() as usize).min(last);
        let rec = &self.records[k];
        let r: [f32; 16] = std::array::from_fn(|c| rec[c / LANES].as_array()[c % LANES]);
        let rgb = |c: usize| Vec3::new(r[c], r[c + 1], r[c + 2]);

        let n = fibres.max(0.0);
        let d = direct.clamp(0.0, 1.0);
        let theta_h = 0.5 * (theta_i + theta_o);
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let cos2_d = (0.5 * (1.0 + cos_i * cos_o + sin_i * sin_o)).max(MIN_COS2_D);
        let inv_cos2_d = 1.0 / cos2_d;
        let c = if self.includes_cosine { cos_i } else { 1.0 };

        let ln_af = rgb(ch::LN_AF);
        let t_f = Vec3::new(
            exp_neg(n * ln_af.x),
            exp_neg(n * ln_af.y),
            exp_neg(n * ln_af.z),
        );
        let spread = n * r[ch::BETA_F2];
        let x_b = theta_h - r[ch::DELTA_B];
        let (d_f, d_b) = (
            self.settings.forward_density,
            self.settings.backward_density,
        );
        let layers = 1.0 - exp_neg(2.0 * behind.max(0.0) * r[ch::LN_AF_LUM]);
        let a_b = rgb(ch::AB) * layers;
        let back_direct = a_b * (2.0 / PI * inv_cos2_d * gaussian(x_b, r[ch::SIGMA_B2]));
        let far_light = (rgb(ch::G_AMP) + a_b * (2.0 * d_b))
            * (gaussian(theta_h - r[ch::G_MEAN], r[ch::G_VAR] + spread) * inv_cos2_d);
        let scattered = (t_f - Vec3::splat(d)).max(Vec3::ZERO);
        let local = single + back_direct * (d_b * c);
        let far = far_light * (d_f * c);
        local * d + scattered * far
    }

    /// [`DualScattering::shade`] for eight samples: the same steps, lane by
    /// lane (the record fetches per lane, the rest in `f32x8`).
    #[inline]
    pub fn shade_x8(
        &self,
        single: Vec3x8,
        t: Vec3x8,
        wi: Vec3x8,
        wo: Vec3x8,
        fibres: f32x8,
        direct: f32x8,
    ) -> Vec3x8 {
        let deep = f32x8::splat(f32::INFINITY);
        self.shade_layered_x8(single, t, wi, wo, fibres, deep, direct)
    }

    /// [`DualScattering::shade_layered`] for eight samples.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn shade_layered_x8(
        &self,
        single: Vec3x8,
        t: Vec3x8,
        wi: Vec3x8,
        wo: Vec3x8,
        fibres: f32x8,
        behind: f32x8,
        direct: f32x8,
    ) -> Vec3x8 {
        let one = f32x8::ONE;
        let zero = f32x8::ZERO;
        let half_pi = f32x8::splat(0.5 * PI);
        // Unclamped: the arccosine clamps, and NaN stays NaN through it.
        let sin_i = wi.dot(t);
        let sin_o = wo.dot(t);
        let theta_i = half_pi - acos_x8(sin_i);
        let theta_o = half_pi - acos_x8(sin_o);
        let invalid = theta_i.is_nan()
            | theta_o.is_nan()
            | fibres.is_nan()
            | behind.is_nan()
            | direct.is_nan();

        let last = self.records.len() - 1;
        let u = ((theta_i + half_pi) * f32x8::splat(last as f32 / PI))
            .fast_max(zero)
            .fast_min(f32x8::splat(last as f32));
        // NaN lanes (NaN out anyway) are clamped to record 0.
        let ki = (u + f32x8::splat(0.5))
            .floor()
            .trunc_int()
            .max(i32x8::ZERO)
            .min(i32x8::splat(last as i32))
            .to_array();
        let mut lo = [[f32x8::ZERO; LANES]; 2];
        for l in 0..LANES {
            // SAFETY: ki[l] is in [0, last] and last < len.
            let rec = unsafe { self.records.get_unchecked(ki[l] as usize) };
            lo[0][l] = rec[0];
            lo[1][l] = rec[1];
        }
        let [r0, r1] = [f32x8::transpose(lo[0]), f32x8::transpose(lo[1])];
        let r = |c: usize| if c < LANES { r0[c] } else { r1[c - LANES] };
        let rgb = |c: usize| Vec3x8::new(r(c), r(c + 1), r(c + 2));

        let n = fibres.fast_max(zero);
        let d = direct.fast_max(zero).fast_min(one);
        let theta_h = f32x8::splat(0.5) * (theta_i + theta_o);
        let cos_i = (one - sin_i * sin_i).fast_max(zero).sqrt();
        let cos_o = (one - sin_o * sin_o).fast_max(zero).sqrt();
        let cos2_d = (f32x8::splat(0.5) * (one + cos_i * cos_o + sin_i * sin_o))
            .fast_max(f32x8::splat(MIN_COS2_D));
        let inv_cos2_d = one / cos2_d;
        let c = if self.includes_cosine { cos_i } else { one };

        let ln_af = rgb(ch::LN_AF);
        let t_f = Vec3x8::new(
            exp_neg_x8(n * ln_af.x),
            exp_neg_x8(n * ln_af.y),
            exp_neg_x8(n * ln_af.z),
        );
        let spread = n * r(ch::BETA_F2);
        let x_b = theta_h - r(ch::DELTA_B);
        let (d_f, d_b) = (
            f32x8::splat(self.settings.forward_density),
            f32x8::splat(self.settings.backward_density),
        );
        let layers = one - exp_neg_x8(f32x8::splat(2.0) * behind.fast_max(zero) * r(ch::LN_AF_LUM));
        let a_b = rgb(ch::AB) * layers;
        let back_direct =
            a_b * (f32x8::splat(2.0 / PI) * inv_cos2_d * gaussian_x8(x_b, r(ch::SIGMA_B2)));
        let g_amp = rgb(ch::G_AMP) + a_b * (f32x8::splat(2.0) * d_b);
        let far_light =
            g_amp * (gaussian_x8(theta_h - r(ch::G_MEAN), r(ch::G_VAR) + spread) * inv_cos2_d);
        let dv = Vec3x8::new(d, d, d);
        let gap = t_f - dv;
        let scattered = Vec3x8::new(
            gap.x.fast_max(zero),
            gap.y.fast_max(zero),
            gap.z.fast_max(zero),
        );
        let local = single + back_direct * (d_b * c);
        let far = far_light * (d_f * c);
        let out = local * d
            + Vec3x8::new(
                scattered.x * far.x,
                scattered.y * far.y,
                scattered.z * far.z,
            );
        Vec3x8::select(invalid, Vec3x8::splat(Vec3::NAN), out)
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
            out.store_block(start, self.shade_x8(s, t, wi, wo, n, d));
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
fn load_padded(a: &[f32], start: usize) -> f32x8 {
    let mut v = [0.0f32; LANES];
    for (l, x) in a.iter().skip(start).take(LANES).enumerate() {
        v[l] = *x;
    }
    f32x8::new(v)
}

/// `1 / sqrt(2 pi)`.
const INV_SQRT_2PI: f32 = 0.398_942_3;

/// The normalised Gaussian `g(x, v) = exp(-x^2 / (2 v)) / sqrt(2 pi v)`,
/// as `exp(-x^2 w / 2) sqrt(w) / sqrt(2 pi)` with `w = 1 / v` (one
/// division).
#[inline(always)]
fn gaussian(x: f32, variance: f32) -> f32 {
    let w = 1.0 / variance.max(MIN_VARIANCE);
    exp_neg(-0.5 * (x * x) * w) * (w.sqrt() * INV_SQRT_2PI)
}

/// [`gaussian`] in eight lanes.
#[inline(always)]
fn gaussian_x8(x: f32x8, variance: f32x8) -> f32x8 {
    let w = f32x8::ONE / variance.fast_max(f32x8::splat(MIN_VARIANCE));
    exp_neg_x8(f32x8::splat(-0.5) * (x * x) * w) * (w.sqrt() * f32x8::splat(INV_SQRT_2PI))
}

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
    r[ch::LN_AF_LUM] = a.a_f.dot(lum).max(MIN_AF).ln();
    r
}

/// Sixteen floats as two vectors.
fn pack(r: [f32; 16]) -> [f32x8; 2] {
    [
        f32x8::new(std::array::from_fn(|c| r[c])),
        f32x8::new(std::array::from_fn(|c| r[LANES + c])),
    ]
}
