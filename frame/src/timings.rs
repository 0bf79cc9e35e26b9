//! Per-stage wall-clock timings of frames.

use std::fmt;
use std::time::Duration;

/// The stages of a frame, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Head pose, roots and rig, fixed simulation steps of the hair.
    Simulate,
    /// Ribbons: skin, fixed cloth steps, blend and normals.
    Ribbon,
    /// Distance LOD, cull, level, refine, interpolate, render vertices.
    Lod,
    /// Opacity shadow map build.
    Shadow,
    /// Shadow map lookups at every render vertex (SIMD batch).
    ShadowLookup,
    /// Per-vertex shading (samples, model, head shadow, colour).
    Shade,
    /// Background and ray-cast head.
    Head,
    /// Ribbons shaded per vertex and rasterised as opaque triangles.
    RibbonDraw,
    /// Back-to-front strand sort.
    Sort,
    /// Hair segments rasterised and blended.
    Hair,
}

impl Stage {
    /// Every stage, in frame order.
    pub const ALL: [Stage; 10] = [
        Stage::Simulate,
        Stage::Ribbon,
        Stage::Lod,
        Stage::Shadow,
        Stage::ShadowLookup,
        Stage::Shade,
        Stage::Head,
        Stage::RibbonDraw,
        Stage::Sort,
        Stage::Hair,
    ];

    /// The stage's name in the timing table.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Simulate => "simulate",
            Stage::Ribbon => "ribbon",
            Stage::Lod => "lod",
            Stage::Shadow => "shadow map build",
            Stage::ShadowLookup => "shadow lookups",
            Stage::Shade => "shade",
            Stage::Head => "head + background",
            Stage::RibbonDraw => "rasterise ribbon",
            Stage::Sort => "sort strands",
            Stage::Hair => "rasterise hair",
        }
    }
}

/// Last and accumulated time of each stage.
#[derive(Clone, Debug, Default)]
pub struct StageTimings {
    last: [Duration; 10],
    total: [Duration; 10],
    count: [u32; 10],
}

impl StageTimings {
    /// Adds one run of `stage` that took `d`.
    pub fn record(&mut self, stage: Stage, d: Duration) {
        let i = stage as usize;
        self.last[i] = d;
        self.total[i] += d;
        self.count[i] += 1;
    }

    /// Time of the stage in the last frame that ran it.
    pub fn last(&self, stage: Stage) -> Duration {
        self.last[stage as usize]
    }

    /// Mean over the frames that ran it (zero if none).
    pub fn mean(&self, stage: Stage) -> Duration {
        let i = stage as usize;
        self.total[i].checked_div(self.count[i]).unwrap_or_default()
    }

    /// How many frames ran the stage.
    pub fn runs(&self, stage: Stage) -> u32 {
        self.count[stage as usize]
    }

    /// Forgets every time.
    pub fn reset(&mut self) {
        *self = StageTimings::default();
    }
}

impl fmt::Display for StageTimings {
    /// A table: stage, runs, mean ms, last ms; and the sum of the means.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<20} {:>6} {:>10} {:>10}",
            "stage", "runs", "mean ms", "last ms"
        )?;
        let mut sum = 0.0;
        for s in Stage::ALL {
            if self.runs(s) == 0 {
                continue;
            }
            let mean = self.mean(s).as_secs_f64() * 1e3;
            sum += mean;
            writeln!(
                f,
                "{:<20} {:>6} {:>10.3} {:>10.3}",
                s.name(),
                self.runs(s),
                mean,
                self.last(s).as_secs_f64() * 1e3
            )?;
        }
        write!(f, "{:<20} {:>6} {:>10.3}", "sum of means", "", sum)
    }
}
