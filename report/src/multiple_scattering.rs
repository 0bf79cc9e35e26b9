//! Multiple scattering: dual scattering (Zinke et al. 2008,
//! [`coif::shading::dual_scattering`]) and single scattering with an exact
//! shadow, against the Monte Carlo path tracer through explicit fibres
//! ([`coif::shading::path_tracer`]), which shares none of dual scattering's
//! assumptions (pbrt-v3's BSDF at every hit's own offset, all orders).
//!
//! Patches of camera rays are traced through fibre scenes lit by one
//! directional light (no environment); each method shades every ray's first
//! hit ([`accuracy::first_hits`]: the exact fibre count `n` and visibility
//! `D` toward the light from the fibre's axis) and the patch means are
//! compared with the tracer's ([`accuracy::relative_rms`] over the set's
//! patches and RGB). Three absorptions, pbrt-v3's eumelanin 0.3 (blond),
//! 1.3 (brown) and 8.0 (dark). Sets of patches, from the density fit of
//! [`coif::shading::dual_scattering::DEFAULT_FORWARD_DENSITY`] and `DEFAULT_BACKWARD_DENSITY`:
//!
//! - **held-out** (not fitted on): light toward (-0.4, 0.5, 0.8), tufts of
//!   volume fraction 0.1 and 0.25, 5 mm thick, three views (two from the
//!   lit side, one from behind): 6 patches;
//! - **training** (what the densities 0.4 and 0.35 were fitted on): light toward
//!   (0.3, 0.2, 1) on tufts of 0.05, 0.15, 0.3, 3 mm thick, and toward
//!   (0.6, -0.2, 0.7) on 0.08, 0.2, 4 mm thick, four views each: 20
//!   patches;
//! - **Sintel crown** (held out, real geometry): Sintel's render hairs as
//!   the frame pipeline interpolates them over her scalp triangles from
//!   her groom's guides (at rest after 0.5 s), at a real scalp's density
//!   ([`CROWN_HAIRS_PER_CM2`], each hair one fibre of radius 0.04 mm), in
//!   millimetres, clipped to a ball of radius [`CROWN_BALL_RADIUS`] whose
//!   centre is [`CROWN_DEPTH`] inside the outermost hair above her highest
//!   root; lit from above (toward (0.2, 1, 0.1), y up), seen from (0.3, 1,
//!   0.6) and (-0.9, 0.5, -0.3) through a 1.5 mm window: 2 patches (the
//!   setting states the hair count and the volume fraction). The head is
//!   not in the scene.
//!
//! Tufts are 40 x 40 mm of fibres of radius 0.04 mm (`path_tracer::tuft`,
//! seed 1), patches 1.5 mm wide; the tracer's settings: no environment,
//! depth up to 10,000, Russian roulette as the tracer does it.
//!
//! Kernels (error: relative RMS of the patch means; time: ns per shaded
//! sample of the method's kernel, in cache over 2,048 random samples, SIMD
//! and the scalar twin):
//!
//! - `multiple scattering <colour>`: single scattering with the exact
//!   shadow (`S D`, pbrt-v3's far field in a [`pbrt::Table`] of 64,
//!   [`pbrt::Table::scattering_simd`]) and dual scattering on the same
//!   table (`DualScattering::from_pbrt`, default settings: densities 0.4 and 0.35,
//!   64 entries; the table then [`DualScattering::shade_simd`], fused per
//!   block of eight as the frame shades), one row per set. The setting
//!   names the set and the tracer's relative standard error on it.
//! - `multiple scattering <colour> marschner`: the same with Marschner's
//!   table ([`marschner::Lut`] of 128, absorption half pbrt's `sigma_a` as
//!   the frame pipeline converts it, `DualScattering::from_marschner`; its
//!   `S` times `cos theta_i`). The tracer is pbrt's model, so this error
//!   mixes the models' difference with multiple scattering: the single
//!   scattering rows show the first alone.
//! - `multiple scattering path tracer`: the reference's own noise, the
//!   relative standard error of its patch means (as a relative RMS over the
//!   set) per colour and set, against ns per path (wall-clock time of the
//!   tracing on all threads times the threads, per path traced).
//! - `multiple scattering path tracer furnace`: the tracer's white furnace
//!   (`sigma_a` = 0, environment 1, no light) through a tuft of volume
//!   fraction 0.25 (20 x 20 x 5 mm): |mean - 1| (largest channel) against
//!   ns per path (one thread).
//!
//! Dual scattering is the pipeline's default (`FrameSettings::
//! multiple_scattering`), so its held-out rows are marked default.
//!
//! Counts: a full run traces [`FULL_RAYS`] rays of [`FULL_PATHS`] paths per
//! patch, a quick run [`QUICK_RAYS`] of [`QUICK_PATHS`] (noisier: the
//! noise is in the setting).

use super::timing::time_batch;
use super::{Options, Path, Row, Timing};
use coif::base::lanes::F32Lanes;
use coif::base::{SplitMix64, Vec3Lanes, LANES};
use coif::shading::dual_scattering::accuracy::{self, HitLighting};
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::path_tracer::{tuft, DirectionalLight, FibreScene, PathTracer, TuftParams};
use coif::shading::{marschner, pbrt, RgbBuffer, ShadingSamples};
use glam::Vec3;

/// The absorptions measured: name and pbrt-v3 eumelanin concentration.
pub const ABSORPTIONS: [(&str, f32); 3] = [("blond", 0.3), ("brown", 1.3), ("dark", 8.0)];

/// Camera rays per patch, full run.
pub const FULL_RAYS: usize = 512;
/// Paths per camera ray, full run.
pub const FULL_PATHS: usize = 64;
/// Camera rays per patch, quick run.
pub const QUICK_RAYS: usize = 256;
/// Paths per camera ray, quick run.
pub const QUICK_PATHS: usize = 32;

/// The pbrt table's resolution (the frame pipeline's).
pub const PBRT_RESOLUTION: usize = 64;
/// The Marschner table's resolution (the frame pipeline's).
pub const MARSCHNER_RESOLUTION: usize = 128;
/// Samples of the timed shading batch.
pub const TIMED_SAMPLES: usize = 2048;

/// Radius of the ball the Sintel crown region is clipped to (mm): two mean
/// free paths of light in hair this sparse. A path crosses `2 f / (pi r)`
/// fibres per mm in hair of volume fraction `f` and fibre radius `r`
/// (0.08 at `f` = 0.005, `r` = 0.04 mm: 12.6 mm between fibres), so the
/// hair that sends light back to a shaded point lies up to a few
/// centimetres round it. A ball of 6 mm (the first choice) cut that hair
/// away: beside its edge half of a hit's back hemisphere was empty, which
/// no count of the hair behind along the light can see, and the reference
/// was a lone wisp rather than a region of a head (MULTIPLE_SCATTERING.md,
/// "Sintel's crown: the diagnosis", with the errors at 6, 12, 18 and 24 mm;
/// `ms_diagnose --crown-radius R` measures any).
pub const CROWN_BALL_RADIUS: f32 = 24.0;
/// Depth of the ball's centre below the outermost hair above her highest
/// root (mm): inside the hair, its top layers lit.
pub const CROWN_DEPTH: f32 = 3.0;
/// Render hairs per cm^2 of the crown region: a real scalp's density, each
/// one fibre of radius 0.04 mm, as the tufts' (the frame draws 20 per cm^2, each
/// standing for several).
pub const CROWN_HAIRS_PER_CM2: f32 = 150.0;

/// Fibre radius of the tufts and of the crown's hairs (mm): a real hair's.
const TUFT_RADIUS: f32 = 0.04;
/// Width of a tuft patch (mm).
const PATCH_WINDOW: f32 = 1.5;
/// Seed of the camera rays and of the tracer.
const RAY_SEED: u64 = 3;
const TRACE_SEED: u64 = 7;
/// Longest path (scatterings) of the tracer.
const MAX_DEPTH: usize = 10_000;

// No commas in settings and metrics (the CSV's readers split on them)
// and no quotes (the plots escape them).

/// Error metric of the pbrt rows.
const VS_TRACER: &str = "relative RMS of patch means vs path tracer";
/// Error metric of the Marschner rows.
const VS_TRACER_MARSCHNER: &str =
    "relative RMS of patch means vs path tracer of the pbrt model (model difference + multiple scattering)";
/// Error metric of the tracer's noise rows.
const TRACER_NOISE: &str = "path tracer relative standard error";
/// Error metric of the furnace row.
const FURNACE: &str = "white furnace |mean - 1|";

/// A set of patches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Set {
    HeldOut,
    Training,
    Crown,
}

impl Set {
    const ALL: [Set; 3] = [Set::HeldOut, Set::Training, Set::Crown];
}

/// A patch: rays through a scene under a light, with their first hits.
struct Patch {
    set: Set,
    scene: usize,
    light: DirectionalLight,
    rays: Vec<(Vec3, Vec3)>,
    hits: Vec<Option<HitLighting>>,
}

/// The scenes and patches of every set, and the crown's description.
struct Cases {
    scenes: Vec<FibreScene>,
    patches: Vec<Patch>,
    crown: String,
}

fn light(to: Vec3) -> DirectionalLight {
    DirectionalLight {
        to_light: to.normalize(),
        irradiance: Vec3::ONE,
    }
}

impl Cases {
    fn new(rays: usize, crown_radius: f32) -> Cases {
        let mut cases = Cases {
            scenes: Vec::new(),
            patches: Vec::new(),
            crown: String::new(),
        };
        let v1 = [
            Vec3::new(0.0, 0.3, 1.0),
            Vec3::new(-0.5, 0.0, 1.0),
            Vec3::new(0.2, 0.8, 0.5),
            Vec3::new(0.3, 0.0, -1.0),
        ];
        let v2 = [
            Vec3::new(0.4, -0.3, 1.0),
            Vec3::new(0.0, 1.0, 0.3),
            Vec3::new(-0.2, 0.3, -1.0),
        ];
        let l1 = light(Vec3::new(0.3, 0.2, 1.0));
        let l2 = light(Vec3::new(-0.4, 0.5, 0.8));
        let l3 = light(Vec3::new(0.6, -0.2, 0.7));
        cases.tufts(Set::HeldOut, l2, &[0.1, 0.25], 5.0, &v2, rays);
        cases.tufts(Set::Training, l1, &[0.05, 0.15, 0.3], 3.0, &v1, rays);
        cases.tufts(Set::Training, l3, &[0.08, 0.2], 4.0, &v1, rays);
        cases.sintel_crown(rays, crown_radius);
        cases
    }

    fn tufts(
        &mut self,
        set: Set,
        light: DirectionalLight,
        fractions: &[f32],
        thickness: f32,
        views: &[Vec3],
        rays: usize,
    ) {
        for &volume_fraction in fractions {
            let tf = tuft(&TuftParams {
                length: 40.0,
                width: 40.0,
                thickness,
                radius: TUFT_RADIUS,
                volume_fraction,
                seed: 1,
            })
            .expect("valid tuft");
            for &view in views {
                let rays = tf
                    .camera_rays(view, PATCH_WINDOW, rays, RAY_SEED)
                    .expect("valid view");
                let hits = accuracy::first_hits(&tf.scene, &rays, light.to_light);
                self.patches.push(Patch {
                    set,
                    scene: self.scenes.len(),
                    light,
                    rays,
                    hits,
                });
            }
            self.scenes.push(tf.scene);
        }
    }

    /// Sintel's render hairs at a real scalp's density, clipped to the
    /// crown ball of `radius` (mm), lit from above, two views.
    fn sintel_crown(&mut self, rays: usize, radius: f32) {
        let (runs, counts, length, centre) = crown_hairs(radius);
        let ball = 4.0 / 3.0 * std::f32::consts::PI * radius.powi(3);
        let fraction = std::f32::consts::PI * TUFT_RADIUS * TUFT_RADIUS * length / ball;
        let scene = FibreScene::from_strands(&runs, &counts, TUFT_RADIUS).expect("crown hairs");
        self.crown = format!(
            "Sintel crown ({} hairs at {} per cm2 in a {:.0} mm ball; fibre radius {} mm; f {:.3}",
            counts.len(),
            CROWN_HAIRS_PER_CM2,
            radius,
            TUFT_RADIUS,
            fraction
        );
        let light = light(Vec3::new(0.2, 1.0, 0.1));
        for view in [Vec3::new(0.3, 1.0, 0.6), Vec3::new(-0.9, 0.5, -0.3)] {
            let rays = coif::shading::path_tracer::orthographic_rays(
                centre,
                view,
                2.0 * radius,
                PATCH_WINDOW,
                rays,
                RAY_SEED,
            )
            .expect("valid view");
            let hits = accuracy::first_hits(&scene, &rays, light.to_light);
            self.patches.push(Patch {
                set: Set::Crown,
                scene: self.scenes.len(),
                light,
                rays,
                hits,
            });
        }
        self.scenes.push(scene);
    }

    fn set_name(&self, set: Set) -> String {
        let n = self.patches.iter().filter(|p| p.set == set).count();
        match set {
            Set::HeldOut => format!("held-out tufts ({n} patches)"),
            Set::Training => format!("training tufts ({n} patches)"),
            Set::Crown => format!("{}; {n} views)", self.crown),
        }
    }
}

/// Sintel's render hairs as the frame interpolates them over her scalp at
/// [`CROWN_HAIRS_PER_CM2`] (groom at rest after 0.5 s of settling, no
/// LOD), in millimetres, clipped to the ball of `radius` around the crown:
/// the runs' points, their counts, their total length and the ball's
/// centre.
fn crown_hairs(radius: f32) -> (Vec<Vec3>, Vec<usize>, f32, Vec3) {
    use coif::frame::{FramePipeline, FrameSettings, HairScene, PrepareMode, ShadingModel};
    let scene = HairScene::sintel().expect("Sintel's scene");
    let settings = FrameSettings {
        width: 32,
        height: 32,
        shading: ShadingModel::KajiyaKay,
        shadows: false,
        real_hairs_per_cm2: CROWN_HAIRS_PER_CM2,
        render_hairs_per_cm2: CROWN_HAIRS_PER_CM2,
        min_lod_fraction: 1.0,
        prepare: PrepareMode::Reference,
        ..FrameSettings::default()
    };
    let mut pipeline = FramePipeline::new(&scene, settings, 0.5).expect("Sintel's pipeline");
    pipeline.frame(1.0 / 30.0, glam::Affine3A::IDENTITY);
    let origin = pipeline.strands().origin();
    let (vertices, per_hair) = pipeline.render_vertices();
    let hairs: Vec<Vec<Vec3>> = vertices
        .chunks(per_hair.max(1))
        .map(|h| {
            h.iter()
                .map(|v| ((Vec3::from(v.position).as_dvec3() + origin) * 1000.0).as_vec3())
                .collect()
        })
        .collect();
    // The ball sits CROWN_DEPTH inside the hair above the highest root.
    let top_root = hairs
        .iter()
        .map(|h| h[0])
        .max_by(|a, b| a.y.total_cmp(&b.y))
        .expect("a hair");
    let outer = hairs
        .iter()
        .flatten()
        .filter(|p| (p.x - top_root.x).hypot(p.z - top_root.z) < 1.0)
        .map(|p| p.y)
        .fold(top_root.y, f32::max);
    let centre = Vec3::new(top_root.x, outer - CROWN_DEPTH, top_root.z);
    let strands: Vec<&[Vec3]> = hairs.iter().map(|h| h.as_slice()).collect();
    let (runs, counts, length) = clip_to_ball(&strands, centre, radius);
    (runs, counts, length, centre)
}

/// The parts of `strands` inside the ball: points of runs, their counts,
/// and their total length.
fn clip_to_ball(strands: &[&[Vec3]], centre: Vec3, radius: f32) -> (Vec<Vec3>, Vec<usize>, f32) {
    let (mut points, mut counts, mut length) = (Vec::new(), Vec::new(), 0.0f32);
    for s in strands {
        let mut open = false;
        for w in s.windows(2) {
            let Some((a, b)) = clip_segment(w[0], w[1], centre, radius) else {
                open = false;
                continue;
            };
            if !(open && points.last() == Some(&a)) {
                points.push(a);
                counts.push(1);
            }
            points.push(b);
            *counts.last_mut().expect("a run") += 1;
            length += (b - a).length();
            // The run continues only if the segment left through its end.
            open = b == w[1];
        }
    }
    (points, counts, length)
}

/// The part of segment `a`-`b` inside the ball, if any.
fn clip_segment(a: Vec3, b: Vec3, centre: Vec3, radius: f32) -> Option<(Vec3, Vec3)> {
    let d = b - a;
    let f = a - centre;
    let (qa, qb, qc) = (d.dot(d), 2.0 * f.dot(d), f.dot(f) - radius * radius);
    if qa <= 0.0 {
        return None;
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let t0 = ((-qb - s) / (2.0 * qa)).max(0.0);
    let t1 = ((-qb + s) / (2.0 * qa)).min(1.0);
    if t1 <= t0 {
        return None;
    }
    let at = |t: f32| {
        if t <= 0.0 {
            a
        } else if t >= 1.0 {
            b
        } else {
            a + d * t
        }
    };
    Some((at(t0), at(t1)))
}

/// One colour's materials.
struct Material {
    name: &'static str,
    params: pbrt::Params,
    table: pbrt::Table,
    dual: DualScattering,
    lut: marschner::Lut,
    dual_lut: DualScattering,
}

impl Material {
    fn new(name: &'static str, eumelanin: f32) -> Material {
        let sigma_a = pbrt::sigma_a_from_concentration(eumelanin, 0.0);
        let params = pbrt::Params {
            sigma_a,
            ..pbrt::Params::default()
        };
        let table = pbrt::Table::new(&params, PBRT_RESOLUTION).expect("valid material");
        let settings = DualScatteringSettings::default();
        let dual = DualScattering::from_pbrt(&table, settings).expect("default settings");
        let lut = marschner::Lut::new(
            &marschner::Params {
                absorption: sigma_a * 0.5,
                ..marschner::Params::default()
            },
            MARSCHNER_RESOLUTION,
        );
        let dual_lut = DualScattering::from_marschner(&lut, settings).expect("default settings");
        Material {
            name,
            params,
            table,
            dual,
            lut,
            dual_lut,
        }
    }
}

/// Patch means of one patch: the tracer's, its standard error, and the
/// four methods' (pbrt single, pbrt dual, Marschner single, Marschner dual).
struct Means {
    traced: Vec3,
    standard_error: Vec3,
    methods: [Vec3; 4],
}

/// The four methods' mean radiance over `hits` (misses count as 0).
fn shade(material: &Material, hits: &[Option<HitLighting>], irradiance: Vec3) -> [Vec3; 4] {
    let (dual, single) = accuracy::shade_hits(hits, &material.table, &material.dual, irradiance);
    let (mut m_single, mut m_dual) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for h in hits.iter().flatten() {
        let cos_i = (1.0 - h.wi.dot(h.tangent).powi(2)).max(0.0).sqrt();
        let s = material.lut.scattering(h.tangent, h.wi, h.wo);
        let f = material
            .dual_lut
            .shade_layered(s, h.tangent, h.wi, h.wo, h.fibres, h.behind, h.direct);
        if f.is_finite() && s.is_finite() {
            m_single += (s * (h.direct * cos_i) * irradiance).as_dvec3();
            m_dual += (f * cos_i * irradiance).as_dvec3();
        }
    }
    let count = hits.len().max(1) as f64;
    [
        single,
        dual,
        (m_single / count).as_vec3(),
        (m_dual / count).as_vec3(),
    ]
}

/// The measured family: every colour's rows, then the furnace.
pub fn rows(options: Options) -> Vec<Row> {
    let (rays, paths) = if options.quick {
        (QUICK_RAYS, QUICK_PATHS)
    } else {
        (FULL_RAYS, FULL_PATHS)
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cases = Cases::new(rays, CROWN_BALL_RADIUS);
    let bench = Bench::new(options);
    let mut rows = Vec::new();
    for (name, eumelanin) in ABSORPTIONS {
        let material = Material::new(name, eumelanin);
        let mut means = Vec::with_capacity(cases.patches.len());
        let (mut traced_paths, mut trace_ns) = (0usize, 0.0f64);
        for p in &cases.patches {
            let tracer = PathTracer::new(&material.params, Some(p.light), Vec3::ZERO, MAX_DEPTH)
                .expect("valid tracer");
            let t0 = std::time::Instant::now();
            let estimates = tracer
                .estimate_threaded(&cases.scenes[p.scene], &p.rays, paths, TRACE_SEED, threads)
                .expect("paths per ray > 0");
            trace_ns += t0.elapsed().as_nanos() as f64 * threads as f64;
            traced_paths += p.rays.len() * paths;
            let n = p.rays.len().max(1) as f32;
            let traced = estimates.iter().map(|e| e.mean).sum::<Vec3>() / n;
            let var = estimates
                .iter()
                .map(|e| e.standard_error * e.standard_error)
                .sum::<Vec3>();
            means.push(Means {
                traced,
                standard_error: Vec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt()) / n,
                methods: shade(&material, &p.hits, p.light.irradiance),
            });
        }
        let ns_per_path = trace_ns / traced_paths.max(1) as f64;
        rows.extend(colour_rows(&cases, &material, &means, &bench, ns_per_path));
    }
    rows.push(furnace(options));
    rows
}

/// One colour's rows: pbrt and Marschner methods per set, and the
/// tracer's noise per set.
fn colour_rows(
    cases: &Cases,
    material: &Material,
    means: &[Means],
    bench: &Bench,
    ns_per_path: f64,
) -> Vec<Row> {
    let times = bench.times(material);
    let pbrt_kernel = format!("multiple scattering {}", material.name);
    let marschner_kernel = format!("multiple scattering {} marschner", material.name);
    let methods: [(&str, &str, &'static str, bool); 4] = [
        (&pbrt_kernel, "single with exact shadow", VS_TRACER, false),
        (&pbrt_kernel, "dual on pbrt table 64", VS_TRACER, true),
        (
            &marschner_kernel,
            "single with exact shadow",
            VS_TRACER_MARSCHNER,
            false,
        ),
        (
            &marschner_kernel,
            "dual on marschner table 128",
            VS_TRACER_MARSCHNER,
            true,
        ),
    ];
    let mut rows = Vec::new();
    for (m, &(kernel, method, metric, dual)) in methods.iter().enumerate() {
        for set in Set::ALL {
            let of_set = cases
                .patches
                .iter()
                .zip(means)
                .filter(|(p, _)| p.set == set)
                .map(|(_, m)| m);
            let error = accuracy::relative_rms(of_set.clone().map(|x| (x.methods[m], x.traced)));
            let noise = noise(of_set);
            let setting = format!(
                "{method}: {} (tracer noise {noise:.3})",
                cases.set_name(set)
            );
            for (path, time) in [(Path::Simd, times[m].0), (Path::Scalar, times[m].1)] {
                rows.push(Row {
                    kernel: kernel.to_string(),
                    setting: setting.clone(),
                    path,
                    element: "sample",
                    time,
                    error_metric: metric,
                    error,
                    is_default: dual && set == Set::HeldOut,
                });
            }
        }
    }
    for set in Set::ALL {
        let of_set = cases
            .patches
            .iter()
            .zip(means)
            .filter(|(p, _)| p.set == set)
            .map(|(_, m)| m);
        rows.push(Row {
            kernel: "multiple scattering path tracer".into(),
            setting: format!("{}: {}", material.name, cases.set_name(set)),
            path: Path::Scalar,
            element: "path",
            time: Timing {
                median: ns_per_path,
                min: ns_per_path,
                max: ns_per_path,
            },
            error_metric: TRACER_NOISE,
            error: noise(of_set),
            is_default: false,
        });
    }
    rows
}

/// The tracer's relative standard error over patches: the relative RMS of
/// (mean + standard error) against the mean.
fn noise<'a>(means: impl Iterator<Item = &'a Means>) -> f64 {
    accuracy::relative_rms(means.map(|m| (m.traced + m.standard_error, m.traced)))
}

/// The white furnace: `sigma_a` = 0, environment 1, no light, a tuft of
/// volume fraction 0.25; |mean - 1| over every path, ns per path on one
/// thread.
fn furnace(options: Options) -> Row {
    let (rays, paths) = if options.quick { (64, 16) } else { (128, 32) };
    let params = pbrt::Params {
        sigma_a: Vec3::ZERO,
        ..pbrt::Params::default()
    };
    let tracer = PathTracer::new(&params, None, Vec3::ONE, MAX_DEPTH).expect("white tracer");
    let tf = tuft(&TuftParams {
        length: 20.0,
        width: 20.0,
        thickness: 5.0,
        radius: TUFT_RADIUS,
        volume_fraction: 0.25,
        seed: 1,
    })
    .expect("valid tuft");
    let rays = tf
        .camera_rays(Vec3::new(0.4, -0.3, 1.0), PATCH_WINDOW, rays, RAY_SEED)
        .expect("valid view");
    let mut mean = Vec3::ZERO;
    let mut scatterings = 0.0f32;
    let time = time_batch(options.reps().min(5), rays.len() * paths, || {
        let estimates = tracer
            .estimate(&tf.scene, &rays, paths, TRACE_SEED)
            .expect("paths per ray > 0");
        let n = estimates.len().max(1) as f32;
        mean = estimates.iter().map(|e| e.mean).sum::<Vec3>() / n;
        scatterings = estimates.iter().map(|e| e.mean_scatterings).sum::<f32>() / n;
    });
    let error = (mean - Vec3::ONE).abs().max_element() as f64;
    Row {
        kernel: "multiple scattering path tracer furnace".into(),
        setting: format!(
            "white furnace: tuft f 0.25; {} paths; {scatterings:.1} scatterings per path",
            rays.len() * paths
        ),
        path: Path::Scalar,
        element: "path",
        time,
        error_metric: FURNACE,
        error,
        is_default: false,
    }
}

/// The timed shading samples: random directions, fibre counts and direct
/// fractions as `benches/shading.rs` draws them.
struct Bench {
    samples: ShadingSamples,
    fibres: Vec<f32>,
    direct: Vec<f32>,
    reps: usize,
}

impl Bench {
    fn new(options: Options) -> Bench {
        let mut rng = SplitMix64::new(6);
        let mut samples = ShadingSamples::with_capacity(TIMED_SAMPLES);
        for _ in 0..TIMED_SAMPLES {
            samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        }
        let mut rng = SplitMix64::new(7);
        let fibres: Vec<f32> = (0..TIMED_SAMPLES).map(|_| rng.range(0.0, 40.0)).collect();
        let direct = fibres.iter().map(|n| (-0.4 * n).exp()).collect();
        Bench {
            samples,
            fibres,
            direct,
            reps: options.reps(),
        }
    }

    /// (SIMD, scalar) time of the four methods, in the order of [`shade`].
    fn times(&self, material: &Material) -> [(Timing, Timing); 4] {
        let (table, lut) = (&material.table, &material.lut);
        [
            self.method(
                |t, wi, wo| table.scattering_simd(t, wi, wo),
                |t, wi, wo| table.scattering(t, wi, wo),
                None,
            ),
            self.method(
                |t, wi, wo| table.scattering_simd(t, wi, wo),
                |t, wi, wo| table.scattering(t, wi, wo),
                Some(&material.dual),
            ),
            self.method(
                |t, wi, wo| lut.scattering_simd(t, wi, wo),
                |t, wi, wo| lut.scattering(t, wi, wo),
                None,
            ),
            self.method(
                |t, wi, wo| lut.scattering_simd(t, wi, wo),
                |t, wi, wo| lut.scattering(t, wi, wo),
                Some(&material.dual_lut),
            ),
        ]
    }

    /// Single scattering alone (`dual` None) or with dual scattering,
    /// fused per block (SIMD) or per sample (scalar).
    fn method(
        &self,
        single_simd: impl Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes,
        single: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
        dual: Option<&DualScattering>,
    ) -> (Timing, Timing) {
        let n = self.samples.len();
        let mut out = RgbBuffer::zeros(n);
        let simd = time_batch(self.reps, n, || {
            let s = std::hint::black_box(&self.samples);
            for start in (0..n).step_by(LANES) {
                let (t, wi, wo) = s.load_block(start);
                let f = single_simd(t, wi, wo);
                let f = match dual {
                    Some(ds) => {
                        let fibres = F32Lanes::new(
                            self.fibres[start..start + LANES]
                                .try_into()
                                .expect("8 lanes"),
                        );
                        let direct = F32Lanes::new(
                            self.direct[start..start + LANES]
                                .try_into()
                                .expect("8 lanes"),
                        );
                        // The frame's hair behind each point: 20 fibres.
                        let behind = F32Lanes::splat(20.0);
                        ds.shade_layered_simd(f, t, wi, wo, fibres, behind, direct)
                    }
                    None => f,
                };
                out.store_block(start, f);
            }
            std::hint::black_box(&out);
        });
        let scalar = time_batch(self.reps, n, || {
            let s = std::hint::black_box(&self.samples);
            for k in 0..n {
                let (t, wi, wo) = s.get(k);
                let f = single(t, wi, wo);
                let f = match dual {
                    Some(ds) => {
                        ds.shade_layered(f, t, wi, wo, self.fibres[k], 20.0, self.direct[k])
                    }
                    None => f,
                };
                out.set(k, f);
            }
            std::hint::black_box(&out);
        });
        (simd, scalar)
    }
}

/// Diagnostics of the comparison (`examples/ms_diagnose.rs`): per colour
/// and patch, the tracer's radiance split by scattering order (paths cut
/// after 1, 2 and 3 scatterings, the same random numbers, so the
/// differences are the orders' contributions), the hits' geometry toward
/// the light (`n`, `m`, `D`), and dual scattering's three terms (`D S`,
/// the local backscatter `D d_b f_back c`, the scattered light), as text.
pub mod diagnose {
    use super::*;

    /// The traced means of one patch: orders 1, 2, 3 and all, and the
    /// standard error of all.
    #[derive(Clone, Debug)]
    pub struct Traced {
        /// Mean radiance of paths cut after 1, 2, 3 scatterings, and uncut.
        pub cut: [Vec3; 4],
        /// Standard error of the uncut mean.
        pub standard_error: Vec3,
        /// Per ray: the means cut after 1, 2 scatterings and uncut.
        pub per_ray: Vec<[Vec3; 3]>,
    }

    /// One patch's description: set name, scene index, hits.
    pub struct PatchInfo<'a> {
        /// "training", "held-out" or "crown".
        pub set: &'static str,
        /// The patch's light.
        pub light: DirectionalLight,
        /// First hits.
        pub hits: &'a [Option<HitLighting>],
        /// Mean over the hits of the fibres behind along the light's line
        /// (`m`) and of the hemisphere's: the mean over 64 directions
        /// `w` uniform in the hemisphere around `-wi` of the fibres crossed
        /// times `cos(w, -wi)` (equal to `m` in a laterally infinite slab).
        pub behind: (f32, f32),
    }

    /// [`PatchInfo::behind`] of a patch.
    fn hemisphere(scene: &FibreScene, rays: &[(Vec3, Vec3)], wi: Vec3) -> (f32, f32) {
        let mut rng = SplitMix64::new(11);
        let (mut line, mut hemi, mut count) = (0.0f64, 0.0f64, 0usize);
        let back = -wi;
        let (u, v) = back.any_orthonormal_pair();
        for &(o, d) in rays {
            let Some(hit) = scene.intersect(o, d, f32::INFINITY) else {
                continue;
            };
            let Some((a, b)) = scene.segment(hit.segment) else {
                continue;
            };
            let ab = b - a;
            let t = ((hit.point - a).dot(ab) / ab.length_squared().max(1e-30)).clamp(0.0, 1.0);
            let axis = a + ab * t;
            line += scene.crossings(axis, back, f32::INFINITY) as f64;
            let mut sum = 0.0f64;
            for _ in 0..64 {
                let c = rng.next_f32();
                let phi = std::f32::consts::TAU * rng.next_f32();
                let s = (1.0 - c * c).max(0.0).sqrt();
                let w = back * c + (u * phi.cos() + v * phi.sin()) * s;
                sum += scene.crossings(axis, w, f32::INFINITY) as f64 * c as f64;
            }
            hemi += sum / 64.0;
            count += 1;
        }
        let n = count.max(1) as f64;
        ((line / n) as f32, (hemi / n) as f32)
    }

    /// Traces every patch of every colour (orders split) and returns, per
    /// colour, per patch, the traced means; `rays` and `paths` per patch,
    /// the crown's ball of `crown_radius` (mm). Then calls `report` with
    /// the cases.
    pub fn run(
        rays: usize,
        paths: usize,
        only_crown: bool,
        crown_radius: f32,
        report: impl Fn(&str, f32, &[PatchInfo], &[Traced]),
    ) {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let cases = Cases::new(rays, crown_radius);
        for (name, eumelanin) in ABSORPTIONS {
            let sigma_a = pbrt::sigma_a_from_concentration(eumelanin, 0.0);
            let params = pbrt::Params {
                sigma_a,
                ..pbrt::Params::default()
            };
            let mut infos = Vec::new();
            let mut traced = Vec::new();
            for p in &cases.patches {
                if only_crown && p.set != Set::Crown {
                    continue;
                }
                let mut cut = [Vec3::ZERO; 4];
                let mut se = Vec3::ZERO;
                let mut per_ray = vec![[Vec3::ZERO; 3]; p.rays.len()];
                for (j, depth) in [1, 2, 3, MAX_DEPTH].into_iter().enumerate() {
                    let tracer = PathTracer::new(&params, Some(p.light), Vec3::ZERO, depth)
                        .expect("valid tracer");
                    let est = tracer
                        .estimate_threaded(
                            &cases.scenes[p.scene],
                            &p.rays,
                            paths,
                            TRACE_SEED,
                            threads,
                        )
                        .expect("paths");
                    let n = p.rays.len().max(1) as f32;
                    cut[j] = est.iter().map(|e| e.mean).sum::<Vec3>() / n;
                    let slot = [Some(0), Some(1), None, Some(2)][j];
                    if let Some(slot) = slot {
                        for (r, e) in per_ray.iter_mut().zip(&est) {
                            r[slot] = e.mean;
                        }
                    }
                    if depth == MAX_DEPTH {
                        let var = est
                            .iter()
                            .map(|e| e.standard_error * e.standard_error)
                            .sum::<Vec3>();
                        se = Vec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt()) / n;
                    }
                }
                traced.push(Traced {
                    cut,
                    standard_error: se,
                    per_ray,
                });
                infos.push(PatchInfo {
                    set: match p.set {
                        Set::HeldOut => "held-out",
                        Set::Training => "training",
                        Set::Crown => "crown",
                    },
                    light: p.light,
                    hits: &p.hits,
                    behind: hemisphere(&cases.scenes[p.scene], &p.rays, p.light.to_light),
                });
            }
            report(name, eumelanin, &infos, &traced);
        }
    }
}
