//! The physics family alone: the strand step against the analytic hanging
//! chain at every setting, as a table (period errors, amplitude kept and
//! peak, ns per vertex-step SIMD and scalar).
//!
//! `cargo run --release -p coif-report --example physics_chain [-- --quick]`

use coif_report::{physics, Options, Path};

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let rows = physics::rows(Options { quick });
    println!(
        "{:<26} {:>12} {:>12} {:>12} {:>10} {:>10}",
        "setting", "mode 1 T err", "mode 1 ampl", "mode 2 T err", "SIMD ns", "scalar ns"
    );
    let settings: Vec<&str> = rows
        .iter()
        .filter(|r| r.kernel == "physics chain mode 1 period" && r.path == Path::Simd)
        .map(|r| r.setting.as_str())
        .collect();
    for s in settings {
        let get = |kernel: &str, path: Path| {
            rows.iter()
                .find(|r| r.kernel == kernel && r.setting == s && r.path == path)
                .expect("row")
        };
        println!(
            "{:<26} {:>12.3e} {:>12.3e} {:>12.3e} {:>10.1} {:>10.1}",
            s,
            get("physics chain mode 1 period", Path::Simd).error,
            get("physics chain mode 1 amplitude", Path::Simd).error,
            get("physics chain mode 2 period", Path::Simd).error,
            get("physics chain mode 1 period", Path::Simd).time.median,
            get("physics chain mode 1 period", Path::Scalar).time.median,
        );
    }
}
