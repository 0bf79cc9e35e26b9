//! The real TressFX grooms in `shared/data/grooms` load and simulate.

use coif_testkit::groom_path;

use coif_geometry::groom::{self, cyhair, tfx};
use coif_kernels::{self as kernels, SimParams, Strands};

#[test]
fn both_shared_grooms_parse_with_their_documented_sizes() {
    for (name, strands, verts) in [
        ("ratboy_mohawk.tfx", 2226, 32),
        ("sintel_lite.tfx", 228, 32),
    ] {
        let Some(path) = groom_path(name) else {
            continue;
        };
        let g = groom::load(&std::fs::read(path).unwrap()).unwrap();
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
fn a_simulated_groom_exports_to_cyhair_and_reads_back() {
    let Some(path) = groom_path("sintel_lite.tfx") else {
        return;
    };
    let g = groom::load(&std::fs::read(path).unwrap()).unwrap();
    let (pts, v) = g.uniform_points(0.01).unwrap();
    let mut s = Strands::from_polylines(&pts, v).unwrap();
    for _ in 0..10 {
        kernels::step(&mut s, &SimParams::default(), &[]);
    }
    let moved = s.positions();
    let counts = vec![v; s.strand_count()];
    let simulated = groom::Groom::from_strands(moved.clone(), &counts).unwrap();
    let bytes = cyhair::write(&simulated, "coif: sintel after 10 steps").unwrap();
    let back = groom::load(&bytes).unwrap();
    assert_eq!(back.strand_count(), 228);
    assert_eq!(back.points(), &moved[..]);
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

#[test]
fn seeded_mutations_of_real_files_never_panic_or_overallocate() {
    use coif_base::SplitMix64;
    let Some(path) = groom_path("sintel_lite.tfx") else {
        return;
    };
    let original = std::fs::read(path).unwrap();
    let mut rng = SplitMix64::new(2024);
    let (mut ok, mut err) = (0, 0);
    for _ in 0..3000 {
        let mut bytes = original.clone();
        match rng.below(3) {
            // Flip bytes, mostly in the header where counts and offsets live.
            0 => {
                for _ in 0..1 + rng.below(4) {
                    let at = if rng.below(4) == 0 {
                        rng.below(bytes.len())
                    } else {
                        rng.below(64)
                    };
                    bytes[at] = rng.next_u64() as u8;
                }
            }
            // Truncate anywhere.
            1 => bytes.truncate(rng.below(bytes.len())),
            // Overwrite a header word with an extreme value.
            _ => {
                let at = 4 * rng.below(8);
                let v = [0u32, 1, u32::MAX, u32::MAX / 16, 0x7FC0_0000][rng.below(5)];
                bytes[at..at + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
        match groom::load(&bytes) {
            Ok(g) => {
                ok += 1;
                // Whatever parsed is consistent and no larger than the input allows.
                assert!(g.vertex_count() * 16 <= bytes.len());
                assert!((0..g.strand_count()).all(|i| g.strand(i).iter().all(|p| p.is_finite())));
            }
            Err(e) => {
                err += 1;
                assert!(!e.to_string().is_empty());
            }
        }
    }
    assert!(
        ok > 0 && err > 0,
        "the mutations exercised both outcomes: {ok} parsed, {err} rejected"
    );
}
