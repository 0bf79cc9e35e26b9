//! `SimParams::validate`: the defaults pass, every out-of-range value is
//! reported.

use coif_kernels::{Error, SimParams};
use glam::Vec3;

#[test]
fn default_is_valid_and_bad_values_are_reported() {
    assert_eq!(SimParams::default().validate(), Ok(()));
    let bad = [
        SimParams {
            dt: 0.0,
            ..Default::default()
        },
        SimParams {
            dt: -1.0,
            ..Default::default()
        },
        SimParams {
            dt: f32::NAN,
            ..Default::default()
        },
        SimParams {
            damping: 1.5,
            ..Default::default()
        },
        SimParams {
            damping: -0.1,
            ..Default::default()
        },
        SimParams {
            damping: f32::NAN,
            ..Default::default()
        },
        SimParams {
            gravity: Vec3::new(0.0, f32::INFINITY, 0.0),
            ..Default::default()
        },
        SimParams {
            pearl_radius: -1.0,
            ..Default::default()
        },
        SimParams {
            max_stretch: f32::NAN,
            ..Default::default()
        },
        SimParams {
            bend_stiffness: 2.0,
            ..Default::default()
        },
        SimParams {
            shape_stiffness: -1.0,
            ..Default::default()
        },
        SimParams {
            pearls_per_segment: 1000,
            ..Default::default()
        },
        SimParams {
            iterations: coif_kernels::MAX_ITERATIONS + 1,
            ..Default::default()
        },
        SimParams {
            local_shape_stiffness: 1.01,
            ..Default::default()
        },
        SimParams {
            local_shape_stiffness: -0.1,
            ..Default::default()
        },
        SimParams {
            local_shape_stiffness: f32::NAN,
            ..Default::default()
        },
        SimParams {
            max_substep: 0.0,
            ..Default::default()
        },
        SimParams {
            stiff_mode_damping: 0.3,
            ..Default::default()
        },
    ];
    for ok in [0.0, 0.5, 1.0] {
        let p = SimParams {
            local_shape_stiffness: ok,
            ..Default::default()
        };
        assert_eq!(p.validate(), Ok(()));
    }
    // Substeps: ceil(dt / max_substep), a whole ratio counting as itself.
    let sub = |dt: f32| {
        SimParams {
            dt,
            ..Default::default()
        }
        .substeps()
    };
    assert_eq!(
        (
            sub(1.0 / 60.0),
            sub(1.0 / 30.0),
            sub(1.0 / 240.0),
            sub(0.001)
        ),
        (4, 8, 1, 1)
    );
    assert_eq!(sub(1.0e6), coif_kernels::MAX_SUBSTEPS);
    for p in bad {
        let e = p.validate().expect_err("must be rejected");
        assert!(matches!(e, Error::InvalidParameter { .. }));
        assert!(!e.to_string().is_empty());
    }
}
