//! Shading: Kajiya-Kay, Marschner (direct and tables) and pbrt (far field
//! at several quadrature orders and tables), per shaded sample.
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
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{self, accuracy::lut_relative_rms_error, Lut, LutLayout};
use coif::shading::pbrt::{self, quality, FarField, Table, DEFAULT_QUADRATURE_ORDER};
use coif::shading::yardstick::{marschner_matching, versus_pbrt};
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

pub fn rows(options: Options) -> Vec<Row> {
    let (n, error_samples) = if options.quick {
        (512, 300)
    } else {
        (4096, 20_000)
    };
    // The Marschner tables' error is dominated by rare samples near the
    // caustics, so it needs many samples to settle (the direct model is cheap).
    let marschner_samples = if options.quick { 300 } else { 100_000 };
    let mut rng = SplitMix64::new(17);
    let mut samples = ShadingSamples::with_capacity(n);
    for _ in 0..n {
        samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    let mut bench = Bench {
        samples,
        out: RgbBuffer::zeros(n),
        reps: options.reps(),
    };
    let seed = 5;
    let mut rows = Vec::new();
    let pbrt_params = pbrt::Params::default();
    let vs_pbrt: Vec<_> = RESOLUTIONS
        .iter()
        .map(|&r| versus_pbrt(&pbrt_params, r, error_samples, seed).expect("default material"))
        .collect();
    let model_error = |res_index: usize, model: &str| -> f64 {
        vs_pbrt[res_index]
            .iter()
            .find(|m| m.model == model)
            .map_or(f64::NAN, |m| m.relative_rms_after_gain)
    };
    const VS_PBRT: &str = "relative RMS vs pbrt far field after least-squares gain";
    const MODELS: &str = "models vs pbrt";

    // Kajiya-Kay: one setting, error against pbrt's far field.
    let kk = KajiyaKay::default();
    let kk_simd = bench.time(|s, o| kk.shade_batch(s, o));
    let kk_scalar = bench.time(|s, o| coif::shading::kajiya_kay::scalar::shade_batch(&kk, s, o));
    let kk_error = model_error(0, "kajiya-kay");
    for (path, time) in [(Path::Simd, kk_simd), (Path::Scalar, kk_scalar)] {
        rows.push(row(
            "kajiya-kay",
            "default".into(),
            path,
            time,
            VS_PBRT,
            kk_error,
            true,
        ));
        rows.push(row(
            MODELS,
            "kajiya-kay".into(),
            path,
            time,
            VS_PBRT,
            kk_error,
            false,
        ));
    }

    // Marschner: direct (scalar only) and tables, against the direct model.
    let m = marschner::Params::default();
    const VS_DIRECT: &str = "relative RMS vs Marschner direct";
    let direct = bench.time(|s, o| marschner::scattering_batch(&m, s, o));
    rows.push(row(
        "marschner",
        "direct".into(),
        Path::Scalar,
        direct,
        VS_DIRECT,
        0.0,
        false,
    ));
    for &res in &RESOLUTIONS {
        let lut = Lut::new(&m, res);
        let error = lut_relative_rms_error(&m, res, LutLayout::default(), marschner_samples, seed);
        let simd = bench.time(|s, o| lut.scattering_batch(s, o));
        let scalar =
            bench.time(|s, o| coif::shading::marschner::lut::scalar::scattering_batch(&lut, s, o));
        for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
            let setting = format!("table {res}");
            let default = res == MARSCHNER_RESOLUTION;
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
    // Marschner matched to the pbrt material, against pbrt.
    let matched = marschner_matching(&pbrt_params);
    let matched_direct = bench.time(|s, o| marschner::scattering_batch(&matched, s, o));
    let e = model_error(0, "marschner direct");
    rows.push(row(
        MODELS,
        "marschner direct".into(),
        Path::Scalar,
        matched_direct,
        VS_PBRT,
        e,
        false,
    ));

    // pbrt: far field at several orders (scalar: the reference path) and
    // tables (SIMD and scalar), against the far field at 4x the order.
    const VS_REF: &str = "relative RMS vs pbrt far field at 4x order";
    for &order in &ORDERS {
        let far = FarField::new(&pbrt_params, order).expect("valid order");
        let time = bench.time(|s, o| far.scattering_batch(s, o));
        let error = quality::far_field_error(&pbrt_params, order, error_samples, seed)
            .expect("valid order") as f64;
        let default = order == DEFAULT_QUADRATURE_ORDER;
        rows.push(row(
            "pbrt",
            format!("far field {order}"),
            Path::Scalar,
            time,
            VS_REF,
            error,
            default,
        ));
    }
    // pbrt exact: the per-h model averaged over stratified offsets.
    for &n in &H_SAMPLES {
        let time = bench.time(|s, o| pbrt::scattering_batch_monte_carlo(&pbrt_params, s, n, 3, o));
        let error = quality::monte_carlo_error(&pbrt_params, n, error_samples, seed)
            .expect("default material") as f64;
        rows.push(row(
            "pbrt exact",
            format!("{n} h per point"),
            Path::Scalar,
            time,
            VS_REF,
            error,
            false,
        ));
    }
    for (i, &res) in RESOLUTIONS.iter().enumerate() {
        let table = Table::new(&pbrt_params, res).expect("valid resolution");
        let error = quality::table_error(&pbrt_params, res, error_samples, seed)
            .expect("valid resolution") as f64;
        let simd = bench.time(|s, o| table.scattering_batch(s, o));
        let scalar =
            bench.time(|s, o| coif::shading::pbrt::table::scalar::scattering_batch(&table, s, o));
        let default = res == PBRT_RESOLUTION;
        let lut = Lut::new(&matched, res);
        let lut_simd = bench.time(|s, o| lut.scattering_batch(s, o));
        let lut_scalar =
            bench.time(|s, o| coif::shading::marschner::lut::scalar::scattering_batch(&lut, s, o));
        for (path, time, lut_time) in [
            (Path::Simd, simd, lut_simd),
            (Path::Scalar, scalar, lut_scalar),
        ] {
            rows.push(row(
                "pbrt",
                format!("table {res}"),
                path,
                time,
                VS_REF,
                error,
                default,
            ));
            let e = model_error(i, &format!("pbrt table {res}"));
            rows.push(row(
                MODELS,
                format!("pbrt table {res}"),
                path,
                time,
                VS_PBRT,
                e,
                false,
            ));
            let e = model_error(i, &format!("marschner table {res}"));
            rows.push(row(
                MODELS,
                format!("marschner table {res}"),
                path,
                lut_time,
                VS_PBRT,
                e,
                false,
            ));
        }
    }
    rows
}
