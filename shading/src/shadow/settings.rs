//! The knobs of an opacity shadow map: resolution, layer count, mode,
//! density and the hair radius.

use crate::Error;

/// How the depth axis of the map is divided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadowMode {
    /// Opacity shadow maps (Kim & Neumann 2001): `layers` planes evenly
    /// spaced between the hair's nearest and farthest depth, the same planes
    /// for every texel. Nalu used 16 of them, packed 4 per RGBA texel.
    #[default]
    Slices,
    /// Deep opacity maps (Yuksel & Keyser 2008): a depth map `z0(x, y)` of
    /// the first hair seen from the light in each texel, and `layers` layers
    /// starting there, so the first layer hugs the lit surface of the hair
    /// whatever its shape. They used 3 layers.
    Deep,
}

/// Settings of an [`OpacityShadowMap`](super::OpacityShadowMap).
///
/// Build with `..Default::default()`; [`ShadowSettings::validate`] reports
/// values outside their ranges (the map constructor calls it).
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Texels per side of the square light-space map (default 256).
    pub resolution: usize,
    /// Slices ([`ShadowMode::Slices`], default 16) or layers
    /// ([`ShadowMode::Deep`], 3 or 4 suffice). Stored 4 per texel.
    pub layers: usize,
    /// Default [`ShadowMode::Slices`].
    pub mode: ShadowMode,
    /// `k` in `T = exp(-k sigma)`, where `sigma` counts the hairs in front
    /// of a point (texel-averaged in the map, exact in the reference): the
    /// optical depth of one hair crossed. Default 0.5 (one hair lets 61 %
    /// through). Nalu wrote `exp(-5.5 * sum)` over per-hair alphas of about
    /// 0.1; `k = 0.5` is the same attenuation per hair.
    pub density: f32,
    /// Radius in metres of a hair as a shadow caster (the capsule of the
    /// exact reference, and the width a segment covers in the map). A
    /// rendered strand usually stands for many real hairs, so this is larger
    /// than a real hair's 40 micrometres; default 0.4 mm.
    pub hair_radius: f32,
}

/// Largest accepted [`ShadowSettings::resolution`] (with at most 4
/// layers: the whole map is bounded by [`MAX_MAP_TEXELS`]).
pub const MAX_RESOLUTION: usize = 8192;
/// Largest accepted [`ShadowSettings::layers`].
pub const MAX_LAYERS: usize = 256;

/// Most RGBA texels a map holds, `resolution^2 x ceil(layers / 4)`:
/// 2^26 (1 GiB of `f32` texels; 8192^2 at 4 layers, 2048^2 at 64).
pub const MAX_MAP_TEXELS: usize = 1 << 26;

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            resolution: 256,
            layers: 16,
            mode: ShadowMode::Slices,
            density: 0.5,
            hair_radius: 0.0004,
        }
    }
}

impl ShadowSettings {
    /// The defaults of deep opacity maps: 3 layers (Yuksel & Keyser 2008).
    pub fn deep() -> Self {
        ShadowSettings {
            layers: 3,
            mode: ShadowMode::Deep,
            ..Default::default()
        }
    }

    /// Checks every field: `2 <= resolution <= 8192`, `1 <= layers <= 256`,
    /// `density` finite and `>= 0`, `hair_radius` finite and `> 0`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidShadowSetting`] for the first setting out of range.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name, value: f32, expected| {
            Err(Error::InvalidShadowSetting {
                name,
                value,
                expected,
            })
        };
        if !(2..=MAX_RESOLUTION).contains(&self.resolution) {
            return bad(
                "resolution",
                self.resolution as f32,
                "2 <= resolution <= 8192",
            );
        }
        if !(1..=MAX_LAYERS).contains(&self.layers) {
            return bad("layers", self.layers as f32, "1 <= layers <= 256");
        }
        // Each bound alone allows 64 GiB (8192^2 texels x 64 RGBA groups):
        // the map as a whole is bounded too.
        if self.resolution * self.resolution * self.groups() > MAX_MAP_TEXELS {
            return bad(
                "resolution",
                self.resolution as f32,
                "resolution^2 x ceil(layers / 4) <= 2^26 RGBA texels (1 GiB)",
            );
        }
        if !(self.density.is_finite() && self.density >= 0.0) {
            return bad("density", self.density, "a finite density >= 0");
        }
        if !(self.hair_radius.is_finite() && self.hair_radius > 0.0) {
            return bad("hair_radius", self.hair_radius, "a finite hair_radius > 0");
        }
        Ok(())
    }

    /// RGBA texels per map texel: `ceil(layers / 4)`.
    pub fn groups(&self) -> usize {
        self.layers.div_ceil(4)
    }
}
