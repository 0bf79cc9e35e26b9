//! Time against error: each kernel's quality knobs measured against a
//! reference, for reports and for choosing settings; and the analytic
//! hanging chain the physics family measures the strand step against.

pub mod chain;
pub mod simulation;
