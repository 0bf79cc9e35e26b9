//! `cargo run --release`: the frame pipeline rendered to a picture.
//!
//! By default: Sintel (her bust and her groom's 228 guides, shipped in
//! `assets/sintel`, CC BY 3.0 Blender Foundation) with interpolated hair,
//! three seconds of motion (a head turn, then a gust of wind), the guides
//! colliding with her bust's distance field, `hair.png` (512 x 512) and a
//! per-stage timing table, the frame's tasks on every core (`--threads`:
//! the calling thread and a worker per other core, `tasks::Workers`). `--scene sphere` is the built-in sphere head with
//! grown guides and a bow's silk ribbons. See `--help`.

/// `println!` that goes quiet once standard output is closed, as when it
/// is piped into `head` (`println!` panics on a broken pipe): the run goes
/// on and still writes every file it was asked for.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        use std::sync::atomic::Ordering;
        if !crate::STDOUT_CLOSED.load(Ordering::Relaxed) {
            if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
                if e.kind() == std::io::ErrorKind::BrokenPipe {
                    crate::STDOUT_CLOSED.store(true, Ordering::Relaxed);
                }
            }
        }
    }};
}

/// Standard output was closed (a broken pipe): [`out!`] prints nothing more.
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

mod crowd;

use clap::Parser;
use coif::base::tasks::{Executor, Serial};
use coif::frame::{
    motion, FramePipeline, FrameSettings, FrameStats, HairColor, HairScene, PrepareMode,
    ShadingModel, DEFAULT_SHADOW_THINNING,
};
use coif::geometry::scene::GrowOptions;
use coif::kernels::SimParams;
use coif::render::RgbImage;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Simulate, level-of-detail, shade and rasterise hair; write a PNG.
#[derive(Parser, Debug)]
#[command(
    name = "coif",
    version,
    about = "Simulate, level-of-detail, shade and rasterise hair; write a PNG and a per-stage timing table.",
    allow_negative_numbers = true
)]
struct Cli {
    /// The built-in scene: sintel (her bust and groom, the default) or
    /// sphere (a sphere head with guides grown over its scalp, 1,783 of the
    /// 2,048 grown kept off the face, and a bow's ribbons).
    /// With --groom: sintel puts the groom on Sintel's bust, sphere on the
    /// head proxy fitted to its roots.
    #[arg(long, value_parser = parse_scene)]
    scene: Option<SceneKind>,
    /// Groom file to draw (TressFX 4 .tfx or cyHair .hair, centimetres);
    /// a bare file name not found here is looked up in the shared groom
    /// folder beside the repository (`ratboy_mohawk.tfx`). Without --mesh
    /// (or --scene sintel) it gets a head proxy fitted to its roots.
    #[arg(long, value_name = "PATH")]
    groom: Option<PathBuf>,
    /// Body mesh for --groom (Wavefront OBJ in the groom's frame and
    /// units, centimetres): drawn under the hair, the guides collide with
    /// its distance field.
    #[arg(
        long,
        value_name = "PATH",
        requires = "groom",
        conflicts_with = "scene"
    )]
    mesh: Option<PathBuf>,
    /// Local shape stiffness in [0, 1]: springs keep each segment's groomed
    /// vector in the head's frame, the groom solved as their rest state
    /// (sag-free); softer swings more. Default: 0.7 for Sintel and a loaded
    /// groom (they keep their style and swing), 0 for the sphere head (its
    /// guides grow straight out and must drape).
    #[arg(long, value_name = "K")]
    local_shape: Option<f32>,
    /// Hair-hair volume in [0, 1]: hair packed denser than its groom is
    /// pushed apart (the hair grid). Default: 1 for Sintel and grooms on a
    /// mesh, 0 otherwise.
    #[arg(long, value_name = "K")]
    volume: Option<f32>,
    /// Hair-hair friction in [0, 1]: each vertex's velocity relative to the
    /// hair around it removed at this rate per step. Default: as --volume.
    #[arg(long, value_name = "K")]
    hair_friction: Option<f32>,
    /// Hair shading model: pbrt (pbrt-v3 far-field table), marschner
    /// (Marschner 2003 table), both with multiple scattering, or
    /// kajiya-kay (cheapest).
    #[arg(long, default_value = "pbrt", value_parser = parse_model)]
    shading: ShadingModel,
    /// Hair colour of the physically based models: blond, brown or dark
    /// (melanin concentrations, d'Eon et al. 2011).
    #[arg(long, default_value = "brown", value_parser = parse_color)]
    hair_color: HairColor,
    /// Single scattering only for marschner and pbrt (by default they add
    /// multiple scattering by dual scattering, Zinke et al. 2008).
    #[arg(long)]
    single_scattering: bool,
    /// Frames of motion to simulate (at --fps); the last one is written.
    #[arg(long, default_value_t = 90)]
    frames: usize,
    /// Frames per second of the motion (1 to 1000).
    #[arg(long, default_value_t = 30.0, value_parser = parse_fps)]
    fps: f32,
    /// Image size, WIDTHxHEIGHT (overrides --width and --height).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(usize, usize)>,
    /// Image width in pixels (1 to 8192).
    #[arg(long, default_value_t = 512, value_parser = pixels)]
    width: usize,
    /// Image height in pixels (1 to 8192).
    #[arg(long, default_value_t = 512, value_parser = pixels)]
    height: usize,
    /// Output PNG of the last frame.
    #[arg(long, short, default_value = "hair.png")]
    output: PathBuf,
    /// Also write a contact sheet: 6 frames of the motion, 3 x 2, in one PNG.
    #[arg(long, value_name = "PATH")]
    sheet: Option<PathBuf>,
    /// Also render every N-th frame (for the timing table; 1 = every
    /// frame, 0 = only the written ones). Other frames only simulate.
    #[arg(long, default_value_t = 10, value_name = "N")]
    render_every: usize,
    /// Most guides kept from a groom (every k-th strand; 4, to fit a head
    /// to their roots, to 2^20).
    #[arg(long, default_value_t = 2048, value_parser = parse_max_guides)]
    max_guides: usize,
    /// Camera direction from the hair, X,Y,Z (default: the scene's own; the
    /// built-in head is seen from the front left, grooms from the side).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_view)]
    view: Option<glam::Vec3>,
    /// Leave out hair self-shadowing (the opacity shadow map).
    #[arg(long)]
    no_shadows: bool,
    /// Leave out the silk ribbons tied to the head (a bow's two tails,
    /// simulated as cloth patches).
    #[arg(long)]
    no_ribbon: bool,
    /// Render hairs per cm^2 (each widened to keep a real scalp's coverage).
    /// Default: 20 for Sintel and grooms on a mesh (half the hairs of 40
    /// and the same picture at 512 px: the distance LOD draws about 7,000
    /// either way), 40 for the sphere head and grooms on a head proxy. From
    /// 0.01 to 250 (a real scalp's density).
    #[arg(long, value_parser = parse_density)]
    density: Option<f32>,
    /// Prepare pass: fused (one pass per group of hairs) or reference
    /// (stage by stage, the shadow map from every hair).
    #[arg(long, default_value = "fused", value_parser = parse_prepare)]
    prepare: PrepareMode,
    /// The fused pass builds the shadow map from every K-th group of render
    /// hairs (1 = all of them).
    #[arg(long, default_value_t = DEFAULT_SHADOW_THINNING, value_name = "K")]
    shadow_thinning: usize,
    /// Draw the hair segments hidden behind the head too (they are culled
    /// by default: exact, the same picture; this measures what it saves).
    #[arg(long)]
    no_occlusion_culling: bool,
    /// Also write the per-stage times as CSV (`stage,runs,mean_ms,last_ms`).
    #[arg(long, value_name = "PATH")]
    timings_csv: Option<PathBuf>,
    /// Also write the whole motion as an animated PNG (every
    /// --animation-every-th frame, played at the motion's speed, looping).
    #[arg(long, value_name = "PATH")]
    animation: Option<PathBuf>,
    /// Frames of the motion per frame of the animation.
    #[arg(long, default_value_t = 1, value_name = "N")]
    animation_every: usize,
    /// Simulate a crowd of N characters instead (no picture): the
    /// simulation cost with and without simulation LOD, off-screen
    /// following and sleeping, and the error per level. Steps of 1/60 s
    /// (--fps does not apply); N from 1 to 1024.
    #[arg(long, value_name = "N", value_parser = parse_crowd)]
    crowd: Option<usize>,
    /// Threads running the frame's parallel stages (the hair's and the
    /// ribbons' simulation, the shadow-map build, the prepare pass, the
    /// hair's runs of tiles; with --crowd, the characters): N threads, the
    /// calling thread and N - 1 workers started once (coif's `Workers`),
    /// 0 = one per core; 1 = the calling thread only.
    /// The picture has the same bytes at any thread count. At most 256.
    #[arg(long, default_value_t = 0, value_name = "N", value_parser = parse_threads)]
    threads: usize,
}

/// The executor of `--threads`: the calling thread for 1, else
/// [`Workers`](coif::base::tasks::Workers): that many threads, the caller's
/// included (0 = one per core), started once.
fn executor(threads: usize) -> Result<Box<dyn Executor>, Box<dyn std::error::Error>> {
    if threads == 1 {
        return Ok(Box::new(Serial));
    }
    Ok(Box::new(coif::base::tasks::Workers::new(threads)?))
}

/// The built-in scenes of `--scene`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SceneKind {
    Sintel,
    Sphere,
}

fn parse_scene(s: &str) -> Result<SceneKind, String> {
    match s {
        "sintel" => Ok(SceneKind::Sintel),
        "sphere" => Ok(SceneKind::Sphere),
        _ => Err(format!("unknown scene {s:?} (sintel, sphere)")),
    }
}

fn parse_prepare(s: &str) -> Result<PrepareMode, String> {
    match s {
        "fused" => Ok(PrepareMode::Fused),
        "reference" => Ok(PrepareMode::Reference),
        _ => Err(format!("unknown prepare pass {s:?} (fused, reference)")),
    }
}

fn parse_model(s: &str) -> Result<ShadingModel, String> {
    s.parse()
}

fn parse_color(s: &str) -> Result<HairColor, String> {
    s.parse()
}

fn parse_view(s: &str) -> Result<glam::Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>().map_err(|e| format!("{c:?}: {e}")))
        .collect::<Result<_, _>>()?;
    // Any finite direction: scaled by its largest component first, so
    // that neither 1e30 (whose square overflows) nor 1e-30 is lost.
    let direction = match v[..] {
        [x, y, z] => {
            let v = glam::Vec3::new(x, y, z);
            let m = v.abs().max_element();
            (v.is_finite() && m > 0.0)
                .then(|| (v / m).try_normalize())
                .flatten()
        }
        _ => None,
    };
    direction.ok_or_else(|| format!("expected three finite numbers X,Y,Z, not all zero, got {s:?}"))
}

fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {s:?}"))?;
    let w: usize = w.trim().parse().map_err(|e| format!("width: {e}"))?;
    let h: usize = h.trim().parse().map_err(|e| format!("height: {e}"))?;
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        return Err("width and height must be 1..=8192".into());
    }
    Ok((w, h))
}

/// A number in `range` (NaN never is), or a message with the range.
fn in_range<T>(s: &str, range: std::ops::RangeInclusive<T>) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display,
    T::Err: std::fmt::Display,
{
    let v: T = s.trim().parse().map_err(|e| format!("{s:?}: {e}"))?;
    if range.contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "expected {} to {}, got {s:?}",
            range.start(),
            range.end()
        ))
    }
}

/// `--width` and `--height`: 1 to 8192, as `--size`.
fn pixels(s: &str) -> Result<usize, String> {
    in_range(s, 1..=8192)
}

/// `--max-guides`: at least 4 (a head is fitted to the kept roots), at
/// most 2^20.
fn parse_max_guides(s: &str) -> Result<usize, String> {
    in_range(s, 4..=1 << 20)
}

/// `--fps`: 1 to 1000 frames per second (a step of at most a second).
fn parse_fps(s: &str) -> Result<f32, String> {
    in_range(s, 1.0..=1000.0)
}

/// `--density`: render hairs per cm^2, 0.01 to 250.
fn parse_density(s: &str) -> Result<f32, String> {
    in_range(s, 0.01..=250.0)
}

/// `--crowd`: 1 to 1024 characters.
fn parse_crowd(s: &str) -> Result<usize, String> {
    in_range(s, 1..=1024)
}

/// `--threads`: 0 (one per core) to 256.
fn parse_threads(s: &str) -> Result<usize, String> {
    in_range(s, 0..=256)
}

/// Hair-against-hair volume and friction from the options: each as given;
/// an unset volume is 1 where the hair sits on a body mesh (Sintel, a
/// groom with `--mesh`) and 0 otherwise, and an unset friction follows the
/// volume (so `--volume 0` turns the hair grid off).
fn hair_against_hair(volume: Option<f32>, friction: Option<f32>, on_body: bool) -> (f32, f32) {
    let volume = volume.unwrap_or(if on_body { 1.0 } else { 0.0 });
    (volume, friction.unwrap_or(volume))
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("coif: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Where `--groom PATH` is looked for, in order: `path` itself, then, for a
/// bare file name, the same name in the shared groom folder beside the
/// repository (`../shared/data/grooms`, from the working directory and from
/// the workspace root).
fn groom_candidates(path: &Path) -> Vec<PathBuf> {
    let mut out = vec![path.to_path_buf()];
    let bare = path.parent().is_none_or(|p| p.as_os_str().is_empty());
    if bare {
        let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for root in [Path::new("."), workspace.as_path()] {
            out.push(root.join("../shared/data/grooms").join(path));
        }
    }
    out
}

/// The first of [`groom_candidates`] that exists, or an error that says
/// where it looked and what a groom is.
fn groom_path(path: &Path) -> Result<PathBuf, String> {
    let candidates = groom_candidates(path);
    if let Some(found) = candidates.iter().find(|p| p.exists()) {
        return Ok(found.clone());
    }
    let looked: Vec<String> = candidates.iter().map(|p| p.display().to_string()).collect();
    Err(format!(
        "no groom file {}: looked at {} (a groom is a TressFX .tfx or cyHair .hair file; \
         the shared ones, ratboy_mohawk.tfx and sintel_lite.tfx, are in shared/data/grooms \
         beside the repository)",
        path.display(),
        looked.join(", ")
    ))
}

/// Reads a file the scene needs, saying which file failed and why.
fn read_file(path: &Path, what: &str) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("cannot read {what} {}: {e}", path.display()))
}

/// The scene of the options: Sintel by default; `--scene sphere` the
/// built-in sphere head; `--groom` on `--mesh`, on Sintel's bust
/// (`--scene sintel`) or on a head proxy. Returns the scene (without
/// ribbons under `--no-ribbon`) and a line describing it.
fn load_scene(cli: &Cli) -> Result<(HairScene, String), Box<dyn std::error::Error>> {
    let (scene, what) = match &cli.groom {
        Some(path) => {
            let path = &groom_path(path)?;
            let bytes = read_file(path, "groom")?;
            let groom =
                coif::groom::load(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            let (scene, on) = match (&cli.mesh, cli.scene) {
                (Some(mesh), _) => {
                    let text = read_file(mesh, "mesh")?;
                    let mesh_data = coif::geometry::mesh::TriangleMesh::from_obj(&text, 0.01)
                        .map_err(|e| format!("{}: {e}", mesh.display()))?;
                    let scene = HairScene::on_mesh(&groom, mesh_data, cli.max_guides, 32)
                        .map_err(|e| format!("{} on {}: {e}", path.display(), mesh.display()))?;
                    (scene, format!("on {}", mesh.display()))
                }
                (None, Some(SceneKind::Sintel)) => {
                    let bust = HairScene::sintel_bust()?;
                    let scene = HairScene::on_mesh(&groom, bust, cli.max_guides, 32)?;
                    (scene, "on Sintel's bust".to_string())
                }
                (None, _) => (
                    HairScene::from_groom(&groom, cli.max_guides, 32)?,
                    "on a head proxy".to_string(),
                ),
            };
            let what = format!(
                "{} ({} strands, {} kept as guides) {on}",
                path.display(),
                groom.strand_count(),
                scene.guide_count()
            );
            (scene, what)
        }
        None if cli.scene == Some(SceneKind::Sphere) => {
            let scene = HairScene::procedural(&GrowOptions {
                strand_count: 2048,
                curl: 0.15,
                ..GrowOptions::default()
            })?;
            let what = format!(
                "built-in sphere head, {} guides grown off the face",
                scene.guide_count()
            );
            (scene, what)
        }
        None => {
            let scene = HairScene::sintel()?;
            let what = format!(
                "Sintel (c) Blender Foundation | durian.blender.org, CC BY 3.0: her bust and \
                 {} guides",
                scene.guide_count()
            );
            (scene, what)
        }
    };
    let scene = if cli.no_ribbon {
        scene.without_ribbons()
    } else {
        scene
    };
    Ok((scene, what))
}

/// What the motion loop produced.
struct Motion {
    /// Stats of the last rendered frame.
    last: FrameStats,
    /// The contact sheet's frames (with `--sheet`).
    tiles: Vec<RgbImage>,
    /// Indices of the sheet's frames.
    sheet_frames: Vec<usize>,
    /// Frames run and the seconds per frame.
    frames: usize,
    dt: f32,
    /// Wall-clock time of the loop.
    total: std::time::Duration,
    /// Frames written to the animation.
    animation_frames: usize,
}

/// The animated PNG of `--animation`, written frame by frame as the
/// motion runs (APNG, looping forever; 8-bit RGB like the stills).
struct Animation {
    writer: png::Writer<std::io::BufWriter<std::fs::File>>,
    image: RgbImage,
    every: usize,
    frames: usize,
}

impl Animation {
    /// The frames of a `frames`-frame motion at `fps` kept: every
    /// `every`-th, each shown `every / fps` seconds.
    fn create(
        path: &Path,
        size: (usize, usize),
        frames: usize,
        every: usize,
        fps: f32,
    ) -> Result<Animation, Box<dyn std::error::Error>> {
        let every = every.max(1);
        let count = frames.div_ceil(every);
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut encoder =
            png::Encoder::new(std::io::BufWriter::new(file), size.0 as u32, size.1 as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_animated(count as u32, 0)?;
        // Delay every / fps seconds as a fraction with a 1/100 s grain,
        // reduced (so that 1000 fps or every 1000th frame still fits the
        // 16-bit numerator and denominator exactly).
        let (num, den) = frame_delay(every, fps);
        encoder.set_frame_delay(num, den)?;
        Ok(Animation {
            writer: encoder.write_header()?,
            image: RgbImage::new(size.0, size.1),
            every,
            frames: 0,
        })
    }

    /// Whether motion frame `f` goes into the animation.
    fn wants(&self, f: usize) -> bool {
        f.is_multiple_of(self.every)
    }

    /// Appends the pipeline's last frame (tone-mapped as tasks on
    /// `executor`).
    fn push(
        &mut self,
        pipeline: &FramePipeline,
        executor: &dyn Executor,
    ) -> Result<(), png::EncodingError> {
        pipeline.encode_into_with(&mut self.image, executor);
        self.writer.write_image_data(&self.image.data)?;
        self.frames += 1;
        Ok(())
    }
}

/// The APNG frame delay `every / fps` seconds as a 16-bit fraction: `fps`
/// to 1/100 (`--fps` is at most 1000), reduced by the greatest common
/// divisor, each part clamped to 16 bits only if it still does not fit.
fn frame_delay(every: usize, fps: f32) -> (u16, u16) {
    let mut num = every as u64 * 100;
    let mut den = ((fps as f64 * 100.0).round() as u64).max(1);
    let (mut a, mut b) = (num, den);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    num /= a;
    den /= a;
    let fit = |x: u64| x.clamp(1, u16::MAX as u64) as u16;
    (fit(num), fit(den))
}

/// Runs `--frames` frames of the built-in head motion: frames that are
/// written (the last, the sheet's) or timed (every `--render-every`-th)
/// render, the others only simulate.
fn run_motion(
    cli: &Cli,
    pipeline: &mut FramePipeline,
    mut animation: Option<&mut Animation>,
    executor: &dyn Executor,
) -> Result<Motion, Box<dyn std::error::Error>> {
    let frames = cli.frames.max(1);
    let dt = 1.0 / cli.fps;
    let sheet_frames: Vec<usize> = (0..6).map(|k| (k * (frames - 1)) / 5).collect();
    let mut tiles = Vec::new();
    let pivot = pipeline.pivot();
    let with_body = pipeline.body_field().is_some();
    let run_start = Instant::now();
    let mut last = Default::default();
    for f in 0..frames {
        let t = f as f32 * dt;
        let pose = if with_body {
            pipeline.set_wind(motion::gust(t, motion::GUST_WIND));
            pipeline.set_turbulence(motion::gust_turbulence(t, motion::GUST_TURBULENCE));
            motion::turn(t, pivot)
        } else {
            motion::turn_and_nod(t, pivot)
        };
        let animated = animation.as_ref().is_some_and(|a| a.wants(f));
        let wanted =
            animated || f + 1 == frames || (cli.sheet.is_some() && sheet_frames.contains(&f));
        if wanted || (cli.render_every > 0 && f % cli.render_every == 0) {
            last = pipeline.frame_with(dt, pose, executor);
            if cli.sheet.is_some() {
                // A motion shorter than six frames shows a frame in more
                // than one tile.
                for _ in sheet_frames.iter().filter(|&&s| s == f) {
                    tiles.push(pipeline.image());
                }
            }
            if let Some(a) = animation.as_mut().filter(|_| animated) {
                a.push(pipeline, executor)?;
            }
        } else {
            pipeline.simulate_with(dt, pose, executor);
        }
    }
    Ok(Motion {
        last,
        tiles,
        sheet_frames,
        frames,
        dt,
        total: run_start.elapsed(),
        animation_frames: animation.map_or(0, |a| a.frames),
    })
}

fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    let executor = executor(cli.threads)?;
    if let Some(n) = cli.crowd {
        return crowd::run(n, cli.frames, executor.as_ref());
    }
    let (width, height) = cli.size.unwrap_or((cli.width, cli.height));
    let start = Instant::now();
    let (scene, what) = load_scene(&cli)?;
    let settings = FrameSettings {
        width,
        height,
        shading: cli.shading,
        hair_sigma_a: cli.hair_color.sigma_a(),
        multiple_scattering: !cli.single_scattering,
        render_hairs_per_cm2: cli
            .density
            .unwrap_or(if scene.body.is_some() { 20.0 } else { 40.0 }),
        view_direction: cli.view,
        shadows: !cli.no_shadows,
        prepare: cli.prepare,
        shadow_thinning: cli.shadow_thinning.max(1),
        occlusion_culling: !cli.no_occlusion_culling,
        ..FrameSettings::default()
    };
    let local_shape = cli
        .local_shape
        .unwrap_or(if cli.groom.is_some() || scene.body.is_some() {
            coif::frame::style::SCENE_STIFFNESS
        } else {
            0.0
        });
    // Calm air at first: the gust sets the wind and its turbulence frame
    // by frame (the loop below).
    let drag = if scene.body.is_some() {
        motion::GUST_DRAG
    } else {
        0.0
    };
    let (volume_stiffness, hair_friction) =
        hair_against_hair(cli.volume, cli.hair_friction, scene.body.is_some());
    let settings = FrameSettings {
        simulation: SimParams {
            local_shape_stiffness: local_shape,
            drag,
            turbulence: 0.0,
            volume_stiffness,
            hair_friction,
            ..settings.simulation
        },
        ..settings
    };
    let mut pipeline = FramePipeline::new(&scene, settings, 1.5)?;
    out!(
        "coif: {what}; {} scalp triangles, {} render hairs, {} ribbons, {} shading{}, {}x{} px{}",
        scene.triangles.len(),
        pipeline.render_hair_count(),
        scene.ribbons.len(),
        cli.shading,
        match (cli.shading, cli.single_scattering) {
            (ShadingModel::KajiyaKay, _) => String::new(),
            (_, true) => format!(" ({} hair, single scattering)", cli.hair_color.name()),
            (_, false) => format!(" ({} hair, dual scattering)", cli.hair_color.name()),
        },
        width,
        height,
        if pipeline.has_shadow_map() {
            ", deep opacity shadow map"
        } else {
            ", no hair self-shadowing (--no-shadows)"
        }
    );
    out!(
        "setup (scene, settle 1.5 s, tables, buffers): {:.0} ms; {} thread{}, {} lanes",
        start.elapsed().as_secs_f64() * 1e3,
        executor.threads(),
        if executor.threads() == 1 { "" } else { "s" },
        coif::kernels::LANES
    );

    let mut animation = match &cli.animation {
        Some(path) => Some(Animation::create(
            path,
            (width, height),
            cli.frames.max(1),
            cli.animation_every,
            cli.fps,
        )?),
        None => None,
    };
    let Motion {
        last,
        tiles,
        sheet_frames,
        frames,
        dt,
        total,
        animation_frames,
    } = run_motion(&cli, &mut pipeline, animation.as_mut(), executor.as_ref())?;
    if let (Some(a), Some(path)) = (animation, &cli.animation) {
        a.writer
            .finish()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        out!(
            "wrote {} ({animation_frames} frames, every {} of the motion)",
            path.display(),
            cli.animation_every.max(1)
        );
    }
    pipeline
        .image()
        .save_png(&cli.output)
        .map_err(|e| format!("{}: {e}", cli.output.display()))?;
    out!(
        "{frames} frames ({:.1} s of motion at {} fps) in {:.2} s; last frame: {} hairs, {} vertices, {} segments/span, width x{:.2}, {} segments drawn ({} of them hidden behind the head, culled)",
        frames as f32 * dt,
        cli.fps,
        total.as_secs_f64(),
        last.hairs,
        last.vertices,
        last.segments_per_span,
        last.width_factor,
        last.segments,
        last.hidden_segments
    );
    out!("\nper-stage time (mean over the frames that ran each stage):");
    out!("{}", pipeline.timings());
    if let Some(path) = &cli.timings_csv {
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        pipeline
            .timings()
            .write_csv(std::io::BufWriter::new(file))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        out!("wrote {}", path.display());
    }
    out!("\nwrote {}", cli.output.display());
    if let Some(path) = &cli.sheet {
        RgbImage::contact_sheet(&tiles, 3, 4, [16, 16, 16])
            .save_png(path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        out!("wrote {} (frames {:?})", path.display(), sheet_frames);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{frame_delay, hair_against_hair, parse_density, parse_fps, parse_view};

    #[test]
    fn a_view_is_any_finite_direction() {
        let x = glam::Vec3::X;
        for s in ["1,0,0", "1e30,0,0", "3e38,0,0", "1e-30,0,0", " 2 , 0 , 0 "] {
            let v = parse_view(s).unwrap_or_else(|e| panic!("{s}: {e}"));
            assert!((v - x).length() < 1e-6, "{s}: {v}");
        }
        let v = parse_view("1e30,1e30,0").unwrap();
        assert!((v - glam::Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        for s in ["0,0,0", "inf,0,0", "nan,1,0", "1,2", "1,2,3,4", "a,b,c"] {
            assert!(parse_view(s).is_err(), "{s} accepted");
        }
    }

    #[test]
    fn rates_and_densities_are_checked() {
        assert_eq!(parse_fps("1"), Ok(1.0));
        assert_eq!(parse_fps("29.97"), Ok(29.97));
        assert_eq!(parse_fps("1000"), Ok(1000.0));
        for s in ["0.5", "0", "-5", "nan", "inf", "1001", "x"] {
            assert!(parse_fps(s).is_err(), "--fps {s} accepted");
        }
        assert_eq!(parse_density("250"), Ok(250.0));
        for s in ["0", "-1", "nan", "inf", "251", "1000"] {
            assert!(parse_density(s).is_err(), "--density {s} accepted");
        }
    }

    #[test]
    fn animation_delays_are_exact_fractions() {
        // every / fps seconds.
        assert_eq!(frame_delay(1, 30.0), (1, 30));
        assert_eq!(frame_delay(2, 30.0), (1, 15));
        assert_eq!(frame_delay(1, 1000.0), (1, 1000));
        assert_eq!(frame_delay(1000, 30.0), (100, 3));
        assert_eq!(frame_delay(3, 1.0), (3, 1));
        assert_eq!(frame_delay(1, 29.97), (100, 2997));
    }

    #[test]
    fn hair_friction_follows_the_volume_unless_given() {
        assert_eq!(hair_against_hair(None, None, true), (1.0, 1.0));
        assert_eq!(hair_against_hair(None, None, false), (0.0, 0.0));
        // `--volume 0` on Sintel turns the grid off (friction follows).
        assert_eq!(hair_against_hair(Some(0.0), None, true), (0.0, 0.0));
        assert_eq!(hair_against_hair(Some(0.5), None, false), (0.5, 0.5));
        assert_eq!(hair_against_hair(Some(0.0), Some(1.0), true), (0.0, 1.0));
        assert_eq!(hair_against_hair(None, Some(0.0), true), (1.0, 0.0));
    }
}
