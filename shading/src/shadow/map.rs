//! The opacity shadow map: storage, build (rasterise, then prefix-sum along
//! depth) and the scalar lookup.

use super::layers::{Layering, DEEP_SPAN};
use super::light_frame::{LightFrame, MapPlacement};
use super::raster::for_each_sample;
use super::raster_simd::for_each_sample_x8;
use super::settings::{ShadowMode, ShadowSettings};
use crate::Error;
use coif_base::{Vec3x8, LANES};
use glam::Vec3;
use wide::f32x8;

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
    ///
    /// The SIMD path: bounds, sample positions, bilinear weights, depths and
    /// plane intervals eight at a time in `f32x8` lanes, deposits in lane
    /// order with scalar adds (the scalar sample order), and the prefix sum
    /// sixteen texels at a time. The map is bit for bit the one
    /// [`OpacityShadowMap::build_scalar`] makes (tested).
    pub fn build(&mut self, light_dir: Vec3, points: &[Vec3], verts_per_strand: usize) {
        let Some(points) = self.prepare(light_dir, points, verts_per_strand, light_bounds_x8)
        else {
            return;
        };
        let (frame, placement, layering) = (self.frame, self.placement, self.layering);
        let (n, r) = (self.settings.resolution, self.settings.hair_radius);
        let nn = n * n;
        let offsets = [0, 1, n, n + 1];
        match self.settings.mode {
            ShadowMode::Slices => {
                let texels = &mut self.texels;
                let near = f32x8::splat(placement.near);
                for_each_sample_x8(&frame, &placement, n, r, points, verts_per_strand, |sp| {
                    let slices = layering.interval_x8(sp.z - near);
                    let w = sp.weights.map(|w| w.to_array());
                    for l in 0..sp.count {
                        let slice = slices[l];
                        let start = (slice / 4) * nn + sp.t0[l];
                        // One bounds check for the four texels.
                        let quad = &mut texels[start..start + n + 2];
                        for (c, o) in offsets.iter().enumerate() {
                            quad[*o][slice % 4] += w[c][l];
                        }
                    }
                });
            }
            ShadowMode::Deep => {
                let z0 = &mut self.first_depth;
                z0.fill(f32::INFINITY);
                for_each_sample_x8(&frame, &placement, n, r, points, verts_per_strand, |sp| {
                    let z = sp.z.to_array();
                    for l in 0..sp.count {
                        let quad = &mut z0[sp.t0[l]..sp.t0[l] + n + 2];
                        for o in offsets {
                            quad[o] = quad[o].min(z[l]);
                        }
                    }
                });
                for z in z0.iter_mut().filter(|z| **z == f32::INFINITY) {
                    *z = placement.near;
                }
                let z0 = &self.first_depth;
                let texels = &mut self.texels;
                for_each_sample_x8(&frame, &placement, n, r, points, verts_per_strand, |sp| {
                    // Each corner's plane interval, relative to its own z0,
                    // gathered lane by lane (every lane's `t0` is clamped
                    // into the map, also past `count`).
                    let mut base = [[0.0f32; LANES]; 4];
                    for l in 0..LANES {
                        let quad = &z0[sp.t0[l]..sp.t0[l] + n + 2];
                        for (c, o) in offsets.iter().enumerate() {
                            base[c][l] = quad[*o];
                        }
                    }
                    let slices = base.map(|b| layering.interval_x8(sp.z - f32x8::new(b)));
                    let w = sp.weights.map(|w| w.to_array());
                    for l in 0..sp.count {
                        for (c, o) in offsets.iter().enumerate() {
                            let slice = slices[c][l];
                            texels[(slice / 4) * nn + sp.t0[l] + o][slice % 4] += w[c][l];
                        }
                    }
                });
            }
        }
        prefix_sum_x8(&mut self.texels, nn, self.settings.layers);
        self.ready = true;
    }

    /// The scalar reference of [`OpacityShadowMap::build`]: the same steps,
    /// one sample at a time, one texel at a time in the prefix sum. Makes
    /// the same map bit for bit.
    pub fn build_scalar(&mut self, light_dir: Vec3, points: &[Vec3], verts_per_strand: usize) {
        let Some(points) = self.prepare(light_dir, points, verts_per_strand, light_bounds) else {
            return;
        };
        let (frame, placement, layering) = (self.frame, self.placement, self.layering);
        let (n, r) = (self.settings.resolution, self.settings.hair_radius);
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

    /// The steps both builds share before rasterising: clears the map, sets
    /// the light frame, takes the light-space bounds of the finite points
    /// (with `bounds`, scalar or SIMD), places the map and its layering.
    /// Returns the whole strands of `points`, or `None` when there is no
    /// usable map (zero or non-finite light, fewer than two vertices per
    /// strand, no finite point, coordinates so large that light space
    /// overflows).
    fn prepare<'p>(
        &mut self,
        light_dir: Vec3,
        points: &'p [Vec3],
        verts_per_strand: usize,
        bounds: LightBounds,
    ) -> Option<&'p [Vec3]> {
        self.ready = false;
        self.texels.fill([0.0; 4]);
        self.frame = LightFrame::new(light_dir)?;
        if verts_per_strand < 2 {
            return None;
        }
        let used = points.len() - points.len() % verts_per_strand;
        let points = &points[..used];
        let (min, max) = bounds(&self.frame, points)?;
        let n = self.settings.resolution;
        self.placement = MapPlacement::cover(min, max, self.settings.hair_radius, n);
        let pl = &self.placement;
        let usable = [pl.inv_texel, pl.x0, pl.y0, max.z - min.z];
        if !usable.iter().all(|v| v.is_finite()) {
            // Finite but astronomically large coordinates: no usable map.
            return None;
        }
        let depth = max.z - min.z;
        self.layering = match self.settings.mode {
            ShadowMode::Slices => Layering::even(self.settings.layers, depth),
            ShadowMode::Deep => Layering::quadratic(self.settings.layers, depth * DEEP_SPAN),
        };
        Some(points)
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

/// A light-space bounds pass: [`light_bounds`] or [`light_bounds_x8`].
type LightBounds = fn(&LightFrame, &[Vec3]) -> Option<(Vec3, Vec3)>;

/// Light-space bounding box `(min, max)` of the finite points, or `None`
/// when no point is finite or a finite point's light-space coordinates
/// overflow (then no map is usable). Light space as
/// [`LightFrame::to_light`]: `x = p . x_axis` and so on.
fn light_bounds(frame: &LightFrame, points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for p in points.iter().filter(|p| p.is_finite()) {
        let l = frame.to_light(*p);
        if !l.is_finite() {
            return None;
        }
        min = min.min(l);
        max = max.max(l);
    }
    // Stays inverted (min > max) when no point is finite.
    (min.x <= max.x).then_some((min, max))
}

/// SIMD twin of [`light_bounds`]: eight points per step, the same dot
/// products (`p.x a.x + p.y a.y + p.z a.z`, unfused), lane-wise minimum and
/// maximum over the finite points, reduced over the lanes at the end (min
/// and max of non-NaN numbers do not depend on the order).
fn light_bounds_x8(frame: &LightFrame, points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let axes = [frame.x_axis, frame.y_axis, frame.z_axis].map(Vec3x8::splat);
    let (inf, neg_inf) = (f32x8::splat(f32::INFINITY), f32x8::splat(f32::NEG_INFINITY));
    let mut min = [inf; 3];
    let mut max = [neg_inf; 3];
    let mut overflow = f32x8::ZERO;
    for chunk in points.chunks(LANES) {
        let mut p = Vec3x8::ZERO;
        let mut finite = [0.0f32; LANES];
        for (l, q) in chunk.iter().enumerate() {
            if q.is_finite() {
                p.set_lane(l, *q);
                finite[l] = 1.0;
            }
        }
        let finite = f32x8::new(finite).simd_gt(f32x8::ZERO);
        for k in 0..3 {
            let c = p.dot(axes[k]);
            overflow |= finite & !c.is_finite();
            min[k] = min[k].min(finite.select(c, inf));
            max[k] = max[k].max(finite.select(c, neg_inf));
        }
    }
    if overflow.any() {
        return None;
    }
    let reduce = |v: [f32x8; 3], f: fn(f32, f32) -> f32| {
        let [x, y, z] = v.map(|c| c.to_array().into_iter().reduce(f).unwrap_or(0.0));
        Vec3::new(x, y, z)
    };
    let (min, max) = (reduce(min, f32::min), reduce(max, f32::max));
    (min.x <= max.x).then_some((min, max))
}

/// SIMD twin of the scalar build's prefix sum along depth
/// (`S[s] = S[s - 1] + deposit[s]` per texel, `S[-1] = 0`, in plane order):
/// sixteen texels at a time, whose four-plane groups (two texels per
/// `f32x8`) are transposed into one vector per plane of the even and one
/// per plane of the odd texels, summed plane after plane (the same adds in
/// the same order as the scalar, so the same bits), and transposed back.
/// Texels past the last multiple of sixteen take the scalar loop. Planes
/// past `layers` in the last group stay untouched, as in the scalar.
fn prefix_sum_x8(texels: &mut [[f32; 4]], nn: usize, layers: usize) {
    const BLOCK: usize = 16;
    let groups = layers.div_ceil(4);
    let blocks = nn / BLOCK;
    let flat = texels.as_flattened_mut();
    for b in 0..blocks {
        let mut carry = [f32x8::ZERO; 2];
        for g in 0..groups {
            let start = (g * nn + b * BLOCK) * 4;
            let chunk = &mut flat[start..start + 4 * BLOCK];
            let rows: [f32x8; 8] = std::array::from_fn(|r| {
                let lanes: [f32; LANES] = chunk[r * LANES..(r + 1) * LANES].try_into().unwrap();
                f32x8::new(lanes)
            });
            // planes[k] = plane 4g + k of the even texels, planes[4 + k] of the odd.
            let mut planes = f32x8::transpose(rows);
            let valid = (layers - 4 * g).min(4);
            for half in 0..2 {
                let p = &mut planes[4 * half..4 * half + 4];
                p[0] = carry[half] + p[0];
                for k in 1..valid {
                    p[k] = p[k - 1] + p[k];
                }
                carry[half] = p[3];
            }
            for (r, row) in f32x8::transpose(planes).iter().enumerate() {
                chunk[r * LANES..(r + 1) * LANES].copy_from_slice(row.as_array());
            }
        }
    }
    for t in blocks * BLOCK..nn {
        let mut sum = 0.0;
        for s in 0..layers {
            let texel = &mut texels[(s / 4) * nn + t][s % 4];
            sum += *texel;
            *texel = sum;
        }
    }
}
