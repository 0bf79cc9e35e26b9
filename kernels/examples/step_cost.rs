//! The strand step's cost on the TressFX mohawk (2,226 strands x 32
//! vertices) at the defaults, all blocks awake: a harness for timing and
//! for counting instructions with callgrind.
//!
//! `cargo run --release -p coif-kernels --example step_cost -- [SHAPE] [SCALAR] [STEPS] [SCENE]`
//! (defaults 0 0 10 spheres): `local_shape_stiffness` = SHAPE, the scalar
//! twin if SCALAR is 1. The rig is the bench's (two 8 cm spheres tangent
//! under the scalp and 14 distractors, `scene::rig_with_distractors`);
//! SCENE changes it: `spheres` (the defaults), `frictionless` (friction 0
//! and 0), `norule` (frictionless and the roots rule off: the same bytes
//! as the step before the world round, frictionless, so the two compare
//! code for code), `empty` (no collider: the step alone), `capsules` (each sphere a capsule of its radius, 2 radii long),
//! `drag` (drag 1 /s in still air: what drag costs the step itself),
//! `wind` (the spheres in a wind of (2, 0, 1) m/s, drag 1 /s), `gusts` (and
//! turbulence 1 m/s), `hair` (volume and hair friction at 1; `volume`
//! and `friction` one of them), `field` (the spheres and one 4 mm field of the
//! shared Sintel bust, its head on the head sphere, moved up or down until
//! the median root lies on its surface). With SHAPE above 0 the
//! sag-free rest state is solved first (its time printed). The set settles for
//! 30 steps, sleeping is off (every block is stepped), then STEPS steps run
//! in `measured_steps`. Prints the time per vertex-step and a hash of the
//! positions. Instruction counts in the README:
//!
//! ```text
//! valgrind --tool=callgrind --toggle-collect='*measured_steps*' \
//!     target/release/examples/step_cost 0 0 5
//! ```
//!
//! divided by 5 steps x 4 substeps x 71,232 vertices.

use coif_geometry::groom;
use coif_geometry::scene::{rig_with_distractors, scalp_spheres};
use coif_kernels::{scalar, step_colliders, Capsule, Colliders, Sdf, SimParams, Strands};
use glam::{Affine3A, Vec3};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: f32| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(d);
    let (shape, use_scalar, steps) = (arg(1, 0.0), arg(2, 0.0) == 1.0, arg(3, 10.0) as usize);
    let Some(path) = coif_testkit::groom_path("ratboy_mohawk.tfx") else {
        std::process::exit(1);
    };
    let g = groom::load(&std::fs::read(path).expect("read the groom")).expect("parse the groom");
    let (pts, v) = g.uniform_points(0.01).expect("uniform points");
    let scene = args.get(4).map(String::as_str).unwrap_or("spheres");
    let near = scalp_spheres(&pts, v, 2, 0.08);
    let mut rig = rig_with_distractors(&near[..2], near[0].center, 0.1, 14);
    let mut params = SimParams {
        local_shape_stiffness: shape,
        sleep_speed: 0.0,
        ..Default::default()
    };
    let mut capsules = Vec::new();
    let mut fields = Vec::new();
    match scene {
        "frictionless" => {
            params.friction = 0.0;
            params.static_friction = 0.0;
        }
        "norule" => {
            params.friction = 0.0;
            params.static_friction = 0.0;
            params.root_exit = 1.0e6;
        }
        "capsules" | "points" => {
            // `points`: capsules with a == b, the spheres' very shapes
            // through the capsule code (its cost per test).
            let half = if scene == "points" { 0.0 } else { 1.0 };
            capsules = rig
                .iter()
                .map(|s| Capsule {
                    a: s.center - Vec3::X * (s.radius * half),
                    b: s.center + Vec3::X * (s.radius * half),
                    radius: s.radius,
                })
                .collect();
            rig.clear();
        }
        "drag" => params.drag = 1.0,
        "wind" | "gusts" => {
            params.wind = Vec3::new(2.0, 0.0, 1.0);
            params.drag = 1.0;
            if scene == "gusts" {
                params.turbulence = 1.0;
            }
        }
        "hair" | "volume" | "friction" => {
            // Hair against hair: `hair` both at 1, or one of them.
            params.volume_stiffness = if scene == "friction" { 0.0 } else { 1.0 };
            params.hair_friction = if scene == "volume" { 0.0 } else { 1.0 };
        }
        "field" => {
            let Some((positions, triangles)) = coif_testkit::sintel_bust() else {
                std::process::exit(1);
            };
            let mut f = Sdf::from_mesh(&positions, &triangles, 0.004).expect("the bust's field");
            // The bust's head on the head sphere, then moved along y until
            // the median root lies on its surface (the scalp).
            let mut at = near[0].center - Vec3::new(0.0, 0.37, 0.0);
            let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
            for _ in 0..4 {
                f.set_transform(Affine3A::from_translation(at))
                    .expect("a translation");
                let mut d: Vec<f32> = roots.iter().map(|r| f.distance(*r)).collect();
                d.sort_by(f32::total_cmp);
                at.y += d[d.len() / 2];
            }
            f.set_transform(Affine3A::from_translation(at))
                .expect("a translation");
            fields.push(f);
        }
        "empty" => rig.clear(),
        _ => {}
    }
    let colliders = Colliders {
        spheres: &rig,
        capsules: &capsules,
        sdfs: &fields,
    };
    let mut s = Strands::from_polylines(&pts, v).expect("strands");
    if shape > 0.0 {
        // The springs' rest state: the groom (out of the skins) holds.
        let t = Instant::now();
        s.solve_sag_free(&params, &colliders)
            .expect("the sag-free solve");
        println!("sag-free solve: {:.1} ms", t.elapsed().as_secs_f64() * 1e3);
    }
    for _ in 0..30 {
        step_colliders(&mut s, &params, &colliders);
    }
    let t = Instant::now();
    measured_steps(&mut s, &params, &colliders, steps, use_scalar);
    let per_step = t.elapsed().as_secs_f64() / steps.max(1) as f64;
    let hash = s.positions().iter().fold(0u64, |h, p| {
        [p.x, p.y, p.z].iter().fold(h, |h, c| {
            h.wrapping_mul(0x100_0000_01b3) ^ c.to_bits() as u64
        })
    });
    println!(
        "{scene}, local shape {shape}, {}: {:.3} ms per step, {:.2} ns per vertex-step, positions hash {hash:016x}",
        if use_scalar { "scalar" } else { "SIMD" },
        per_step * 1e3,
        per_step * 1e9 / pts.len() as f64,
    );
}

/// The steps counted (callgrind `--toggle-collect='*measured_steps*'`).
#[inline(never)]
fn measured_steps(
    s: &mut Strands,
    p: &SimParams,
    colliders: &Colliders<'_>,
    steps: usize,
    use_scalar: bool,
) {
    for _ in 0..steps {
        if use_scalar {
            scalar::step_colliders(s, p, colliders);
        } else {
            step_colliders(s, p, colliders);
        }
    }
}
