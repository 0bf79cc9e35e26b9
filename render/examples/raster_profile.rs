//! Harness for instruction counts of the binned hair rasteriser:
//! `valgrind --tool=callgrind --toggle-collect='*raster_profile*counted*'
//! target/release/examples/raster_profile [simd|scalar|reference]`.
//!
//! A synthetic scene shaped like the demo's default frame: 13,300 strands
//! of 64 vertices (837,900 segments) over a 512 x 512 frame, segments
//! about 3.7 px long and 0.3 to 0.6 px wide, hanging around a head-sized
//! region, drawn once (after one warm-up draw outside the counted region).

use coif_base::tasks::Serial;
use coif_base::SplitMix64;
use coif_render::raster::HairRaster;
use coif_render::sort::DepthOrder;
use coif_render::{hair, scalar, Camera, Framebuffer, ShadedVertex};
use glam::Vec3;

const SIZE: usize = 512;
const VPS: usize = 64;

fn scene() -> (Camera, Vec<ShadedVertex>) {
    let camera = Camera::look_at(
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::ZERO,
        Vec3::Y,
        0.5,
        SIZE,
        SIZE,
    );
    let px = 1.5 / camera.pixels_per_metre(1.0);
    let mut rng = SplitMix64::new(3);
    let mut out = Vec::with_capacity(13_300 * VPS);
    for _ in 0..13_300 {
        let root = rng.unit_vector() * 0.1;
        let mut p = Vec3::new(root.x, root.y.abs() + 0.02, root.z);
        let mut dir = (Vec3::new(root.x, 0.0, root.z).normalize_or_zero() * 0.4
            + Vec3::new(0.0, -1.0, 0.0))
        .normalize();
        let width = rng.range(0.3, 0.6) * px;
        let color = Vec3::new(rng.range(0.2, 0.6), rng.range(0.1, 0.4), 0.1);
        for k in 0..VPS {
            out.push(ShadedVertex {
                position: p.into(),
                width,
                color: (color * (0.6 + 0.4 * k as f32 / VPS as f32)).into(),
                strand_parameter: k as f32 / (VPS - 1) as f32,
            });
            dir = (dir + rng.unit_vector() * 0.15).normalize();
            p += dir * 3.7 * px;
        }
    }
    (camera, out)
}

#[inline(never)]
fn counted(
    which: &str,
    raster: &mut HairRaster,
    frame: &mut Framebuffer,
    camera: &Camera,
    v: &[ShadedVertex],
    order: &DepthOrder,
) -> usize {
    match which {
        "scalar" => scalar::draw(raster, frame, camera, v, VPS, order, 0.8, &Serial),
        "reference" => hair::draw_shaded(frame, camera, v, VPS, order, 0.8),
        _ => raster.draw(frame, camera, v, VPS, order, 0.8, &Serial),
    }
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "simd".into());
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let (camera, v) = scene();
    let mut order = DepthOrder::with_capacity(v.len() / VPS);
    order.sort(&camera, &v, VPS);
    let mut raster = HairRaster::new(SIZE, SIZE, v.len()).unwrap();
    let mut frame = Framebuffer::new(SIZE, SIZE);
    frame.clear_gradient(Vec3::splat(0.2), Vec3::splat(0.05));
    let backdrop = frame.clone();
    let mut n = counted(which.as_str(), &mut raster, &mut frame, &camera, &v, &order);
    let t = std::time::Instant::now();
    for _ in 0..reps {
        frame.pixels.copy_from_slice(&backdrop.pixels);
        n = counted(which.as_str(), &mut raster, &mut frame, &camera, &v, &order);
    }
    let ns = t.elapsed().as_nanos() as f64 / (reps * n) as f64;
    let sum: f64 = frame.pixels.iter().map(|p| p.color.x as f64).sum();
    println!(
        "{which}: {n} segments, {:?}, {ns:.1} ns/segment, checksum {sum:.6}",
        raster.stats()
    );
}
