//! The SIMD batch lookup: eight points per step in `F32Lanes` lanes, the same
//! arithmetic in the same order as the one-point
//! [`OpacityShadowMap::transmittance`] (which `shadow/scalar/lookup.rs`
//! runs per point). Texel reads: with up to four layers (one RGBA group,
//! the frame's deep map) each lane loads its corners' 16-byte texels as
//! rows, transposed into one vector per plane, and picks its two planes by
//! selects; with more layers, gathers at flat indices computed in `i32`
//! lanes; the first depth (deep mode) is gathered (`shadow/gather.rs`).
//! Steps, in both:
//!
//! 1. Light-space coordinates, texel coordinates, the four corner texels
//!    and the bilinear fractions.
//! 2. Per corner: the opacity in front of the point's depth, linear between
//!    the texel's planes (0 outside the map).
//! 3. Bilinear blend of the four, `T = exp(-alpha sigma)`.

use super::gather::gather;
use super::layers::{FEW, ODD_RECIPROCALS};
use super::map::OpacityShadowMap;
use super::settings::ShadowMode;
use crate::Error;
use coif_base::lanes::{from_groups, F32Group, F32Lanes, I32Lanes, GROUP_LANES};
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

impl OpacityShadowMap {
    /// SIMD batch: transmittance of every point of `points` into `out`
    /// (one per point). Agrees with [`super::scalar::transmittance_batch`]
    /// to float rounding of the exponential (measured in the tests: below
    /// 1e-6). Allocates nothing.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] (and nothing written) unless `out.len() ==
    /// points.len()`.
    pub fn transmittance_batch(&self, points: &[Vec3], out: &mut [f32]) -> Result<(), Error> {
        check_lengths(points, out)?;
        let len = points.len();
        if !self.ready {
            out.fill(1.0);
            return Ok(());
        }
        for (chunk, o) in points[..len]
            .chunks(LANES)
            .zip(out[..len].chunks_mut(LANES))
        {
            let mut p = Vec3Lanes::ZERO;
            for (l, q) in chunk.iter().enumerate() {
                p.set_lane(l, *q);
            }
            let t = self.transmittance_simd(p);
            o.copy_from_slice(&t.as_array()[..chunk.len()]);
        }
        Ok(())
    }

    /// Transmittance toward the light of eight points, one per lane: the
    /// eight-lane twin of [`OpacityShadowMap::transmittance`], the same
    /// steps in the same order (`T = exp(-alpha sigma)`, sigma bilinear
    /// over the four texels around the point, linear in depth between each
    /// texel's planes). A lane whose point is not finite gives 1 and never
    /// disturbs the other lanes; before a build found hair every lane is 1.
    /// Agrees with [`OpacityShadowMap::transmittance`] to the rounding of
    /// the exponential (below 1e-6, tested). For a fused per-vertex pass:
    /// no frame-sized buffer, no allocation.
    #[inline]
    pub fn transmittance_simd(&self, p: Vec3Lanes) -> F32Lanes {
        (F32Lanes::splat(-self.hair_opacity) * self.hairs_in_front_simd(p)).exp()
    }

    /// The texel-averaged number of hairs between each lane's point and the
    /// light, sigma (`T = exp(-alpha sigma)`, see
    /// [`OpacityShadowMap::hairs_in_front`]): the steps of
    /// [`OpacityShadowMap::transmittance_simd`] before the exponential. 0 for
    /// a non-finite point and before a build found hair.
    #[inline]
    pub fn hairs_in_front_simd(&self, p: Vec3Lanes) -> F32Lanes {
        self.sigma_simd::<false>(p).0
    }

    /// [`OpacityShadowMap::hairs_in_front_simd`] and, from the same texel
    /// fetches, the hairs on the light's whole ray through each point (the
    /// last plane's count, blended the same way): the hair in front of and
    /// behind the point, as dual scattering takes them
    /// (`crate::dual_scattering::DualScattering::shade_layered_simd`).
    /// `(0, 0)` for a non-finite point and before a build found hair.
    #[inline]
    pub fn hairs_in_front_and_through_simd(&self, p: Vec3Lanes) -> (F32Lanes, F32Lanes) {
        self.sigma_simd::<true>(p)
    }

    /// The lookup of sigma at each point, and with `THROUGH` the last
    /// plane's sigma too (else 0).
    #[inline(always)]
    fn sigma_simd<const THROUGH: bool>(&self, p: Vec3Lanes) -> (F32Lanes, F32Lanes) {
        let one = F32Lanes::ONE;
        if !self.ready {
            return (F32Lanes::ZERO, F32Lanes::ZERO);
        }
        let finite = p.finite();
        let p = Vec3Lanes::select(finite, p, Vec3Lanes::ZERO);
        // 1. Light space, texel coordinates, corners and fractions.
        let f = &self.frame;
        let lx = p.dot(Vec3Lanes::splat(f.x_axis));
        let ly = p.dot(Vec3Lanes::splat(f.y_axis));
        let lz = p.dot(Vec3Lanes::splat(f.z_axis));
        let pl = &self.placement;
        let inv_h = F32Lanes::splat(pl.inv_texel);
        let half = F32Lanes::splat(0.5);
        let u = (lx - F32Lanes::splat(pl.x0)) * inv_h - half;
        let v = (ly - F32Lanes::splat(pl.y0)) * inv_h - half;
        // A finite point so far away that its light-space coordinates
        // overflow is outside the map: lit, as in the scalar.
        let finite = finite & u.is_finite() & v.is_finite() & lz.is_finite();
        let zero = F32Lanes::ZERO;
        let (u, v, lz) = (
            finite.select(u, zero),
            finite.select(v, zero),
            finite.select(lz, zero),
        );
        let (fu, fv) = (u.floor(), v.floor());
        let (fx, fy) = (u - fu, v - fv);

        // The four corner texels of each lane: indices clamped into the map
        // (so the gathers need no branches) and a mask of the corners that
        // really are inside it; the others contribute 0, as in the scalar.
        let last = F32Lanes::splat((self.settings.resolution - 1) as f32);
        let inside = |a: F32Lanes| a.simd_ge(F32Lanes::ZERO) & a.simd_le(last);
        // Clamped into [0, n - 1] (NaN-free: finite lanes only), so the
        // truncation is exact; corner indices below n^2 <= 2^26 in i32.
        let clamp = |a: F32Lanes| a.fast_max(F32Lanes::ZERO).fast_min(last).fast_trunc_int();
        let (fu1, fv1) = (fu + one, fv + one);
        let (in_x, in_x1, in_y, in_y1) = (inside(fu), inside(fu1), inside(fv), inside(fv1));
        let valid = [in_x & in_y, in_x1 & in_y, in_x & in_y1, in_x1 & in_y1];
        let row = I32Lanes::splat(self.settings.resolution as i32);
        let (cx, cx1, cy, cy1) = (clamp(fu), clamp(fu1), clamp(fv) * row, clamp(fv1) * row);
        let corner = [cy + cx, cy + cx1, cy1 + cx, cy1 + cx1];

        // 2. Opacity in front of the depth in each corner. With one group
        // of four planes (up to four layers, the frame's deep map) a corner's
        // planes are one 16-byte texel: two corners' texels per lane are
        // loaded as one row and transposed into plane vectors, then each
        // lane picks its pair by its interval; a deep map of up to three
        // layers keeps each texel's first depth in its free fourth plane
        // (`OpacityShadowMap::keep_depth_in_texels`), so the same loads
        // bring it. More planes: two gathers.
        let one_group = self.settings.layers <= 4;
        let depth_in_texel = self.depth_in_texels();
        let mut planes = [[F32Lanes::ZERO; 8]; 2];
        if one_group {
            let ct = corner.map(|c| c.to_array());
            planes[0] = self.texel_planes_simd(&ct[0], &ct[1]);
            planes[1] = self.texel_planes_simd(&ct[2], &ct[3]);
        }
        let mut sigma = [F32Lanes::ZERO; 4];
        let mut through = [F32Lanes::ZERO; 4];
        let last_plane = self.settings.layers - 1;
        for (c, out) in sigma.iter_mut().enumerate() {
            let p = &planes[c / 2][4 * (c % 2)..4 * (c % 2) + 4];
            let base = match self.settings.mode {
                ShadowMode::Slices => F32Lanes::splat(pl.near),
                ShadowMode::Deep if depth_in_texel => p[3],
                ShadowMode::Deep => gather(&self.first_depth, corner[c]),
            };
            let (s, i, frac) = self.locate_simd(lz - base);
            let first = i.simd_eq(F32Lanes::ZERO);
            let (prev, next) = if one_group {
                pick_pair(p, i)
            } else if self.flat_fits() {
                self.plane_pair_simd(corner[c], s, first)
            } else {
                self.plane_pair_lanes(corner[c], s)
            };
            *out = valid[c].select(prev + frac * (next - prev), F32Lanes::ZERO);
            if THROUGH {
                let last = if one_group {
                    p[last_plane]
                } else {
                    let s = I32Lanes::splat(last_plane as i32);
                    self.plane_pair_lanes(corner[c], s).1
                };
                through[c] = valid[c].select(last, F32Lanes::ZERO);
            }
        }
        // 3. Bilinear blend (the exponential is the caller's).
        let blend = |v: &[F32Lanes; 4]| {
            let s =
                (v[0] * (one - fx) + v[1] * fx) * (one - fy) + (v[2] * (one - fx) + v[3] * fx) * fy;
            finite.select(s, F32Lanes::ZERO)
        };
        let front = blend(&sigma);
        (
            front,
            if THROUGH {
                blend(&through)
            } else {
                F32Lanes::ZERO
            },
        )
    }

    /// [`super::layers::Layering::locate`] on eight depths: interval
    /// indices (as `i32` and as `f32`) and fractions. `fast_max` /
    /// `fast_min` (one instruction; equal to the scalar's `max` / `min` on
    /// the finite values here: non-finite points were replaced by the
    /// origin in step 1).
    #[inline(always)]
    fn locate_simd(&self, x: F32Lanes) -> (I32Lanes, F32Lanes, F32Lanes) {
        let ly = &self.layering;
        let one = F32Lanes::ONE;
        let q = x.fast_max(F32Lanes::ZERO) * F32Lanes::splat(ly.scale);
        let i = ly.interval_f32x8(x);
        let f = if ly.quadratic && ly.count <= FEW {
            // The scalar's table entry `1 / (2 i + 1)`, by selects.
            let r = ODD_RECIPROCALS;
            let is = |k: f32| i.simd_eq(F32Lanes::splat(k));
            let recip = is(0.0).select(
                F32Lanes::splat(r[0]),
                is(1.0).select(
                    F32Lanes::splat(r[1]),
                    is(2.0).select(F32Lanes::splat(r[2]), F32Lanes::splat(r[3])),
                ),
            );
            ((q - i * i) * recip).fast_min(one)
        } else if ly.quadratic {
            ((q - i * i) / (F32Lanes::splat(2.0) * i + one)).fast_min(one)
        } else {
            (q - i).fast_min(one)
        };
        // In [0, L - 1]: exact in i32.
        (i.fast_trunc_int(), i, f)
    }

    /// The four planes of texel `a[l]` and of texel `b[l]` per lane (one
    /// group of planes): rows `[texel a, texel b]` per lane, transposed, so
    /// that `[0..4]` are planes 0 to 3 of the `a` texels and `[4..8]` those
    /// of the `b` texels. Texel indices are in the map (clamped corners).
    #[inline(always)]
    fn texel_planes_simd(&self, a: &[i32; LANES], b: &[i32; LANES]) -> [F32Lanes; 8] {
        // The corners are clamped into the map by construction; clamped
        // again here (a no-op) so that the reads need no bounds check.
        let Some(last) = self.texels.len().checked_sub(1) else {
            return [F32Lanes::ZERO; 8];
        };
        let last = I32Lanes::splat(last.min(i32::MAX as usize) as i32);
        let in_map = |i: &[i32; LANES]| I32Lanes::new(*i).max(I32Lanes::ZERO).min(last).to_array();
        let (a, b) = (in_map(a), in_map(b));
        // One 8 x 8 transpose per group of eight lanes.
        let mut groups = [[F32Group::ZERO; 8]; LANES / GROUP_LANES];
        for (k, planes) in groups.iter_mut().enumerate() {
            let rows = std::array::from_fn(|j| {
                let l = k * GROUP_LANES + j;
                // SAFETY: 0 <= a[l], b[l] <= texels.len() - 1 (clamped above).
                let (x, y) = unsafe {
                    (
                        *self.texels.get_unchecked(a[l] as usize),
                        *self.texels.get_unchecked(b[l] as usize),
                    )
                };
                F32Group::new([x[0], x[1], x[2], x[3], y[0], y[1], y[2], y[3]])
            });
            *planes = F32Group::transpose(rows);
        }
        std::array::from_fn(|p| from_groups(groups.map(|g| g[p])))
    }

    /// Whether every flat float index into the map, `(s / 4) 4 n^2 + 4 t +
    /// s % 4`, fits in an `i32` lane (every map up to 2^29 texels).
    #[inline(always)]
    fn flat_fits(&self) -> bool {
        self.texels.len() <= (i32::MAX as usize) / 4
    }

    /// The stored opacities `(S[s - 1], S[s])` (`S[-1] = 0`, the lanes of
    /// `first`) of one texel per lane: two gathers from the flat map at
    /// `(s / 4) 4 n^2 + 4 t + s % 4` and the same for `s - 1`.
    #[inline(always)]
    fn plane_pair_simd(
        &self,
        texel: I32Lanes,
        s: I32Lanes,
        first: F32Lanes,
    ) -> (F32Lanes, F32Lanes) {
        let nn = self.settings.resolution * self.settings.resolution;
        let nn4 = I32Lanes::splat((4 * nn) as i32);
        let three = I32Lanes::splat(3);
        let t4 = texel << 2;
        let flat_index = |s: I32Lanes| {
            let group: I32Lanes = s >> 2;
            group * nn4 + t4 + (s & three)
        };
        let flat = self.texels.as_flattened();
        let next = gather(flat, flat_index(s));
        let below = gather(flat, flat_index((s - I32Lanes::ONE).max(I32Lanes::ZERO)));
        (first.select(F32Lanes::ZERO, below), next)
    }

    /// [`OpacityShadowMap::plane_pair`] lane by lane (maps too large for
    /// `i32` flat indices).
    #[inline(always)]
    fn plane_pair_lanes(&self, texel: I32Lanes, s: I32Lanes) -> (F32Lanes, F32Lanes) {
        let (texel, s) = (texel.to_array(), s.to_array());
        let pairs: [(f32, f32); LANES] =
            std::array::from_fn(|l| self.plane_pair(texel[l] as usize, s[l] as usize));
        (
            F32Lanes::new(pairs.map(|p| p.0)),
            F32Lanes::new(pairs.map(|p| p.1)),
        )
    }
}

/// The pair `(S[i - 1], S[i])` (`S[-1] = 0`) from one texel's four planes
/// `p` per lane, by the lane's interval `i` (an exact small integer in
/// `0..4`): selects, no memory access.
#[inline(always)]
fn pick_pair(p: &[F32Lanes], i: F32Lanes) -> (F32Lanes, F32Lanes) {
    let is = |k: f32| i.simd_eq(F32Lanes::splat(k));
    let (i0, i1, i2) = (is(0.0), is(1.0), is(2.0));
    let next = i0.select(p[0], i1.select(p[1], i2.select(p[2], p[3])));
    let prev = i0.select(F32Lanes::ZERO, i1.select(p[0], i2.select(p[1], p[2])));
    (prev, next)
}

/// `Ok` if `out` holds one value per point.
pub(crate) fn check_lengths(points: &[Vec3], out: &[f32]) -> Result<(), Error> {
    if out.len() == points.len() {
        Ok(())
    } else {
        Err(Error::CountMismatch {
            what: "transmittances (one per point)",
            expected: points.len(),
            got: out.len(),
        })
    }
}
