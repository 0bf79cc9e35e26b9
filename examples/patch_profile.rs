//! Instruction counts of the patch step (the figures of kernels/PATCH.md): a settled
//! 32 x 32 ribbon on a 10 cm head, stepped a fixed number of times, SIMD or
//! scalar. Run under callgrind and divide by steps x particles:
//!
//! ```text
//! cargo build --release --example patch_profile
//! valgrind --tool=callgrind target/release/examples/patch_profile simd 200
//! ```

use coif::kernels::patch::{self, ribbon_on_sphere};
use coif::kernels::{SimParams, Sphere};
use glam::Vec3;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| "simd".into());
    let steps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(200);
    let head = Sphere {
        center: Vec3::new(0.0, 1.6, 0.0),
        radius: 0.1,
    };
    let ribbon = ribbon_on_sphere(&head, Vec3::new(0.2, 0.5, -1.0), 0.2, 0.4, 32, 32);
    let rig = [head];
    let mut p = ribbon.patch().expect("valid ribbon");
    let params = SimParams::default();
    for _ in 0..steps {
        if path == "scalar" {
            patch::scalar::step(&mut p, &params, &rig);
        } else {
            patch::step(&mut p, &params, &rig);
        }
    }
    let x = p.positions();
    println!(
        "{path}: {steps} steps of {} particles; first free particle at {}",
        x.len(),
        x[32]
    );
}
