//! The opacity shadow map: storage, the steps both builds share
//! ([`OpacityShadowMap::prepare`]) and the one-point lookup
//! [`OpacityShadowMap::transmittance`]. The SIMD build is in `build.rs`
//! (scalar twin `scalar/build.rs`), the batch lookup in `lookup.rs`
//! (scalar twin `scalar/lookup.rs`).

use super::layers::{Layering, DEEP_SPAN};
use super::light_frame::{LightFrame, MapPlacement};
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
/// Allocated once by [`OpacityShadowMap::new`]; [`OpacityShadowMap::build`] (or
/// [`scalar::build`](super::scalar::build)) rewrites it in place without allocating.
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
    ///
    /// # Errors
    ///
    /// As [`ShadowSettings::validate`].
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

    /// The first depth `z0` of texel `(x, y)` (deep mode: the light-space
    /// depth where its layers start); `None` in slices mode or outside the
    /// map.
    pub fn first_depth(&self, x: usize, y: usize) -> Option<f32> {
        let n = self.settings.resolution;
        (x < n && y < n)
            .then(|| self.first_depth.get(y * n + x).copied())
            .flatten()
    }

    /// The steps both builds share before rasterising: clears the map, sets
    /// the light frame, takes the light-space bounds of the finite points
    /// (with `bounds`, scalar or SIMD), places the map and its layering.
    /// Returns the whole strands of `points`, or `None` when there is no
    /// usable map (zero or non-finite light, fewer than two vertices per
    /// strand, no finite point, coordinates so large that light space
    /// overflows).
    pub(super) fn prepare<'p>(
        &mut self,
        light_dir: Vec3,
        points: &'p [Vec3],
        verts_per_strand: usize,
        bounds: LightBounds,
    ) -> Option<&'p [Vec3]> {
        let used = points.len() - points.len() % verts_per_strand.max(1);
        let points = &points[..used];
        self.prepare_with(light_dir, verts_per_strand, |frame| bounds(frame, points))
            .then_some(points)
    }

    /// [`Self::prepare`] for any hair layout: `bounds` gives the
    /// light-space bounds of its finite points in the new light frame.
    /// False when there is no usable map.
    pub(super) fn prepare_with(
        &mut self,
        light_dir: Vec3,
        verts_per_strand: usize,
        bounds: impl FnOnce(&LightFrame) -> Option<(Vec3, Vec3)>,
    ) -> bool {
        // 1. Clear, light frame, bounds, placement and layering.
        self.ready = false;
        self.texels.fill([0.0; 4]);
        let Some(frame) = LightFrame::new(light_dir) else {
            return false;
        };
        self.frame = frame;
        if verts_per_strand < 2 {
            return false;
        }
        let Some((min, max)) = bounds(&self.frame) else {
            return false;
        };
        let n = self.settings.resolution;
        self.placement = MapPlacement::cover(min, max, self.settings.hair_radius, n);
        let pl = &self.placement;
        let usable = [pl.inv_texel, pl.x0, pl.y0, max.z - min.z];
        if !usable.iter().all(|v| v.is_finite()) {
            // Finite but astronomically large coordinates: no usable map.
            return false;
        }
        let depth = max.z - min.z;
        self.layering = match self.settings.mode {
            ShadowMode::Slices => Layering::even(self.settings.layers, depth),
            ShadowMode::Deep => Layering::quadratic(self.settings.layers, depth * DEEP_SPAN),
        };
        true
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
        (-self.hair_opacity * self.hairs_in_front(p)).exp()
    }

    /// The texel-averaged number of hairs between `p` and the light, sigma
    /// of [`OpacityShadowMap::transmittance`] (`T = exp(-alpha sigma)`):
    /// the number of fibres the light crosses, which multiple scattering
    /// needs (`crate::dual_scattering`). 0 where the transmittance is 1
    /// for want of a map, a finite point or hair in front.
    pub fn hairs_in_front(&self, p: Vec3) -> f32 {
        self.blend_texels(p, |t, z| self.texel_sigma_at(t, z))
    }

    /// Steps 1-3 of [`OpacityShadowMap::hairs_in_front`] with `corner(t,
    /// z)` the value of texel `t` at light-space depth `z`: the four texels
    /// around `p`, bilinear (0 outside the map and where there is no map,
    /// finite point or hair).
    #[inline]
    fn blend_texels(&self, p: Vec3, corner: impl Fn(usize, f32) -> f32) -> f32 {
        if !self.ready || !p.is_finite() {
            return 0.0;
        }
        // 1. Light space, texel coordinates, corners and fractions.
        let l = self.frame.to_light(p);
        let (u, v) = self.placement.texel_coords(l.x, l.y);
        if !(u.is_finite() && v.is_finite() && l.z.is_finite()) {
            // So far away that light space overflows: outside the map, lit.
            return 0.0;
        }
        let (fu, fv) = (u.floor(), v.floor());
        let (fx, fy) = (u - fu, v - fv);
        let (i0, j0) = (fu as isize, fv as isize);
        // 2. The value at the depth in each corner.
        let at = |i, j| self.texel_index(i, j).map_or(0.0, |t| corner(t, l.z));
        let (s00, s10, s01, s11) = (
            at(i0, j0),
            at(i0 + 1, j0),
            at(i0, j0 + 1),
            at(i0 + 1, j0 + 1),
        );
        // 3. Bilinear blend (the exponential is the caller's).
        (s00 * (1.0 - fx) + s10 * fx) * (1.0 - fy) + (s01 * (1.0 - fx) + s11 * fx) * fy
    }

    /// Whether the map keeps each texel's first depth `z0` also in the
    /// texel's fourth plane: deep mode with at most three layers, where
    /// that plane is never used (the SIMD lookups then read `z0` with the
    /// planes, one 16-byte load per corner, instead of a gather).
    #[inline(always)]
    pub(super) fn depth_in_texels(&self) -> bool {
        self.settings.mode == ShadowMode::Deep && self.settings.layers < 4
    }

    /// The last step of both builds: where [`Self::depth_in_texels`],
    /// copies `z0` into every texel's fourth plane (no plane a lookup or
    /// [`Self::stored_opacity`] reads as an opacity).
    pub(super) fn keep_depth_in_texels(&mut self) {
        if self.depth_in_texels() {
            for (t, z) in self.texels.iter_mut().zip(&self.first_depth) {
                t[3] = *z;
            }
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

    /// [`OpacityShadowMap::hairs_in_front`] and the hairs on the light's
    /// whole ray through `p` (the last plane's count, blended the same
    /// way): the scalar twin of
    /// [`OpacityShadowMap::hairs_in_front_and_through_simd`]. `(0, 0)` where
    /// there is no map, finite point or hair.
    pub fn hairs_in_front_and_through(&self, p: Vec3) -> (f32, f32) {
        let last = self.settings.layers - 1;
        (
            self.hairs_in_front(p),
            self.blend_texels(p, |t, _| self.plane_pair(t, last).1),
        )
    }

    /// Opacity in front of depth `z` in texel `t`: linear between its
    /// planes.
    #[inline(always)]
    fn texel_sigma_at(&self, t: usize, z: f32) -> f32 {
        let (s, f) = self.layering.locate(z - self.base_depth(t));
        let (prev, next) = self.plane_pair(t, s);
        prev + f * (next - prev)
    }
}

/// A light-space bounds pass (the SIMD build's or the scalar one's):
/// `(min, max)` of the finite points in light space, or `None` when there is
/// no usable map.
pub(super) type LightBounds = fn(&LightFrame, &[Vec3]) -> Option<(Vec3, Vec3)>;
