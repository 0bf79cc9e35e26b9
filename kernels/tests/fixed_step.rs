//! `FixedStep`: variable frame times turned into whole fixed steps.

use coif_kernels::FixedStep;

#[test]
fn whole_steps_and_cap() {
    let mut f = FixedStep::new(0.01, 4).unwrap();
    assert_eq!(f.advance(0.025), 2);
    assert!((f.remainder() - 0.5).abs() < 1e-3);
    assert_eq!(f.advance(0.005), 1);
    assert_eq!(f.advance(1.0), 4, "capped");
    assert!(f.remainder() <= 1.0);
    assert_eq!(f.advance(f32::NAN), 0);
    assert_eq!(f.advance(-1.0), 0);
    // 60 frames of 1/60 s at dt 1/120: 120 steps in all.
    let mut g = FixedStep::new(1.0 / 120.0, 8).unwrap();
    let total: u32 = (0..60).map(|_| g.advance(1.0 / 60.0)).sum();
    assert!((119..=120).contains(&total), "{total}");
    assert!(FixedStep::new(0.0, 1).is_err());
    assert!(FixedStep::new(0.1, 0).is_err());
}
