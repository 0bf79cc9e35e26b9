//! Refinement: B-spline segments per span against chord error.
//!
//! Times [`coif::lod::refine_strands`] (SIMD) and
//! [`coif::lod::scalar::refine_strands`] (positions and tangents) over a
//! grown head of curly guides, per guide (input) vertex: the same work
//! unit at every setting, so settings compare on the Pareto front (per
//! output vertex, a finer level looks cheaper because fixed per-span work
//! is shared by more outputs; divide by `refined_len(16, N) / 16` output
//! vertices per guide vertex to get it). The error is the largest
//! chord error ([`coif::lod::quality::chord_error`], metres) over every
//! 8th guide.

use super::timing::time_batch;
use super::{Options, Path, Row};
use coif::geometry::scene::{grow_on_sphere, GrowOptions};
use coif::kernels::Strands;
use coif::lod::{self, quality::chord_error, RefinedGuides};

/// Segments per span measured.
pub const SEGMENTS: [usize; 7] = [1, 2, 3, 4, 6, 8, 16];

/// The frame pipeline's `max_segments_per_span` default.
pub const DEFAULT_SEGMENTS: usize = 3;

/// The `refinement` rows: every segment count, SIMD and scalar.
pub fn rows(options: Options) -> Vec<Row> {
    let (strand_count, verts) = if options.quick { (64, 16) } else { (1024, 16) };
    let g = grow_on_sphere(&GrowOptions {
        strand_count,
        verts_per_strand: verts,
        curl: 0.3,
        ..Default::default()
    });
    let strands = Strands::from_polylines(&g.points, verts).expect("grown guides are valid");
    let max = *SEGMENTS.last().unwrap_or(&16);
    let mut guides = RefinedGuides::new(strands.blocks(), max).expect("valid refinement shape");
    let mut rows = Vec::new();
    for n in SEGMENTS {
        guides.set_segments_per_span(n).unwrap();
        let error = g
            .points
            .chunks(verts)
            .step_by(8)
            .map(|c| chord_error(c, n) as f64)
            .fold(0.0, f64::max);
        let inputs = strand_count * verts;
        let simd = time_batch(options.reps(), inputs, || {
            std::hint::black_box(lod::refine_strands(strands.blocks(), None, &mut guides).unwrap());
        });
        let scalar = time_batch(options.reps(), inputs, || {
            std::hint::black_box(
                lod::scalar::refine_strands(strands.blocks(), None, &mut guides).unwrap(),
            );
        });
        for (path, time) in [(Path::Simd, simd), (Path::Scalar, scalar)] {
            rows.push(Row {
                kernel: "refinement".into(),
                setting: format!("segments={n}"),
                path,
                element: "guide vertex",
                time,
                error_metric: "largest chord error (m)",
                error,
                is_default: n == DEFAULT_SEGMENTS,
            });
        }
    }
    rows
}
