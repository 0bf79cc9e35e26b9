//! Marschner et al. 2003, "Light Scattering from Human Hair Fibers": the
//! direct evaluation and the factored lookup tables of NVIDIA's Nalu demo
//! (GPU Gems 2, chapter 23).
//!
//! S(wi, wo) = sum over p in {R, TT, TRT} of M_p(theta_h) N_p(theta_d, phi) / cos^2 theta_d
//!
//! Conventions (shared by every model in this crate): `t` is the tangent root to tip, `wi`
//! points toward the light, `wo` toward the viewer; sin theta = w . t;
//! phi = phi_o - phi_i is the azimuth difference in the normal plane;
//! theta_h = (theta_i + theta_o) / 2, theta_d = (theta_o - theta_i) / 2.
//!
//! One concept per file: [`params`] (table 1 of the paper), [`longitudinal`]
//! (M_p), [`fresnel`] (Bravais indices and Fresnel), [`azimuthal`] (roots of
//! phi(p, h), exact and cubic, and N_p), [`caustic`] (the TRT glints),
//! [`eccentricity`] (elliptical fibres), [`lut`] (the factored tables and
//! their SIMD batch lookup), [`accuracy`] (error of tables and of the cubic
//! root approximation, for reports).
//!
//! Robustness: directions need not be unit length (only their directions
//! are used); `scattering` is finite and non-negative for every pair of
//! non-zero finite directions, including along the fibre (phi is then
//! undefined and taken as 0) and grazing. cos theta_d is clamped below at
//! [`MIN_COS_THETA_D`] (theta_d <= 84.3 deg), where the model's
//! 1 / cos^2 theta_d would otherwise diverge. A zero-length `t`, `wi` or `wo`
//! gives zero for that sample; a NaN or infinite component gives NaN for that
//! sample.

pub mod accuracy;
pub mod azimuthal;
pub mod caustic;
pub mod eccentricity;
pub mod fresnel;
pub mod longitudinal;
pub mod lut;
pub mod params;

pub use lut::{Lut, LutLayout};
pub use params::{Params, RootSolver};

use crate::{RgbBuffer, ShadingSamples};
use azimuthal::{n_plain, Interface};
use glam::Vec3;
use params::Sanitised;

/// Smallest cos theta_d used (the model's 1 / cos^2 theta_d and Bravais'
/// eta' = sqrt(eta^2 - sin^2 theta_d) / cos theta_d diverge as theta_d -> 90 deg;
/// only about 1e-4 of uniformly random direction pairs reach the clamp).
pub const MIN_COS_THETA_D: f32 = 0.1;

/// The three lobes of [`scattering`], each M_p N_p / cos^2 theta_d, per RGB.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lobes {
    /// The R lobe (surface reflection).
    pub r: Vec3,
    /// The TT lobe (transmission through the fibre).
    pub tt: Vec3,
    /// The TRT lobe (one internal reflection).
    pub trt: Vec3,
}

impl Lobes {
    /// `R + TT + TRT`.
    pub fn sum(&self) -> Vec3 {
        self.r + self.tt + self.trt
    }
}

/// Longitudinal and azimuthal angles of a (t, wi, wo) configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FibreAngles {
    /// theta_i, theta_o in [-pi/2, pi/2].
    pub theta_i: f64,
    /// theta_o in [-pi/2, pi/2].
    pub theta_o: f64,
    /// phi = phi_o - phi_i in (-pi, pi]; 0 when either direction is along t.
    pub phi: f64,
}

/// What a degenerate input gives instead of angles.
pub(crate) enum Degenerate {
    Zero,
    Nan,
}

/// Angles of `wi`, `wo` about the fibre `t`, scale invariant:
/// sin theta_i = (wi . t) / (|wi| |t|), and phi from
/// cos phi ~ wi . wo - (wi . t)(wo . t) / |t|^2 and sin phi ~ t . (wi x wo) / |t|.
pub(crate) fn fibre_angles(t: Vec3, wi: Vec3, wo: Vec3) -> Result<FibreAngles, Degenerate> {
    if !(t.is_finite() && wi.is_finite() && wo.is_finite()) {
        return Err(Degenerate::Nan);
    }
    let (t, wi, wo) = (t.as_dvec3(), wi.as_dvec3(), wo.as_dvec3());
    let (lt2, li2, lo2) = (t.length_squared(), wi.length_squared(), wo.length_squared());
    if lt2 < 1e-30 || li2 < 1e-30 || lo2 < 1e-30 {
        return Err(Degenerate::Zero);
    }
    let (a, b) = (wi.dot(t), wo.dot(t));
    let sin_i = (a / (li2 * lt2).sqrt()).clamp(-1.0, 1.0);
    let sin_o = (b / (lo2 * lt2).sqrt()).clamp(-1.0, 1.0);
    let cos_num = wi.dot(wo) - a * b / lt2;
    let sin_num = t.dot(wi.cross(wo)) / lt2.sqrt();
    Ok(FibreAngles {
        theta_i: sin_i.asin(),
        theta_o: sin_o.asin(),
        phi: sin_num.atan2(cos_num),
    })
}

/// Bravais indices and refraction angle for index `eta` at theta_d.
pub(crate) fn interface(eta: f64, cos_theta_d: f64) -> Interface {
    let sin_d2 = (1.0 - cos_theta_d * cos_theta_d).max(0.0);
    let (eta_perp, eta_par) = fresnel::bravais(eta, sin_d2.sqrt(), cos_theta_d);
    Interface {
        eta_perp,
        eta_par,
        cos_theta_t: (1.0 - sin_d2 / (eta * eta)).max(1e-12).sqrt(),
    }
}

/// (N_R, N_TT, N_TRT) per RGB channel at |cos theta_d| (clamped to
/// [`MIN_COS_THETA_D`], 1]) and azimuth `phi`, without the 1 / cos^2 theta_d.
/// TRT uses the eccentric index eta*(phi_h) with phi_h = phi / 2 (see
/// [`eccentricity`]) and the caustic treatment of [`caustic`].
pub(crate) fn n_terms(p: &Sanitised, cos_theta_d: f64, phi: f64) -> [[f64; 3]; 3] {
    let c = cos_theta_d.abs().clamp(MIN_COS_THETA_D as f64, 1.0);
    let round = interface(p.eta, c);
    let n_r = n_plain(0, phi, &round, &p.absorption, p.roots);
    let n_tt = n_plain(1, phi, &round, &p.absorption, p.roots);
    let eta_star = eccentricity::effective_eta(p.eta, p.eccentricity, phi.cos());
    let n_trt = caustic::n_trt(p, phi, &interface(eta_star, c));
    [n_r, n_tt, n_trt]
}

/// The three lobes at the given angles, in f64.
pub(crate) fn lobes_at(p: &Sanitised, a: &FibreAngles) -> [[f64; 3]; 3] {
    let theta_h = 0.5 * (a.theta_i + a.theta_o);
    let cos_d = (0.5 * (a.theta_o - a.theta_i))
        .cos()
        .max(MIN_COS_THETA_D as f64);
    let m = longitudinal::m_terms(p, theta_h);
    let n = n_terms(p, cos_d, a.phi);
    let inv = 1.0 / (cos_d * cos_d);
    [0, 1, 2].map(|k| n[k].map(|v| (m[k] * v * inv).max(0.0)))
}

fn to_vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// The three lobes of [`scattering`] separately.
pub fn lobes(params: &Params, t: Vec3, wi: Vec3, wo: Vec3) -> Lobes {
    match fibre_angles(t, wi, wo) {
        Ok(a) => {
            let l = lobes_at(&Sanitised::new(params), &a);
            Lobes {
                r: to_vec3(l[0]),
                tt: to_vec3(l[1]),
                trt: to_vec3(l[2]),
            }
        }
        Err(Degenerate::Zero) => Lobes::default(),
        Err(Degenerate::Nan) => Lobes {
            r: Vec3::NAN,
            tt: Vec3::NAN,
            trt: Vec3::NAN,
        },
    }
}

/// S = sum_p M_p N_p / cos^2 theta_d, per RGB channel, no cosine factor.
/// t: unit tangent; wi: unit, toward the light; wo: unit, toward the viewer.
/// Evaluated directly (roots by `params.roots`), in f64 internally.
pub fn scattering(params: &Params, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
    lobes(params, t, wi, wo).sum()
}

/// [`scattering`] for every sample of `samples` into `out` (resized to
/// `samples.len()`). Scalar: the direct model has no SIMD path (its root
/// finding branches per sample); use a [`Lut`] for speed.
pub fn scattering_batch(params: &Params, samples: &ShadingSamples, out: &mut RgbBuffer) {
    let p = Sanitised::new(params);
    out.resize(samples.len());
    for i in 0..samples.len() {
        let (t, wi, wo) = samples.get(i);
        let v = match fibre_angles(t, wi, wo) {
            Ok(a) => {
                let l = lobes_at(&p, &a);
                to_vec3(l[0]) + to_vec3(l[1]) + to_vec3(l[2])
            }
            Err(Degenerate::Zero) => Vec3::ZERO,
            Err(Degenerate::Nan) => Vec3::NAN,
        };
        out.set(i, v);
    }
}
