//! The shadow map's per-frame calls (SIMD and scalar builds, lookups) allocate nothing, and a
//! rebuild is deterministic: the same hair gives the same map bit for bit,
//! whatever was built before.

mod common;

use coif_base::SplitMix64;
use coif_shading::shadow::{OpacityShadowMap, ShadowMode, ShadowSettings};
use coif_testkit::counting::allocations;
use glam::Vec3;

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

fn curly_hair(strands: usize, verts: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::with_capacity(strands * verts);
    for _ in 0..strands {
        let mut p = rng.unit_vector() * 0.1;
        let d = rng.unit_vector();
        for _ in 0..verts {
            pts.push(p);
            p += (d + rng.unit_vector() * 0.4).normalize() * 0.01;
        }
    }
    pts
}

fn snapshot(map: &OpacityShadowMap) -> Vec<u32> {
    let s = map.settings();
    let n = s.resolution;
    let mut v = Vec::with_capacity(n * n * s.layers);
    for y in 0..n {
        for x in 0..n {
            for l in 0..s.layers {
                v.push(map.stored_opacity(x, y, l).to_bits());
            }
        }
    }
    v
}

#[test]
fn build_and_lookups_allocate_nothing_and_rebuilds_are_deterministic() {
    let hair = curly_hair(400, 16, 1);
    let other = curly_hair(300, 16, 2);
    let queries = curly_hair(50, 16, 3);
    let mut out = vec![0.0; queries.len()];
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
        map.build(light, &hair, 16);
        let first = snapshot(&map);
        assert!(first.iter().any(|b| f32::from_bits(*b) > 0.1));

        let before = allocations();
        map.build(light, &other, 16);
        coif_shading::shadow::scalar::build(&mut map, light, &other, 16);
        map.build(light, &hair, 16);
        map.transmittance_batch(&queries, &mut out);
        coif_shading::shadow::scalar::transmittance_batch(&map, &queries, &mut out);
        let t = map.transmittance(queries[7]);
        let after = allocations();
        assert_eq!(
            after - before,
            0,
            "{mode:?}: allocations in build or lookup"
        );
        assert!((0.0..=1.0).contains(&t));

        // The counter does see allocations (the snapshot makes one).
        assert!(snapshot(&map) == first, "{mode:?}: rebuild differs");
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
