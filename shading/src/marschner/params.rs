//! Parameters of Marschner et al. 2003, "Light Scattering from Human Hair
//! Fibers", table 1 of the paper.

use glam::Vec3;

/// How the roots `h` of `phi(p, h) = 2 p gamma_t - 2 gamma_i + p pi` are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RootSolver {
    /// Safeguarded Newton iteration on the exact equation (in `f64`), on each
    /// interval where `phi(p, h)` is monotone.
    #[default]
    Exact,
    /// The paper's cubic approximation of `phi` in `gamma_i` (Marschner 2003,
    /// section 4.2.3), solved in closed form.
    Cubic,
}

/// Marschner et al. 2003. Angles in radians; absorption sigma_a per unit
/// fibre radius, per RGB channel.
///
/// The default gives the paper's typical values (table 1): eta 1.55,
/// alpha_R -7.5 deg, beta_R 7.5 deg, eccentricity 0.9, glint scale 2,
/// caustic width 15 deg, fade range 0.3, caustic limit 0.5, and an absorption
/// (0.27, 0.45, 0.89) that equals pbrt-v3's default brown (eumelanin 1.3)
/// halved: Marschner's `T = exp(-4 sigma_a' cos^2 gamma_t)` then matches
/// pbrt's `exp(-2 sigma_a cos gamma_t / cos theta_t)` at normal incidence.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Index of refraction of the fibre (paper: 1.55).
    pub eta: f32,
    /// Longitudinal shift of the R lobe, alpha_R (paper: -10 to -5 deg).
    /// TT is shifted by -alpha_R / 2 and TRT by -3 alpha_R / 2.
    pub alpha_r: f32,
    /// Longitudinal width (standard deviation) of the R lobe, beta_R (paper:
    /// 5 to 10 deg). TT has beta_R / 2, TRT 2 beta_R.
    pub beta_r: f32,
    /// Volume absorption sigma_a per unit fibre radius, per RGB channel.
    pub absorption: Vec3,
    /// Ratio of the minor to the major axis of the elliptical cross section,
    /// a (paper: 0.85 to 1; 1 is round).
    pub eccentricity: f32,
    /// k_G, scale of the TRT glints (paper: 0.5 to 5).
    pub glint_scale: f32,
    /// w_c, azimuthal width of the TRT caustic Gaussians, radians (paper: 10
    /// to 25 deg).
    pub caustic_width: f32,
    /// Delta eta', the range of eta' above 2 over which the glints fade out
    /// (paper: 0.2 to 0.4).
    pub caustic_fade_range: f32,
    /// Delta h_M, the largest h-interval a caustic may gather (paper: 0.5).
    pub caustic_limit: f32,
    /// Root finder for the azimuthal scattering function `N_p`.
    pub roots: RootSolver,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            eta: 1.55,
            alpha_r: (-7.5f32).to_radians(),
            beta_r: 7.5f32.to_radians(),
            absorption: Vec3::new(0.5447, 0.9061, 1.7810) * 0.5,
            eccentricity: 0.9,
            glint_scale: 2.0,
            caustic_width: 15f32.to_radians(),
            caustic_fade_range: 0.3,
            caustic_limit: 0.5,
            roots: RootSolver::Exact,
        }
    }
}

/// Parameters in `f64`, sanitised so that no parameter value can make the
/// evaluation divide by zero: eta >= 1.0001, widths >= 1e-4, eccentricity
/// in [0.1, 10], absorption >= 0. NaN parameters pass through: they never
/// panic, but the results are meaningless (zero or NaN).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sanitised {
    pub eta: f64,
    pub alpha_r: f64,
    pub beta_r: f64,
    pub absorption: [f64; 3],
    pub eccentricity: f64,
    pub glint_scale: f64,
    pub caustic_width: f64,
    pub caustic_fade_range: f64,
    pub caustic_limit: f64,
    pub roots: RootSolver,
}

fn at_least(x: f32, lo: f64) -> f64 {
    let x = x as f64;
    if x < lo {
        lo
    } else {
        x
    }
}

impl Sanitised {
    pub fn new(p: &Params) -> Self {
        let ecc = at_least(p.eccentricity, 0.1);
        Sanitised {
            eta: at_least(p.eta, 1.0001),
            alpha_r: p.alpha_r as f64,
            beta_r: at_least(p.beta_r.abs(), 1e-4),
            absorption: [
                at_least(p.absorption.x, 0.0),
                at_least(p.absorption.y, 0.0),
                at_least(p.absorption.z, 0.0),
            ],
            eccentricity: if ecc > 10.0 { 10.0 } else { ecc },
            glint_scale: at_least(p.glint_scale, 0.0),
            caustic_width: at_least(p.caustic_width.abs(), 1e-4),
            caustic_fade_range: at_least(p.caustic_fade_range, 1e-4),
            caustic_limit: at_least(p.caustic_limit, 0.0),
            roots: p.roots,
        }
    }
}
