//! The roots rule measured (`SimParams::root_exit`): how far hair whose
//! roots sit on or in a collider keeps its groom.
//!
//! `cargo run --release -p coif-kernels --example roots_rule`
//!
//! Two scenes, 3 s at rest under gravity with `local_shape_stiffness = 1`
//! (the groom held), for several slopes of the rule and without the
//! collider:
//! - Sintel's groom (`sintel_lite.tfx`, 228 x 32) on a 4 mm field of her
//!   bust (`sintel_bust.obj`), the mesh it was made for;
//! - the TressFX mohawk (2,226 x 32) under a head sphere fitted to its
//!   roots and shrunk until a seventh of them lie inside its skin.
//!
//! Per run: the mean tip drift relative to the root as a share of the mean
//! strand length (as `tests/strand_mohawk.rs` measures it), the largest
//! stretch of a root segment, and the mean distance of vertices 1-3 from
//! the groom (hair pushed off the scalp). Skips a scene whose files are
//! absent.

use coif_geometry::groom;
use coif_geometry::scene::fit_sphere;
use coif_kernels::{step_colliders, Colliders, Sdf, SimParams, Sphere, Strands};
use glam::Vec3;

/// (tip drift %, largest root-segment stretch %, mean move of vertices
/// 1-3 in mm) after 3 s.
fn measure(pts: &[Vec3], v: usize, colliders: &Colliders<'_>, root_exit: f32) -> (f64, f64, f64) {
    let params = SimParams {
        local_shape_stiffness: 1.0,
        root_exit,
        ..Default::default()
    };
    let mut s = Strands::from_polylines(pts, v).expect("strands");
    for _ in 0..(3.0 / params.dt).round() as usize {
        step_colliders(&mut s, &params, colliders);
    }
    let now = s.positions();
    let (mut drift, mut len, mut stretch, mut near, mut count) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0);
    for k in 0..s.strand_count() {
        let (g, p) = (&pts[k * v..(k + 1) * v], &now[k * v..(k + 1) * v]);
        drift += ((p[v - 1] - p[0]) - (g[v - 1] - g[0])).length() as f64;
        len += g
            .windows(2)
            .map(|w| (w[1] - w[0]).length() as f64)
            .sum::<f64>();
        let rest = (g[1] - g[0]).length() as f64;
        stretch = stretch.max((p[1] - p[0]).length() as f64 / rest - 1.0);
        for i in 1..4.min(v) {
            near += (p[i] - g[i]).length() as f64;
            count += 1;
        }
    }
    (
        100.0 * drift / len,
        100.0 * stretch,
        1000.0 * near / count as f64,
    )
}

fn table(name: &str, pts: &[Vec3], v: usize, colliders: &Colliders<'_>) {
    println!("\n{name}\n| root_exit | tip drift | root segment stretch | vertices 1-3 moved |");
    println!("|---|---|---|---|");
    let (d, s, n) = measure(pts, v, &Colliders::default(), 0.5);
    println!("| no collider | {d:.2} % | {s:.2} % | {n:.2} mm |");
    for exit in [1.0e6f32, 2.0, 1.0, 0.5, 0.25, 0.0] {
        let (d, s, n) = measure(pts, v, colliders, exit);
        let label = if exit >= 1.0e6 {
            "off (every vertex out)".to_string()
        } else {
            exit.to_string()
        };
        println!("| {label} | {d:.2} % | {s:.2} % | {n:.2} mm |");
    }
}

fn main() {
    if let (Some(path), Some((positions, triangles))) = (
        coif_testkit::groom_path("sintel_lite.tfx"),
        coif_testkit::sintel_bust(),
    ) {
        let g = groom::load(&std::fs::read(path).expect("read")).expect("parse");
        let (pts, v) = g.uniform_points(0.01).expect("uniform");
        let field = Sdf::from_mesh(&positions, &triangles, 0.004).expect("field");
        let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
        let inside = roots.iter().filter(|r| field.distance(**r) < 0.0).count();
        let in_skin = roots.iter().filter(|r| field.distance(**r) < 0.002).count();
        println!(
            "Sintel: {} strands, {inside} roots inside the bust, {in_skin} inside its 2 mm skin",
            roots.len()
        );
        table(
            "Sintel on her bust (4 mm field)",
            &pts,
            v,
            &Colliders {
                sdfs: std::slice::from_ref(&field),
                ..Default::default()
            },
        );
    }
    if let Some(path) = coif_testkit::groom_path("ratboy_mohawk.tfx") {
        let g = groom::load(&std::fs::read(path).expect("read")).expect("parse");
        let (pts, v) = g.uniform_points(0.01).expect("uniform");
        let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
        let fit = fit_sphere(&roots).expect("a sphere through the roots");
        // Shrink until a seventh of the roots lie inside the skin (2 mm).
        let skin = SimParams::default().pearl_radius;
        let mut radius = fit.radius;
        let inside = |r: f32| {
            roots
                .iter()
                .filter(|p| (**p - fit.center).length() < r + skin)
                .count()
        };
        while inside(radius) > roots.len() / 7 {
            radius -= 0.0005;
        }
        let head = Sphere {
            center: fit.center,
            radius,
        };
        println!(
            "\nmohawk: head sphere of {:.1} cm, {} of {} roots inside its skin",
            radius * 100.0,
            inside(radius),
            roots.len()
        );
        table(
            "Mohawk under a head sphere that cuts a seventh of its roots",
            &pts,
            v,
            &Colliders::spheres(std::slice::from_ref(&head)),
        );
    }
}
