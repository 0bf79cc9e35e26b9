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
    ];
    for p in bad {
        let e = p.validate().expect_err("must be rejected");
        assert!(matches!(e, Error::InvalidParameter { .. }));
        assert!(!e.to_string().is_empty());
    }
}
