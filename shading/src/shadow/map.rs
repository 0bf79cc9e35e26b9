//! The opacity shadow map: storage, build (rasterise, then prefix-sum along
//! depth) and the scalar lookup.

use super::layers::{Layering, DEEP_SPAN};
use super::light_frame::{LightFrame, MapPlacement};
use super::raster::for_each_sample;
use super::settings::{ShadowMode, ShadowSettings};
use crate::Error;
use glam::Vec3;

/// An opacity shadow map of hair for one directional light.
///
/// Storage (Nalu's packing, GPU Gems 2 ch. 23: four slices per RGBA texel,
/// one RGBA map per group of four slices):
/// `texels[(s / 4) * n^2 + y * n + x][s % 4]` is the opacity `S[s]`
/// accumulated in front of plane `s` of texel `(x, y)`, in
/// `G = ceil(layers / 4)` RGBA maps of `n x n` texels one after another.
/// Hair at similar depths then writes into one map of `16 n^2` bytes
/// (1 MiB at 256^2) rather than all of them, and the two planes a lookup
/// reads per texel are usually in one RGBA texel, with the texel beside it
/// in the same cache line. Deep mode adds the depth map
/// `z0[y * n + x]`, the light-space depth of the first hair in the texel.
///
/// Allocated once by [`OpacityShadowMap::new`]; [`OpacityShadowMap::build`]
/// rewrites it in place without allocating.
#[derive(Clone, Debug)]
pub struct OpacityShadowMap {
    pub(super) settings: ShadowSettings,
    pub(super) texels: Vec<[f32; 4]>,
    pub(super) first_depth: Vec<f32>,
    pub(super) frame: LightFrame,
    pub(super) placement: MapPlacement,
    pub(super) layering: Layering,
    /// `alpha = 1 - exp(-k)`, the opacity of one hair: the lookup's
    /// `T = exp(-alpha sigma)` (see [`OpacityShadowMap::transmittance`]).
    pub(super) hair_opacity: f32,
    /// False until a build saw at least one finite segment: every lookup
    /// then answers 1 (fully lit).
    pub(super) ready: bool,
}

impl OpacityShadowMap {
    /// Allocates the map for these settings (once; no per-frame allocation
    /// afterwards). Fails when [`ShadowSettings::validate`] does.
    pub fn new(settings: ShadowSettings) -> Result<OpacityShadowMap, Error> {
        settings.validate()?;
        let n = settings.resolution;
        let groups = settings.groups();
        let frame = LightFrame::new(Vec3::Z).expect("+z is a valid light direction");
        Ok(OpacityShadowMap {
            texels: vec![[0.0; 4]; n * n * groups],
            first_depth: match settings.mode {
                ShadowMode::Slices => Vec::new(),
                ShadowMode::Deep => vec![0.0; n * n],
            },
            frame,
            placement: MapPlacement::cover(Vec3::ZERO, Vec3::ZERO, 0.0, n),
            layering: Layering::even(settings.layers, 1.0),
            ready: false,
            hair_opacity: -(-settings.density).exp_m1(),
            settings,
        })
    }

    /// The settings the map was made with.
    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    /// The light frame of the last build.
    pub fn frame(&self) -> &LightFrame {
        &self.frame
    }

    /// Where the last build placed the map in light space (footprint,
    /// texel size, near and far depth).
    pub fn placement(&self) -> &MapPlacement {
        &self.placement
    }

    /// `alpha = 1 - exp(-density)`, the opacity of one hair, which scales
    /// the stored count in the lookup.
    pub fn hair_opacity(&self) -> f32 {
        self.hair_opacity
    }

    /// Whether the last build found any hair (otherwise every lookup is 1).
    pub fn is_ready(&self) -> bool {
        self.ready
    }

    /// The cumulative opacity `S[s]` stored for plane `s` of texel `(x, y)`
    /// (0 outside the map).
    pub fn stored_opacity(&self, x: usize, y: usize, s: usize) -> f32 {
        let n = self.settings.resolution;
        if x >= n || y >= n || s >= self.settings.layers {
            return 0.0;
        }
        self.texels[(s / 4) * n * n + y * n + x][s % 4]
    }

    /// Rebuilds the map for a directional light shining along `light_dir`
    /// (from the light toward the scene; normalised here) from hair
    /// polylines: `points` holds `verts_per_strand` points per strand,
    /// strand after strand (a trailing partial strand is ignored).
    /// Segments with a non-finite end are skipped. No allocation.
    ///
    /// Steps: light frame; light-space bounds of the finite points (the
    /// footprint in x, y padded by the hair radius and a texel, and
    /// `[near, far]` in z); deep mode only, the depth map `z0` (the nearest
    /// sample splatted into each texel); every segment's samples deposit
    /// their coverage into the interval of planes they lie in; a prefix sum
    /// along depth per texel makes the opacity cumulative.
    pub fn build(&mut self, light_dir: Vec3, points: &[Vec3], verts_per_strand: usize) {
        self.ready = false;
        self.texels.fill([0.0; 4]);
        let Some(frame) = LightFrame::new(light_dir) else {
            return;
        };
        self.frame = frame;
        if verts_per_strand < 2 {
            return;
        }
        let used = points.len() - points.len() % verts_per_strand;
        let points = &points[..used];

        let mut min = Vec3::splat(f32::INFINITY);
        let mut max = Vec3::splat(f32::NEG_INFINITY);
        // Stays inverted (min > max) when no point is finite.
        for p in points.iter().filter(|p| p.is_finite()) {
            let l = frame.to_light(*p);
            min = min.min(l);
            max = max.max(l);
        }
        if min.x > max.x {
            return;
        }
        let n = self.settings.resolution;
        let r = self.settings.hair_radius;
        self.placement = MapPlacement::cover(min, max, r, n);
        let pl = &self.placement;
        let usable = [pl.inv_texel, pl.x0, pl.y0, max.z - min.z];
        if !usable.iter().all(|v| v.is_finite()) {
            // Finite but astronomically large coordinates: no usable map.
            return;
        }
        let depth = max.z - min.z;
        self.layering = match self.settings.mode {
            ShadowMode::Slices => Layering::even(self.settings.layers, depth),
            ShadowMode::Deep => Layering::quadratic(self.settings.layers, depth * DEEP_SPAN),
        };

        let placement = self.placement;
        let layering = self.layering;
        let nn = n * n;
        // The four texels of a splat, relative to its lower-left one.
        let offsets = [0, 1, n, n + 1];
        match self.settings.mode {
            ShadowMode::Slices => {
                let texels = &mut self.texels;
                for_each_sample(
                    &frame,
                    &placement,
                    n,
                    r,
                    points,
                    verts_per_strand,
                    |sp, z| {
                        let (slice, _) = layering.locate(z - placement.near);
                        let plane = &mut texels[(slice / 4) * nn..(slice / 4 + 1) * nn];
                        for (o, w) in offsets.iter().zip(sp.weights) {
                            plane[sp.t0 + o][slice % 4] += w;
                        }
                    },
                );
            }
            ShadowMode::Deep => {
                let z0 = &mut self.first_depth;
                z0.fill(f32::INFINITY);
                for_each_sample(
                    &frame,
                    &placement,
                    n,
                    r,
                    points,
                    verts_per_strand,
                    |sp, z| {
                        for o in offsets {
                            let d = &mut z0[sp.t0 + o];
                            *d = d.min(z);
                        }
                    },
                );
                for z in z0.iter_mut().filter(|z| **z == f32::INFINITY) {
                    *z = placement.near;
                }
                let z0 = &self.first_depth;
                let texels = &mut self.texels;
                for_each_sample(
                    &frame,
                    &placement,
                    n,
                    r,
                    points,
                    verts_per_strand,
                    |sp, z| {
                        for (o, w) in offsets.iter().zip(sp.weights) {
                            let t = sp.t0 + o;
                            let (slice, _) = layering.locate(z - z0[t]);
                            texels[(slice / 4) * nn + t][slice % 4] += w;
                        }
                    },
                );
            }
        }
        let layers = self.settings.layers;
        for t in 0..nn {
            let mut sum = 0.0;
            for s in 0..layers {
                let texel = &mut self.texels[(s / 4) * nn + t][s % 4];
                sum += *texel;
                *texel = sum;
            }
        }
        self.ready = true;
    }

    /// Transmittance toward the light, in [0, 1] (1 = fully lit), at a
    /// point: `T = exp(-alpha sigma)` (Kim & Neumann 2001, eq. 1), where
    /// sigma, the texel-averaged number of hairs in front, is bilinear over
    /// the four texels around the point and, in each, linear in depth
    /// between its planes (see [`super::layers`]), and `alpha = 1 - exp(-k)`
    /// is the opacity of one hair (`k = density`). Why `alpha` and not `k`:
    /// when the hairs in front of a texel lie at random (Poisson) positions
    /// with mean count sigma, the mean of the exact `exp(-k n)` over the
    /// texel is `exp(-sigma (1 - exp(-k)))`; `exp(-k sigma)` would
    /// over-shadow (Jensen's inequality), by 0.10 in mean on a draped head. Points outside
    /// the map's footprint or in front of the hair are lit (1); behind the
    /// last plane they get the last plane's opacity. A non-finite point, or
    /// any point before a build found hair, gets 1.
    pub fn transmittance(&self, p: Vec3) -> f32 {
        if !self.ready || !p.is_finite() {
            return 1.0;
        }
        let l = self.frame.to_light(p);
        let (u, v) = self.placement.texel_coords(l.x, l.y);
        let (fu, fv) = (u.floor(), v.floor());
        let (fx, fy) = (u - fu, v - fv);
        let (i0, j0) = (fu as isize, fv as isize);
        let s00 = self.texel_sigma(i0, j0, l.z);
        let s10 = self.texel_sigma(i0 + 1, j0, l.z);
        let s01 = self.texel_sigma(i0, j0 + 1, l.z);
        let s11 = self.texel_sigma(i0 + 1, j0 + 1, l.z);
        let sigma = (s00 * (1.0 - fx) + s10 * fx) * (1.0 - fy) + (s01 * (1.0 - fx) + s11 * fx) * fy;
        (-self.hair_opacity * sigma).exp()
    }

    /// Scalar twin of [`OpacityShadowMap::transmittance_batch`]: one
    /// [`OpacityShadowMap::transmittance`] per point, into `out` (same
    /// length; extra entries of either are ignored).
    pub fn transmittance_batch_scalar(&self, points: &[Vec3], out: &mut [f32]) {
        for (o, p) in out.iter_mut().zip(points) {
            *o = self.transmittance(*p);
        }
    }

    /// Texel index of `(i, j)`, or `None` outside the map.
    #[inline(always)]
    pub(super) fn texel_index(&self, i: isize, j: isize) -> Option<usize> {
        let n = self.settings.resolution;
        (i >= 0 && j >= 0 && (i as usize) < n && (j as usize) < n)
            .then(|| j as usize * n + i as usize)
    }

    /// The depth where texel `t`'s planes start: `near` or `z0(t)`.
    #[inline(always)]
    pub(super) fn base_depth(&self, t: usize) -> f32 {
        match self.settings.mode {
            ShadowMode::Slices => self.placement.near,
            ShadowMode::Deep => self.first_depth[t],
        }
    }

    /// Stored opacities `(S[s - 1], S[s])` of texel `t` (`S[-1] = 0`).
    #[inline(always)]
    pub(super) fn plane_pair(&self, t: usize, s: usize) -> (f32, f32) {
        let nn = self.settings.resolution * self.settings.resolution;
        let next = self.texels[(s / 4) * nn + t][s % 4];
        let prev = if s == 0 {
            0.0
        } else {
            self.texels[((s - 1) / 4) * nn + t][(s - 1) % 4]
        };
        (prev, next)
    }

    /// Opacity in front of depth `z` in texel `(i, j)`: linear between its
    /// planes; 0 outside the map.
    #[inline(always)]
    fn texel_sigma(&self, i: isize, j: isize, z: f32) -> f32 {
        let Some(t) = self.texel_index(i, j) else {
            return 0.0;
        };
        let (s, f) = self.layering.locate(z - self.base_depth(t));
        let (prev, next) = self.plane_pair(t, s);
        prev + f * (next - prev)
    }
}
