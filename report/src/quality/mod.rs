//! Time against error: each kernel's quality knobs measured against a
//! reference, for reports and for choosing settings.

pub mod simulation;
