//! Shading: Kajiya-Kay (Kajiya and Kay 1989), Marschner (Marschner et al.
//! 2003; direct and tables) and pbrt's hair model (Chiang et al. 2016, as
//! implemented in pbrt-v3; far field at several quadrature orders and
//! tables), per shaded sample.
//!
//! Samples are random (t, wi, wo), each uniform on the unit sphere. Errors
//! are relative RMS over RGB (`sqrt(sum |a - r|^2 / sum |r|^2)`):
//! - Marschner tables against the direct model
//!   ([`coif::shading::marschner::accuracy::lut_relative_rms_error`]);
//! - pbrt far field and tables against the far field at 4x its recommended
//!   order ([`coif::shading::pbrt::quality`]);
//! - every model against pbrt's far field at its recommended order
//!   ([`coif::shading::yardstick::versus_pbrt`], kernel
//!   `models vs pbrt`): how far each cheaper model is from the physical one,
//!   after the least-squares gain (Kajiya-Kay has no physical scale, so
//!   the error before the gain mostly measures its brightness).
//! - pbrt exact (kernel `pbrt exact`): the exact per-`h` model averaged over
//!   1, 4, 16, 64 stratified (jittered) offsets per shading point
//!   ([`coif::shading::pbrt::scattering_batch_monte_carlo`], the Monte
//!   Carlo estimate pbrt makes with one random `h` per camera ray), against
//!   the same far field at 4x order
//!   ([`coif::shading::pbrt::quality::monte_carlo_error`]); time per
//!   shading point (all its offsets). Scalar only: there is no SIMD path.

use super::timing::time_batch;
use super::{Options, Path, Row, Timing};
use coif::base::SplitMix64;
use coif::shading::kajiya_kay::{self, KajiyaKay};
use coif::shading::marschner::{self, accuracy::lut_relative_rms_error, Lut, LutLayout};
use coif::shading::pbrt::{self, quality, FarField, Table, DEFAULT_QUADRATURE_ORDER};
use coif::shading::yardstick::{self, marschner_matching, versus_pbrt};
use coif::shading::{RgbBuffer, ShadingSamples};

/// The frame pipeline's Marschner table resolution (`shading_model.rs`).
pub const MARSCHNER_RESOLUTION: usize = 128;
/// The frame pipeline's pbrt table resolution (`shading_model.rs`).
pub const PBRT_RESOLUTION: usize = 64;

/// Table resolutions measured (Marschner and pbrt).
pub const RESOLUTIONS: [usize; 4] = [32, 64, 128, 256];
/// pbrt far-field quadrature orders measured.
pub const ORDERS: [usize; 4] = [16, 36, 72, 144];
/// Offsets `h` per shading point of the exact pbrt model measured.
pub const H_SAMPLES: [usize; 4] = [1, 4, 16, 64];

struct Bench {
    samples: ShadingSamples,
    out: RgbBuffer,
    reps: usize,
}

impl Bench {
    fn time(&mut self, shade: impl Fn(&ShadingSamples, &mut RgbBuffer)) -> Timing {
        let (samples, out) = (&self.samples, &mut self.out);
        time_batch(self.reps, samples.len(), || {
            shade(samples, out);
            std::hint::black_box(&*out);
        })
    }
}

#[allow(clippy::too_many_arguments)]
fn row(
    kernel: &str,
    setting: String,
    path: Path,
    time: Timing,
    error_metric: &'static str,
    error: f64,
    is_default: bool,
) -> Row {
    Row {
        kernel: kernel.into(),
        setting,
        path,
        element: "sample",
        time,
        error_metric,
        error,
        is_default,
    }
}

/// Error metric of every model against pbrt's far field.
const VS_PBRT: &str = "relative RMS vs pbrt far field after least-squares gain";
/// Error metric of the Marschner tables.
const VS_DIRECT: &str = "relative RMS vs Marschner direct";
/// Error metric of pbrt's far field and tables.
const VS_REF: &str = "relative RMS vs pbrt far field at 4x order";
/// Kernel name of the models compared with pbrt.
const MODELS: &str = "models vs pbrt";
/// Seed of the error samples.
const SEED: u64 = 5;

/// What every shading step shares: the timed samples, the pbrt material,
/// and each model's error against pbrt per table resolution.
struct Study {
    bench: Bench,
    pbrt: pbrt::Params,
    /// Samples of the far-field and table errors.
    error_samples: usize,
    /// Samples of the Marschner table error: dominated by rare samples
    /// near the caustics, so it needs many to settle (the direct model is
    /// cheap).
    marschner_samples: usize,
    /// [`versus_pbrt`] at each of [`RESOLUTIONS`].
    vs_pbrt: Vec<Vec<yardstick::ModelError>>,
}

impl Study {
    fn new(options: Options) -> Study {
        let (n, error_samples) = if options.quick {
            (512, 300)
        } else {
            (4096, 20_000)
        };
        let marschner_samples = if options.quick { 300 } else { 100_000 };
        let mut rng = SplitMix64::new(17);
        let mut samples = ShadingSamples::with_capacity(n);
        for _ in 0..n {
            samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        }
        let pbrt = pbrt::Params::default();
        let vs_pbrt = RESOLUTIONS
            .iter()
            .map(|&r| versus_pbrt(&pbrt, r, error_samples, SEED).expect("default material"))
            .collect();
        Study {
            bench: Bench {
                samples,
                out: RgbBuffer::zeros(n),
                reps: options.reps(),
            },
            pbrt,
            error_samples,
            marschner_samples,
            vs_pbrt,
        }
    }

    /// A model's error against pbrt, tables at `RESOLUTIONS[res_index]`.
    fn model_error(&self, res_index: usize, model: &str) -> f64 {
        self.vs_pbrt[res_index]
            .iter()
            .find(|m| m.model == model)
            .map_or(f64::NAN, |m| m.relative_rms_after_gain)
    }
}

/// The shading rows: `kajiya-kay`, `marschner`, `pbrt`, `pbrt exact` and
/// `models vs pbrt`.
pub fn rows(options: Options) -> Vec<Row> {
    let mut study = Study::new(options);
    let mut rows = kajiya_kay(&mut study);
    rows.extend(marschner(&mut study));
    rows.extend(pbrt_far_field(&mut study));
    rows.extend(pbrt_exact(&mut study));
    rows.extend(tables(&mut study));
    rows
}

/// Kajiya-Kay: one setting, error against pbrt's far field (also a
/// `models vs pbrt` row).
fn kajiya_kay(study: &mut Study) -> Vec<Row> {
    let kk = KajiyaKay::default();
    let simd = study.bench.time(|s, o| kk.shade_batch(s, o));
    let scalar = study
        .bench
        .time(|s, o| kajiya_kay::scalar::shade_batch(&kk, s, o));
    let error = study.model_error(0, "kajiya-kay");
    let mut rows = Vec::new();
    for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
        let at = |kernel, setting: &str, is_default| {
            row(
                kernel,
                setting.into(),
                path,
                time,
                VS_PBRT,
                error,
                is_default,
            )
        };
        rows.push(at("kajiya-kay", "default", true));
        rows.push(at(MODELS, "kajiya-kay", false));
    }
    rows
}

/// Marschner: direct (scalar only, the reference) and tables against the
/// direct model; then the direct model matched to the pbrt material,
/// against pbrt (`models vs pbrt`).
fn marschner(study: &mut Study) -> Vec<Row> {
    let m = marschner::Params::default();
    let direct = study
        .bench
        .time(|s, o| marschner::scattering_batch(&m, s, o));
    let mut rows = vec![row(
        "marschner",
        "direct".into(),
        Path::Scalar,
        direct,
        VS_DIRECT,
        0.0,
        false,
    )];
    for &res in &RESOLUTIONS {
        let lut = Lut::new(&m, res);
        let error =
            lut_relative_rms_error(&m, res, LutLayout::default(), study.marschner_samples, SEED);
        let simd = study.bench.time(|s, o| lut.scattering_batch(s, o));
        let scalar = study
            .bench
            .time(|s, o| marschner::lut::scalar::scattering_batch(&lut, s, o));
        for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
            let default = res == MARSCHNER_RESOLUTION;
            let setting = format!("table {res}");
            rows.push(row(
                "marschner",
                setting,
                path,
                time,
                VS_DIRECT,
                error,
                default,
            ));
        }
    }
    let matched = marschner_matching(&study.pbrt);
    let time = study
        .bench
        .time(|s, o| marschner::scattering_batch(&matched, s, o));
    let error = study.model_error(0, "marschner direct");
    let setting = "marschner direct".into();
    rows.push(row(
        MODELS,
        setting,
        Path::Scalar,
        time,
        VS_PBRT,
        error,
        false,
    ));
    rows
}

/// pbrt's far field at each of [`ORDERS`] (scalar: the reference path),
/// against the far field at 4x the order.
fn pbrt_far_field(study: &mut Study) -> Vec<Row> {
    let mut rows = Vec::new();
    for &order in &ORDERS {
        let far = FarField::new(&study.pbrt, order).expect("valid order");
        let time = study.bench.time(|s, o| far.scattering_batch(s, o));
        let error = quality::far_field_error(&study.pbrt, order, study.error_samples, SEED)
            .expect("valid order") as f64;
        let default = order == DEFAULT_QUADRATURE_ORDER;
        let setting = format!("far field {order}");
        rows.push(row(
            "pbrt",
            setting,
            Path::Scalar,
            time,
            VS_REF,
            error,
            default,
        ));
    }
    rows
}

/// pbrt exact: the per-`h` model averaged over each of [`H_SAMPLES`]
/// stratified offsets per shading point (scalar only).
fn pbrt_exact(study: &mut Study) -> Vec<Row> {
    let mut rows = Vec::new();
    for &n in &H_SAMPLES {
        let params = &study.pbrt;
        let time = study
            .bench
            .time(|s, o| pbrt::scattering_batch_monte_carlo(params, s, n, 3, o));
        let error = quality::monte_carlo_error(params, n, study.error_samples, SEED)
            .expect("default material") as f64;
        let setting = format!("{n} h per point");
        rows.push(row(
            "pbrt exact",
            setting,
            Path::Scalar,
            time,
            VS_REF,
            error,
            false,
        ));
    }
    rows
}

/// Tables at each of [`RESOLUTIONS`], SIMD and scalar: pbrt's against its
/// far field at 4x order, and pbrt's and the matched Marschner's against
/// pbrt (`models vs pbrt`).
fn tables(study: &mut Study) -> Vec<Row> {
    let matched = marschner_matching(&study.pbrt);
    let mut rows = Vec::new();
    for (i, &res) in RESOLUTIONS.iter().enumerate() {
        let table = Table::new(&study.pbrt, res).expect("valid resolution");
        let error = quality::table_error(&study.pbrt, res, study.error_samples, SEED)
            .expect("valid resolution") as f64;
        let simd = study.bench.time(|s, o| table.scattering_batch(s, o));
        let scalar = study
            .bench
            .time(|s, o| pbrt::table::scalar::scattering_batch(&table, s, o));
        let lut = Lut::new(&matched, res);
        let lut_simd = study.bench.time(|s, o| lut.scattering_batch(s, o));
        let lut_scalar = study
            .bench
            .time(|s, o| marschner::lut::scalar::scattering_batch(&lut, s, o));
        let pbrt_vs = study.model_error(i, &format!("pbrt table {res}"));
        let marschner_vs = study.model_error(i, &format!("marschner table {res}"));
        for (path, time, lut_time) in [
            (Path::Simd, simd, lut_simd),
            (Path::Scalar, scalar, lut_scalar),
        ] {
            let default = res == PBRT_RESOLUTION;
            rows.push(row(
                "pbrt",
                format!("table {res}"),
                path,
                time,
                VS_REF,
                error,
                default,
            ));
            let setting = format!("pbrt table {res}");
            rows.push(row(MODELS, setting, path, time, VS_PBRT, pbrt_vs, false));
            let setting = format!("marschner table {res}");
            rows.push(row(
                MODELS,
                setting,
                path,
                lut_time,
                VS_PBRT,
                marschner_vs,
                false,
            ));
        }
    }
    rows
}
