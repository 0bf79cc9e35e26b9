//! Collisions: how deep hair gets into spheres, capsules and mesh fields
//! against what the contacts cost, measured by the exact distance to the
//! collider (not by the step's own test).
//!
//! Scenes, one step of dt = 1/60 s per frame, default parameters otherwise
//! (friction 0.3 / 0.5, pearl radius 2 mm, sleeping off):
//!
//! - **drape**: a curtain of [`CURTAIN`] strands of [`VERTS`] vertices on
//!   1.2 cm links (28.8 cm), roots in a 32 cm row 3 cm above the collider's
//!   top and 6 cm behind it, starting straight out over the top; they fall,
//!   land and drape for 1.5 s. Colliders: a sphere of radius 10 cm, a
//!   capsule of radius 8 cm on a 40 cm horizontal axis under the curtain
//!   (a towel on a bar), the field of an icosphere of radius 10 cm (1,280
//!   triangles, 4 mm cells) and, when the shared mesh folder is present,
//!   the field of the Sintel bust (5,952 triangles, 4 mm cells; the curtain
//!   over the top of her head).
//! - **sweep**: 8 x 8 strands of the same shape hanging from a 14 cm square
//!   grid of roots; the collider goes through the hair at 3 m/s along x,
//!   from 25 cm on one side to 25 cm on the other and back, twice
//!   (0.67 s), then stands for 0.08 s. Colliders: a sphere of radius 5 cm,
//!   a thin capsule (a rod of radius 5 mm, what pearls are for: a 1.2 cm
//!   segment whose ends sit on its skin crosses 1.4 mm into it) on a 24 cm
//!   axis across the hair (along z), the icosphere's field at radius 5 cm
//!   (moved by `Sdf::set_transform`).
//!
//! Error: the deepest penetration of the hair's centre line into the
//! collider's own surface (not counting the pearl radius), in metres, at
//! the end of every step over the run:
//!
//! - sphere: `R - |c - s|` with `s` the segment's closest point to the
//!   centre `c`, every segment exactly;
//! - capsule: `r - ` the distance between the segment and the axis (the
//!   minimum of `|p + s d1 - (a + t d2)|` over `s, t` in [0, 1]: the
//!   stationary point when it falls inside the square, else the four
//!   end-point-to-segment distances; Ericson, Real-Time Collision
//!   Detection, 2005, 5.1.9), every segment exactly;
//! - fields: points every 1.5 mm along every segment (its ends and 7
//!   between), measured against the MESH, not the field: the unsigned
//!   distance to the nearest triangle by brute force over all triangles and
//!   the sign by the generalised winding number (`w >= 1/2` inside), in f64
//!   (`coif_testkit::meshes::brute`). Brute force over every point is too
//!   slow (about 14,000 points a frame), so the field picks the candidates:
//!   only points whose field distance is below [`FIELD_SLACK`] = 1 mm are
//!   measured, deepest field value first, and a point is skipped once its
//!   field depth plus the slack cannot beat the deepest exact depth found
//!   so far in the run. The slack is above the field's error near the
//!   surface (`kernels/SDF.md`: median 0.025 mm and 95th percentile 0.1 mm
//!   on the icosphere, 0.07 and 0.91 mm on the bust), so a point the field
//!   puts 1 mm outside is taken as outside; the family prints the largest
//!   field-against-exact difference it saw among the points it measured
//!   (first full run: at most 0.67 mm on the icosphere, but 1.2 mm on the
//!   bust, so there a skipped point could lie up to 0.2 mm deeper than the
//!   row says).
//!
//! Settings: `max_substep` 1/120, 1/240 (default), 1/480 s (2, 4, 8
//! substeps: contacts at every substep, so at 60 x that many rates per
//! second) x `pearls_per_segment` 0, 1 (default), 2. Time: ns per
//! vertex-step (a step = all its substeps, contacts included) of the
//! median step of each run, the spread the range over repeated runs
//! (three in a full report, one in a quick run); SIMD (`step_colliders`)
//! and scalar (`scalar::step_colliders`, the same bits: the error is the
//! SIMD run's). A quick run measures the default `max_substep` with 0 and 1
//! pearls, the sphere, capsule and icosphere field, and no bust.
//!
//! What the committed full run shows (`docs/report/summary.md` has the
//! figures): no segment entered the sphere, the wide capsule or the
//! icosphere's field at any setting, draped or swept at 3 m/s (a pushed
//! vertex sits a pearl radius, 2 mm, outside, more than a 1.2 cm chord
//! sags on these radii). The first full run found hair 5-7 mm inside the
//! draped field and 8-40 mm inside the swept one: the push out of a field
//! was capped at `FIELD_EXIT_SPEED h` for every contact, which the step now
//! applies only beyond what the substep's relative motion explains. Fields
//! collide with vertices only (pearls act on spheres and capsules), so the
//! pearl settings of a field differ in time alone, and on the bust, whose
//! curvature is tighter than the icosphere's, segments between vertices
//! dip 2.3-3.0 mm into it (the vertices stay out). The rod (radius 5 mm)
//! moves 2.5, 1.25 and 0.6 cm per substep at 3 m/s: at 1/120 and 1/240 s it
//! jumps segments whatever the pearls (4.4-5 mm deep, about its radius); at
//! 1/480 s one or two pearls keep it to 1.6-1.7 mm, none lets 4.4 mm in.

use super::{Options, Path, Row, Timing};
use coif::kernels::{self as kernels, scalar, Capsule, Colliders, Sdf, SimParams, Sphere, Strands};
use coif_testkit::meshes::{brute, icosphere, seg_dist, Mesh};
use glam::{Affine3A, DVec3, Vec3};
use std::time::Instant;

/// Strands of the curtain.
pub const CURTAIN: usize = 64;
/// Vertices per strand in both scenes.
pub const VERTS: usize = 25;
/// Rest length of a segment (m).
pub const LINK: f32 = 0.012;
/// Points measured per segment on fields: `FIELD_POINTS + 1` from end to end.
pub const FIELD_POINTS: usize = 8;
/// Field distance below which a point is measured by brute force (m).
pub const FIELD_SLACK: f32 = 0.001;
/// Grid spacing of the fields (m).
pub const FIELD_CELL: f32 = 0.004;
/// Speed of the swept collider (m/s).
pub const SWEEP_SPEED: f32 = 3.0;
/// `max_substep` values measured, as the denominator of 1/n seconds.
pub const MAX_SUBSTEP: [u32; 3] = [120, 240, 480];
/// Pearls per segment measured.
pub const PEARLS: [u32; 3] = [0, 1, 2];

/// A scene of the family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scene {
    /// A curtain falls over a still collider and drapes (1.5 s).
    Drape,
    /// A collider sweeps through hanging hair at 3 m/s (0.75 s).
    Sweep,
}

impl Scene {
    /// `drape` or `sweep`.
    pub fn name(self) -> &'static str {
        match self {
            Scene::Drape => "drape",
            Scene::Sweep => "sweep",
        }
    }

    /// Frames (steps of 1/60 s) of the scene.
    pub fn frames(self) -> usize {
        match self {
            Scene::Drape => 90,
            Scene::Sweep => 45,
        }
    }

    /// Where the collider is (its offset from its base place) at time `t`.
    pub fn offset(self, t: f32) -> Vec3 {
        match self {
            Scene::Drape => Vec3::ZERO,
            Scene::Sweep => {
                // 0.5 m out and back at SWEEP_SPEED, twice, then still.
                let leg = 0.5 / SWEEP_SPEED;
                let t = t.min(4.0 * leg);
                let phase = (t / leg) as u32;
                let f = t / leg - phase as f32;
                let x = if phase.is_multiple_of(2) { f } else { 1.0 - f };
                let x = if t >= 4.0 * leg { 0.0 } else { x };
                Vec3::new(-0.25 + 0.5 * x, 0.0, 0.0)
            }
        }
    }
}

/// What the hair collides with.
enum Shape {
    Sphere(Sphere),
    Capsule(Capsule),
    /// A mesh, its field, and the name of the kernel's collider.
    Field(Box<(Mesh, Sdf)>, &'static str),
}

impl Shape {
    fn name(&self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Capsule(_) => "capsule",
            Shape::Field(_, name) => name,
        }
    }

    fn metric(&self) -> &'static str {
        match self {
            Shape::Field(..) => {
                "deepest penetration over the run at points every 1.5 mm against the mesh by brute force (m)"
            }
            _ => "deepest penetration of any segment over the run by the exact distance (m)",
        }
    }
}

/// The strands of a scene around a collider whose top is at `top` (the
/// highest point of its surface).
fn strands(scene: Scene, top: Vec3) -> Vec<Vec3> {
    let mut points = Vec::new();
    match scene {
        Scene::Drape => {
            for i in 0..CURTAIN {
                let x = top.x - 0.16 + 0.32 * i as f32 / (CURTAIN - 1) as f32;
                for v in 0..VERTS {
                    points.push(Vec3::new(x, top.y + 0.03, top.z - 0.06 + LINK * v as f32));
                }
            }
        }
        Scene::Sweep => {
            for i in 0..8 {
                for k in 0..8 {
                    let (x, z) = (-0.07 + 0.02 * i as f32, -0.07 + 0.02 * k as f32);
                    for v in 0..VERTS {
                        points.push(Vec3::new(x, 0.15 - LINK * v as f32, z));
                    }
                }
            }
        }
    }
    points
}

/// Distance between the segments `p1 q1` and `p2 q2` (f64).
pub fn segment_distance(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
    let ends = seg_dist(p1, p2, q2)
        .min(seg_dist(q1, p2, q2))
        .min(seg_dist(p2, p1, q1))
        .min(seg_dist(q2, p1, q1));
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, b, e) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let (c, f) = (d1.dot(r), d2.dot(r));
    let denom = a * e - b * b;
    if denom <= 1e-12 * a * e || a == 0.0 {
        return ends;
    }
    let t = (a * f - b * c) / denom;
    let s = (b * t - c) / a;
    if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
        ends.min((r + d1 * s - d2 * t).length())
    } else {
        ends
    }
}

/// The deepest penetration seen so far, and what the field measurement saw.
#[derive(Default)]
struct Depth {
    deepest: f64,
    /// Points measured by brute force.
    brute: usize,
    /// Largest |field - exact signed distance| among them (m).
    field_error: f64,
}

/// The colliders of one (scene, shape) and the penetration measurement.
struct Body {
    shape: Shape,
    spheres: Vec<Sphere>,
    capsules: Vec<Capsule>,
    sdfs: Vec<Sdf>,
}

impl Body {
    fn new(shape: Shape) -> Body {
        let mut body = Body {
            shape,
            spheres: Vec::new(),
            capsules: Vec::new(),
            sdfs: Vec::new(),
        };
        match &body.shape {
            Shape::Sphere(s) => body.spheres.push(s.clone()),
            Shape::Capsule(c) => body.capsules.push(*c),
            Shape::Field(f, _) => body.sdfs.push(f.1.clone()),
        }
        body
    }

    /// Moves the collider to `offset` from its base place.
    fn place(&mut self, offset: Vec3) {
        match &self.shape {
            Shape::Sphere(s) => self.spheres[0].center = s.center + offset,
            Shape::Capsule(c) => {
                self.capsules[0].a = c.a + offset;
                self.capsules[0].b = c.b + offset;
            }
            Shape::Field(..) => self.sdfs[0]
                .set_transform(Affine3A::from_translation(offset))
                .expect("a translation is rigid"),
        }
    }

    fn colliders(&self) -> Colliders<'_> {
        Colliders {
            spheres: &self.spheres,
            capsules: &self.capsules,
            sdfs: &self.sdfs,
        }
    }

    /// The top of the collider at its base place.
    fn top(&self) -> Vec3 {
        match &self.shape {
            Shape::Sphere(s) => s.center + Vec3::Y * s.radius,
            Shape::Capsule(c) => (c.a + c.b) * 0.5 + Vec3::Y * c.radius,
            Shape::Field(f, _) => (f.0)
                .0
                .iter()
                .copied()
                .max_by(|a, b| a.y.total_cmp(&b.y))
                .expect("a mesh has vertices"),
        }
    }

    /// Measures `positions` (strands of `VERTS`) at the collider's current
    /// place `offset` into `depth`.
    fn measure(&self, positions: &[Vec3], offset: Vec3, depth: &mut Depth) {
        let segments = positions
            .chunks_exact(VERTS)
            .flat_map(|s| s.windows(2).map(|w| (w[0].as_dvec3(), w[1].as_dvec3())));
        match &self.shape {
            Shape::Sphere(_) => {
                let s = &self.spheres[0];
                let c = s.center.as_dvec3();
                for (p, q) in segments {
                    depth.deepest = depth.deepest.max(s.radius as f64 - seg_dist(c, p, q));
                }
            }
            Shape::Capsule(_) => {
                let k = &self.capsules[0];
                let (a, b) = (k.a.as_dvec3(), k.b.as_dvec3());
                for (p, q) in segments {
                    depth.deepest = depth
                        .deepest
                        .max(k.radius as f64 - segment_distance(p, q, a, b));
                }
            }
            Shape::Field(f, _) => {
                let (mesh, _) = &**f;
                let sdf = &self.sdfs[0];
                let slack = FIELD_SLACK as f64;
                let mut candidates: Vec<(f64, DVec3)> = Vec::new();
                for (p, q) in segments {
                    for j in 0..=FIELD_POINTS {
                        let x = p + (q - p) * (j as f64 / FIELD_POINTS as f64);
                        let d = sdf.distance(x.as_vec3()) as f64;
                        if d < slack && slack - d > depth.deepest {
                            candidates.push((d, x));
                        }
                    }
                }
                candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
                for (d, x) in candidates {
                    if slack - d <= depth.deepest {
                        break;
                    }
                    let (unsigned, winding) = brute(mesh, (x - offset.as_dvec3()).as_vec3());
                    let signed = if winding >= 0.5 { -unsigned } else { unsigned };
                    depth.brute += 1;
                    depth.field_error = depth.field_error.max((d - signed).abs());
                    depth.deepest = depth.deepest.max(-signed);
                }
            }
        }
    }
}

/// The step of a path.
fn stepper(path: Path) -> fn(&mut Strands, &SimParams, &Colliders<'_>) {
    match path {
        Path::Simd => kernels::step_colliders,
        Path::Scalar => scalar::step_colliders,
    }
}

/// One run of `scene` against `body`: (median seconds per step, the final
/// positions); measures into `depth` if given.
fn run(
    scene: Scene,
    body: &mut Body,
    params: &SimParams,
    path: Path,
    mut depth: Option<&mut Depth>,
) -> (f64, Vec<Vec3>) {
    let points = strands(scene, body.top());
    let mut s = Strands::from_polylines(&points, VERTS).expect("a valid scene");
    let step = stepper(path);
    let mut times = Vec::with_capacity(scene.frames());
    let mut positions = points;
    for f in 0..scene.frames() {
        let offset = scene.offset((f + 1) as f32 * params.dt);
        body.place(offset);
        let t0 = Instant::now();
        step(&mut s, params, &body.colliders());
        times.push(t0.elapsed().as_secs_f64());
        if let Some(depth) = depth.as_deref_mut() {
            s.write_positions(&mut positions)
                .expect("positions holds every point");
            body.measure(&positions, offset, depth);
        }
    }
    s.write_positions(&mut positions)
        .expect("positions holds every point");
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], positions)
}

/// The colliders of a scene: sphere, capsule, icosphere field and (drape,
/// when present and not quick) the bust's field.
fn shapes(scene: Scene, options: Options) -> Vec<Shape> {
    let (radius, capsule) = match scene {
        Scene::Drape => (
            0.1,
            Capsule {
                a: Vec3::new(-0.2, 0.0, 0.0),
                b: Vec3::new(0.2, 0.0, 0.0),
                radius: 0.08,
            },
        ),
        Scene::Sweep => (
            0.05,
            Capsule {
                a: Vec3::new(0.0, 0.0, -0.12),
                b: Vec3::new(0.0, 0.0, 0.12),
                radius: 0.005,
            },
        ),
    };
    let field = |mesh: Mesh, name| {
        let sdf = Sdf::from_mesh(&mesh.0, &mesh.1, FIELD_CELL).expect("the mesh builds a field");
        Shape::Field(Box::new((mesh, sdf)), name)
    };
    let mut out = vec![
        Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius,
        }),
        Shape::Capsule(capsule),
        field(icosphere(3, radius), "field"),
    ];
    if scene == Scene::Drape && !options.quick {
        if let Some(bust) = coif_testkit::sintel_bust() {
            out.push(field(bust, "bust field"));
        }
    }
    out
}

/// The `collisions <scene> <collider>` rows, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let (rates, pearls, reps): (&[u32], &[u32], usize) = if options.quick {
        (&[240], &[0, 1], 1)
    } else {
        (&MAX_SUBSTEP, &PEARLS, 3)
    };
    let defaults = SimParams::default();
    let mut rows = Vec::new();
    for scene in [Scene::Drape, Scene::Sweep] {
        let per_step = (scene_strands(scene) * VERTS) as f64;
        for shape in shapes(scene, options) {
            let kernel = format!("collisions {} {}", scene.name(), shape.name());
            let metric = shape.metric();
            let mut body = Body::new(shape);
            for &rate in rates {
                for &p in pearls {
                    let params = SimParams {
                        max_substep: 1.0 / rate as f32,
                        pearls_per_segment: p,
                        sleep_speed: 0.0,
                        ..Default::default()
                    };
                    let mut depth = Depth::default();
                    let mut simd = Vec::with_capacity(reps);
                    let (t, last) = run(scene, &mut body, &params, Path::Simd, Some(&mut depth));
                    simd.push(t);
                    for _ in 1..reps {
                        simd.push(run(scene, &mut body, &params, Path::Simd, None).0);
                    }
                    let mut scalar = Vec::with_capacity(reps);
                    for r in 0..reps {
                        let (t, scalar_last) = run(scene, &mut body, &params, Path::Scalar, None);
                        if r == 0 && scalar_last != last {
                            eprintln!("{kernel}: the scalar run ended elsewhere than the SIMD run");
                        }
                        scalar.push(t);
                    }
                    eprintln!(
                        "{kernel} 1/{rate} pearls={p}: deepest {:.3} mm ({} points by brute force, field off by up to {:.3} mm)",
                        depth.deepest * 1e3,
                        depth.brute,
                        depth.field_error * 1e3
                    );
                    let ns = |s: Vec<f64>| {
                        Timing::from_samples(s.into_iter().map(|t| t * 1e9 / per_step).collect())
                    };
                    let is_default = params.max_substep == defaults.max_substep
                        && p == defaults.pearls_per_segment;
                    let setting = format!("max_substep=1/{rate} pearls={p}");
                    for (path, time) in [(Path::Simd, ns(simd)), (Path::Scalar, ns(scalar))] {
                        rows.push(Row {
                            kernel: kernel.clone(),
                            setting: setting.clone(),
                            path,
                            element: "vertex-step",
                            time,
                            error_metric: metric,
                            error: depth.deepest.max(0.0),
                            is_default,
                        });
                    }
                }
            }
        }
    }
    rows
}

/// Strands of a scene.
fn scene_strands(scene: Scene) -> usize {
    match scene {
        Scene::Drape => CURTAIN,
        Scene::Sweep => 64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_against_sampling() {
        let cases = [
            // Crossing at a right angle 1 apart.
            (
                DVec3::new(-1., 0., 0.),
                DVec3::new(1., 0., 0.),
                DVec3::new(0., -1., 1.),
                DVec3::new(0., 1., 1.),
            ),
            // Parallel, overlapping.
            (
                DVec3::new(0., 0., 0.),
                DVec3::new(2., 0., 0.),
                DVec3::new(1., 0.5, 0.),
                DVec3::new(3., 0.5, 0.),
            ),
            // Skew, closest at the ends.
            (
                DVec3::new(0., 0., 0.),
                DVec3::new(1., 0.2, 0.),
                DVec3::new(2., 1., 0.3),
                DVec3::new(3., -1., 0.7),
            ),
            // A point segment.
            (
                DVec3::new(0.3, 0.4, 0.),
                DVec3::new(0.3, 0.4, 0.),
                DVec3::new(0., 0., 0.),
                DVec3::new(1., 0., 0.),
            ),
        ];
        for (p1, q1, p2, q2) in cases {
            let mut sampled = f64::INFINITY;
            for i in 0..=400 {
                for j in 0..=400 {
                    let a = p1 + (q1 - p1) * (i as f64 / 400.0);
                    let b = p2 + (q2 - p2) * (j as f64 / 400.0);
                    sampled = sampled.min(a.distance(b));
                }
            }
            let exact = segment_distance(p1, q1, p2, q2);
            assert!(
                exact <= sampled + 1e-12 && sampled - exact < 1e-4,
                "{exact} vs {sampled}"
            );
        }
    }

    #[test]
    fn sweep_goes_out_and_back_at_three_metres_a_second() {
        let s = Scene::Sweep;
        assert_eq!(s.offset(0.0).x, -0.25);
        let leg = 0.5 / SWEEP_SPEED;
        assert!((s.offset(leg * 0.999).x - 0.25).abs() < 1e-3);
        assert!((s.offset(leg * 1.5).x).abs() < 1e-5);
        let v = (s.offset(0.05).x - s.offset(0.04).x) / 0.01;
        assert!((v - SWEEP_SPEED).abs() < 1e-3, "{v}");
        assert_eq!(s.offset(10.0).x, -0.25);
        assert_eq!(Scene::Drape.offset(0.3), Vec3::ZERO);
    }
}
