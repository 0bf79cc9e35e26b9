//! The SIMD lookup: eight points per step in `f32x8` lanes, the same
//! arithmetic in the same order as the scalar
//! [`OpacityShadowMap::transmittance`], with the texel reads done lane by
//! lane (manual gathers).

use super::map::OpacityShadowMap;
use super::settings::ShadowMode;
use coif_kernels::{Vec3x8, LANES};
use glam::Vec3;
use wide::f32x8;

impl OpacityShadowMap {
    /// SIMD batch: transmittance of every point of `points` into `out`
    /// (same length; extra entries of either are ignored). Agrees with
    /// [`OpacityShadowMap::transmittance_batch_scalar`] to float rounding of
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
            let t = self.transmittance_x8(chunk);
            o.copy_from_slice(&t.as_array()[..chunk.len()]);
        }
    }

    /// Transmittance of up to 8 points (lanes past `points.len()` and
    /// non-finite points give 1).
    #[inline]
    fn transmittance_x8(&self, points: &[Vec3]) -> f32x8 {
        let mut p = Vec3x8::ZERO;
        let mut finite = [0.0f32; LANES];
        for (l, q) in points.iter().enumerate() {
            if q.is_finite() {
                p.set_lane(l, *q);
                finite[l] = 1.0;
            }
        }
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
        let (fu, fv) = (fu.to_array(), fv.to_array());

        // The four corner texels of each lane (None outside the map).
        let mut corner = [[None; LANES]; 4];
        for l in 0..LANES {
            let (i0, j0) = (fu[l] as isize, fv[l] as isize);
            corner[0][l] = self.texel_index(i0, j0);
            corner[1][l] = self.texel_index(i0 + 1, j0);
            corner[2][l] = self.texel_index(i0, j0 + 1);
            corner[3][l] = self.texel_index(i0 + 1, j0 + 1);
        }

        let mut sigma = [f32x8::ZERO; 4];
        match self.settings.mode {
            ShadowMode::Slices => {
                let (s, frac) = self.locate_x8(lz - f32x8::splat(pl.near));
                for (c, out) in sigma.iter_mut().enumerate() {
                    *out = self.corner_sigma_x8(&corner[c], &s, frac);
                }
            }
            ShadowMode::Deep => {
                for (c, out) in sigma.iter_mut().enumerate() {
                    let mut base = [0.0f32; LANES];
                    for l in 0..LANES {
                        if let Some(t) = corner[c][l] {
                            base[l] = self.first_depth[t];
                        }
                    }
                    let (s, frac) = self.locate_x8(lz - f32x8::new(base));
                    *out = self.corner_sigma_x8(&corner[c], &s, frac);
                }
            }
        }
        let one = f32x8::ONE;
        let s = (sigma[0] * (one - fx) + sigma[1] * fx) * (one - fy)
            + (sigma[2] * (one - fx) + sigma[3] * fx) * fy;
        let t = (f32x8::splat(-self.hair_opacity) * s).exp();
        f32x8::new(finite).simd_gt(f32x8::ZERO).select(t, one)
    }

    /// [`super::layers::Layering::locate`] on eight depths: interval indices
    /// and fractions.
    #[inline(always)]
    fn locate_x8(&self, x: f32x8) -> ([usize; LANES], f32x8) {
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
        let i = i.to_array();
        let mut s = [0usize; LANES];
        for l in 0..LANES {
            s[l] = i[l] as usize;
        }
        (s, f)
    }

    /// Opacity in front of each lane's depth in one corner texel per lane:
    /// gathers `S[s - 1], S[s]` and interpolates with `frac`.
    #[inline(always)]
    fn corner_sigma_x8(
        &self,
        texel: &[Option<usize>; LANES],
        s: &[usize; LANES],
        frac: f32x8,
    ) -> f32x8 {
        let mut prev = [0.0f32; LANES];
        let mut next = [0.0f32; LANES];
        for l in 0..LANES {
            if let Some(t) = texel[l] {
                (prev[l], next[l]) = self.plane_pair(t, s[l]);
            }
        }
        let (prev, next) = (f32x8::new(prev), f32x8::new(next));
        prev + frac * (next - prev)
    }
}
