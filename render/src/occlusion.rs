//! Hair segments hidden behind opaque spheres, found before they are
//! binned, so that the rasteriser never sets them up nor walks their
//! pixels: exact culling, the frame's bytes unchanged.
//!
//! A sphere of radius `R` whose centre `C` lies at distance `D = |C - E|`
//! from the eye `E` covers every pixel whose ray's angle to `C - E` is
//! below `alpha = asin(R / D)` (the ray meets the sphere), and the depth
//! it writes there is the view depth of the entry point,
//! `t_in (dir . forward)` with `t_in <= dir . (C - E) <= D`. A hair
//! segment from `a` to `b` draws only pixels whose centre lies within its
//! reach `0.5 max(w_a, w_b) + 0.75` pixels of the projected segment
//! (the bounds the binning uses), at view depths between those of its
//! ends (the fragment's `t` is in `[0, 1)`). Two screen points `d` pixels
//! apart see rays at most `d / f` radians apart (`f` the focal length in
//! pixels: the image plane is at least `f` from the eye). So when
//!
//! 1. both ends' directions make an angle below
//!    `beta = alpha - (m + 1) / f` with `C - E`, the segment's reach being
//!    below `m` (one of [`REACH_TIERS_PX`]; a spherical cap
//!    narrower than a hemisphere is convex, so the whole segment's
//!    directions, a great-circle arc between the ends', lie in it, and
//!    every pixel it can draw lies a pixel inside the covered disc), and
//! 2. both ends lie deeper than `D (1 + 1e-4)` (so does every fragment),
//!
//! every fragment of the segment fails the depth test against the
//! sphere's (or a nearer surface's) depth: drawing the segment changes
//! nothing, and it is left out. The test in the image's coordinates: with
//! `u = (x - W/2) / f`, `v = (y - H/2) / f` a point's ray is `(u, v, 1)`
//! in the camera's (right, down, forward) basis, and its angle to the
//! unit `c` is below `beta` when `s = u c_x + v c_y + c_z > 0` and
//! `s^2 > cos^2(beta) (u^2 + v^2 + 1)`. The same operations, in the same
//! order, decide in the scalar twin and in eight lanes ([`Lane`]).
//!
//! The caller promises that the spheres were drawn opaque into the frame
//! (their depth written, as `crate::head::draw_spheres` does) before the
//! hair and that nothing since has moved a depth farther.

use crate::line::ScreenVertex;
use crate::Camera;
use coif_base::lanes::Lane;
use coif_base::Sphere;
use glam::Vec3;

/// Most spheres one draw culls against (more are ignored: culling is
/// only ever a saving).
pub const MAX_OCCLUDERS: usize = 8;

/// The reaches (pixels) a segment is tested at: one below the first is
/// tested against the cap shrunk by that reach plus a pixel, one below
/// the second against the cap shrunk by the second plus
/// a pixel; wider segments are always drawn. Two tiers, because a fixed
/// margin wide enough for close-up hair (several pixels wide) gives up
/// the rim of the disc where most hidden hair of a distant head lies.
pub const REACH_TIERS_PX: [f32; 2] = [2.0, 8.0];

/// One draw's occluders in the camera's terms: per sphere the unit
/// direction of its centre in the (right, down, forward) basis, `cos^2`
/// of the shrunken cap's half-angle and the depth beyond which a point is
/// behind it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct OccluderCones {
    count: usize,
    axis: [[f32; 3]; MAX_OCCLUDERS],
    /// Per tier of [`REACH_TIERS_PX`].
    cos2: [[f32; 2]; MAX_OCCLUDERS],
    depth: [f32; MAX_OCCLUDERS],
    /// Image centre and `1 / f`.
    centre: [f32; 2],
    inv_focal: f32,
}

impl OccluderCones {
    /// The cones of `spheres` (at most [`MAX_OCCLUDERS`], in the camera's
    /// space) seen by `camera`; a sphere that holds the eye, is not finite,
    /// or covers too few pixels for the margin is left out.
    pub fn new(camera: &Camera, spheres: &[Sphere]) -> OccluderCones {
        let (eye, forward, right, down, focal) = camera.basis();
        let mut cones = OccluderCones {
            centre: [0.5 * camera.width() as f32, 0.5 * camera.height() as f32],
            inv_focal: 1.0 / focal,
            ..OccluderCones::default()
        };
        if !(focal.is_finite() && focal > 0.0) {
            return cones;
        }
        for s in spheres.iter().take(MAX_OCCLUDERS) {
            let c: Vec3 = s.center - eye;
            let d = c.length();
            if !(c.is_finite() && s.radius.is_finite() && s.radius > 0.0 && s.radius < 0.999 * d) {
                continue;
            }
            let alpha = (s.radius / d).asin();
            let beta = REACH_TIERS_PX.map(|m| alpha - (m + 1.0) / focal);
            if beta[0] <= 0.0 {
                continue;
            }
            let k = cones.count;
            cones.axis[k] = [c.dot(right) / d, c.dot(down) / d, c.dot(forward) / d];
            // An empty wide tier (the cap narrower than its margin) is
            // never entered: cos^2 > 1 beats any s^2 / q <= 1.
            cones.cos2[k] = beta.map(|b| if b > 0.0 { b.cos() * b.cos() } else { 2.0 });
            cones.depth[k] = d * (1.0 + 1e-4);
            cones.count += 1;
        }
        cones
    }

    /// Whether there is any sphere to cull against.
    pub fn any(&self) -> bool {
        self.count > 0
    }

    /// Whether segment `a -> b` (both ends valid) is hidden (module doc).
    #[inline]
    pub fn hides(&self, a: &ScreenVertex, b: &ScreenVertex) -> bool {
        self.hides_lanes(
            [a.x, a.y, a.depth, a.width_px],
            [b.x, b.y, b.depth, b.width_px],
        )
    }

    /// [`OccluderCones::hides`] of eight segments, one per lane: ends as
    /// `[x, y, depth, width]` planes; the lanes' mask. Lanes with a NaN
    /// are never hidden.
    #[inline(always)]
    pub fn hides_lanes<T: Lane>(
        &self,
        [ax, ay, az, aw]: [T; 4],
        [bx, by, bz, bw]: [T; 4],
    ) -> T::Mask {
        let reach = T::splat(0.5) * aw.max(bw) + T::splat(0.75);
        // Below each tier (false for a NaN width).
        let tight = reach.lt(T::splat(REACH_TIERS_PX[0]));
        let wide = reach.lt(T::splat(REACH_TIERS_PX[1]));
        let ray = |x: T, y: T| {
            let u = (x - T::splat(self.centre[0])) * T::splat(self.inv_focal);
            let v = (y - T::splat(self.centre[1])) * T::splat(self.inv_focal);
            (u, v, u * u + v * v + T::splat(1.0))
        };
        let (a, b) = (ray(ax, ay), ray(bx, by));
        let mut hidden = !T::all_lanes();
        for k in 0..self.count {
            let [cx, cy, cz] = self.axis[k].map(T::splat);
            let [cos2_tight, cos2_wide] = self.cos2[k].map(T::splat);
            let depth = T::splat(self.depth[k]);
            // Inside the cap for the segment's tier, and behind the centre.
            let inside = |(u, v, q): (T, T, T), z: T| {
                let s = u * cx + v * cy + cz;
                let s2 = s * s;
                let in_cap = (tight & s2.gt(cos2_tight * q)) | (wide & s2.gt(cos2_wide * q));
                s.gt(T::splat(0.0)) & in_cap & z.gt(depth)
            };
            hidden = hidden | (inside(a, az) & inside(b, bz));
        }
        hidden
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::head::ray_sphere;
    use coif_base::lanes::F32Lanes;

    /// Every pixel centre within a hidden segment's reach sees the
    /// sphere, nearer than the segment: sampled over random segments.
    #[test]
    fn hidden_segments_lie_behind_covered_pixels() {
        let camera = Camera::look_at(Vec3::new(0.0, 0.1, 1.2), Vec3::ZERO, Vec3::Y, 0.7, 320, 240);
        let sphere = Sphere {
            center: Vec3::new(0.02, -0.01, 0.0),
            radius: 0.2,
        };
        let cones = OccluderCones::new(&camera, std::slice::from_ref(&sphere));
        assert!(cones.any());
        let mut rng = coif_base::SplitMix64::new(5);
        let (mut hidden, mut tried) = (0, 0);
        while tried < 4000 {
            let p = |rng: &mut coif_base::SplitMix64| {
                Vec3::new(
                    rng.range(-0.3, 0.3),
                    rng.range(-0.3, 0.3),
                    rng.range(-0.35, 0.05),
                )
            };
            let (pa, pb) = (p(&mut rng), p(&mut rng));
            let w = rng.range(0.0, 12.0);
            let sv = |q: Vec3| {
                let s = camera.project(q, 1e-3).unwrap();
                ScreenVertex {
                    x: s.x,
                    y: s.y,
                    depth: s.z,
                    width_px: w,
                    color: Vec3::ONE,
                }
            };
            let (a, b) = (sv(pa), sv(pb));
            tried += 1;
            let scalar = cones.hides(&a, &b);
            let lanes = |v: &ScreenVertex| [v.x, v.y, v.depth, v.width_px].map(F32Lanes::splat);
            let wide = cones.hides_lanes(lanes(&a), lanes(&b)).to_bitmask();
            let all = (1u64 << coif_base::LANES) - 1;
            assert_eq!(
                u64::from(wide),
                if scalar { all } else { 0 },
                "twins disagree"
            );
            if !scalar {
                continue;
            }
            hidden += 1;
            // Pixel centres within the reach of the projected segment.
            let reach = 0.5 * a.width_px.max(b.width_px) + 0.75;
            for i in 0..=16 {
                let t = i as f32 / 16.0;
                let (x, y) = (a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
                let z = a.depth + t * (b.depth - a.depth);
                for (ox, oy) in [(0.0, 0.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
                    let (px, py) = (x + ox * reach, y + oy * reach);
                    let (px, py) = (px.floor() + 0.5, py.floor() + 0.5);
                    let dir = camera.ray_direction(px, py);
                    let hit = ray_sphere(camera.eye(), dir, &sphere).expect("covered");
                    assert!(hit * dir.dot(camera.forward()) < z, "in front");
                }
            }
        }
        assert!(hidden > 200 && hidden < tried, "{hidden} of {tried} hidden");
    }

    #[test]
    fn spheres_holding_the_eye_or_too_small_are_left_out() {
        let camera = Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 0.7, 64, 64);
        let around = Sphere {
            center: Vec3::new(0.0, 0.0, 0.9),
            radius: 0.5,
        };
        let tiny = Sphere {
            center: Vec3::ZERO,
            radius: 1e-3,
        };
        let nan = Sphere {
            center: Vec3::NAN,
            radius: 0.1,
        };
        assert!(!OccluderCones::new(&camera, &[around, tiny, nan]).any());
    }
}
