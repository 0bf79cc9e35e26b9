//! Material parameters of pbrt-v3's hair BSDF and the per-material constants
//! its constructor derives from them (`HairBSDF::HairBSDF` in pbrt-v3
//! `src/materials/hair.cpp`).

use super::melanin::sigma_a_from_concentration;
use crate::Error;
use glam::Vec3;

/// pbrt-v3's hair material. Angles in radians; `sigma_a` is the absorption
/// coefficient per unit fibre radius, per RGB channel.
#[derive(Clone, Debug)]
pub struct Params {
    /// Index of refraction of the fibre interior.
    pub eta: f32,
    /// Longitudinal roughness in (0, 1].
    pub beta_m: f32,
    /// Azimuthal roughness in (0, 1].
    pub beta_n: f32,
    /// Cuticle scale tilt, radians (pbrt-v3 takes degrees in the scene file
    /// and converts; since its 2018 fix the conversion is applied).
    pub alpha: f32,
    /// Absorption coefficient per unit radius, RGB.
    pub sigma_a: Vec3,
}

impl Default for Params {
    /// pbrt-v3's defaults: eta 1.55, beta_m = beta_n = 0.3, alpha = 2 degrees,
    /// sigma_a of eumelanin concentration 1.3, about (0.5447, 0.9061, 1.7810).
    fn default() -> Self {
        Params {
            eta: 1.55,
            beta_m: 0.3,
            beta_n: 0.3,
            alpha: 2.0f32.to_radians(),
            sigma_a: sigma_a_from_concentration(1.3, 0.0),
        }
    }
}

impl Params {
    /// Checks the ranges the model needs: `eta` finite and > 1 (at 1,
    /// `eta'` is 0/0 along the fibre), `beta_m`
    /// and `beta_n` in (0, 1] (pbrt-v3 allows 0, where its variance is 0 and
    /// `M_p` divides by zero), `alpha` finite with |alpha| < pi/4, and
    /// `sigma_a` finite and non-negative.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] for the first parameter out of range.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name, value| Err(Error::InvalidParameter { name, value });
        if !(self.eta.is_finite() && self.eta > 1.0) {
            return bad("eta", self.eta);
        }
        if !(self.beta_m > 0.0 && self.beta_m <= 1.0) {
            return bad("beta_m", self.beta_m);
        }
        if !(self.beta_n > 0.0 && self.beta_n <= 1.0) {
            return bad("beta_n", self.beta_n);
        }
        if self.alpha.is_nan() || self.alpha.abs() >= std::f32::consts::FRAC_PI_4 {
            return bad("alpha", self.alpha);
        }
        for c in self.sigma_a.to_array() {
            if !(c.is_finite() && c >= 0.0) {
                return bad("sigma_a", c);
            }
        }
        Ok(())
    }
}

/// `sqrt(pi / 8)` as pbrt-v3 spells it (`SqrtPiOver8`).
const SQRT_PI_OVER_8: f32 = 0.626_657_07;

/// pbrt-v3's `Pow<n>`: recursive squaring, `Pow<n> = Pow<n/2>^2 * Pow<n & 1>`.
/// The multiplication order is reproduced because it changes the rounding.
pub(crate) fn pow_n(v: f32, n: u32) -> f32 {
    match n {
        0 => 1.0,
        1 => v,
        _ => {
            let half = pow_n(v, n / 2);
            half * half * pow_n(v, n & 1)
        }
    }
}

/// The constants pbrt-v3's `HairBSDF` constructor derives from the material.
#[derive(Clone, Copy, Debug)]
pub struct Lobes {
    /// Longitudinal variances: `v0 = (0.726 beta_m + 0.812 beta_m^2 +
    /// 3.7 beta_m^20)^2` (Chiang 2016 eq. 7), `v1 = v0 / 4`, `v2 = v3 = 4 v0`.
    pub v: [f32; 4],
    /// Logistic scale `s = sqrt(pi/8) (0.265 beta_n + 1.194 beta_n^2 +
    /// 5.372 beta_n^22)` (Chiang 2016 eq. 8).
    pub s: f32,
    /// `sin(2^k alpha)`, `k = 0, 1, 2`, by the double-angle recurrence.
    pub sin_2k_alpha: [f32; 3],
    /// `cos(2^k alpha)`, `k = 0, 1, 2`.
    pub cos_2k_alpha: [f32; 3],
}

impl Lobes {
    /// The per-lobe terms precomputed from `params`.
    pub fn new(params: &Params) -> Lobes {
        let bm = params.beta_m;
        let v0 = {
            let x = 0.726 * bm + 0.812 * (bm * bm) + 3.7 * pow_n(bm, 20);
            x * x
        };
        let bn = params.beta_n;
        let s = SQRT_PI_OVER_8 * (0.265 * bn + 1.194 * (bn * bn) + 5.372 * pow_n(bn, 22));
        let mut sin_2k_alpha = [0.0f32; 3];
        let mut cos_2k_alpha = [0.0f32; 3];
        sin_2k_alpha[0] = params.alpha.sin();
        cos_2k_alpha[0] = (1.0 - sin_2k_alpha[0] * sin_2k_alpha[0]).max(0.0).sqrt();
        for i in 1..3 {
            sin_2k_alpha[i] = 2.0 * cos_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
            cos_2k_alpha[i] = cos_2k_alpha[i - 1] * cos_2k_alpha[i - 1]
                - sin_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
        }
        Lobes {
            v: [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0],
            s,
            sin_2k_alpha,
            cos_2k_alpha,
        }
    }

    /// `(sin theta_o', cos theta_o')` for lobe `p`: theta_o rotated by the
    /// cuticle tilt, `-2 alpha`, `+alpha`, `+4 alpha` for p = 0, 1, 2 and
    /// untilted for p = 3 (pbrt-v3 since 2019), with pbrt's `abs` on the
    /// cosine for out-of-range rotations.
    #[inline]
    pub fn tilt(&self, p: usize, sin_theta_o: f32, cos_theta_o: f32) -> (f32, f32) {
        let (s, c) = (self.sin_2k_alpha, self.cos_2k_alpha);
        let (sin_op, cos_op) = match p {
            0 => (
                sin_theta_o * c[1] - cos_theta_o * s[1],
                cos_theta_o * c[1] + sin_theta_o * s[1],
            ),
            1 => (
                sin_theta_o * c[0] + cos_theta_o * s[0],
                cos_theta_o * c[0] - sin_theta_o * s[0],
            ),
            2 => (
                sin_theta_o * c[2] + cos_theta_o * s[2],
                cos_theta_o * c[2] - sin_theta_o * s[2],
            ),
            _ => (sin_theta_o, cos_theta_o),
        };
        (sin_op, cos_op.abs())
    }
}
