//! Profiling harness behind shading/SHADOWS.md's build figures: builds the
//! opacity shadow map of a draped head repeatedly, SIMD or scalar, for
//! callgrind instruction counts or wall-clock timing.
//!
//! ```text
//! cargo run --release --example shadow_profile -- MODE(slices|deep) LAYERS BUILDS RES STRANDS VERTS PATH(simd|scalar)
//! valgrind --tool=callgrind target/release/examples/shadow_profile slices 16 10 256 2048 32 simd
//! ```
use coif::frame::drape::draped_on_sphere;
use coif::shading::shadow::{OpacityShadowMap, ShadowMode, ShadowSettings};
use glam::Vec3;
use std::time::Instant;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mode = if a.get(1).map(|s| s.as_str()) == Some("deep") {
        ShadowMode::Deep
    } else {
        ShadowMode::Slices
    };
    let layers: usize = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(16);
    let builds: usize = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(10);
    let res: usize = a.get(4).map(|s| s.parse().unwrap()).unwrap_or(256);
    let strands: usize = a.get(5).map(|s| s.parse().unwrap()).unwrap_or(2048);
    let verts: usize = a.get(6).map(|s| s.parse().unwrap()).unwrap_or(32);
    let scalar = a.get(7).map(|s| s.as_str()) == Some("scalar");
    let (pts, _) = draped_on_sphere(strands, verts, 60);
    let light = Vec3::new(1.0, -0.5, 0.3).normalize();
    let mut map = OpacityShadowMap::new(ShadowSettings {
        mode,
        layers,
        resolution: res,
        ..Default::default()
    })
    .unwrap();
    let t = Instant::now();
    for _ in 0..builds {
        if scalar {
            coif::shading::shadow::scalar::build(&mut map, light, &pts, verts)
        } else {
            map.build(light, &pts, verts)
        }
    }
    let segs = strands * (verts - 1);
    println!(
        "{:.1} ns/segment",
        t.elapsed().as_nanos() as f64 / (builds * segs) as f64
    );
    println!("check {}", map.stored_opacity(res / 2, res / 2, layers - 1));
    let (f, pl) = (map.frame(), map.placement());
    let mut samples = 0usize;
    let mut chunks = 0usize;
    for st in pts.chunks(verts) {
        for w in st.windows(2) {
            let d = f.to_light(w[1]) - f.to_light(w[0]);
            let n = ((d.x * d.x + d.y * d.y).sqrt() * pl.inv_texel)
                .ceil()
                .max(1.0) as usize;
            samples += n;
            chunks += n.div_ceil(8);
        }
    }
    println!(
        "samples/segment {:.2}, lane use {:.2}",
        samples as f64 / segs as f64,
        samples as f64 / (8 * chunks) as f64
    );
}
