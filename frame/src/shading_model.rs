//! Which hair shading model a frame uses, with its prepared tables.

use super::Error;
use coif_base::Vec3Lanes;
use coif_shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif_shading::kajiya_kay::KajiyaKay;
use coif_shading::{marschner, pbrt, RgbBuffer, ShadingSamples};
use glam::Vec3;
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
    /// default parameters with the frame's absorption
    /// (`FrameSettings::hair_sigma_a`, halved: Marschner's convention per
    /// unit radius as in `marschner::Params`), plus dual scattering unless
    /// `FrameSettings::multiple_scattering` is off.
    Marschner,
    /// pbrt-v3's hair BSDF far field, lookup table ([`pbrt::Table`], 64),
    /// default parameters with `sigma_a` = `FrameSettings::hair_sigma_a`,
    /// plus dual scattering unless `FrameSettings::multiple_scattering` is off.
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
pub fn demo_sigma_a() -> Vec3 {
    pbrt::sigma_a_from_concentration(0.8, 0.3)
}

/// Hair colours by melanin (d'Eon et al. 2011's concentrations, through
/// `pbrt::sigma_a_from_concentration`), for the physically based models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HairColor {
    /// Blond: eumelanin 0.3.
    Blond,
    /// Medium brown: eumelanin 0.8, pheomelanin 0.3 ([`demo_sigma_a`]).
    Brown,
    /// Dark brown: eumelanin 1.3 (pbrt-v3's default).
    Dark,
}

impl HairColor {
    /// Every colour, in the order of the CLI help.
    pub const ALL: [HairColor; 3] = [HairColor::Blond, HairColor::Brown, HairColor::Dark];

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            HairColor::Blond => "blond",
            HairColor::Brown => "brown",
            HairColor::Dark => "dark",
        }
    }

    /// Absorption per unit radius (pbrt-v3's `sigma_a`).
    pub fn sigma_a(self) -> Vec3 {
        match self {
            HairColor::Blond => pbrt::sigma_a_from_concentration(0.3, 0.0),
            HairColor::Brown => demo_sigma_a(),
            HairColor::Dark => pbrt::sigma_a_from_concentration(1.3, 0.0),
        }
    }
}

impl FromStr for HairColor {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        HairColor::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("unknown hair colour {s:?} (blond, brown, dark)"))
    }
}

/// Light multiplier of the physically based models. Their fibres are
/// energy-normalised: under the same light they are several times darker
/// than Kajiya-Kay, whose diffuse term is not normalised (about ten times
/// in single scattering; dual scattering gives back part of it, most for
/// light hair). The demo raises their light by this factor so the models'
/// pictures are comparable; the relative shading is untouched.
pub const PHYSICAL_LIGHT_SCALE: f32 = 6.0;

/// Marschner table resolution (1-3 % relative RMS of the direct model with the default layout).
pub const MARSCHNER_RESOLUTION: usize = 128;
/// pbrt table resolution.
pub const PBRT_RESOLUTION: usize = 64;

/// A model ready to shade batches: the tables are built once.
pub enum Shader {
    /// Kajiya-Kay (Kajiya and Kay 1989) with two shifted highlights (Scheuermann 2004).
    KajiyaKay(KajiyaKay),
    /// The factored Marschner et al. 2003 model in lookup tables, with its
    /// dual scattering tables when multiple scattering is on.
    Marschner(Box<marschner::Lut>, Option<Box<DualScattering>>),
    /// The pbrt-v3 hair BSDF (Chiang et al. 2016) far field in a lookup
    /// table, with its dual scattering tables when multiple scattering is on.
    Pbrt(Box<pbrt::Table>, Option<Box<DualScattering>>),
}

impl Shader {
    /// The model's tables (Marschner: 128, pbrt: 64 per axis) for the
    /// brown of [`demo_sigma_a`], with multiple scattering.
    pub fn new(model: ShadingModel) -> Result<Shader, Error> {
        Shader::with_material(model, demo_sigma_a(), true)
    }

    /// The model's tables for absorption `sigma_a` (pbrt-v3's, per unit
    /// radius; Marschner gets half of it, see [`ShadingModel::Marschner`]),
    /// and dual scattering tables ([`DualScatteringSettings::default`])
    /// when `multiple_scattering` (ignored by Kajiya-Kay).
    ///
    /// # Errors
    ///
    /// [`Error::Shading`] for an absorption pbrt refuses (negative or not finite).
    pub fn with_material(
        model: ShadingModel,
        sigma_a: Vec3,
        multiple_scattering: bool,
    ) -> Result<Shader, Error> {
        let ds = DualScatteringSettings::default();
        Ok(match model {
            ShadingModel::KajiyaKay => Shader::KajiyaKay(KajiyaKay::default()),
            ShadingModel::Marschner => {
                let params = marschner::Params {
                    absorption: sigma_a * 0.5,
                    ..marschner::Params::default()
                };
                let pbrt_check = pbrt::Params {
                    sigma_a,
                    ..pbrt::Params::default()
                };
                pbrt_check.validate()?;
                let lut = marschner::Lut::new(&params, MARSCHNER_RESOLUTION);
                let dual = if multiple_scattering {
                    Some(Box::new(DualScattering::from_marschner(&lut, ds)?))
                } else {
                    None
                };
                Shader::Marschner(Box::new(lut), dual)
            }
            ShadingModel::Pbrt => {
                let params = pbrt::Params {
                    sigma_a,
                    ..pbrt::Params::default()
                };
                let table = pbrt::Table::new(&params, PBRT_RESOLUTION)?;
                let dual = if multiple_scattering {
                    Some(Box::new(DualScattering::from_pbrt(&table, ds)?))
                } else {
                    None
                };
                Shader::Pbrt(Box::new(table), dual)
            }
        })
    }

    /// The dual scattering tables, when the model has them.
    pub fn dual_scattering(&self) -> Option<&DualScattering> {
        match self {
            Shader::KajiyaKay(_) => None,
            Shader::Marschner(_, d) | Shader::Pbrt(_, d) => d.as_deref(),
        }
    }

    /// Single scattering of every sample into `out` (SIMD batch paths).
    pub fn shade_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        match self {
            Shader::KajiyaKay(k) => k.shade_batch(samples, out),
            Shader::Marschner(l, _) => l.scattering_batch(samples, out),
            Shader::Pbrt(t, _) => t.scattering_batch(samples, out),
        }
    }

    /// Single scattering of eight samples (the per-element `_x8` function of the
    /// model: `KajiyaKay::shade_simd`, `marschner::Lut::scattering_simd`,
    /// `pbrt::Table::scattering_simd`), the same numbers as
    /// [`Shader::shade_batch`] gives for those samples.
    #[inline(always)]
    pub fn scattering_simd(&self, t: Vec3Lanes, wi: Vec3Lanes, wo: Vec3Lanes) -> Vec3Lanes {
        match self {
            Shader::KajiyaKay(k) => k.shade_simd(t, wi, wo),
            Shader::Marschner(l, _) => l.scattering_simd(t, wi, wo),
            Shader::Pbrt(p, _) => p.scattering_simd(t, wi, wo),
        }
    }

    /// Whether the output still lacks the fibre's cosine factor
    /// `cos theta_i = sqrt(1 - (t . wi)^2)` of the lighting integral
    /// `L = S cos theta_i E`: true for Marschner's `S`; pbrt's far field
    /// includes it and Kajiya-Kay's diffuse term is that sine already.
    pub fn needs_cosine(&self) -> bool {
        matches!(self, Shader::Marschner(..))
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
