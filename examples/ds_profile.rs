//! Instruction counts of dual scattering against the table it adds to, for
//! callgrind: `cargo build --release --example ds_profile`, then
//! `valgrind --tool=callgrind ./target/release/examples/ds_profile MODE`
//! with MODE `kajiya-kay`, `marschner`, `marschner-dual`, `pbrt` or
//! `pbrt-dual`, and read
//! the inclusive count of `ds_profile::measured` (100 passes over 2,048
//! samples in cache, eight at a time as the frame's fused pass shades:
//! the table's `scattering_simd`, then `DualScattering::shade_layered_simd`
//! with hair counts 0-40 in front, their transmittance `exp(-0.4 n)`, and
//! 20 fibres behind).

use coif::base::lanes::F32Lanes;
use coif::base::{Vec3Lanes, LANES};
use coif::kernels::rng::SplitMix64;
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{Lut, Params};
use coif::shading::{pbrt, RgbBuffer, ShadingSamples};
use std::hint::black_box;

const SAMPLES: usize = 2048;
const PASSES: usize = 100;

#[inline(never)]
fn measured(
    single: &dyn Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes,
    dual: Option<&DualScattering>,
    samples: &ShadingSamples,
    fibres: &[f32],
    direct: &[f32],
    out: &mut RgbBuffer,
) {
    for _ in 0..PASSES {
        for start in (0..samples.len()).step_by(LANES) {
            let (t, wi, wo) = samples.load_block(start);
            let s = single(t, wi, wo);
            let f = match dual {
                Some(ds) => {
                    let n =
                        F32Lanes::new(fibres[start..start + LANES].try_into().expect("a block"));
                    let d =
                        F32Lanes::new(direct[start..start + LANES].try_into().expect("a block"));
                    ds.shade_layered_simd(s, t, wi, wo, n, F32Lanes::splat(20.0), d)
                }
                None => s,
            };
            out.store_block(start, f);
        }
        black_box(&out);
    }
}

fn main() {
    let mode = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "marschner-dual".into());
    let mut rng = SplitMix64::new(1);
    let mut samples = ShadingSamples::with_capacity(SAMPLES);
    let mut fibres = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        fibres.push(rng.range(0.0, 40.0));
    }
    let direct: Vec<f32> = fibres.iter().map(|n| (-0.4 * n).exp()).collect();
    let blond = pbrt::sigma_a_from_concentration(0.3, 0.0);
    let lut = Lut::new(
        &Params {
            absorption: blond * 0.5,
            ..Params::default()
        },
        128,
    );
    let table = pbrt::Table::new(
        &pbrt::Params {
            sigma_a: blond,
            ..pbrt::Params::default()
        },
        64,
    )
    .expect("valid parameters");
    let settings = DualScatteringSettings::default();
    let mut out = RgbBuffer::zeros(SAMPLES);
    match mode.as_str() {
        "marschner" | "marschner-dual" => {
            let ds = DualScattering::from_marschner(&lut, settings).expect("valid settings");
            let dual = (mode == "marschner-dual").then_some(&ds);
            let single = |t, wi, wo| lut.scattering_simd(t, wi, wo);
            measured(&single, dual, &samples, &fibres, &direct, &mut out);
        }
        "pbrt" | "pbrt-dual" => {
            let ds = DualScattering::from_pbrt(&table, settings).expect("valid settings");
            let dual = (mode == "pbrt-dual").then_some(&ds);
            let single = |t, wi, wo| table.scattering_simd(t, wi, wo);
            measured(&single, dual, &samples, &fibres, &direct, &mut out);
        }
        "kajiya-kay" => {
            let model = KajiyaKay::default();
            let single = |t, wi, wo| model.shade_simd(t, wi, wo);
            measured(&single, None, &samples, &fibres, &direct, &mut out);
        }
        other => {
            eprintln!(
                "unknown mode {other:?} (kajiya-kay, marschner, marschner-dual, pbrt, pbrt-dual)"
            );
            std::process::exit(2);
        }
    }
    println!("{}", out.get(5));
}
