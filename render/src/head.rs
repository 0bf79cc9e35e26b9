//! The head: spheres ray-cast per pixel, Lambert plus ambient.
//!
//! For pixel centre ray `o + s d` and sphere `(c, r)`: with `m = o - c`,
//! `s = -m.d - sqrt((m.d)^2 - (|m|^2 - r^2))` (nearest hit, `|d| = 1`).
//! Shading: `L = albedo (ambient + E max(n . wi, 0) T)` with `T` the
//! light's transmittance at the hit point (hair shadow; 1 without shadows).

use super::{Camera, Framebuffer, Pixel};
use coif_base::lanes::F32Lanes;
use coif_base::tasks::{for_each_chunk_mut, Executor, Serial};
use coif_base::{Sphere, Vec3Lanes, LANES};
use glam::Vec3;
use std::sync::atomic::{AtomicUsize, Ordering};

/// How the head is lit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadShading {
    /// Diffuse albedo (linear RGB).
    pub albedo: Vec3,
    /// Unit direction toward the light.
    pub to_light: Vec3,
    /// Irradiance of the light (linear RGB).
    pub light: Vec3,
    /// Ambient irradiance (linear RGB).
    pub ambient: Vec3,
}

/// Nearest positive ray parameter at which the unit ray `origin + s dir`
/// enters `sphere`, if it does.
#[inline]
pub fn ray_sphere(origin: Vec3, dir: Vec3, sphere: &Sphere) -> Option<f32> {
    let m = origin - sphere.center;
    let b = m.dot(dir);
    let c = m.length_squared() - sphere.radius * sphere.radius;
    let disc = b * b - c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let s = -b - disc.sqrt();
    if s > 0.0 {
        Some(s)
    } else {
        let s2 = -b + disc.sqrt();
        (s2 > 0.0).then_some(s2)
    }
}

/// Whether the ray from `p` toward the light (`to_light`, unit) is blocked
/// by any of `spheres` (p itself outside them, or on a surface: hits closer
/// than `epsilon` are ignored).
#[inline]
pub fn occluded(p: Vec3, to_light: Vec3, spheres: &[Sphere], epsilon: f32) -> bool {
    spheres.iter().any(|s| {
        let m = p - s.center;
        let b = m.dot(to_light);
        let c = m.length_squared() - s.radius * s.radius;
        // Ahead of p (b < 0) and the line meets the sphere; p outside (c > 0).
        let disc = b * b - c;
        c > epsilon * s.radius && b < 0.0 && disc > 0.0
    })
}

/// Pixels `[x0, x1) x [y0, y1)` outside which no ray through a pixel
/// centre meets any of `spheres`: the box of the projected corners of each
/// sphere's bounding cube (a sphere lies inside its cube, and the
/// projection of a convex body in front of the eye lies inside the hull of
/// its projected corners), grown by a pixel; the whole frame when a corner
/// is behind the eye or not finite.
pub fn screen_bounds(
    camera: &Camera,
    spheres: &[Sphere],
    width: usize,
    height: usize,
) -> [usize; 4] {
    let whole = [0, width, 0, height];
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for s in spheres {
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { -1.0 } else { 1.0 },
                if k & 2 == 0 { -1.0 } else { 1.0 },
                if k & 4 == 0 { -1.0 } else { 1.0 },
            );
            let Some(p) = camera.project(s.center + corner * s.radius, 1e-6) else {
                return whole;
            };
            lo = lo.min(p.truncate());
            hi = hi.max(p.truncate());
        }
    }
    if spheres.is_empty() {
        return [0, 0, 0, 0];
    }
    let clamp = |v: f32, max: usize| v.clamp(0.0, max as f32) as usize;
    [
        clamp(lo.x.floor() - 1.0, width),
        clamp(hi.x.ceil() + 1.0, width),
        clamp(lo.y.floor() - 1.0, height),
        clamp(hi.y.ceil() + 1.0, height),
    ]
}

/// Ray-casts `spheres` (the head rig near the hair, in the camera's space)
/// over the whole frame: where a ray hits, writes the Lambert-lit colour and
/// the hit's view depth; `transmittance(p)` gives the light's visibility at
/// hit point `p` (hair shadow), and other spheres' shadows are added by
/// [`occluded`]. Only the pixels inside [`screen_bounds`] are cast.
/// Returns the number of pixels covered. On the calling thread; see
/// [`draw_spheres_with`] for tasks.
pub fn draw_spheres(
    frame: &mut Framebuffer,
    camera: &Camera,
    spheres: &[Sphere],
    shading: &HeadShading,
    transmittance: impl Fn(Vec3) -> f32 + Sync,
) -> usize {
    draw_spheres_with(frame, camera, spheres, shading, &transmittance, &Serial)
}

/// Fewest rows of pixels a task of [`draw_spheres_with`] casts.
const HEAD_ROWS: usize = 4;

/// Most tasks [`draw_spheres_with`] makes.
const HEAD_TASKS: usize = 64;

/// [`draw_spheres`] with bands of rows as tasks on `executor` (at least 4
/// rows each, at most 64 tasks: rows through the middle of the head cost
/// more, so the bands are short for the work to spread evenly): every
/// pixel's ray depends on that pixel alone, so the bytes are the same with
/// any number of threads. `transmittance` is asked one point at a time
/// ([`draw_spheres_lanes`] with each lane looked up alone: the same
/// pixels).
pub fn draw_spheres_with(
    frame: &mut Framebuffer,
    camera: &Camera,
    spheres: &[Sphere],
    shading: &HeadShading,
    transmittance: &(dyn Fn(Vec3) -> f32 + Sync),
    executor: &dyn Executor,
) -> usize {
    let lanes = |p: Vec3Lanes| F32Lanes::new(std::array::from_fn(|l| transmittance(p.lane(l))));
    draw_spheres_lanes(frame, camera, spheres, shading, &lanes, executor)
}

/// [`draw_spheres_with`] with the light's transmittance looked up eight
/// hit points at a time (`transmittance` gets the lit pixels of a row in
/// its lanes, in row order, spare lanes repeating the first point; an
/// eight-lane shadow-map lookup costs a fraction of eight one-point
/// ones). Each pixel's ray, hit, normal, Lambert term and head shadow are
/// computed as before, one pixel at a time; its colour is
/// `albedo (ambient + E lambert T)` with `T` its lane's value clamped to
/// `[0, 1]`.
pub fn draw_spheres_lanes(
    frame: &mut Framebuffer,
    camera: &Camera,
    spheres: &[Sphere],
    shading: &HeadShading,
    transmittance: &(dyn Fn(Vec3Lanes) -> F32Lanes + Sync),
    executor: &dyn Executor,
) -> usize {
    let eye = camera.eye();
    let forward = camera.forward();
    let width = frame.width();
    let [x0, x1, y0, y1] = screen_bounds(camera, spheres, width, frame.height());
    if x0 >= x1 || y0 >= y1 {
        return 0;
    }
    let covered = AtomicUsize::new(0);
    let band_rows = HEAD_ROWS.max((y1 - y0).div_ceil(HEAD_TASKS));
    let rows = &mut frame.pixels[y0 * width..y1 * width];
    let colour = |lit: f32| shading.albedo * (shading.ambient + shading.light * lit);
    for_each_chunk_mut(executor, rows, band_rows * width, &|band_index, band| {
        let mut here = 0;
        for (r, row) in band.chunks_mut(width).enumerate() {
            let y = y0 + band_index * band_rows + r;
            // Lit pixels waiting for their lookup: (x, Lambert term), and
            // their hit points in lanes.
            let mut waiting = [(0usize, 0.0f32); LANES];
            let mut points = Vec3Lanes::ZERO;
            let mut count = 0;
            let flush = |row: &mut [Pixel], waiting: &[(usize, f32)], points: &mut Vec3Lanes| {
                for l in waiting.len()..LANES {
                    points.set_lane(l, points.lane(0));
                }
                let t = transmittance(*points).to_array();
                for (&(x, lambert), t) in waiting.iter().zip(t) {
                    row[x].color = colour(lambert * t.clamp(0.0, 1.0));
                }
            };
            for x in x0..x1 {
                let dir = camera.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
                let mut best: Option<(f32, usize)> = None;
                for (k, s) in spheres.iter().enumerate() {
                    if let Some(t) = ray_sphere(eye, dir, s) {
                        if best.is_none_or(|(bt, _)| t < bt) {
                            best = Some((t, k));
                        }
                    }
                }
                let Some((t, k)) = best else { continue };
                let p = eye + dir * t;
                let n = (p - spheres[k].center) / spheres[k].radius;
                let lambert = n.dot(shading.to_light).max(0.0);
                row[x] = Pixel {
                    color: colour(0.0),
                    depth: t * dir.dot(forward),
                };
                if lambert > 0.0 && !occluded(p + n * 1e-4, shading.to_light, spheres, 1e-3) {
                    waiting[count] = (x, lambert);
                    points.set_lane(count, p);
                    count += 1;
                    if count == LANES {
                        flush(row, &waiting, &mut points);
                        count = 0;
                    }
                }
                here += 1;
            }
            if count > 0 {
                flush(row, &waiting[..count], &mut points);
            }
        }
        covered.fetch_add(here, Ordering::Relaxed);
    });
    covered.into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_ray_outside_the_screen_bounds_hits_a_sphere() {
        let camera = Camera::look_at(Vec3::new(0.3, 0.1, 1.0), Vec3::ZERO, Vec3::Y, 0.7, 120, 90);
        let spheres = [
            Sphere {
                center: Vec3::new(0.05, 0.0, 0.0),
                radius: 0.1,
            },
            Sphere {
                center: Vec3::new(-0.1, 0.08, -0.05),
                radius: 0.04,
            },
        ];
        let [x0, x1, y0, y1] = screen_bounds(&camera, &spheres, 120, 90);
        assert!(
            x0 > 0 && x1 < 120 && y0 > 0 && y1 < 90,
            "{x0} {x1} {y0} {y1}"
        );
        let mut hits = 0;
        for y in 0..90 {
            for x in 0..120 {
                let dir = camera.ray_direction(x as f32 + 0.5, y as f32 + 0.5);
                if spheres
                    .iter()
                    .any(|s| ray_sphere(camera.eye(), dir, s).is_some())
                {
                    hits += 1;
                    assert!((x0..x1).contains(&x) && (y0..y1).contains(&y), "({x}, {y})");
                }
            }
        }
        assert!(hits > 300, "{hits}");
        // A sphere around the eye: the whole frame.
        let around = [Sphere {
            center: camera.eye(),
            radius: 0.5,
        }];
        assert_eq!(screen_bounds(&camera, &around, 120, 90), [0, 120, 0, 90]);
    }

    #[test]
    fn rays_hit_the_sphere_at_the_right_distance_and_shadows_fall_behind_it() {
        let s = Sphere {
            center: Vec3::new(0.0, 0.0, -2.0),
            radius: 0.5,
        };
        assert!((ray_sphere(Vec3::ZERO, Vec3::NEG_Z, &s).unwrap() - 1.5).abs() < 1e-6);
        assert!(ray_sphere(Vec3::ZERO, Vec3::X, &s).is_none());
        // From inside, the exit point.
        assert!((ray_sphere(s.center, Vec3::X, &s).unwrap() - 0.5).abs() < 1e-6);
        // A point behind the sphere, seen from a light in front of it, is shadowed.
        assert!(occluded(
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::Z,
            std::slice::from_ref(&s),
            1e-3
        ));
        assert!(!occluded(
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::Z,
            std::slice::from_ref(&s),
            1e-3
        ));
        assert!(!occluded(Vec3::new(2.0, 0.0, -3.0), Vec3::Z, &[s], 1e-3));
    }

    /// The eight-lane lookups land on the pixels whose points they got:
    /// a transmittance that varies with the point (a ramp across the head,
    /// so every lane of a batch has its own value, and the last batch of a
    /// row is partial) gives every pixel the colour of the one-point path,
    /// serially and with the bands' tasks run in reverse.
    #[test]
    fn lane_lookups_colour_the_pixels_of_their_points() {
        let camera = Camera::look_at(Vec3::new(0.2, 0.3, 1.0), Vec3::ZERO, Vec3::Y, 0.7, 97, 61);
        let spheres = [
            Sphere {
                center: Vec3::new(0.03, 0.0, 0.0),
                radius: 0.15,
            },
            Sphere {
                center: Vec3::new(-0.12, -0.1, 0.02),
                radius: 0.06,
            },
        ];
        let shading = HeadShading {
            albedo: Vec3::new(0.8, 0.6, 0.5),
            to_light: Vec3::new(-0.4, 0.7, 0.6).normalize(),
            light: Vec3::ONE,
            ambient: Vec3::splat(0.1),
        };
        let ramp = |p: Vec3| 0.5 + 4.0 * p.x - 3.0 * p.y;
        let mut want = Framebuffer::new(97, 61);
        let covered = draw_spheres(&mut want, &camera, &spheres, &shading, ramp);
        assert!(covered > 400, "{covered}");
        let lanes = |p: Vec3Lanes| F32Lanes::new(std::array::from_fn(|l| ramp(p.lane(l))));
        // And tasks last first, split for four threads.
        for executor in [
            &Serial as &dyn Executor,
            &coif_testkit::executors::Backwards(4),
        ] {
            let mut got = Framebuffer::new(97, 61);
            let n = draw_spheres_lanes(&mut got, &camera, &spheres, &shading, &lanes, executor);
            assert_eq!(n, covered);
            assert!(got.pixels == want.pixels);
        }
        // Lit pixels really do read their own point: with the lanes
        // reversed, pixels change.
        let reversed = |p: Vec3Lanes| {
            let t = lanes(p).to_array();
            F32Lanes::new(std::array::from_fn(|l| t[LANES - 1 - l]))
        };
        let mut wrong = Framebuffer::new(97, 61);
        draw_spheres_lanes(&mut wrong, &camera, &spheres, &shading, &reversed, &Serial);
        assert!(wrong.pixels != want.pixels);
    }
}
