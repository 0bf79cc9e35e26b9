//! The shadow map's per-frame calls (SIMD and scalar builds, from points
//! and in lane layout with tasks, lookups) allocate nothing, and a
//! rebuild is deterministic: the same hair gives the same map bit for bit,
//! whatever was built before.

mod common;

use coif_base::tasks::Serial;
use coif_shading::shadow::{BuildScratch, LaneRows, OpacityShadowMap, ShadowMode, ShadowSettings};
use coif_testkit::counting::allocations;
use glam::Vec3;

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

#[test]
fn build_and_lookups_allocate_nothing_and_rebuilds_are_deterministic() {
    let hair = common::curly_hair(400, 16, 1, 0.4);
    let other = common::curly_hair(300, 16, 2, 0.4);
    let queries = common::curly_hair(50, 16, 3, 0.4);
    let mut out = vec![0.0; queries.len()];
    let (rows, strands) = common::lane_rows(&other, 16);
    let lanes = LaneRows {
        rows: &rows,
        verts: 16,
        strands,
    };
    let light = Vec3::new(0.2, -1.0, 0.1);
    for mode in [ShadowMode::Slices, ShadowMode::Deep] {
        let layers = if mode == ShadowMode::Deep { 3 } else { 16 };
        let mut map = OpacityShadowMap::new(ShadowSettings {
            resolution: 64,
            layers,
            mode,
            ..Default::default()
        })
        .unwrap();
        let mut scratch = BuildScratch::new(map.settings(), 3).unwrap();
        map.build(light, &hair, 16);
        let first = common::stored_bits(&map);
        assert!(first.iter().any(|b| f32::from_bits(*b) > 0.1));

        let before = allocations();
        map.build(light, &other, 16);
        coif_shading::shadow::scalar::build(&mut map, light, &other, 16);
        map.build_lanes(&Serial, &mut scratch, light, &lanes)
            .unwrap();
        coif_shading::shadow::scalar::build_lanes(&mut map, light, &lanes);
        map.build(light, &hair, 16);
        map.transmittance_batch(&queries, &mut out).unwrap();
        coif_shading::shadow::scalar::transmittance_batch(&map, &queries, &mut out).unwrap();
        let t = map.transmittance(queries[7]);
        let after = allocations();
        assert_eq!(
            after - before,
            0,
            "{mode:?}: allocations in build or lookup"
        );
        assert!((0.0..=1.0).contains(&t));

        // The counter does see allocations (the snapshot makes one).
        assert!(
            common::stored_bits(&map) == first,
            "{mode:?}: rebuild differs"
        );
        assert!(allocations() > after);

        // The scalar build allocates nothing either.
        let before = allocations();
        coif_shading::shadow::scalar::build(&mut map, light, &hair, 16);
        assert_eq!(
            allocations() - before,
            0,
            "{mode:?}: allocations in build_scalar"
        );
    }
}
