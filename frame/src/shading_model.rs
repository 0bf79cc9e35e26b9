//! Which hair shading model a frame uses, with its prepared tables.

use super::Error;
use coif_base::Vec3x8;
use coif_shading::kajiya_kay::KajiyaKay;
use coif_shading::{marschner, pbrt, RgbBuffer, ShadingSamples};
use std::fmt;
use std::str::FromStr;

/// The per-vertex hair shading model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadingModel {
    /// Kajiya-Kay with Scheuermann's two shifted highlights
    /// ([`KajiyaKay::default`], brown hair).
    #[default]
    KajiyaKay,
    /// Marschner 2003, factored lookup tables ([`marschner::Lut`], 128),
    /// default parameters with the absorption of [`demo_sigma_a`] (halved,
    /// Marschner's convention per unit radius as in `marschner::Params`).
    Marschner,
    /// pbrt-v3's hair BSDF far field, lookup table ([`pbrt::Table`], 64),
    /// default parameters with `sigma_a` = [`demo_sigma_a`].
    Pbrt,
}

impl ShadingModel {
    /// Every model, in the order of the CLI help.
    pub const ALL: [ShadingModel; 3] = [
        ShadingModel::KajiyaKay,
        ShadingModel::Marschner,
        ShadingModel::Pbrt,
    ];

    /// The CLI name (`kajiya-kay`, `marschner`, `pbrt`).
    pub fn name(self) -> &'static str {
        match self {
            ShadingModel::KajiyaKay => "kajiya-kay",
            ShadingModel::Marschner => "marschner",
            ShadingModel::Pbrt => "pbrt",
        }
    }
}

impl fmt::Display for ShadingModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ShadingModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ShadingModel::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("unknown shading model {s:?} (kajiya-kay, marschner, pbrt)"))
    }
}

/// Absorption of the demo's hair for the physically based models: medium
/// brown, eumelanin 0.8 and pheomelanin 0.3 (d'Eon 2011 via
/// `pbrt::sigma_a_from_concentration`); pbrt-v3's default (eumelanin 1.3)
/// is nearly black in single scattering.
pub fn demo_sigma_a() -> glam::Vec3 {
    pbrt::sigma_a_from_concentration(0.8, 0.3)
}

/// Light multiplier of the physically based models. Their fibres are
/// energy-normalised and single-scattering only (no multiple scattering,
/// which carries most of the light in real brown hair), so under the same
/// light they are about ten times darker than Kajiya-Kay, whose diffuse
/// term is not normalised. The demo raises their light by this factor so
/// the three pictures are comparable; the relative shading is untouched.
pub const PHYSICAL_LIGHT_SCALE: f32 = 6.0;

/// Marschner table resolution (1-3 % relative RMS of the direct model with the default layout).
pub const MARSCHNER_RESOLUTION: usize = 128;
/// pbrt table resolution.
pub const PBRT_RESOLUTION: usize = 64;

/// A model ready to shade batches: the tables are built once.
pub enum Shader {
    /// Kajiya-Kay (Kajiya and Kay 1989) with two shifted highlights (Scheuermann 2004).
    KajiyaKay(KajiyaKay),
    /// The factored Marschner et al. 2003 model in lookup tables.
    Marschner(Box<marschner::Lut>),
    /// The pbrt-v3 hair BSDF (Chiang et al. 2016) far field in a lookup table.
    Pbrt(Box<pbrt::Table>),
}

impl Shader {
    /// Builds the model's tables (Marschner: 128, pbrt: 64 per axis).
    pub fn new(model: ShadingModel) -> Result<Shader, Error> {
        Ok(match model {
            ShadingModel::KajiyaKay => Shader::KajiyaKay(KajiyaKay::default()),
            ShadingModel::Marschner => Shader::Marschner(Box::new(marschner::Lut::new(
                &marschner::Params::default(),
                MARSCHNER_RESOLUTION,
            ))),
            ShadingModel::Pbrt => Shader::Pbrt(Box::new(pbrt::Table::new(
                &pbrt::Params::default(),
                PBRT_RESOLUTION,
            )?)),
        })
    }

    /// Scattering of every sample into `out` (SIMD batch paths).
    pub fn shade_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        match self {
            Shader::KajiyaKay(k) => k.shade_batch(samples, out),
            Shader::Marschner(l) => l.scattering_batch(samples, out),
            Shader::Pbrt(t) => t.scattering_batch(samples, out),
        }
    }

    /// Scattering of eight samples (the per-element `_x8` function of the
    /// model: `KajiyaKay::shade_x8`, `marschner::Lut::scattering_x8`,
    /// `pbrt::Table::scattering_x8`), the same numbers as
    /// [`Shader::shade_batch`] gives for those samples.
    #[inline(always)]
    pub fn scattering_x8(&self, t: Vec3x8, wi: Vec3x8, wo: Vec3x8) -> Vec3x8 {
        match self {
            Shader::KajiyaKay(k) => k.shade_x8(t, wi, wo),
            Shader::Marschner(l) => l.scattering_x8(t, wi, wo),
            Shader::Pbrt(p) => p.scattering_x8(t, wi, wo),
        }
    }

    /// Whether the output still lacks the fibre's cosine factor
    /// `cos theta_i = sqrt(1 - (t . wi)^2)` of the lighting integral
    /// `L = S cos theta_i E`: true for Marschner's `S`; pbrt's far field
    /// includes it and Kajiya-Kay's diffuse term is that sine already.
    pub fn needs_cosine(&self) -> bool {
        matches!(self, Shader::Marschner(_))
    }

    /// Multiplier of the light's irradiance for this model
    /// ([`PHYSICAL_LIGHT_SCALE`] for the physically based ones).
    pub fn light_scale(&self) -> f32 {
        match self {
            Shader::KajiyaKay(_) => 1.0,
            _ => PHYSICAL_LIGHT_SCALE,
        }
    }
}
