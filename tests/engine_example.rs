//! `examples/engine.rs`, the integrator's example, runs to the end on the
//! shipped Sintel groom and bust (CI runs it here).

#[path = "../examples/engine.rs"]
mod engine;

#[test]
fn the_engine_example_runs_on_the_shipped_files() {
    engine::main().expect("the engine example runs");
}
