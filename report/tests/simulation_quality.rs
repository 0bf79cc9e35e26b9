//! The time-against-error study measures what it claims: more iterations
//! bring the whipping scene closer to the converged run, every row is finite,
//! and the CSV has one line per row.

use coif_report::quality::simulation::{converged, measure_setting, to_csv, Scene};

#[test]
fn more_iterations_come_closer_to_the_converged_run() {
    let reference = converged(Scene::Whipping);
    let coarse = measure_setting(Scene::Whipping, 1, 1, &reference);
    let fine = measure_setting(Scene::Whipping, 32, 1, &reference);
    for r in [&coarse, &fine] {
        assert!(r.simd_ns_per_vertex_step.is_finite() && r.simd_ns_per_vertex_step > 0.0);
        assert!(r.scalar_ns_per_vertex_step.is_finite() && r.scalar_ns_per_vertex_step > 0.0);
        assert!(r.max_stretch.is_finite() && r.max_stretch < 0.06, "{r:?}");
        assert!(r.max_penetration <= 1e-3, "{r:?}");
    }
    assert!(
        fine.rms_distance_to_converged < coarse.rms_distance_to_converged * 0.9,
        "32 iterations {} vs 1 iteration {}",
        fine.rms_distance_to_converged,
        coarse.rms_distance_to_converged
    );
    let csv = to_csv(&[coarse, fine]);
    assert_eq!(csv.lines().count(), 3);
    assert!(csv.lines().nth(1).unwrap().starts_with("whipping,1,1,"));
}
