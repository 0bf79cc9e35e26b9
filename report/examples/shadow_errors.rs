//! The shadow maps' error table of `benches/shadow.rs` (`time_vs_error`)
//! without the timing: the draped head (512 x 16), 128^2 maps, slices 4-64
//! and deep 2-16 against the footprint reference (16 rays over 2 mm, every
//! 8th strand's vertices). Used to re-measure `shading/SHADOWS.md` after a
//! change to the build.
//!
//! `cargo run --release -p coif-report --example shadow_errors`

use coif::frame::drape::draped_on_sphere;
use coif::shading::shadow::quality::{error_of_map, reference_transmittance, Footprint};
use coif::shading::shadow::{OpacityShadowMap, ShadowMode, ShadowSettings};
use glam::Vec3;

fn main() {
    let (pts, verts) = draped_on_sphere(512, 16, 60);
    let light = Vec3::new(1.0, -0.5, 0.3).normalize();
    let stride = 8;
    let footprint = Footprint {
        rays: 16,
        radius: 0.002,
    };
    let reference = reference_transmittance(
        &ShadowSettings::default(),
        light,
        &pts,
        verts,
        stride,
        footprint,
    );
    println!("setting     mean|e|  rms     max     bias    mean T_ref");
    let settings = [4, 8, 16, 32, 64]
        .map(|l| (ShadowMode::Slices, l))
        .into_iter()
        .chain([2, 3, 4, 8, 16].map(|l| (ShadowMode::Deep, l)));
    for (mode, layers) in settings {
        let s = ShadowSettings {
            mode,
            layers,
            resolution: 128,
            ..Default::default()
        };
        let mut map = OpacityShadowMap::new(s).expect("valid settings");
        map.build(light, &pts, verts);
        let e = error_of_map(&map, &pts, verts, stride, &reference);
        println!(
            "{:<11} {:.4}  {:.4}  {:.4}  {:+.4}  {:.3}",
            format!("{mode:?} {layers}"),
            e.mean_abs,
            e.rms,
            e.max_abs,
            e.bias,
            e.mean_reference
        );
    }
}
