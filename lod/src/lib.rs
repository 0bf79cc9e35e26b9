//! coif-lod: refinement, interpolation, fits, level of detail.
