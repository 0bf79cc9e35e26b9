//! coif-report: one report of run time against error for every kernel,
//! and the quality studies behind it ([`quality`]).
//!
//! [`run`] measures each kernel at several settings of its quality knob,
//! SIMD and scalar side by side where both exist, and returns one [`Row`]
//! per kernel x setting x path. [`csv::to_csv`] writes them as
//! `results.csv`, [`summary::to_markdown`] as a Markdown summary (tables,
//! SIMD speed-ups, defaults off the Pareto front), [`plot::svg`] as one
//! time-against-error plot per kernel (drawn with `plotters`); [`write()`]
//! writes all three. [`csv::from_csv`] reads a `results.csv` back, so
//! [`write_figures`] can redraw the summary and plots without measuring.
//!
//! [`multiple_scattering`] measures dual scattering and single scattering
//! with an exact shadow against the Monte Carlo path tracer through
//! explicit fibres (held-out and training tufts, a region of Sintel's
//! groom), the tracer's noise, and its white furnace.
//!
//! [`roofline`] measures this machine's floors (bandwidth, instruction
//! throughput) and every per-frame kernel's time per element in cache and
//! streaming against them ([`roofline_markdown`], `roofline.md`).
//!
//! Time is the median over repeated runs of the whole batch, divided by
//! the number of elements (vertex-steps, output vertices, samples, ...);
//! the spread is the smallest and largest of those runs. Errors come from
//! each crate's public quality functions (see each family's module).

#![warn(missing_docs)]

pub mod collisions;
pub mod csv;
pub mod fits;
pub mod friction;
pub mod interpolation;
pub mod multiple_scattering;
pub mod patch;
pub mod physics;
pub mod plot;
pub mod quality;
pub mod refinement;
pub mod roofline;
pub mod shading;
pub mod shadow;
pub mod shape;
pub mod sim_lod;
pub mod simulation;
pub mod summary;
pub mod timing;
pub mod volume;
pub mod wind;

pub use timing::Timing;

/// How much work a run does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    /// Few repetitions and small sizes (tests, smoke runs).
    pub quick: bool,
}

impl Options {
    /// Repetitions of each timed batch.
    pub fn reps(&self) -> usize {
        if self.quick {
            3
        } else {
            15
        }
    }
}

/// Which implementation a row times.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Path {
    /// The SIMD path (eight lanes at a time).
    Simd,
    /// The scalar reference path (one element at a time).
    Scalar,
}

impl Path {
    /// The path's name in the CSV, summary and plots: `simd` or `scalar`.
    pub fn name(self) -> &'static str {
        match self {
            Path::Simd => "simd",
            Path::Scalar => "scalar",
        }
    }
}

/// One kernel at one setting on one path.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Kernel name, e.g. `"refinement"`.
    pub kernel: String,
    /// The quality setting, e.g. `"segments=4"`.
    pub setting: String,
    /// Which implementation was timed.
    pub path: Path,
    /// What one element is (`"vertex-step"`, `"output vertex"`, `"sample"`, ...).
    pub element: &'static str,
    /// Nanoseconds per element: median, fastest and slowest run.
    pub time: Timing,
    /// What the error measures and against what.
    pub error_metric: &'static str,
    /// The error in the units of `error_metric` (0 for a reference
    /// measured against itself).
    pub error: f64,
    /// The setting the library or pipeline uses by default.
    pub is_default: bool,
}

impl Row {
    /// Time and error both finite, time positive, error non-negative.
    pub fn is_finite(&self) -> bool {
        self.time.median.is_finite()
            && self.time.min.is_finite()
            && self.time.max.is_finite()
            && self.time.median > 0.0
            && self.error.is_finite()
            && self.error >= 0.0
    }
}

/// A kernel family's measurement.
type Measure = fn(Options) -> Vec<Row>;

/// A kernel family of the report: its name, the prefixes of the kernel
/// names its rows carry (every row's kernel starts with one of them, and
/// no other family's row does: [`family_of`]) and its measurement.
#[derive(Clone, Copy)]
pub struct Family {
    /// The family's name in the progress lines, e.g. `"simulation LOD"`.
    pub name: &'static str,
    /// Prefixes of the kernel names it writes.
    pub kernels: &'static [&'static str],
    /// Measures the family's rows.
    pub measure: Measure,
}

/// Every kernel family, in the order [`run`] measures them.
pub const FAMILIES: [Family; 15] = [
    Family {
        name: "simulation",
        kernels: &["simulation settling", "simulation whipping"],
        measure: simulation::rows,
    },
    Family {
        name: "simulation LOD",
        kernels: &["simulation LOD "],
        measure: sim_lod::rows,
    },
    Family {
        name: "physics",
        kernels: &["physics chain "],
        measure: physics::rows,
    },
    Family {
        name: "wind",
        kernels: &["wind "],
        measure: wind::rows,
    },
    Family {
        name: "collisions",
        kernels: &["collisions "],
        measure: collisions::rows,
    },
    Family {
        name: "shape",
        kernels: &["shape "],
        measure: shape::rows,
    },
    Family {
        name: "volume",
        kernels: &["volume "],
        measure: volume::rows,
    },
    Family {
        name: "hair friction",
        kernels: &["hair friction "],
        measure: friction::rows,
    },
    Family {
        name: "refinement",
        kernels: &["refinement"],
        measure: refinement::rows,
    },
    Family {
        name: "fits",
        kernels: &["fits"],
        measure: fits::rows,
    },
    Family {
        name: "interpolation",
        kernels: &["interpolation"],
        measure: interpolation::rows,
    },
    Family {
        name: "shading",
        kernels: &["kajiya-kay", "marschner", "pbrt", "models vs pbrt"],
        measure: shading::rows,
    },
    Family {
        name: "multiple scattering",
        kernels: &["multiple scattering"],
        measure: multiple_scattering::rows,
    },
    Family {
        name: "shadow maps",
        kernels: &["shadow "],
        measure: shadow::rows,
    },
    Family {
        name: "patch",
        kernels: &["patch"],
        measure: patch::rows,
    },
];

/// The family whose kernel-name prefixes match `kernel` (the longest
/// matching prefix wins), if any.
pub fn family_of(kernel: &str) -> Option<&'static Family> {
    FAMILIES
        .iter()
        .flat_map(|f| f.kernels.iter().map(move |k| (f, *k)))
        .filter(|(_, k)| kernel.starts_with(k))
        .max_by_key(|(_, k)| k.len())
        .map(|(f, _)| f)
}

/// Measures every kernel family of [`FAMILIES`], in order: simulation,
/// simulation LOD (sleeping and guide levels against their error), physics
/// (the strand step against the analytic hanging chain), wind (equilibrium
/// and decay against their closed forms), collisions (penetration by the
/// exact distance), shape (Sintel's groom at rest and in a head turn
/// against the groom and the hair carried rigidly), volume (draped hair's packing with the hair grid
/// against without), hair friction (a kicked lock's relative motion and
/// common motion), refinement, fits, interpolation, shading, multiple
/// scattering (single and dual scattering against the path tracer through
/// explicit fibres), shadow maps, cloth patches.
pub fn run(options: Options) -> Vec<Row> {
    let mut rows = Vec::new();
    for family in &FAMILIES {
        let t0 = std::time::Instant::now();
        rows.extend((family.measure)(options));
        eprintln!(
            "report: {} measured in {:.1} s",
            family.name,
            t0.elapsed().as_secs_f64()
        );
    }
    rows
}

/// The roofline section ([`roofline`]): floors and kernels measured now,
/// as Markdown headed by the machine line.
pub fn roofline_markdown(options: Options, machine: &str) -> String {
    let t0 = std::time::Instant::now();
    let floors = roofline::measure_floors(options);
    let rows = roofline::measure(options, &floors, roofline::KERNELS);
    eprintln!(
        "report: roofline measured in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    format!(
        "# coif roofline\n\nMeasured on {machine}.\n\n{}",
        roofline::to_markdown(&floors, &rows)
    )
}

/// Writes the roofline Markdown as `roofline.md` into `dir` (created if
/// missing). Returns the path.
pub fn write_roofline(
    markdown: &str,
    dir: &std::path::Path,
) -> std::io::Result<std::path::PathBuf> {
    std::fs::create_dir_all(dir)?;
    let path = dir.join("roofline.md");
    std::fs::write(&path, markdown)?;
    Ok(path)
}

/// Writes `results.csv`, `summary.md` and one SVG plot per kernel into `dir`
/// (created if missing). Returns the paths written.
pub fn write(
    rows: &[Row],
    dir: &std::path::Path,
    machine: &str,
) -> std::io::Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let csv_path = dir.join("results.csv");
    std::fs::write(&csv_path, csv::to_csv(rows))?;
    let mut written = vec![csv_path];
    written.extend(write_figures(rows, dir, machine)?);
    Ok(written)
}

/// Writes one SVG plot per kernel and `summary.md` into `dir` (created if
/// missing), but not `results.csv`: what redrawing from a CSV read back
/// with [`csv::from_csv`] needs. Returns the paths written.
pub fn write_figures(
    rows: &[Row],
    dir: &std::path::Path,
    machine: &str,
) -> std::io::Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let mut plots = Vec::new();
    for kernel in summary::kernels(rows) {
        let file = format!("{}.svg", plot::file_stem(&kernel));
        let of_kernel: Vec<&Row> = rows.iter().filter(|r| r.kernel == kernel).collect();
        let path = dir.join(&file);
        std::fs::write(&path, plot::svg(&kernel, &of_kernel)?)?;
        written.push(path);
        plots.push((kernel, file));
    }
    let md_path = dir.join("summary.md");
    std::fs::write(&md_path, summary::to_markdown(rows, &plots, machine))?;
    written.push(md_path);
    Ok(written)
}
