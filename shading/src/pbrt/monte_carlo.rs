//! pbrt-v3's exact per-`h` BSDF used the way pbrt uses it: a renderer
//! tracing one camera ray through a fibre hits it at a random offset `h`
//! and evaluates [`super::scattering_local`] there, which makes every ray
//! a one-sample Monte Carlo estimate of the far field
//! `1/2 * integral over h in [-1, 1] of scattering_local(h)`
//! (d'Eon et al. 2011, section 4; Chiang et al. 2016, section 4.1).
//!
//! [`scattering_monte_carlo`] takes `n` stratified (jittered) offsets per
//! shading point, `h_k = -1 + 2 (k + u_k) / n` with `u_k` uniform in
//! `[0, 1)`, and averages: an unbiased estimate whose variance falls with
//! `n` (at least as fast as `1/n`; faster where the integrand is smooth).
//! Scalar only: the exact model is pbrt's reference path, not a hot path.

use super::params::{Lobes, Params};
use super::scattering_local_with;
use crate::{RgbBuffer, ShadingSamples};
use coif_base::rng::SplitMix64;
use glam::Vec3;

/// `(wo, wi)` in pbrt-v3's local frame for world directions: x = `t`, y =
/// the normalised part of `wo` normal to `t` (so `wo` has azimuth 0, as in
/// [`super::world_angles`]), z = x cross y. Where `wo` is parallel to `t`
/// any normal serves as y.
#[inline]
pub fn local_directions(t: Vec3, wi: Vec3, wo: Vec3) -> (Vec3, Vec3) {
    let po = wo - t * wo.dot(t);
    let y = po
        .try_normalize()
        .unwrap_or_else(|| t.any_orthonormal_vector());
    let z = t.cross(y);
    let to_local = |w: Vec3| Vec3::new(w.dot(t), w.dot(y), w.dot(z));
    (to_local(wo), to_local(wi))
}

/// The far field estimated from `h_samples` (at least 1) stratified
/// offsets drawn from `rng`: `1/n sum_k scattering_local(h_k)`. World
/// directions as in [`super::FarField::eval`] (`t` unit tangent, `wi`
/// toward the light, `wo` toward the viewer). NaN input gives NaN.
pub fn scattering_monte_carlo(
    lobes: &Lobes,
    params: &Params,
    t: Vec3,
    wi: Vec3,
    wo: Vec3,
    h_samples: usize,
    rng: &mut SplitMix64,
) -> Vec3 {
    let n = h_samples.max(1);
    let (wo_l, wi_l) = local_directions(t, wi, wo);
    let mut sum = Vec3::ZERO;
    for k in 0..n {
        let h = -1.0 + 2.0 * (k as f32 + rng.next_f32()) / n as f32;
        sum += scattering_local_with(lobes, params, h, wo_l, wi_l);
    }
    sum / n as f32
}

/// [`scattering_monte_carlo`] over a batch, offsets from one generator
/// seeded with `seed`. `out` is resized to the batch; allocates nothing
/// once it has that size.
pub fn scattering_batch_monte_carlo(
    params: &Params,
    samples: &ShadingSamples,
    h_samples: usize,
    seed: u64,
    out: &mut RgbBuffer,
) {
    out.resize(samples.len());
    let lobes = Lobes::new(params);
    let mut rng = SplitMix64::new(seed);
    for k in 0..samples.len() {
        let (t, wi, wo) = samples.get(k);
        out.set(
            k,
            scattering_monte_carlo(&lobes, params, t, wi, wo, h_samples, &mut rng),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::{quality::random_configurations, FarField};

    #[test]
    fn local_frame_puts_wo_at_azimuth_zero_and_keeps_angles() {
        for (t, wi, wo) in random_configurations(50, 3) {
            let (wo_l, wi_l) = local_directions(t, wi, wo);
            assert!(wo_l.z.abs() < 1e-5 && wo_l.y >= 0.0, "{wo_l}");
            assert!((wo_l.x - wo.dot(t)).abs() < 1e-6);
            assert!((wi_l.x - wi.dot(t)).abs() < 1e-6);
            assert!((wi_l.length() - 1.0).abs() < 1e-5);
            assert!((wi_l.dot(wo_l) - wi.dot(wo)).abs() < 1e-5);
        }
    }

    #[test]
    fn many_offsets_converge_to_the_far_field() {
        let params = Params::default();
        let lobes = Lobes::new(&params);
        let far = FarField::new(&params, 512).unwrap();
        let mut rng = SplitMix64::new(11);
        let (mut err, mut norm) = (0.0f64, 0.0f64);
        for (t, wi, wo) in random_configurations(40, 9) {
            let r = far.eval(t, wi, wo).as_dvec3();
            let e = scattering_monte_carlo(&lobes, &params, t, wi, wo, 4096, &mut rng).as_dvec3();
            err += (e - r).length_squared();
            norm += r.length_squared();
        }
        let rel = (err / norm).sqrt();
        assert!(rel < 0.01, "relative RMS {rel}");
    }

    #[test]
    fn error_against_the_far_field_falls_with_more_offsets() {
        let params = Params::default();
        let e: Vec<f32> = [1, 4, 16, 64]
            .iter()
            .map(|&n| crate::pbrt::quality::monte_carlo_error(&params, n, 300, 5).unwrap())
            .collect();
        assert!(e.windows(2).all(|w| w[1] < w[0]), "{e:?}");
        // One offset per point is a noisy estimate of the same mean.
        assert!(e[0] > 0.1 && e[3] < 0.2 * e[0], "{e:?}");
    }

    #[test]
    fn nan_direction_gives_nan_and_batch_is_per_sample() {
        let params = Params::default();
        let mut samples = ShadingSamples::with_capacity(2);
        samples.push(Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y);
        samples.push(Vec3::X, Vec3::Y, Vec3::new(0.0, 0.6, 0.8));
        let mut out = RgbBuffer::zeros(0);
        scattering_batch_monte_carlo(&params, &samples, 4, 1, &mut out);
        assert!(out.get(0).is_nan());
        assert!(out.get(1).is_finite() && out.get(1).max_element() > 0.0);
    }
}
