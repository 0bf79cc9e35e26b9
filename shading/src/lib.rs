//! coif-shading: hair shading models and lookup tables.
