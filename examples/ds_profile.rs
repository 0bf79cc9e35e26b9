use coif::base::Vec3x8;
use coif::kernels::rng::SplitMix64;
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::marschner::{Lut, Params};
use coif::shading::{RgbBuffer, ShadingSamples};
use std::hint::black_box;
use wide::f32x8;

#[inline(never)]
fn single(lut: &Lut, s: &ShadingSamples, out: &mut RgbBuffer) {
    for start in (0..s.len()).step_by(8) {
        let (t, wi, wo) = s.load_block(start);
        out.store_block(start, lut.scattering_x8(t, wi, wo));
    }
}
#[inline(never)]
fn single_pbrt(table: &coif::shading::pbrt::Table, s: &ShadingSamples, out: &mut RgbBuffer) {
    for start in (0..s.len()).step_by(8) {
        let (t, wi, wo) = s.load_block(start);
        out.store_block(start, table.scattering_x8(t, wi, wo));
    }
}
#[inline(never)]
fn dual_pbrt(
    table: &coif::shading::pbrt::Table,
    ds: &DualScattering,
    s: &ShadingSamples,
    n: &[f32],
    out: &mut RgbBuffer,
) {
    for start in (0..s.len()).step_by(8) {
        let (t, wi, wo) = s.load_block(start);
        let nn = f32x8::new(n[start..start + 8].try_into().unwrap());
        let f = ds.shade_x8(
            table.scattering_x8(t, wi, wo),
            t,
            wi,
            wo,
            nn,
            nn * f32x8::splat(0.02),
        );
        out.store_block(start, f);
    }
}
#[inline(never)]
fn dual(lut: &Lut, ds: &DualScattering, s: &ShadingSamples, n: &[f32], out: &mut RgbBuffer) {
    for start in (0..s.len()).step_by(8) {
        let (t, wi, wo) = s.load_block(start);
        let nn = f32x8::new(n[start..start + 8].try_into().unwrap());
        let f = ds.shade_x8(
            lut.scattering_x8(t, wi, wo),
            t,
            wi,
            wo,
            nn,
            nn * f32x8::splat(0.02),
        );
        out.store_block(start, f);
    }
}
fn main() {
    let m = 2048;
    let mut rng = SplitMix64::new(1);
    let mut s = ShadingSamples::default();
    let mut n = vec![];
    for _ in 0..m {
        s.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        n.push(rng.range(0.0, 40.0));
    }
    let lut = Lut::new(&Params::default(), 128);
    let ds = DualScattering::from_marschner(&lut, DualScatteringSettings::default()).unwrap();
    let mut out = RgbBuffer::zeros(m);
    let table = coif::shading::pbrt::Table::new(&Default::default(), 64).unwrap();
    let dsp = DualScattering::from_pbrt(&table, DualScatteringSettings::default()).unwrap();
    let mode = std::env::args().nth(1).unwrap();
    for _ in 0..100 {
        if mode == "single" {
            single(&lut, black_box(&s), &mut out)
        } else {
            dual(&lut, &ds, black_box(&s), &n, &mut out)
        }
    }
    println!("{}", out.get(5));
}
