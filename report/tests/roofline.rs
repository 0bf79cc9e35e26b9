//! The roofline in quick mode on two kernels: floors positive and ordered
//! as a memory hierarchy is, each floor the larger of its two bounds, the
//! Markdown table has one row per kernel.

use coif_report::roofline::{self, Floors, KERNELS};
use coif_report::Options;

#[test]
fn quick_roofline_rows_follow_the_floor_formula() {
    let options = Options { quick: true };
    let floors: Floors = roofline::measure_floors(options);
    for bw in floors.cache.iter().chain(&floors.dram) {
        assert!(bw.is_finite() && *bw > 0.0, "{floors:?}");
    }
    assert!(
        floors.cache[0] > floors.dram[0],
        "reading from cache is faster than from DRAM: {floors:?}"
    );
    assert!(floors.fma_x8_per_ns > 0.0 && floors.instructions_per_ns > 0.0);
    let picked: Vec<_> = KERNELS
        .iter()
        .filter(|k| k.name == "Kajiya-Kay" || k.name.starts_with("shadow lookup"))
        .copied()
        .collect();
    assert_eq!(picked.len(), 2);
    let rows = roofline::measure(options, &floors, &picked);
    for r in &rows {
        let compute = r.instructions / floors.instructions_per_ns;
        assert_eq!(r.floor_cache, compute.max(r.bytes / floors.cache[2]));
        assert_eq!(r.floor_stream, compute.max(r.bytes / floors.dram[2]));
        assert!(r.floor_stream >= r.floor_cache);
        assert!(
            r.ratio_cache().is_finite() && r.ratio_cache() > 0.0,
            "{r:?}"
        );
        assert!(
            r.ratio_stream().is_finite() && r.ratio_stream() > 0.0,
            "{r:?}"
        );
    }
    let md = roofline::to_markdown(&floors, &rows);
    for r in &rows {
        assert_eq!(md.matches(&format!("| {} |", r.name)).count(), 1, "{md}");
    }
    assert!(md.contains("| copy (read + write) bandwidth |"));
}

#[test]
fn every_kernel_has_counts_and_a_reason() {
    for k in KERNELS {
        assert!(k.bytes > 0.0 && k.instructions > 0.0, "{}", k.name);
        assert!(!k.note.is_empty(), "{} has no note", k.name);
    }
}
