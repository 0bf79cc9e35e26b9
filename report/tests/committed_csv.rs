//! The committed report (`docs/report/results.csv`) holds every family the
//! code measures ([`coif_report::FAMILIES`]), and nothing the code no
//! longer writes: regenerate it (`cargo run --release -p coif-report --
//! --out docs/report`) when a family is added or renamed.

use coif_report::{csv, family_of, FAMILIES};
use std::path::PathBuf;

fn committed_rows() -> Vec<coif_report::Row> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/report/results.csv");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    csv::from_csv(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn committed_csv_has_rows_of_every_family() {
    let rows = committed_rows();
    let missing: Vec<&str> = FAMILIES
        .iter()
        .filter(|f| {
            !rows
                .iter()
                .any(|r| family_of(&r.kernel).is_some_and(|g| g.name == f.name))
        })
        .map(|f| f.name)
        .collect();
    assert!(
        missing.is_empty(),
        "docs/report/results.csv has no rows of {missing:?}: regenerate it"
    );
}

#[test]
fn every_committed_kernel_belongs_to_a_family() {
    let rows = committed_rows();
    let mut strays: Vec<&str> = rows
        .iter()
        .filter(|r| family_of(&r.kernel).is_none())
        .map(|r| r.kernel.as_str())
        .collect();
    strays.dedup();
    assert!(
        strays.is_empty(),
        "kernels in docs/report/results.csv that no family writes: {strays:?}"
    );
}

#[test]
fn family_names_and_prefixes_are_distinct() {
    for (i, f) in FAMILIES.iter().enumerate() {
        assert!(!f.kernels.is_empty(), "{}", f.name);
        for g in &FAMILIES[i + 1..] {
            assert_ne!(f.name, g.name);
            for k in f.kernels {
                assert!(!g.kernels.contains(k), "{k} in {} and {}", f.name, g.name);
            }
        }
        for k in f.kernels {
            assert_eq!(
                family_of(k).map(|g| g.name),
                Some(f.name),
                "{k} is claimed by another family"
            );
        }
    }
}
