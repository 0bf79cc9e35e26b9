//! An engine's integration, groom file to shaded render-hair buffers:
//! `cargo run --release --example engine [GROOM.tfx MESH.obj]` (default:
//! Sintel's shipped groom and bust). Load, resample, triangulate the roots,
//! build the strands and the body's field once; then per frame one head
//! pose, one step, refine, interpolate, write vertices and shade them into
//! buffers sized once. Prints the per-stage times.
use coif::geometry::{mesh::TriangleMesh, scene::fit_sphere, triangulate::scalp_triangles};
use coif::glam::{Affine3A, Quat, Vec3};
use coif::kernels::{step_colliders, Colliders, Sdf, SimParams, Strands};
use coif::lod::{self, level, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex};
use coif::shading::{kajiya_kay::KajiyaKay, vertices::shade_vertices};
use std::time::{Duration, Instant};

const VERTS: usize = 24; // guide points per strand, whatever the file has
const ASSETS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/sintel/");

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let groom_path = args
        .get(1)
        .cloned()
        .unwrap_or(format!("{ASSETS}sintel_lite.tfx"));
    let mesh_path = args
        .get(2)
        .cloned()
        .unwrap_or(format!("{ASSETS}sintel_bust.obj"));
    let read = |p: &str| std::fs::read(p).map_err(|e| format!("{p}: {e}"));

    // Once: the groom in metres at one vertex count, its scalp, the body.
    let setup = Instant::now();
    let groom = coif::groom::load(&read(&groom_path)?)?;
    let guides = groom.resampled(VERTS, 0.01)?; // centimetres -> metres
    let roots: Vec<Vec3> = guides.iter().step_by(VERTS).copied().collect();
    let head = fit_sphere(&roots).ok_or("no head fits the roots")?;
    let scalp = scalp_triangles(&roots, head.center);
    let bust = TriangleMesh::from_obj(&read(&mesh_path)?, 0.01)?;
    let mut field = Sdf::from_mesh(bust.positions(), bust.triangles(), 0.004)?;
    let mut hair = Strands::from_polylines(&guides, VERTS)?;
    let params = SimParams {
        local_shape_stiffness: 0.7, // a groom keeps its style and swings
        volume_stiffness: 1.0,      // hair against hair
        hair_friction: 1.0,
        ..SimParams::default()
    };
    params.validate()?;
    // The groom is the springs' rest state under gravity (sag-free).
    let colliders = Colliders {
        sdfs: std::slice::from_ref(&field),
        ..Colliders::default()
    };
    hair.solve_sag_free(&params, &colliders)?;

    // Once: LOD and shading buffers for every render hair at the finest level.
    let max_segments = 3;
    let interp = Interpolation::new(&roots, &scalp, 20.0, 7)?; // 20 render hairs per cm^2
    let mut guides_refined = RefinedGuides::new(hair.blocks(), max_segments)?;
    let mut hairs = RenderHairs::new(&interp, &guides_refined);
    let capacity = interp.hair_count() * lod::refined_len(VERTS, max_segments);
    let mut vertices = vec![RenderVertex::default(); capacity];
    let mut colours = vec![Vec3::ZERO; capacity];
    let model = KajiyaKay::default();
    let to_light = Vec3::new(-0.5, 0.7, 0.5).normalize();
    let eye_world = head.center + Vec3::new(-0.3, 0.05, 0.7);
    println!(
        "{}: {} strands -> {} guides x {VERTS}, {} scalp triangles, {} render hairs; bust {} triangles; setup {:.0} ms",
        groom_path,
        groom.strand_count(),
        hair.strand_count(),
        scalp.len(),
        interp.hair_count(),
        bust.triangles().len(),
        setup.elapsed().as_secs_f64() * 1e3
    );

    // Per frame: a head turn of 60 degrees and back over 2 s, at 60 Hz.
    let pivot = head.center - Vec3::Y * head.radius;
    let mut times = [Duration::ZERO; 4];
    let frames = 120;
    let mut drawn = 0;
    for f in 0..frames {
        let t = f as f32 / 60.0;
        let yaw = 60f32.to_radians() * (std::f32::consts::PI * t).sin().max(0.0);
        let pose = Affine3A::from_translation(pivot)
            * Affine3A::from_quat(Quat::from_rotation_y(yaw))
            * Affine3A::from_translation(-pivot);

        let start = Instant::now();
        hair.set_head_pose(pose)?; // roots and rest frame, one call
        field.set_transform(pose)?;
        let colliders = Colliders {
            sdfs: std::slice::from_ref(&field),
            ..Colliders::default()
        };
        step_colliders(&mut hair, &params, &colliders);
        let simulated = Instant::now();

        // LOD: every group drawn, the level from the camera distance.
        let px_per_m = level::pixels_per_metre((eye_world - head.center).length(), 0.7, 720.0);
        let segments = level::segments_per_span(
            level::max_second_difference_strands(hair.blocks()),
            px_per_m,
            0.5,
            max_segments,
        );
        guides_refined.set_segments_per_span(segments)?;
        lod::refine_strands(hair.blocks(), None, &mut guides_refined)?;
        lod::interpolate(
            &interp,
            &guides_refined,
            None,
            interp.group_count(),
            &mut hairs,
        )?;
        drawn = lod::write_render_vertices(
            &interp,
            &hairs,
            interp.group_count(),
            HairWidth::default(),
            1.0,
            &mut vertices,
        )?;
        let refined = Instant::now();

        // Shading: the eye in the vertices' space (relative to the origin).
        let eye = eye_world - hair.origin().as_vec3();
        shade_vertices(&model, &vertices[..drawn], to_light, eye, &mut colours)?;
        let shaded = Instant::now();
        for (k, d) in times
            .iter_mut()
            .zip([start, simulated, refined, shaded].windows(2))
        {
            *k += d[1] - d[0];
        }
        times[3] += shaded - start;
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3 / frames as f64;
    println!(
        "per frame (mean of {frames}): step {:.2} ms, refine + interpolate + vertices {:.2} ms, shade {:.2} ms, total {:.2} ms; {drawn} vertices",
        ms(times[0]),
        ms(times[1]),
        ms(times[2]),
        ms(times[3])
    );
    // A renderer uploads lod::vertex_bytes(&vertices[..drawn]) and the colours.
    Ok(())
}
