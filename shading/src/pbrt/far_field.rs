//! The far-field form of pbrt-v3's hair BSDF: the average over the offset
//! `h` across the fibre, `S(wi, wo) = 1/2 * integral_{-1}^{1} sum_p M_p A_p N_p dh`,
//! which is what a rasteriser shading a fibre thinner than a pixel sees.
//!
//! The integral is taken in `gamma = asin h` (`dh = cos gamma d gamma`),
//! which removes the square-root behaviour of the integrand at `h = +-1`,
//! by Gauss-Legendre quadrature of a chosen order (PBRT.md gives the
//! measured error per order). `M_p` does not depend on `h` and is evaluated
//! once per call; the nodes' `A_p N_p` terms are summed with the weights.

use super::attenuation::{ap, P_MAX};
use super::azimuthal::{logistic, logistic_cdf, wrap};
use super::exp3;
use super::longitudinal::mp;
use super::params::{Lobes, Params};
use crate::{Error, RgbBuffer, ShadingSamples};
use glam::Vec3;
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Quadrature order for the default material: [`recommended_order`] of
/// `Params::default()` (relative RMS error 8e-7 against four times the
/// order; 36 nodes give 1.6e-3; PBRT.md).
pub const DEFAULT_QUADRATURE_ORDER: usize = 72;

/// Largest order [`recommended_order`] returns.
pub const MAX_QUADRATURE_ORDER: usize = 2048;

/// Most Gauss-Legendre nodes [`FarField::new`] accepts: four times
/// [`MAX_QUADRATURE_ORDER`], the accuracy references' order
/// (`quality::reference_order`).
pub const MAX_FAR_FIELD_ORDER: usize = 4 * MAX_QUADRATURE_ORDER;

/// The quadrature order that resolves the narrowest azimuthal lobe.
///
/// Along h the R lobe's logistic has width about `s / 2` in gamma
/// (`dPhi/dgamma_o = -2`), and Gauss-Legendre converges geometrically
/// once the node spacing (about `pi / n`) is below that width. Measured on
/// the default material (s = 0.117): 32 nodes give 3e-3 relative RMS error,
/// 64 give 3e-6. So `n = 8 / s`, rounded up to a multiple of 8, clamped to
/// [16, 2048].
pub fn recommended_order(params: &Params) -> usize {
    let s = Lobes::new(params).s;
    let n = (8.0 / s).ceil();
    if n.is_nan() || n >= MAX_QUADRATURE_ORDER as f32 {
        return MAX_QUADRATURE_ORDER;
    }
    (n as usize).div_ceil(8).max(2) * 8
}

/// One quadrature node: the offset `h`, `gamma_o = asin h`, and its weight
/// (Gauss-Legendre weight times `cos gamma` times 1/2 for the average).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub h: f32,
    pub gamma_o: f32,
    pub weight: f32,
}

/// Gauss-Legendre nodes and weights on [-1, 1], by Newton's method on the
/// Legendre polynomial P_n (three-term recurrence), in f64. The negative
/// nodes are the exact mirrors of the positive ones.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n.div_ceil(2) {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x).
            let (mut p0, mut p1) = (1.0f64, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pn1) / (x * x - 1.0);
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    let mirrored: Vec<(f64, f64)> = out[..n / 2].iter().rev().map(|&(x, w)| (-x, w)).collect();
    if n % 2 == 1 {
        out.last_mut().expect("n >= 1").0 = 0.0;
    }
    out.extend(mirrored);
    out
}

/// Gauss-Legendre in gamma = asin h on [-pi/2, pi/2], as nodes in h with
/// weights that average over h.
fn quadrature_nodes(order: usize) -> Vec<Node> {
    let half_pi = std::f64::consts::FRAC_PI_2;
    gauss_legendre(order)
        .into_iter()
        .map(|(x, w)| {
            let gamma = half_pi * x;
            let h = gamma.sin() as f32;
            Node {
                h,
                gamma_o: h.clamp(-1.0, 1.0).asin(),
                weight: (0.5 * half_pi * w * gamma.cos()) as f32,
            }
        })
        .collect()
}

/// The far-field model of one material, with its quadrature prepared.
#[derive(Clone, Debug)]
pub struct FarField {
    params: Params,
    lobes: Lobes,
    nodes: Vec<Node>,
    /// `1 / (LogisticCDF(pi) - LogisticCDF(-pi))` as pbrt computes it.
    trim: f32,
}

impl FarField {
    /// Validates `params`; `order` >= 1 Gauss-Legendre nodes in gamma.
    ///
    /// # Errors
    ///
    /// As [`Params::validate`], and [`Error::InvalidQuadratureOrder`] on
    /// `order == 0` or above [`MAX_FAR_FIELD_ORDER`].
    pub fn new(params: &Params, order: usize) -> Result<FarField, Error> {
        params.validate()?;
        if !(1..=MAX_FAR_FIELD_ORDER).contains(&order) {
            return Err(Error::InvalidQuadratureOrder(order));
        }
        let nodes = quadrature_nodes(order);
        let lobes = Lobes::new(params);
        let s = lobes.s;
        Ok(FarField {
            params: params.clone(),
            lobes,
            nodes,
            trim: logistic_cdf(PI, s) - logistic_cdf(-PI, s),
        })
    }

    /// The material parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Quadrature points over the offset `h`.
    pub fn order(&self) -> usize {
        self.nodes.len()
    }

    /// The offsets `h` and weights of the quadrature: the far-field value is
    /// `sum_k weight_k * scattering_local(h_k)` (up to rounding).
    pub fn nodes(&self) -> impl Iterator<Item = (f32, f32)> + '_ {
        self.nodes.iter().map(|n| (n.h, n.weight))
    }

    fn view(&self) -> View<'_> {
        View {
            params: &self.params,
            lobes: &self.lobes,
            nodes: &self.nodes,
            trim: self.trim,
        }
    }

    /// The far field in pbrt-v3's local frame (see [`super::scattering_local`]).
    pub fn eval_local(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.view().eval_local(wo, wi)
    }

    /// The far field for `sin theta_i`, `sin theta_o` and the relative
    /// azimuth `phi` (any sign: the far field is even and 2 pi periodic in phi).
    pub fn eval_angles(&self, sin_theta_i: f32, sin_theta_o: f32, phi: f32) -> Vec3 {
        self.view().eval_angles(sin_theta_i, sin_theta_o, phi)
    }

    /// The far field in world space: `t` the unit tangent, `wi` toward the
    /// light, `wo` toward the viewer (all unit). See [`world_angles`] for the
    /// frame.
    pub fn eval(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        self.view().eval(t, wi, wo)
    }

    /// [`FarField::eval`] over a batch (scalar: the far field is the
    /// reference, not a hot path). `out` is resized to the batch.
    pub fn scattering_batch(&self, samples: &ShadingSamples, out: &mut RgbBuffer) {
        out.resize(samples.len());
        let view = self.view();
        for k in 0..samples.len() {
            let (t, wi, wo) = samples.get(k);
            out.set(k, view.eval(t, wi, wo));
        }
    }

    /// `M_p(theta_i, theta_o)` for p = 0..3 (tilted for p < 3), independent
    /// of `h`.
    pub fn longitudinal(&self, sin_i: f32, cos_i: f32, sin_o: f32, cos_o: f32) -> [f32; 4] {
        self.view().longitudinal(sin_i, cos_i, sin_o, cos_o)
    }

    /// For each `phi` in `phis`: the h-averaged `[A_0 N_0, A_1 N_1, A_2 N_2,
    /// A_3 / (2 pi)]` at `theta_o`. The per-node work that does not depend
    /// on phi (refraction, transmittance, Fresnel) is done once per node.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] (and nothing written) unless `out.len() ==
    /// phis.len()`.
    pub fn azimuthal(
        &self,
        sin_o: f32,
        cos_o: f32,
        phis: &[f32],
        out: &mut [[Vec3; 4]],
    ) -> Result<(), Error> {
        if out.len() != phis.len() {
            return Err(Error::CountMismatch {
                what: "azimuthal terms (one per phi)",
                expected: phis.len(),
                got: out.len(),
            });
        }
        self.view().azimuthal(sin_o, cos_o, phis, out);
        Ok(())
    }
}

/// The borrowed state of a far-field evaluation, shared by [`FarField`]
/// and the allocation-free [`scattering`].
struct View<'a> {
    params: &'a Params,
    lobes: &'a Lobes,
    nodes: &'a [Node],
    trim: f32,
}

impl View<'_> {
    /// The far field in pbrt-v3's local frame (see [`super::scattering_local`]).
    fn eval_local(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let sin_o = wo.x;
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let sin_i = wi.x;
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let phi = wi.z.atan2(wi.y) - wo.z.atan2(wo.y);
        let m = self.longitudinal(sin_i, cos_i, sin_o, cos_o);
        let mut n = [Vec3::ZERO; 4];
        self.azimuthal(sin_o, cos_o, &[phi], std::slice::from_mut(&mut n));
        combine(&m, &n)
    }

    /// The far field for `sin theta_i`, `sin theta_o` and the relative
    /// azimuth `phi` (any sign: the far field is even and 2 pi periodic in phi).
    fn eval_angles(&self, sin_theta_i: f32, sin_theta_o: f32, phi: f32) -> Vec3 {
        let cos_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();
        let cos_o = (1.0 - sin_theta_o * sin_theta_o).max(0.0).sqrt();
        let m = self.longitudinal(sin_theta_i, cos_i, sin_theta_o, cos_o);
        let mut n = [Vec3::ZERO; 4];
        self.azimuthal(sin_theta_o, cos_o, &[phi], std::slice::from_mut(&mut n));
        combine(&m, &n)
    }

    /// The far field in world space: `t` the unit tangent, `wi` toward the
    /// light, `wo` toward the viewer (all unit). See [`world_angles`] for the
    /// frame.
    fn eval(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (sin_i, sin_o, cos_phi) = world_angles(t, wi, wo);
        self.eval_angles(sin_i, sin_o, cos_phi.clamp(-1.0, 1.0).acos())
    }

    /// `M_p(theta_i, theta_o)` for p = 0..3 (tilted for p < 3), independent
    /// of `h`.
    fn longitudinal(&self, sin_i: f32, cos_i: f32, sin_o: f32, cos_o: f32) -> [f32; 4] {
        let mut m = [0.0; 4];
        for (p, m_p) in m.iter_mut().enumerate() {
            let (sin_op, cos_op) = self.lobes.tilt(p, sin_o, cos_o);
            *m_p = mp(cos_i, cos_op, sin_i, sin_op, self.lobes.v[p]);
        }
        m
    }

    /// For each `phi` in `phis`: the h-averaged `[A_0 N_0, A_1 N_1, A_2 N_2,
    /// A_3 / (2 pi)]` at `theta_o`. The per-node work that does not depend
    /// on phi (refraction, transmittance, Fresnel) is done once per node.
    fn azimuthal(&self, sin_o: f32, cos_o: f32, phis: &[f32], out: &mut [[Vec3; 4]]) {
        let eta = self.params.eta;
        let sin_t = sin_o / eta;
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        let etap = (eta * eta - sin_o * sin_o).sqrt() / cos_o;
        for o in out.iter_mut() {
            *o = [Vec3::ZERO; 4];
        }
        // Nodes come in mirrored pairs (k, n-1-k) with h and -h: refraction
        // depth, transmittance and Fresnel depend on h^2 only, so they are
        // computed once per pair; gamma_o and gamma_t change sign.
        let n = self.nodes.len();
        for k in 0..n.div_ceil(2) {
            let node = &self.nodes[k];
            let sin_gamma_t = node.h / etap;
            let cos_gamma_t = (1.0 - sin_gamma_t * sin_gamma_t).max(0.0).sqrt();
            let gamma_t = sin_gamma_t.clamp(-1.0, 1.0).asin();
            let transmittance = exp3(-self.params.sigma_a * (2.0 * cos_gamma_t / cos_t));
            let a = ap(cos_o, eta, node.h, transmittance);
            let mirror = &self.nodes[n - 1 - k];
            let pair: &[(&Node, f32)] = if n - 1 - k == k {
                &[(node, gamma_t)]
            } else {
                &[(node, gamma_t), (mirror, -gamma_t)]
            };
            for &(nd, g_t) in pair {
                let centres = [0, 1, 2].map(|p| super::azimuthal::phi(p, nd.gamma_o, g_t));
                for (&phi, o) in phis.iter().zip(out.iter_mut()) {
                    for p in 0..P_MAX {
                        let n_p = logistic(wrap(phi - centres[p]), self.lobes.s) / self.trim;
                        o[p] += a[p] * (n_p * nd.weight);
                    }
                    o[P_MAX] += a[P_MAX] * (nd.weight / (2.0 * PI));
                }
            }
        }
    }
}

/// `sum_p M_p * [A_p N_p]` in a fixed order.
#[inline]
pub(crate) fn combine(m: &[f32; 4], n: &[Vec3; 4]) -> Vec3 {
    n[0] * m[0] + n[1] * m[1] + n[2] * m[2] + n[3] * m[3]
}

/// `(sin theta_i, sin theta_o, cos phi)` of world directions: `sin theta =
/// w . t`; `cos phi` is the cosine of the angle between the projections of
/// `wi` and `wo` on the normal plane. This is pbrt's frame with x = t and
/// the normal chosen so that `wo` has azimuth 0 (y = the normalised normal
/// plane part of `wo`, z = x cross y), so pbrt's `phi_i - phi_o` is the
/// relative azimuth; its sign does not matter because the far field is even
/// in phi. Where `wi` or `wo` is parallel to `t` the azimuth is undefined
/// and `cos phi` comes out 0.
#[inline]
pub fn world_angles(t: Vec3, wi: Vec3, wo: Vec3) -> (f32, f32, f32) {
    let sin_i = wi.dot(t);
    let sin_o = wo.dot(t);
    let pi_ = wi - t * sin_i;
    let po = wo - t * sin_o;
    let len2 = pi_.length_squared() * po.length_squared();
    let cos_phi = pi_.dot(po) / len2.max(1e-30).sqrt();
    (sin_i.clamp(-1.0, 1.0), sin_o.clamp(-1.0, 1.0), cos_phi)
}

/// The far-field form of pbrt-v3's hair model in world space, for
/// comparison with `marschner::scattering(params, t, wi, wo)`:
/// `1/2 * integral over h in [-1, 1] of scattering_local`, with
/// [`recommended_order`] nodes (their nodes are computed once per order
/// and cached; no allocation after that). `t` unit tangent, `wi` unit toward
/// the light, `wo` unit toward the viewer.
///
/// Note the cosine: like pbrt's `f * |cos|`, this already contains the
/// projected-solid-angle factor (outgoing radiance = integral of
/// `L_i * scattering` over the sphere of `wi`; Marschner's `S` needs
/// `* cos theta_i` for the same integral).
///
/// Derives the material's constants on each call; for many samples build
/// a [`FarField`] once. Invalid parameters give NaN.
pub fn scattering(params: &Params, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
    const SLOTS: usize = MAX_QUADRATURE_ORDER / 8;
    static NODES: [OnceLock<Vec<Node>>; SLOTS] = [const { OnceLock::new() }; SLOTS];
    if params.validate().is_err() {
        return Vec3::NAN;
    }
    let order = recommended_order(params);
    let nodes = NODES[order / 8 - 1].get_or_init(|| quadrature_nodes(order));
    let lobes = Lobes::new(params);
    View {
        params,
        lobes: &lobes,
        nodes,
        trim: logistic_cdf(PI, lobes.s) - logistic_cdf(-PI, lobes.s),
    }
    .eval(t, wi, wo)
}
