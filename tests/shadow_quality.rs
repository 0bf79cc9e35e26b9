//! Opacity shadow maps against the exact reference on a draped head of hair.

use coif::kernels::{self, SimParams, Strands};
use coif::scene::{grow_on_sphere, GrowOptions};
use coif::shading::shadow::quality::shadow_error;
use coif::shading::shadow::{OpacityShadowMap, ShadowSettings};
use glam::Vec3;

/// Hair grown on a sphere head and draped under gravity for `steps` steps.
fn draped_head(strands: usize, verts: usize, steps: usize) -> (Vec<Vec3>, usize) {
    let scene = grow_on_sphere(&GrowOptions {
        strand_count: strands,
        verts_per_strand: verts,
        curl: 0.3,
        ..Default::default()
    });
    let rig = [scene.head.clone()];
    let params = SimParams::default();
    let mut s = Strands::from_polylines(&scene.points, scene.verts_per_strand).unwrap();
    for _ in 0..steps {
        kernels::step(&mut s, &params, &rig);
    }
    (s.positions(), scene.verts_per_strand)
}

/// The quality scene: 512 draped strands of 16 vertices, lit from the side
/// and a little above.
fn scene() -> (Vec<Vec3>, usize, Vec3) {
    let (pts, verts) = draped_head(512, 16, 60);
    (pts, verts, Vec3::new(1.0, -0.5, 0.3).normalize())
}

#[test]
fn lit_side_of_the_head_is_brighter_than_the_far_side() {
    let (pts, verts) = draped_head(512, 16, 60);
    // Light from +x toward -x.
    let light = -Vec3::X;
    for settings in [ShadowSettings::default(), ShadowSettings::deep()] {
        let mut map = OpacityShadowMap::new(settings.clone()).unwrap();
        map.build(light, &pts, verts);
        let mut t = vec![0.0; pts.len()];
        map.transmittance_batch(&pts, &mut t);
        let mean = |keep: &dyn Fn(&Vec3) -> bool| {
            let v: Vec<f32> = pts
                .iter()
                .zip(&t)
                .filter(|(p, _)| keep(p))
                .map(|(_, t)| *t)
                .collect();
            assert!(v.len() > 200);
            v.iter().sum::<f32>() / v.len() as f32
        };
        let lit = mean(&|p| p.x > 0.06);
        let far = mean(&|p| p.x < -0.06);
        assert!(
            lit > far + 0.1,
            "{:?}: lit side mean T {lit}, far side {far}",
            settings.mode
        );
    }
}

#[test]
fn more_slices_give_less_error() {
    let (pts, verts, light) = scene();
    let err = |layers| {
        let s = ShadowSettings {
            layers,
            ..Default::default()
        };
        shadow_error(&s, light, &pts, verts, 8).unwrap()
    };
    let (e4, e16, e64) = (err(4), err(16), err(64));
    assert!(e4.samples > 500);
    assert!(
        e64.mean_abs < e16.mean_abs && e16.mean_abs < e4.mean_abs,
        "mean |error| 4: {}, 16: {}, 64: {}",
        e4.mean_abs,
        e16.mean_abs,
        e64.mean_abs
    );
}

#[test]
fn deep_beats_slices_at_three_layers() {
    let (pts, verts, light) = scene();
    let osm = ShadowSettings {
        layers: 3,
        ..Default::default()
    };
    let deep = ShadowSettings::deep();
    let e_osm = shadow_error(&osm, light, &pts, verts, 8).unwrap();
    let e_deep = shadow_error(&deep, light, &pts, verts, 8).unwrap();
    assert!(
        e_deep.mean_abs < 0.9 * e_osm.mean_abs && e_deep.rms < e_osm.rms,
        "deep {e_deep:?} vs slices {e_osm:?}"
    );
}
