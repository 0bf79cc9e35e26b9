//! The path tracer: pbrt-v3's hair BSDF sampled at every fibre hit, at
//! that hit's own offset `h`, with next-event estimation to a directional
//! light and a uniform environment for escaped rays.
//!
//! One path from `(origin, dir)` (unit `dir` after normalisation):
//!
//! ```text
//! L = 0, beta = 1
//! for k = 1, 2, ...:
//!     hit = nearest fibre (excluding the previous hit's segment)
//!     no hit:            L += beta * L_env; stop
//!     k > max_depth:     stop
//!     frame at the hit:  x = tangent, y = wo's normal part, z = x cross y (wo = -dir)
//!     light unshadowed:  L += beta * f(h, wo, l) * E     (f = scattering_local, f |cos| in pbrt)
//!     wi ~ pbrt's Sample_f(h, wo); beta *= f(h, wo, wi) / pdf(wi)
//!     k > 3 and max(beta) < 0.99: Russian roulette, q = max(0.05, 1 - max(beta))
//!     continue from the hit point along wi
//! ```
//!
//! So `max_depth` is the largest number of scattering events on a path:
//! environment light reaches the camera after at most `max_depth`
//! scatterings, and the light after at most `max_depth` (its last one at the
//! next-event estimate). Light is never hit by sampled rays (a directional
//! light has no area), so there is no double counting and no MIS.
//!
//! **Leaving the fibre.** The continuation ray and the shadow ray start at
//! the hit point and ignore the segment just hit, and any entry into
//! another capsule at a point inside it (see
//! [`FibreScene::intersect_excluding`]): the BSDF already includes the
//! internal paths of that fibre (TT, TRT, ...), so the ray must pass through
//! it. Without the exclusion a transmitted ray would hit the fibre's inner
//! side or re-enter it at once; with it, a single straight fibre scatters
//! every path exactly once (tested), and the white furnace stays at 1.
//!
//! **Shadows.** The shadow ray is binary: any fibre between the hit and the
//! light blocks it. Light that reaches a hit through other fibres arrives
//! via the sampled paths (they scatter at those fibres), never as a
//! transmittance through them.

use super::fibres::FibreScene;
use crate::pbrt::{sample, scattering_local_with, Lobes, Params};
use crate::Error;
use coif_base::rng::SplitMix64;
use glam::{DVec3, Vec3};

/// A directional light: unit direction toward the light and the
/// irradiance it delivers on a surface facing it (RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Direction toward the light (normalised by [`PathTracer::new`]).
    pub to_light: Vec3,
    /// Irradiance, RGB, finite and non-negative.
    pub irradiance: Vec3,
}

/// The largest `max_depth` accepted.
pub const MAX_DEPTH_LIMIT: usize = 1 << 20;

/// Scatterings after which Russian roulette may end a path (pbrt's
/// `bounces > 3`).
pub const ROULETTE_AFTER: usize = 3;

/// Russian roulette applies once the largest channel of the path's
/// throughput falls below this. pbrt-v3 uses 1; a white fibre's weights are
/// 1 only up to rounding (a few 1e-5), so at 1 the roulette would end 5 %
/// of white paths at every scattering and add variance (unbiased, but the
/// white furnace's standard error rose from 0 to 0.2-0.3 % with it).
pub const ROULETTE_THRESHOLD: f32 = 0.99;

/// The path tracer's settings: material, lights and depth.
#[derive(Clone, Debug)]
pub struct PathTracer {
    params: Params,
    lobes: Lobes,
    light: Option<DirectionalLight>,
    environment: Vec3,
    max_depth: usize,
}

/// One traced path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSample {
    /// The path's radiance estimate.
    pub radiance: Vec3,
    /// Scattering events on the path.
    pub scatterings: usize,
}

/// The mean of many paths through one camera ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadianceEstimate {
    /// Mean radiance over the paths.
    pub mean: Vec3,
    /// Standard error of that mean, per channel (`sqrt(var / n)`, the
    /// unbiased sample variance; 0 for one path).
    pub standard_error: Vec3,
    /// Mean number of scattering events per path.
    pub mean_scatterings: f32,
    /// The most scattering events on one path.
    pub max_scatterings: usize,
}

/// The generator seed of ray `index` under `seed`: two rounds of the
/// SplitMix64 finaliser over `seed` and `index`, so that each ray's paths
/// depend only on `(seed, index)` (not on threads or order).
pub fn ray_seed(seed: u64, index: usize) -> u64 {
    let mut a = SplitMix64::new(seed);
    let s = a.next_u64();
    let mut b = SplitMix64::new(s ^ (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    b.next_u64()
}

impl PathTracer {
    /// Validates the material ([`Params::validate`]), the light (finite,
    /// non-zero direction; finite non-negative irradiance), the environment
    /// radiance (finite, non-negative) and `max_depth <= MAX_DEPTH_LIMIT`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming the first bad value
    /// (`"to_light"`, `"irradiance"`, `"environment"`, `"max_depth"`, or a
    /// material parameter).
    pub fn new(
        params: &Params,
        light: Option<DirectionalLight>,
        environment: Vec3,
        max_depth: usize,
    ) -> Result<PathTracer, Error> {
        params.validate()?;
        let bad_rgb = |name, v: Vec3| {
            v.to_array()
                .into_iter()
                .find(|c| !(c.is_finite() && *c >= 0.0))
                .map(|value| Error::InvalidParameter { name, value })
        };
        let light = match light {
            Some(l) => {
                let to_light = l.to_light.try_normalize().ok_or(Error::InvalidParameter {
                    name: "to_light",
                    value: l.to_light.length(),
                })?;
                if let Some(e) = bad_rgb("irradiance", l.irradiance) {
                    return Err(e);
                }
                Some(DirectionalLight {
                    to_light,
                    irradiance: l.irradiance,
                })
            }
            None => None,
        };
        if let Some(e) = bad_rgb("environment", environment) {
            return Err(e);
        }
        if max_depth > MAX_DEPTH_LIMIT {
            return Err(Error::InvalidParameter {
                name: "max_depth",
                value: max_depth as f32,
            });
        }
        Ok(PathTracer {
            params: params.clone(),
            lobes: Lobes::new(params),
            light,
            environment,
            max_depth,
        })
    }

    /// The material.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The largest number of scattering events on a path.
    pub fn max_depth(&self) -> usize {
        self.max_depth
    }

    /// One path's radiance toward `-dir` from `origin` (see the module
    /// documentation). NaN for non-finite or zero `origin`/`dir`.
    pub fn radiance(
        &self,
        scene: &FibreScene,
        origin: Vec3,
        dir: Vec3,
        rng: &mut SplitMix64,
    ) -> Vec3 {
        self.trace(scene, origin, dir, rng).radiance
    }

    /// [`PathTracer::radiance`] with the path's number of scatterings.
    pub fn trace(
        &self,
        scene: &FibreScene,
        origin: Vec3,
        dir: Vec3,
        rng: &mut SplitMix64,
    ) -> PathSample {
        let (Some(mut d), true) = (dir.try_normalize(), origin.is_finite()) else {
            return PathSample {
                radiance: Vec3::NAN,
                scatterings: 0,
            };
        };
        let mut o = origin;
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut exclude = None;
        let mut k = 0usize;
        loop {
            let Some(hit) = scene.intersect_excluding(o, d, f32::INFINITY, exclude) else {
                radiance += beta * self.environment;
                break;
            };
            if k == self.max_depth {
                break;
            }
            k += 1;
            // pbrt's local frame at the hit: x = tangent, y = wo's normal
            // part, z = x cross y (as pbrt::local_directions).
            let t = hit.tangent;
            let wo = -d;
            let y = (wo - t * wo.dot(t))
                .try_normalize()
                .unwrap_or_else(|| t.any_orthonormal_vector());
            let z = t.cross(y);
            let to_local = |w: Vec3| Vec3::new(w.dot(t), w.dot(y), w.dot(z));
            let wo_l = to_local(wo);

            if let Some(light) = &self.light {
                let f = scattering_local_with(
                    &self.lobes,
                    &self.params,
                    hit.h,
                    wo_l,
                    to_local(light.to_light),
                );
                if f.max_element() > 0.0
                    && !scene.occluded_excluding(
                        hit.point,
                        light.to_light,
                        f32::INFINITY,
                        Some(hit.segment),
                    )
                {
                    radiance += beta * f * light.irradiance;
                }
            }

            let u = [
                rng.next_f32(),
                rng.next_f32(),
                rng.next_f32(),
                rng.next_f32(),
            ];
            let s = sample(&self.lobes, &self.params, hit.h, wo_l, u);
            if !(s.pdf > 0.0 && s.weight.is_finite()) || s.weight.max_element() <= 0.0 {
                break;
            }
            beta *= s.weight;
            let wi = (t * s.wi.x + y * s.wi.y + z * s.wi.z).normalize_or_zero();
            if wi == Vec3::ZERO {
                break;
            }
            let m = beta.max_element();
            if k > ROULETTE_AFTER && m < ROULETTE_THRESHOLD {
                let q = (1.0 - m).max(0.05);
                if rng.next_f32() < q {
                    break;
                }
                beta /= 1.0 - q;
            }
            o = hit.point;
            d = wi;
            exclude = Some(hit.segment);
        }
        PathSample {
            radiance,
            scatterings: k,
        }
    }

    /// `paths_per_ray` paths through each ray `(origin, dir)`, ray `i`'s
    /// generator seeded with [`ray_seed`]`(seed, i)`: the result for a ray
    /// depends only on the scene, the tracer, the ray, `seed` and `i`.
    /// Runs on the calling thread.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] (`"paths_per_ray"`) if it is 0.
    pub fn estimate(
        &self,
        scene: &FibreScene,
        rays: &[(Vec3, Vec3)],
        paths_per_ray: usize,
        seed: u64,
    ) -> Result<Vec<RadianceEstimate>, Error> {
        self.estimate_threaded(scene, rays, paths_per_ray, seed, 1)
    }

    /// [`PathTracer::estimate`] on `threads` scoped threads (0 counts as 1),
    /// each taking a contiguous share of the rays: the same bytes for any
    /// thread count, since every ray has its own generator.
    ///
    /// # Errors
    ///
    /// As [`PathTracer::estimate`].
    pub fn estimate_threaded(
        &self,
        scene: &FibreScene,
        rays: &[(Vec3, Vec3)],
        paths_per_ray: usize,
        seed: u64,
        threads: usize,
    ) -> Result<Vec<RadianceEstimate>, Error> {
        if paths_per_ray == 0 {
            return Err(Error::InvalidParameter {
                name: "paths_per_ray",
                value: 0.0,
            });
        }
        let empty = RadianceEstimate {
            mean: Vec3::ZERO,
            standard_error: Vec3::ZERO,
            mean_scatterings: 0.0,
            max_scatterings: 0,
        };
        let mut out = vec![empty; rays.len()];
        let threads = threads.clamp(1, rays.len().max(1));
        let chunk = rays.len().div_ceil(threads).max(1);
        let run = |first: usize, rays: &[(Vec3, Vec3)], out: &mut [RadianceEstimate]| {
            for (j, (&(o, d), e)) in rays.iter().zip(out.iter_mut()).enumerate() {
                *e = self.estimate_one(scene, o, d, paths_per_ray, ray_seed(seed, first + j));
            }
        };
        if threads == 1 {
            run(0, rays, &mut out);
        } else {
            std::thread::scope(|scope| {
                for (c, (r, o)) in rays.chunks(chunk).zip(out.chunks_mut(chunk)).enumerate() {
                    let run = &run;
                    scope.spawn(move || run(c * chunk, r, o));
                }
            });
        }
        Ok(out)
    }

    fn estimate_one(
        &self,
        scene: &FibreScene,
        origin: Vec3,
        dir: Vec3,
        paths: usize,
        seed: u64,
    ) -> RadianceEstimate {
        let mut rng = SplitMix64::new(seed);
        let (mut s1, mut s2) = (DVec3::ZERO, DVec3::ZERO);
        let (mut scat, mut max_scat) = (0u64, 0usize);
        for _ in 0..paths {
            let p = self.trace(scene, origin, dir, &mut rng);
            let x = p.radiance.as_dvec3();
            s1 += x;
            s2 += x * x;
            scat += p.scatterings as u64;
            max_scat = max_scat.max(p.scatterings);
        }
        let n = paths as f64;
        let mean = s1 / n;
        let standard_error = if paths > 1 {
            ((s2 - s1 * mean).max(DVec3::ZERO) / (n - 1.0) / n).map(f64::sqrt)
        } else {
            DVec3::ZERO
        };
        RadianceEstimate {
            mean: mean.as_vec3(),
            standard_error: standard_error.as_vec3(),
            mean_scatterings: (scat as f64 / n) as f32,
            max_scatterings: max_scat,
        }
    }
}
