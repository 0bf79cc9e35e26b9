//! `coif --crowd N`: N characters with the built-in head's hair at
//! different distances (a quarter near the camera, a quarter off screen,
//! the rest far; every other one turning and nodding, the others standing
//! still), simulated twice over the same frames: skipping what the scene
//! does not need (simulation LOD by on-screen height, rigid following off
//! screen, sleeping) and simulating everyone fully. Prints the simulation
//! time per frame of both, the share of strand-steps advanced, and the RMS
//! distance of the skipping run to the full one per level. Simulation
//! only: nothing is drawn.

use coif::base::tasks::Executor;
use coif::frame::crowd::{add_distances, settled_head, Crowd};
use coif::frame::sim_lod::STRIDES;
use coif::kernels::SimParams;
use std::time::{Duration, Instant};

/// Runs the crowd of `n` for `frames` frames of 1/60 s, the characters as
/// tasks on `executor`.
pub fn run(
    n: usize,
    frames: usize,
    executor: &dyn Executor,
) -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    // Settled for 7 s: the pose the characters start from and followers
    // keep their shape relative to.
    let (scene, settled) = settled_head(2048, 32)?;
    let params = SimParams::default();
    let build = |skip| Crowd::standard(&scene, &settled, n, &params, skip);
    let (mut lean, mut full) = (build(true)?, build(false)?);
    out!(
        "coif --crowd {n}: {} guides x {} points per character, {} characters ({} near, {} off screen, the rest far; every other one moving); setup {:.0} ms",
        full.guide_count() / n.max(1),
        full.verts_per_strand(),
        n,
        n.div_ceil(4),
        n / 4,
        start.elapsed().as_secs_f64() * 1e3
    );
    let (mut t_lean, mut t_full) = (Duration::ZERO, Duration::ZERO);
    let (mut advanced, mut everyone) = (0usize, 0usize);
    let mut errors = vec![(0.0f64, 0usize); STRIDES.len() + 1];
    let frames = frames.max(1);
    for f in 0..frames {
        let t = f as f32 * params.dt;
        let t0 = Instant::now();
        lean.step(t, executor);
        t_lean += t0.elapsed();
        let t0 = Instant::now();
        full.step(t, executor);
        t_full += t0.elapsed();
        advanced += lean.simulated_strands();
        everyone += full.simulated_strands();
        add_distances(&lean, &full, &mut errors);
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3 / frames as f64;
    out!(
        "{frames} frames of 1/60 s, {} thread(s): simulating everyone fully {:.2} ms per frame; with simulation LOD, off-screen following and sleeping {:.2} ms per frame ({:.1} %); strand-steps advanced {:.1} %",
        executor.threads(),
        ms(t_full),
        ms(t_lean),
        100.0 * t_lean.as_secs_f64() / t_full.as_secs_f64().max(1e-12),
        100.0 * advanced as f64 / everyone.max(1) as f64
    );
    out!("last frame, per character (level 0 = every guide simulated, strides {STRIDES:?}):");
    for i in 0..lean.len() {
        if let Some(c) = lean.character_step(i) {
            out!(
                "  {i:2}: {:<10} level {} (stride {}), {:4} of {} strands stepped",
                if c.visible { "on screen" } else { "off screen" },
                c.level,
                STRIDES[c.level.min(STRIDES.len() - 1)],
                c.simulated,
                c.guides
            );
        }
    }
    out!("RMS distance to simulating everyone fully, over all frames:");
    for (g, (sum, count)) in errors.iter().enumerate() {
        if *count == 0 {
            continue;
        }
        let what = if g + 1 == errors.len() {
            "off screen (rigid)".to_string()
        } else {
            format!("level {g} (stride {})", STRIDES[g])
        };
        out!(
            "  {what:<20} {:.2} mm over {} character-frames",
            1e3 * (sum / *count as f64).sqrt(),
            count / full.verts_per_strand().max(1) / (full.guide_count() / n.max(1)).max(1)
        );
    }
    Ok(())
}
