//! The real TressFX grooms in `shared/data/grooms` load and simulate.

use coif::groom::tfx;
use coif::kernels::{self, SimParams, Strands};
use std::path::PathBuf;

fn groom_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data/grooms")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared groom folder is not beside the repository)",
            p.display()
        );
        None
    }
}

#[test]
fn both_shared_grooms_parse_with_their_documented_sizes() {
    for (name, strands, verts) in [
        ("ratboy_mohawk.tfx", 2226, 32),
        ("sintel_lite.tfx", 228, 32),
    ] {
        let Some(path) = groom_path(name) else {
            continue;
        };
        let g = tfx::parse(&std::fs::read(path).unwrap()).unwrap();
        assert_eq!(g.strand_count(), strands, "{name}");
        assert_eq!(g.vertex_count(), strands * verts, "{name}");
        assert!(g.strand(0).iter().all(|p| p.is_finite()));
        // Centimetre-ish units: strands are a few to tens of units long.
        let len: f32 = g.strand(0).windows(2).map(|w| (w[1] - w[0]).length()).sum();
        assert!(
            len > 0.5 && len < 200.0,
            "{name}: strand 0 is {len} units long"
        );
    }
}

#[test]
fn the_mohawk_simulates_in_metres() {
    let Some(path) = groom_path("ratboy_mohawk.tfx") else {
        return;
    };
    let g = tfx::parse(&std::fs::read(path).unwrap()).unwrap();
    let (pts, v) = g.uniform_points(0.01).unwrap();
    let mut s = Strands::from_polylines(&pts, v).unwrap();
    let params = SimParams::default();
    for _ in 0..30 {
        kernels::step(&mut s, &params, &[]);
    }
    let m = kernels::measure(&s, &[]);
    assert!(s.positions().iter().all(|p| p.is_finite()));
    assert!(m.max_tip_strain <= params.max_stretch + 1e-4);
}
