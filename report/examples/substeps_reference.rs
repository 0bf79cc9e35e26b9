//! How well resolved the substeps study's reference is: the RMS vertex
//! distance over all frames between the reference (32 substeps of 8
//! projections per step of 1/60 s) and a run twice as fine (64 substeps,
//! the most a step runs, of 8 projections). Differences between settings
//! below this are not resolved by the study.
//!
//! `cargo run --release -p coif-report --example substeps_reference`

use coif_report::quality::simulation::{
    converged_substeps, converged_substeps_with, trajectory_distance, Scene, REFERENCE_ITERATIONS,
    REFERENCE_SUBSTEPS,
};

fn main() {
    for scene in [Scene::Settling, Scene::Whipping] {
        let reference = converged_substeps(scene);
        let finer = converged_substeps_with(scene, 2 * REFERENCE_SUBSTEPS, REFERENCE_ITERATIONS);
        println!(
            "{}: reference vs {} substeps: RMS distance over all frames {:.4} m",
            scene.name(),
            2 * REFERENCE_SUBSTEPS,
            trajectory_distance(&reference, &finer)
        );
    }
}
