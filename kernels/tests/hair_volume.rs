//! Hair against hair (`hair_grid/`: volume and friction on a grid of the
//! hair), at `volume_stiffness = 1` and `hair_friction = 1` against both
//! off: hair draped on a head packs at most half as densely in its densest
//! places and fills at least 1.6 times the cells, and still settles; a
//! kicked lock's velocities relative to the lock fall to a third within
//! 0.1 s while its common motion stays; sparse hair hanging at rest does not
//! move; SIMD = scalar; the same bytes on 1 and 2 threads; the stability
//! matrix with both on; off is the step as before, bit for bit; pressure
//! from awake hair wakes sleeping hair, and friction slower than
//! `sleep_speed` does not.

mod common;

use coif_geometry::scene::{grow_on_sphere, GrowOptions};
use coif_kernels::rng::SplitMix64;
use coif_kernels::tasks::Rayon;
use coif_kernels::{scalar, step, step_with, SimParams, Sphere, Strands};
use glam::Vec3;
use std::collections::HashMap;

fn on(cell: f32) -> SimParams {
    SimParams {
        volume_stiffness: 1.0,
        hair_friction: 1.0,
        hair_grid_cell: cell,
        sleep_speed: 0.0,
        ..Default::default()
    }
}

fn off() -> SimParams {
    SimParams {
        sleep_speed: 0.0,
        ..Default::default()
    }
}

/// `count` strands of 25 cm grown straight out of the top of a 9 cm head
/// (the cap above a fifth of its radius), and the head.
fn head_of_hair(count: usize, verts: usize) -> (Vec<Vec3>, usize, Vec<Sphere>) {
    let head = grow_on_sphere(&GrowOptions {
        strand_count: count,
        verts_per_strand: verts,
        length: 0.25,
        center: Vec3::new(0.0, 1.6, 0.0),
        radius: 0.09,
        lowest_root: 0.2,
        curl: 0.0,
        seed: 3,
    });
    (head.points, head.verts_per_strand, vec![head.head])
}

/// The hair of [`head_of_hair`] dropped for `seconds` under `p`; returns
/// it and the fastest vertex's speed over the last step.
fn drape(p: &SimParams, seconds: f32) -> (Strands, f32) {
    let (pts, verts, rig) = head_of_hair(1024, 24);
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    for _ in 0..(seconds / p.dt) as usize {
        step(&mut s, p, &rig);
    }
    let before = s.positions();
    step(&mut s, p, &rig);
    let speed = s
        .positions()
        .iter()
        .zip(&before)
        .map(|(a, b)| a.distance(*b) / p.dt)
        .fold(0.0f32, f32::max);
    (s, speed)
}

/// The 99th percentile of segments per 5 mm cell (a segment counted in the
/// cell of its midpoint; the two segments at the root left out, the
/// scalp's crowd) and the number of cells with any.
fn packing(s: &Strands) -> (usize, usize) {
    let pts = s.positions();
    let mut cells: HashMap<[i32; 3], usize> = HashMap::new();
    for strand in pts.chunks(s.verts_per_strand()) {
        for w in strand.windows(2).skip(2) {
            let m = (w[0] + w[1]) * 0.5 / 0.005;
            let key = [m.x.floor() as i32, m.y.floor() as i32, m.z.floor() as i32];
            *cells.entry(key).or_default() += 1;
        }
    }
    let mut counts: Vec<usize> = cells.values().copied().collect();
    counts.sort_unstable();
    (counts[counts.len() * 99 / 100], counts.len())
}

#[test]
fn draped_hair_keeps_its_volume_and_settles() {
    let (without, _) = drape(&off(), 3.0);
    let (with, speed) = drape(&on(SimParams::default().hair_grid_cell), 3.0);
    let (p99_off, cells_off) = packing(&without);
    let (p99_on, cells_on) = packing(&with);
    eprintln!(
        "segments per 5 mm cell, 99th percentile: {p99_off} -> {p99_on}; cells {cells_off} -> {cells_on} ({:.2}x); fastest vertex after 3 s {speed:.3} m/s",
        cells_on as f32 / cells_off as f32
    );
    assert!(2 * p99_on <= p99_off, "{p99_on} vs {p99_off}");
    assert!(cells_on * 10 >= cells_off * 16, "{cells_on} vs {cells_off}");
    assert!(speed < 0.3, "still moving at {speed} m/s after 3 s");
    assert!(with.positions().iter().all(|p| p.is_finite()));
}

/// A lock of 64 strands of 20 cm (roots 3 mm apart on an 8 x 8 grid)
/// hanging at rest, kicked: every strand at (1, 0, 0) m/s plus its own
/// random velocity of up to 0.5 m/s per axis, across the lock.
fn kicked_lock(p: &SimParams) -> (Vec<f32>, Vec<f32>) {
    let verts = 21;
    let mut pts = Vec::new();
    for i in 0..64 {
        let root = Vec3::new((i % 8) as f32 * 0.003, 1.0, (i / 8) as f32 * 0.003);
        pts.extend((0..verts).map(|v| root - Vec3::Y * (0.01 * v as f32)));
    }
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    let mut rng = SplitMix64::new(11);
    let kick: Vec<Vec3> = (0..64)
        .map(|_| {
            Vec3::X
                + Vec3::new(
                    rng.range(-0.5, 0.5),
                    rng.range(-0.5, 0.5),
                    rng.range(-0.5, 0.5),
                )
        })
        .collect();
    let x = s.positions();
    let prev: Vec<Vec3> = x
        .iter()
        .enumerate()
        .map(|(i, x)| {
            if i % verts == 0 {
                *x
            } else {
                // The kick grows along the strand from its root.
                *x - kick[i / verts] * p.dt * (i % verts) as f32 / verts as f32
            }
        })
        .collect();
    s.set_state(&x, &prev).unwrap();
    let relative_rms = |vel: &[Vec3]| {
        let mut sum2 = 0.0f32;
        for v in verts / 4..verts {
            let row: Vec<Vec3> = (0..64).map(|k| vel[k * verts + v]).collect();
            let m = row.iter().sum::<Vec3>() / 64.0;
            sum2 += row.iter().map(|r| (*r - m).length_squared()).sum::<f32>();
        }
        (sum2 / (64 * (verts - verts / 4)) as f32).sqrt()
    };
    let kicked: Vec<Vec3> = x.iter().zip(&prev).map(|(a, b)| (*a - *b) / p.dt).collect();
    // Per step for 0.1 s: the RMS of the velocities relative to the lock's
    // mean at each vertex row, and the lock's mean velocity along x (the
    // vertices beyond the first quarter).
    let (mut relative, mut mean) = (vec![relative_rms(&kicked)], Vec::new());
    let mut last = s.positions();
    for _ in 0..6 {
        step(&mut s, p, &[]);
        let now = s.positions();
        let vel: Vec<Vec3> = now
            .iter()
            .zip(&last)
            .map(|(a, b)| (*a - *b) / p.dt)
            .collect();
        relative.push(relative_rms(&vel));
        let rows = verts / 4..verts;
        let n = 64 * rows.len();
        let mx: f32 = rows
            .flat_map(|v| (0..64).map(move |k| k * verts + v))
            .map(|i| vel[i].x)
            .sum();
        mean.push(mx / n as f32);
        last = now;
    }
    (relative, mean)
}

#[test]
fn a_kicked_lock_moves_as_one_and_keeps_its_common_motion() {
    let (rel_off, mean_off) = kicked_lock(&off());
    let (rel_on, mean_on) = kicked_lock(&on(SimParams::default().hair_grid_cell));
    eprintln!("relative RMS off {rel_off:?}\n            on  {rel_on:?}\nmean x off {mean_off:?}\n       on  {mean_on:?}");
    // Within 0.1 s (6 steps) the strands' motion relative to the lock falls
    // to a third of the kick's; without friction it does not.
    assert!(rel_on[6] <= rel_on[0] / 3.0, "{rel_on:?}");
    assert!(rel_off[6] > rel_off[0] / 3.0, "{rel_off:?}");
    // The lock's common motion is kept: within 15 % of the frictionless
    // lock's at every step.
    for (a, b) in mean_on.iter().zip(&mean_off) {
        assert!(
            (a - b).abs() <= 0.15 * b.abs(),
            "{mean_on:?} vs {mean_off:?}"
        );
    }
}

#[test]
fn sparse_hair_hanging_at_rest_does_not_move() {
    // 64 strands of 30 cm, roots 5 cm apart, hanging straight down.
    let verts = 31;
    let mut pts = Vec::new();
    for i in 0..64 {
        let root = Vec3::new((i % 8) as f32 * 0.05, 2.0, (i / 8) as f32 * 0.05);
        pts.extend((0..verts).map(|v| root - Vec3::Y * (0.01 * v as f32)));
    }
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    let start = s.positions();
    let p = on(SimParams::default().hair_grid_cell);
    for _ in 0..(2.0 / p.dt) as usize {
        step(&mut s, &p, &[]);
    }
    let moved = s
        .positions()
        .iter()
        .zip(&start)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(moved <= 5e-4, "moved {moved} m");
}

#[test]
fn simd_equals_scalar_and_threads_give_the_same_bytes() {
    let (pts, verts, rig) = head_of_hair(96, 16);
    let p = on(SimParams::default().hair_grid_cell);
    let mut simd = Strands::from_polylines(&pts, verts).unwrap();
    let mut lanes = simd.clone();
    let mut threaded = simd.clone();
    let pool = Rayon::new(2).unwrap();
    let mut worst = 0.0f32;
    for _ in 0..60 {
        step(&mut simd, &p, &rig);
        scalar::step(&mut lanes, &p, &rig);
        step_with(&mut threaded, &p, &rig, &pool);
        let (a, b) = (simd.positions(), lanes.positions());
        worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| x.distance(*y))
            .fold(worst, f32::max);
        assert!(
            simd.positions_local() == threaded.positions_local(),
            "2 threads differ"
        );
    }
    eprintln!("SIMD vs scalar over 1 s: {worst} m");
    assert!(worst <= 1e-3, "{worst}");
}

#[test]
fn off_is_the_step_as_before_bit_for_bit() {
    // A cell or a grid that never runs changes nothing.
    let (pts, verts, rig) = head_of_hair(64, 12);
    let mut a = Strands::from_polylines(&pts, verts).unwrap();
    let mut b = a.clone();
    let other = SimParams {
        hair_grid_cell: 0.05,
        ..off()
    };
    for _ in 0..30 {
        step(&mut a, &off(), &rig);
        step(&mut b, &other, &rig);
    }
    assert!(a.positions_local() == b.positions_local());
}

#[test]
fn stable_under_the_stability_matrix() {
    let (pts, verts, rig) = head_of_hair(48, 12);
    for dt in [1.0 / 240.0, 1.0 / 60.0, 1.0 / 15.0] {
        for g in [1.0, 100.0] {
            for jump in [0.0f32, 10.0] {
                let p = SimParams {
                    dt,
                    gravity: Vec3::new(0.0, -9.81 * g, 0.0),
                    ..on(0.015)
                };
                let mut s = Strands::from_polylines(&pts, verts).unwrap();
                let roots: Vec<Vec3> = pts.iter().step_by(verts).copied().collect();
                for k in 0..60 {
                    // Roots jump back and forth by `jump` metres.
                    let shift = if k % 20 == 10 { jump } else { 0.0 };
                    let moved: Vec<Vec3> = roots.iter().map(|r| *r + Vec3::X * shift).collect();
                    s.set_roots(&moved).unwrap();
                    step(&mut s, &p, &rig);
                    let x = s.positions();
                    assert!(
                        x.iter()
                            .all(|p| p.is_finite() && p.abs().max_element() < 1e3),
                        "dt {dt} g {g} jump {jump}: step {k}"
                    );
                }
            }
        }
    }
    // Far from the origin, one strand thrown 1e30 m away (as a bad state
    // would) spreads nothing through the grid: the others move exactly as
    // when it is thrown a mere 20 km away (out of the grid's reach
    // either way), with both finite.
    let far: Vec<Vec3> = pts.iter().map(|p| *p + Vec3::splat(1.0e4)).collect();
    let p = on(0.015);
    let run = |throw: f32| {
        let mut s = Strands::from_polylines(&far, verts).unwrap();
        let mut x = s.positions();
        for v in 0..verts {
            x[3 * verts + v] += Vec3::new(throw, -throw, 0.0);
        }
        let prev = x.clone();
        s.set_state(&x, &prev).unwrap();
        for _ in 0..30 {
            step(&mut s, &p, &[]);
        }
        s.positions()
    };
    let (near, thrown) = (run(2.0e4), run(1.0e30));
    for (i, (a, b)) in near.iter().zip(&thrown).enumerate() {
        if i / verts != 3 {
            assert!(b.is_finite() && a == b, "vertex {i}: {a} vs {b}");
        }
    }
}

/// A lock of eight strands of `verts` vertices 1 cm apart, hanging from a
/// 4 x 2 grid of roots 4 mm apart whose first is at `x = x0`, `y = 1`.
fn lock(x0: f32, verts: usize) -> Vec<Vec3> {
    (0..8)
        .flat_map(|i| {
            let root = Vec3::new(x0 + (i % 4) as f32 * 0.004, 1.0, (i / 4) as f32 * 0.004);
            (0..verts).map(move |v| root - Vec3::Y * (0.01 * v as f32))
        })
        .collect()
}

/// Two locks of eight strands (one block each) hanging 20 cm apart fall
/// asleep; then the second's roots move into the first. The moving lock
/// packs the sleeping one denser than its groom: the grid's push wakes it
/// (both blocks awake); without volume and friction it sleeps on.
#[test]
fn pressure_from_awake_hair_wakes_sleeping_hair() {
    let verts = 16;
    let pts: Vec<Vec3> = [lock(0.0, verts), lock(0.2, verts)].concat();
    let run = |p: &SimParams| {
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        for _ in 0..240 {
            step(&mut s, p, &[]);
        }
        let asleep = s.awake_strands();
        // The second lock's roots onto the first's.
        let roots: Vec<Vec3> = pts
            .iter()
            .step_by(verts)
            .enumerate()
            .map(|(i, r)| {
                if i >= 8 {
                    *r - Vec3::X * 0.2 + Vec3::Z * 0.002
                } else {
                    *r
                }
            })
            .collect();
        s.set_roots(&roots).unwrap();
        step(&mut s, p, &[]);
        step(&mut s, p, &[]);
        (asleep, s.awake_strands())
    };
    let with = SimParams {
        sleep_speed: 0.02,
        ..on(SimParams::default().hair_grid_cell)
    };
    let without = SimParams {
        sleep_speed: 0.02,
        ..Default::default()
    };
    assert_eq!(run(&with), (0, 16), "both asleep, then both awake");
    assert_eq!(run(&without), (0, 8), "only the moved lock wakes");
}

/// Two locks of eight strands (one block each) hanging through each other
/// fall asleep; then the second's roots circle, slowly (5 mm/s) and then
/// fast (10 cm/s). The grid's friction drags the sleeping lock toward the
/// moving one's velocity: slower than `sleep_speed`, it does not wake it
/// (a trembling strand must not keep a whole head awake); faster, it does.
#[test]
fn friction_slower_than_sleep_speed_leaves_sleeping_hair_asleep() {
    let verts = 16;
    let pts: Vec<Vec3> = [lock(0.0, verts), lock(0.002, verts)].concat();
    let p = SimParams {
        sleep_speed: 0.02,
        ..on(SimParams::default().hair_grid_cell)
    };
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    for _ in 0..240 {
        step(&mut s, &p, &[]);
    }
    assert_eq!(s.sleeping_strands(), 16, "both locks asleep at rest");
    // The second lock's roots on a 4 mm circle at `speed` m/s.
    let circle = |s: &mut Strands, speed: f32, steps: usize, t0: &mut f32| -> usize {
        let mut first_asleep = 0;
        for k in 0..steps {
            *t0 += p.dt;
            let a = speed / 0.004 * *t0;
            let off = Vec3::new(0.004 * a.cos() - 0.004, 0.0, 0.004 * a.sin());
            let roots: Vec<Vec3> = pts
                .iter()
                .step_by(verts)
                .enumerate()
                .map(|(i, r)| if i >= 8 { *r + off } else { *r })
                .collect();
            s.set_roots(&roots).unwrap();
            step(s, &p, &[]);
            if k == steps - 1 {
                first_asleep = s.sleeping_strands();
            }
        }
        first_asleep
    };
    let mut t = 0.0;
    // Slowly for 2 s: the first lock sleeps through it (it may wake in
    // the first steps, while the second lock starts, and falls asleep
    // again).
    assert_eq!(
        circle(&mut s, 0.005, 120, &mut t),
        8,
        "slow: the first lock asleep"
    );
    // Fast: the first lock wakes.
    circle(&mut s, 0.1, 10, &mut t);
    assert_eq!(s.awake_strands(), 16, "fast: both locks awake");
}

/// Simulation LOD: a level with every other guide carries the same hair,
/// so its volume must not shrink: the draped layer is as thick (the mean
/// distance of the vertices from the head's centre) within 10 %.
#[test]
fn half_the_guides_keep_the_volume() {
    let (pts, verts, rig) = head_of_hair(1024, 24);
    let half: Vec<Vec3> = pts.chunks(verts).step_by(2).flatten().copied().collect();
    let thickness_with = |pts: &[Vec3], p: &SimParams| {
        let mut s = Strands::from_polylines(pts, verts).unwrap();
        for _ in 0..180 {
            step(&mut s, p, &rig);
        }
        let c = rig[0].center;
        let x = s.positions();
        x.iter().map(|q| q.distance(c)).sum::<f32>() / x.len() as f32
    };
    let p = on(SimParams::default().hair_grid_cell);
    let (all, some) = (thickness_with(&pts, &p), thickness_with(&half, &p));
    let flat = thickness_with(&half, &off());
    let r = rig[0].radius;
    eprintln!("mean distance from the head's centre: all guides {all:.4}, half {some:.4}, half without volume {flat:.4} (head {r})");
    // The volume is there (the layer is thicker than without) ...
    assert!(some - r >= 1.15 * (flat - r), "{some} vs {flat}");
    // ... and as thick with half the guides.
    assert!(
        ((some - r) - (all - r)).abs() <= 0.1 * (all - r),
        "{all} vs {some}"
    );
}

/// Wind through dense hair: a lock of 64 strands (8 x 8 roots 3 mm apart)
/// and a lone strand 30 cm beside it, 20 cm each, in a steady wind along
/// +x for 2 s. With the grid, the hair upwind shields the lock's inside:
/// its downwind strands bend less than the lone strand and less than its
/// upwind ones; without, every strand bends alike.
#[test]
fn dense_hair_shields_its_inside_from_the_wind() {
    let verts = 21;
    let mut pts = Vec::new();
    let root = |i: usize| {
        if i < 64 {
            Vec3::new((i % 8) as f32 * 0.003, 1.0, (i / 8) as f32 * 0.003)
        } else {
            Vec3::new(0.0, 1.0, 0.3)
        }
    };
    for i in 0..65 {
        pts.extend((0..verts).map(|v| root(i) - Vec3::Y * (0.01 * v as f32)));
    }
    let bend = |p: &SimParams| {
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        for _ in 0..120 {
            step(&mut s, p, &[]);
        }
        let x = s.positions();
        // Tip displacement along the wind, per strand.
        (0..65)
            .map(|i| x[i * verts + verts - 1].x - root(i).x)
            .collect::<Vec<f32>>()
    };
    let windy = |p: SimParams| SimParams {
        wind: Vec3::new(3.0, 0.0, 0.0),
        drag: 2.0,
        ..p
    };
    let mean = |b: &[f32], column: usize| (0..8).map(|r| b[r * 8 + column]).sum::<f32>() / 8.0;
    let with = bend(&windy(on(SimParams::default().hair_grid_cell)));
    let without = bend(&windy(off()));
    eprintln!(
        "tip along the wind: lone {:.4} / {:.4}; lock upwind column {:.4} / {:.4}; downwind column {:.4} / {:.4} (with / without the grid)",
        with[64],
        without[64],
        mean(&with, 0),
        mean(&without, 0),
        mean(&with, 7),
        mean(&without, 7)
    );
    assert!(mean(&with, 7) < 0.85 * with[64], "{with:?}");
    assert!(mean(&with, 7) < 0.9 * mean(&with, 0), "{with:?}");
    assert!((mean(&without, 7) - without[64]).abs() < 0.05 * without[64]);
    assert!(
        with[64] > 0.9 * without[64],
        "the lone strand feels the whole wind"
    );
}

/// `Strands::set_hair_shares`: a guide standing for more hair weighs more
/// in the grid. Guides on one side of the head standing for four times the
/// hair keep that side's layer thicker than the other's; with equal shares
/// the two sides drape alike. Bad shares are refused.
#[test]
fn guides_standing_for_more_hair_weigh_more() {
    let (pts, verts, rig) = head_of_hair(1024, 24);
    let p = on(SimParams::default().hair_grid_cell);
    let roots: Vec<Vec3> = pts.iter().step_by(verts).copied().collect();
    let c = rig[0].center;
    let sides = |shares: Option<Vec<f32>>| {
        let mut s = Strands::from_polylines(&pts, verts).unwrap();
        if let Some(sh) = shares {
            s.set_hair_shares(&sh).unwrap();
        }
        for _ in 0..180 {
            step(&mut s, &p, &rig);
        }
        let x = s.positions();
        let mut sum = [0.0f32; 2];
        let mut n = [0usize; 2];
        for (i, q) in x.iter().enumerate() {
            let side = usize::from(roots[i / verts].x > c.x);
            sum[side] += q.distance(c) - rig[0].radius;
            n[side] += 1;
        }
        [sum[0] / n[0] as f32, sum[1] / n[1] as f32]
    };
    let equal = sides(None);
    let shares: Vec<f32> = roots
        .iter()
        .map(|r| if r.x > c.x { 4.0 } else { 1.0 })
        .collect();
    let weighted = sides(Some(shares));
    eprintln!(
        "layer thickness (x < 0, x > 0): equal shares {equal:?}, four times on x > 0 {weighted:?}"
    );
    assert!((equal[0] - equal[1]).abs() < 0.1 * equal[0], "{equal:?}");
    assert!(weighted[1] > 1.1 * weighted[0], "{weighted:?}");
    let mut s = Strands::from_polylines(&pts, verts).unwrap();
    assert!(s.set_hair_shares(&[1.0; 3]).is_err());
    let mut bad = vec![1.0; roots.len()];
    bad[5] = -1.0;
    assert!(s.set_hair_shares(&bad).is_err());
    bad[5] = f32::NAN;
    assert!(s.set_hair_shares(&bad).is_err());
}
