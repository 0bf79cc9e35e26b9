//! The shadow map build as independent tasks (`build_tasks`): the same
//! bytes whatever runs the tasks (in order, in reverse, on three threads),
//! bit for bit `build` with one task, and with several tasks the same map
//! up to the grouping of the float sums; scratch for other settings gives
//! no map instead of a panic.

mod common;

use coif_base::tasks::{Executor, Serial};
use coif_shading::shadow::{BuildScratch, LaneRows, OpacityShadowMap, ShadowMode, ShadowSettings};
use coif_testkit::executors::Backwards;
use glam::Vec3;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Three scoped threads taking indices from a shared counter.
struct Threads;

// SAFETY: the counter hands each index to exactly one thread, and the scope
// joins every thread before `run` returns.
unsafe impl Executor for Threads {
    fn threads(&self) -> usize {
        3
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let next = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..3 {
                s.spawn(|| loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= count {
                        break;
                    }
                    task(i);
                });
            }
        });
    }
}

#[test]
fn task_builds_have_the_same_bytes_on_any_executor() {
    let (verts, light) = (16, Vec3::new(1.0, -0.5, 0.3));
    let mut pts = common::curly_hair(301, verts, 11, 0.5);
    pts[40] = Vec3::NAN;
    for settings in [
        ShadowSettings {
            resolution: 64,
            ..Default::default()
        },
        ShadowSettings {
            resolution: 64,
            layers: 5,
            mode: ShadowMode::Deep,
            ..Default::default()
        },
    ] {
        let mut single = OpacityShadowMap::new(settings.clone()).unwrap();
        single.build(light, &pts, verts);
        let reference = common::stored_bits(&single);
        assert!(reference.iter().filter(|b| **b != 0).count() > 1000);

        let mut one = BuildScratch::new(&settings, 1).unwrap();
        let mut map = OpacityShadowMap::new(settings.clone()).unwrap();
        map.build_tasks(&Serial, &mut one, light, &pts, verts)
            .unwrap();
        assert_eq!(
            common::stored_bits(&map),
            reference,
            "one task is build, bit for bit"
        );

        let mut scratch = BuildScratch::new(&settings, 7).unwrap();
        let executors: [&dyn Executor; 3] = [&Serial, &Backwards(1), &Threads];
        let mut maps = Vec::new();
        for e in executors {
            let mut m = OpacityShadowMap::new(settings.clone()).unwrap();
            m.build_tasks(e, &mut scratch, light, &pts, verts).unwrap();
            maps.push(common::stored_bits(&m));
            let p = pts[200];
            assert!((m.transmittance(p) - single.transmittance(p)).abs() < 1e-5);
        }
        assert_eq!(maps[0], maps[1], "reverse order: same bytes");
        assert_eq!(maps[0], maps[2], "three threads: same bytes");
        for (a, b) in maps[0].iter().zip(&reference) {
            let (a, b) = (f32::from_bits(*a), f32::from_bits(*b));
            assert!((a - b).abs() <= 1e-5 * b.abs().max(1.0), "{a} vs {b}");
        }
    }
}

/// The lane-layout build as tasks (ranges of blocks): the same bytes on
/// any executor, and within float rounding of the one-task build (each
/// texel sums the same deposits grouped by task).
#[test]
fn lane_task_builds_have_the_same_bytes_on_any_executor() {
    let (verts, light) = (16, Vec3::new(1.0, -0.5, 0.3));
    let mut pts = common::curly_hair(301, verts, 11, 0.5);
    pts[40] = Vec3::NAN;
    let (rows, strands) = common::lane_rows(&pts, verts);
    let hair = LaneRows {
        rows: &rows,
        verts,
        strands,
    };
    let settings = ShadowSettings {
        resolution: 64,
        mode: ShadowMode::Deep,
        ..Default::default()
    };
    let mut one = BuildScratch::new(&settings, 1).unwrap();
    let mut single = OpacityShadowMap::new(settings.clone()).unwrap();
    single.build_lanes(&Serial, &mut one, light, &hair).unwrap();
    let reference = common::stored_bits(&single);
    assert!(reference.iter().filter(|b| **b != 0).count() > 1000);
    let mut scratch = BuildScratch::new(&settings, 7).unwrap();
    let executors: [&dyn Executor; 3] = [&Serial, &Backwards(1), &Threads];
    let mut maps = Vec::new();
    for e in executors {
        let mut m = OpacityShadowMap::new(settings.clone()).unwrap();
        m.build_lanes(e, &mut scratch, light, &hair).unwrap();
        maps.push(common::stored_bits(&m));
    }
    assert_eq!(maps[0], maps[1], "reverse order: same bytes");
    assert_eq!(maps[0], maps[2], "three threads: same bytes");
    for (a, b) in maps[0].iter().zip(&reference) {
        let (a, b) = (f32::from_bits(*a), f32::from_bits(*b));
        assert!((a - b).abs() <= 1e-5 * b.abs().max(1.0), "{a} vs {b}");
    }
}

#[test]
fn scratch_for_other_settings_gives_no_map() {
    let settings = ShadowSettings {
        resolution: 32,
        ..Default::default()
    };
    let other = ShadowSettings {
        resolution: 16,
        ..Default::default()
    };
    let mut scratch = BuildScratch::new(&other, 2).unwrap();
    let mut map = OpacityShadowMap::new(settings).unwrap();
    let built = map.build_tasks(
        &Serial,
        &mut scratch,
        Vec3::NEG_Z,
        &common::curly_hair(20, 8, 11, 0.5),
        8,
    );
    assert!(matches!(
        built,
        Err(coif_shading::Error::CountMismatch { .. })
    ));
    assert!(!map.is_ready());
    assert_eq!(map.transmittance(Vec3::ZERO), 1.0);
    assert!(BuildScratch::new(&ShadowSettings { layers: 0, ..other }, 2).is_err());
}
