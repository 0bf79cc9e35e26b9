//! Per-stage wall-clock timings of frames.

use std::fmt;
use std::time::Duration;

/// The stages of a frame, in order: four totals (`simulate`, `prepare`,
/// `raster`, `frame`) and the finer rows inside them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Everything a frame simulates: head pose, roots and rig, the hair's
    /// fixed steps and the ribbons'.
    Simulate,
    /// Inside `simulate`: the ribbons (skin, fixed cloth steps, blend, normals).
    Ribbon,
    /// Everything between simulation and pixels: LOD, shadow map, shading.
    Prepare,
    /// Inside `prepare`: distance LOD, cull, level, refine (the reference
    /// pipeline also interpolates and writes render vertices here).
    Lod,
    /// Inside `prepare`: the opacity shadow map (the fused pipeline
    /// includes interpolating the thinned hairs it is built from).
    Shadow,
    /// Inside `prepare`, reference pipeline only: shadow map lookups at
    /// every render vertex (SIMD batch).
    ShadowLookup,
    /// Inside `prepare`: per-vertex shading (the fused pipeline:
    /// interpolation, model, shadow lookup, head shadow and colour per group).
    Shade,
    /// Everything that writes pixels: head, ribbons, hair.
    Raster,
    /// Inside `raster`: background and ray-cast head.
    Head,
    /// Inside `raster`: the body mesh posed, shaded per vertex and
    /// rasterised as opaque triangles.
    Body,
    /// Inside `raster`: ribbons shaded per vertex and rasterised as opaque triangles.
    RibbonDraw,
    /// Inside `raster`: back-to-front strand sort.
    Sort,
    /// Inside `raster`: hair segments rasterised and blended.
    Hair,
    /// The whole frame ([`crate::FramePipeline::frame`]).
    Frame,
}

/// Number of [`Stage`]s.
const STAGES: usize = Stage::ALL.len();

impl Stage {
    /// Every stage, in frame order.
    pub const ALL: [Stage; 14] = [
        Stage::Simulate,
        Stage::Ribbon,
        Stage::Prepare,
        Stage::Lod,
        Stage::Shadow,
        Stage::ShadowLookup,
        Stage::Shade,
        Stage::Raster,
        Stage::Head,
        Stage::Body,
        Stage::RibbonDraw,
        Stage::Sort,
        Stage::Hair,
        Stage::Frame,
    ];

    /// The stage's name in the timing table and the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Simulate => "simulate",
            Stage::Ribbon => "ribbon",
            Stage::Prepare => "prepare",
            Stage::Lod => "lod",
            Stage::Shadow => "shadow map build",
            Stage::ShadowLookup => "shadow lookups",
            Stage::Shade => "shade",
            Stage::Raster => "raster",
            Stage::Head => "head + background",
            Stage::Body => "rasterise body",
            Stage::RibbonDraw => "rasterise ribbon",
            Stage::Sort => "sort strands",
            Stage::Hair => "rasterise hair",
            Stage::Frame => "frame",
        }
    }

    /// Whether the stage is one of the four totals (not inside another).
    pub fn is_total(self) -> bool {
        matches!(
            self,
            Stage::Simulate | Stage::Prepare | Stage::Raster | Stage::Frame
        )
    }
}

/// Last and accumulated time of each stage.
#[derive(Clone, Debug, Default)]
pub struct StageTimings {
    last: [Duration; STAGES],
    total: [Duration; STAGES],
    count: [u32; STAGES],
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

    /// The stages that ran, as CSV: the header `stage,runs,mean_ms,last_ms`
    /// and one row per stage in frame order (means over the frames that
    /// ran the stage, milliseconds with three decimals).
    pub fn write_csv(&self, mut out: impl std::io::Write) -> std::io::Result<()> {
        writeln!(out, "stage,runs,mean_ms,last_ms")?;
        for s in Stage::ALL {
            if self.runs(s) == 0 {
                continue;
            }
            writeln!(
                out,
                "{},{},{:.3},{:.3}",
                s.name(),
                self.runs(s),
                self.mean(s).as_secs_f64() * 1e3,
                self.last(s).as_secs_f64() * 1e3
            )?;
        }
        Ok(())
    }
}

impl fmt::Display for StageTimings {
    /// A table: stage, runs, mean ms, last ms; the rows inside a total
    /// indented under it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:<22} {:>6} {:>10} {:>10}",
            "stage", "runs", "mean ms", "last ms"
        )?;
        for s in Stage::ALL {
            if self.runs(s) == 0 {
                continue;
            }
            let indent = if s.is_total() { "" } else { "  " };
            write!(
                f,
                "\n{:<22} {:>6} {:>10.3} {:>10.3}",
                format!("{indent}{}", s.name()),
                self.runs(s),
                self.mean(s).as_secs_f64() * 1e3,
                self.last(s).as_secs_f64() * 1e3
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_has_the_header_and_a_row_per_stage_that_ran() {
        let mut t = StageTimings::default();
        t.record(Stage::Frame, Duration::from_millis(4));
        t.record(Stage::Frame, Duration::from_millis(2));
        t.record(Stage::Prepare, Duration::from_micros(1500));
        let mut out = Vec::new();
        t.write_csv(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "stage,runs,mean_ms,last_ms\nprepare,1,1.500,1.500\nframe,2,3.000,2.000\n"
        );
    }
}
