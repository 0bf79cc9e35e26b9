//! The SIMD batch lookup: eight points per step in `f32x8` lanes, the same
//! arithmetic in the same order as the one-point
//! [`OpacityShadowMap::transmittance`] (which `shadow/scalar/lookup.rs`
//! runs per point), with the texel reads done lane by lane (manual
//! gathers). Steps, in both:
//!
//! 1. Light-space coordinates, texel coordinates, the four corner texels
//!    and the bilinear fractions.
//! 2. Per corner: the opacity in front of the point's depth, linear between
//!    the texel's planes (0 outside the map).
//! 3. Bilinear blend of the four, `T = exp(-alpha sigma)`.

use super::map::OpacityShadowMap;
use super::settings::ShadowMode;
use coif_base::{Vec3x8, LANES};
use glam::Vec3;
use wide::{f32x8, i32x8};

impl OpacityShadowMap {
    /// SIMD batch: transmittance of every point of `points` into `out`
    /// (same length; extra entries of either are ignored). Agrees with
    /// [`super::scalar::transmittance_batch`] to float rounding of
    /// the exponential (measured in the tests: below 1e-6).
    pub fn transmittance_batch(&self, points: &[Vec3], out: &mut [f32]) {
        let len = points.len().min(out.len());
        if !self.ready {
            out[..len].fill(1.0);
            return;
        }
        for (chunk, o) in points[..len]
            .chunks(LANES)
            .zip(out[..len].chunks_mut(LANES))
        {
            let mut p = Vec3x8::ZERO;
            for (l, q) in chunk.iter().enumerate() {
                p.set_lane(l, *q);
            }
            let t = self.transmittance_x8(p);
            o.copy_from_slice(&t.as_array()[..chunk.len()]);
        }
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
    pub fn transmittance_x8(&self, p: Vec3x8) -> f32x8 {
        let one = f32x8::ONE;
        if !self.ready {
            return one;
        }
        let finite = p.finite();
        let p = Vec3x8::select(finite, p, Vec3x8::ZERO);
        // 1. Light space, texel coordinates, corners and fractions.
        let f = &self.frame;
        let lx = p.dot(Vec3x8::splat(f.x_axis));
        let ly = p.dot(Vec3x8::splat(f.y_axis));
        let lz = p.dot(Vec3x8::splat(f.z_axis));
        let pl = &self.placement;
        let inv_h = f32x8::splat(pl.inv_texel);
        let half = f32x8::splat(0.5);
        let u = (lx - f32x8::splat(pl.x0)) * inv_h - half;
        let v = (ly - f32x8::splat(pl.y0)) * inv_h - half;
        let (fu, fv) = (u.floor(), v.floor());
        let (fx, fy) = (u - fu, v - fv);

        // The four corner texels of each lane: indices clamped into the map
        // (so the gathers need no branches) and a mask of the corners that
        // really are inside it; the others contribute 0, as in the scalar.
        let last = f32x8::splat((self.settings.resolution - 1) as f32);
        let inside = |a: f32x8| a.simd_ge(f32x8::ZERO) & a.simd_le(last);
        // Clamped into [0, n - 1] (NaN-free: finite lanes only), so the
        // truncation is exact; corner indices below n^2 <= 2^26 in i32.
        let clamp = |a: f32x8| a.max(f32x8::ZERO).min(last).fast_trunc_int();
        let (fu1, fv1) = (fu + one, fv + one);
        let (in_x, in_x1, in_y, in_y1) = (inside(fu), inside(fu1), inside(fv), inside(fv1));
        let valid = [in_x & in_y, in_x1 & in_y, in_x & in_y1, in_x1 & in_y1];
        let row = i32x8::splat(self.settings.resolution as i32);
        let (cx, cx1, cy, cy1) = (clamp(fu), clamp(fu1), clamp(fv) * row, clamp(fv1) * row);
        let corner = [cy + cx, cy + cx1, cy1 + cx, cy1 + cx1].map(|c| c.to_array());

        // 2. Opacity in front of the depth in each corner.
        let mut sigma = [f32x8::ZERO; 4];
        match self.settings.mode {
            ShadowMode::Slices => {
                let (s, frac) = self.locate_x8(lz - f32x8::splat(pl.near));
                for (c, out) in sigma.iter_mut().enumerate() {
                    *out = valid[c].select(self.corner_sigma_x8(&corner[c], &s, frac), f32x8::ZERO);
                }
            }
            ShadowMode::Deep => {
                for (c, out) in sigma.iter_mut().enumerate() {
                    let base: [f32; LANES] =
                        std::array::from_fn(|l| self.first_depth[corner[c][l] as usize]);
                    let (s, frac) = self.locate_x8(lz - f32x8::new(base));
                    *out = valid[c].select(self.corner_sigma_x8(&corner[c], &s, frac), f32x8::ZERO);
                }
            }
        }
        // 3. Bilinear blend and exponential.
        let s = (sigma[0] * (one - fx) + sigma[1] * fx) * (one - fy)
            + (sigma[2] * (one - fx) + sigma[3] * fx) * fy;
        let t = (f32x8::splat(-self.hair_opacity) * s).exp();
        finite.select(t, one)
    }

    /// [`super::layers::Layering::locate`] on eight depths: interval indices
    /// and fractions.
    #[inline(always)]
    fn locate_x8(&self, x: f32x8) -> ([i32; LANES], f32x8) {
        let ly = &self.layering;
        let last = f32x8::splat((ly.count - 1) as f32);
        let one = f32x8::ONE;
        let q = x.max(f32x8::ZERO) * f32x8::splat(ly.scale);
        let (i, f) = if ly.quadratic {
            let i = q.sqrt().floor().min(last);
            let f = ((q - i * i) / (f32x8::splat(2.0) * i + one)).min(one);
            (i, f)
        } else {
            let i = q.floor().min(last);
            (i, (q - i).min(one))
        };
        // In [0, L - 1]: exact in i32.
        (i.fast_trunc_int().to_array(), f)
    }

    /// Opacity in front of each lane's depth in one corner texel per lane:
    /// gathers `S[s - 1], S[s]` (`S[-1] = 0`) and interpolates with `frac`.
    #[inline(always)]
    fn corner_sigma_x8(&self, texel: &[i32; LANES], s: &[i32; LANES], frac: f32x8) -> f32x8 {
        let nn = self.settings.resolution * self.settings.resolution;
        let mut prev = [0.0f32; LANES];
        let mut next = [0.0f32; LANES];
        for l in 0..LANES {
            let (t, s) = (texel[l] as usize, s[l] as usize);
            next[l] = self.texels[(s >> 2) * nn + t][s & 3];
            let p = s.saturating_sub(1);
            let below = self.texels[(p >> 2) * nn + t][p & 3];
            prev[l] = if s == 0 { 0.0 } else { below };
        }
        let (prev, next) = (f32x8::new(prev), f32x8::new(next));
        prev + frac * (next - prev)
    }
}
