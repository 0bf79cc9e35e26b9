//! Opacity shadow maps against the exact reference on a draped head of hair.

use coif::frame::drape::draped_on_sphere;
use coif::shading::shadow::quality::{
    error_of_map, reference_transmittance, shadow_error, Footprint, ShadowError,
};
use coif::shading::shadow::{OpacityShadowMap, ShadowSettings};
use glam::Vec3;
use std::sync::OnceLock;

/// Hair grown on a sphere head and draped under gravity for `steps` steps.
fn draped_head(strands: usize, verts: usize, steps: usize) -> (Vec<Vec3>, usize) {
    draped_on_sphere(strands, verts, steps)
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
        map.transmittance_batch(&pts, &mut t).unwrap();
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

/// Errors of several settings against one footprint reference (16 rays
/// over 2 mm), at every vertex of every 8th strand.
fn errors(settings: &[ShadowSettings]) -> Vec<ShadowError> {
    static SCENE: OnceLock<(Vec<Vec3>, usize, Vec3, Vec<f32>)> = OnceLock::new();
    let (pts, verts, light, reference) = SCENE.get_or_init(|| {
        let (pts, verts, light) = scene();
        let footprint = Footprint {
            rays: 16,
            radius: 0.002,
        };
        let s = ShadowSettings::default();
        let reference = reference_transmittance(&s, light, &pts, verts, 8, footprint);
        (pts, verts, light, reference)
    });
    settings
        .iter()
        .map(|s| {
            let mut map = OpacityShadowMap::new(s.clone()).unwrap();
            map.build(*light, pts, *verts);
            error_of_map(&map, pts, *verts, 8, reference)
        })
        .collect()
}

fn slices(layers: usize) -> ShadowSettings {
    ShadowSettings {
        layers,
        resolution: 128,
        ..Default::default()
    }
}

#[test]
fn more_slices_give_less_error() {
    let e = errors(&[slices(4), slices(16), slices(64)]);
    assert!(e[0].samples > 500);
    // The scene is shadowed enough for the comparison to mean something.
    assert!(e[0].mean_reference < 0.8, "{:?}", e[0]);
    assert!(
        e[2].mean_abs < e[1].mean_abs && e[1].mean_abs < e[0].mean_abs,
        "mean |error| 4: {:?}, 16: {:?}, 64: {:?}",
        e[0],
        e[1],
        e[2]
    );
}

#[test]
fn deep_beats_slices_at_three_layers() {
    let deep = ShadowSettings {
        resolution: 128,
        ..ShadowSettings::deep()
    };
    let e = errors(&[slices(3), deep]);
    assert!(
        e[1].mean_abs < 0.9 * e[0].mean_abs && e[1].rms < e[0].rms,
        "deep {:?} vs slices {:?}",
        e[1],
        e[0]
    );
}

#[test]
fn point_reference_is_the_contract_exact_transmittance() {
    // shadow_error's point reference is exact_transmittance at each vertex:
    // a map that is lit everywhere (zero density) has error 1 - T_exact.
    let (pts, verts, light) = scene();
    let s = ShadowSettings::default();
    let reference = reference_transmittance(&s, light, &pts, verts, 64, Footprint::POINT);
    let mut k = 0;
    for strand in pts.chunks_exact(verts).step_by(64) {
        for p in strand {
            let t = coif::shading::shadow::exact_transmittance(&s, light, &pts, verts, *p);
            assert_eq!(reference[k], t);
            k += 1;
        }
    }
    assert_eq!(k, reference.len());
    let e = shadow_error(&s, light, &pts, verts, 64).unwrap();
    assert_eq!(e.samples, k);
    assert!(e.mean_abs > 0.0 && e.mean_abs < 0.5, "{e:?}");
}
