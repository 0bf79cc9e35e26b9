//! The Markdown summary: a table per kernel, the SIMD speed-up of each
//! kernel, and the defaults that are not on the Pareto front.

use super::{Path, Row};

/// Kernel names in order of first appearance.
pub fn kernels(rows: &[Row]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        if !names.contains(&r.kernel) {
            names.push(r.kernel.clone());
        }
    }
    names
}

/// Whether `row` is on the Pareto front of time against error: no other
/// row of the same kernel and path is both faster and more accurate.
pub fn on_pareto_front<'a>(rows: impl IntoIterator<Item = &'a Row>, row: &Row) -> bool {
    !rows.into_iter().any(|o| {
        o.kernel == row.kernel
            && o.path == row.path
            && o.time.median < row.time.median
            && o.error < row.error
    })
}

/// Scalar median over SIMD median, per setting that has both paths.
pub fn speedups(rows: &[Row], kernel: &str) -> Vec<(String, f64, bool)> {
    rows.iter()
        .filter(|r| r.kernel == kernel && r.path == Path::Simd)
        .filter_map(|simd| {
            rows.iter()
                .find(|s| s.kernel == kernel && s.path == Path::Scalar && s.setting == simd.setting)
                .map(|scalar| {
                    (
                        simd.setting.clone(),
                        scalar.time.median / simd.time.median,
                        simd.is_default,
                    )
                })
        })
        .collect()
}

fn fmt_ns(ns: f64) -> String {
    if ns >= 100.0 {
        format!("{ns:.0}")
    } else if ns >= 10.0 {
        format!("{ns:.1}")
    } else {
        format!("{ns:.2}")
    }
}

/// What the run measures, per kernel family (the summary's first list).
pub const MEASURED: &str = "What is measured (knob; time per element; error):

- **simulation** (`simulation <scene>`, settling and whipping): iterations (projections of \
the length constraints per substep) x pearls at one step of 1/60 s per frame and the default 4 \
substeps; ns per vertex-step; RMS distance at the end to a converged run (256 projections, 3 \
pearls), and as their own kernels the largest stretch and the deepest penetration seen.
- **simulation substeps** (`simulation <scene> substeps`): the solver's own substep knob, one \
step of 1/60 s per frame with `max_substep = dt / n`, n = 2, 4, 8, 16 substeps per step \
(default 4; 1 projection, 1 pearl); ns per vertex-step (a step = all its substeps), so the \
settings compare; the same three errors against a run of 32 substeps of 8 projections and 3 \
pearls, the distance taken at the end of every frame (RMS over all frames). That reference \
is itself resolved to about 5 mm (settling) and 10 cm (whipping, whose flailing hair is \
chaotic) against 64 substeps (`cargo run --release -p coif-report --example \
substeps_reference`): smaller differences are noise. The step spreads its damping over its substeps, so every setting keeps \
the same velocity per step.
- **simulation LOD** (`simulation LOD sleeping`, `simulation LOD guides`): the built-in head, 1 s still, 3 s of turn and nod, 6 s still; `sleep_speed` 0-0.05 m/s (the setting names the share of strand-steps advanced) and the simulation level simulating every k-th guide (k = 1, 2, 4, 8, the others following, sleeping off); ns per vertex-step of every guide; RMS distance over all frames to never sleeping and to every guide simulated.
- **physics** (`physics chain mode 1 period`, `... mode 1 amplitude`, `... mode 2 period`): \
the strand step against the analytic hanging chain, which a converged run of the step cannot \
judge: 31 links of 1 cm pinned at the top, g = 9.81, started at rest in mode 1 or 2 of its \
tension matrix K (periods from K's eigenvalues, `omega_k^2 = (g/l) lambda_k`; shape from the \
eigenvector) with the tip 2 % of the length off vertical, undamped, no collisions, 12 s; \
errors: |period error| from the tip's zero crossings (1 where it did not cross three times), \
and `max(1 - kept, peak - 1)` of the mode 1 amplitude (kept: over the last period; peak: over \
the run). Settings: substeps n = dt / max_substep in 2, 4, 8, 16 x `stiff_mode_damping` a in \
0, 0.05, 0.15 at dt = 1/60 s (default n 4, a 0.05), and dt = 1/30 s at the default \
max_substep (8 substeps). ns per vertex-step on 64 identical chains (8 SIMD blocks); mode read \
from strand 0 (`cargo run --release -p coif-report --example physics_chain` prints the \
family as one table). Diverging settings are measured as they come out of the step (its guard \
restores non-finite strands). The closed form is undamped, so the amplitude the blend a > 0 \
takes is counted as error although it is the blend's purpose (it damps the stiff modes; mode \
1 is the slowest, mode 2 loses more); a does not change the cost, so time differences \
between the a settings of one n are noise.
- **wind** (`wind equilibrium`, `wind decay`): the strand step's linear drag against two \
closed forms that do not depend on the solver. Equilibrium: a chain of equal masses in gravity \
g and a steady wind w with drag c hangs straight along g + c w; one strand of 32 vertices on \
1 cm links settles for 10 s (at least 5 c L / |a|) at the default damping; error the angle in \
degrees between tip - root and g + c w, the worst of three winds (2, 5 and 8 m/s; up to 3.4 g). \
Decay: with damping 1 every mode of the chain obeys theta'' + c theta' + omega^2 theta = 0 and \
decays as exp(-c t / 2); the 31-link chain started in mode 1, tip 3 degrees off; the peaks of \
the tip's swing fitted in log against time; error |rate - c/2| / (c/2). Settings: max_substep \
1/120, 1/240 (default), 1/480, 1/960 s at dt = 1/60 s x drag 1 and 4 per second (the setting \
names the substeps run: more in winds beyond 2 g, `SimParams::substeps`); ns per vertex-step \
on 32 identical strands. The blend `stiff_mode_damping` takes about a omega^2 h per second on \
top of the drag and counts as error.
- **collisions** (`collisions <scene> <collider>`): penetration against cost. Scenes: a curtain \
of 64 strands of 25 vertices on 1.2 cm links falling over a still collider and draping (1.5 s), \
and 8 x 8 hanging strands that a collider sweeps through at 3 m/s (twice out and back). \
Colliders: a sphere, a capsule (a 16 cm bar under the curtain, a 1 cm rod through the hair), \
the field of an icosphere (1,280 triangles, 4 mm cells) and, when the shared meshes are \
present, the field of the Sintel bust (drape only). Error: the deepest penetration of the \
hair's centre line into the collider's own surface at the end of any step, by the exact \
distance: analytic point-to-segment (sphere) and segment-to-segment (capsule) distance over \
every segment; for fields, points every 1.5 mm along every segment against the mesh itself by \
brute force over its triangles (sign by the winding number), the points picked by the field \
(those it puts within 1 mm of the surface, deepest first). Settings: max_substep 1/120, 1/240 \
(default), 1/480 s x pearls per segment 0, 1 (default), 2 (fields collide with vertices only: \
their pearl settings differ in time alone); ns per vertex-step.
- **shape** (`shape rest drift`, `shape kinks`, `shape return`): the local shape springs \
(`local_shape_stiffness`, `kernels/src/shape.rs`) from the sag-free rest state \
(`Strands::solve_sag_free`) on Sintel's groom and bust (228 x 32 guides, her 4 mm field, the \
default `SimParams` but the stiffness): 3 s at rest from the groom, then a 40-degree head turn \
in 0.5 s held for 2.5 s (`coif::frame::style`). Errors against the groom and the hair carried \
rigidly by the head: the 95th percentile distance from the groom after the rest (m; goal <= 3 mm \
from 0.7 to 1), the largest share of interior vertices turning 30 degrees or more beyond their \
groomed angle at rest or in the turn (goal <= 1 % from 0.5 to 1), the tips' RMS from the rigidly \
carried hair 2.5 s after (m; goal <= 3 mm at 0.7). The setting names the stiffness, the solve \
(`sag-free`, or `as built` without it) and the swing: the tips' largest RMS from the rigidly \
carried hair in the turn (goal >= 10 mm at 0.7). Settings: 1, 0.9, 0.7 (the scenes' default), \
0.6, 0.5, 0.3 sag-free, 1 and 0.7 as built; ns per vertex-step of the step, one thread, the \
median step of each of three runs.
- **volume** (`volume packing`, `volume cells`, `volume settling`): hair-hair volume through \
the hair grid (`volume_stiffness`, `kernels/src/hair_grid/`). 1,024 strands of 24 vertices, 25 cm, \
grown straight out of the top of a 9 cm head and dropped onto it for 3 s (the kernels' \
`hair_volume` test scene); measured at the end: segments per 5 mm cell (at the segment's \
midpoint, the two root segments left out), their 99th percentile and the occupied cells, and \
the fastest vertex speed. No exact reference exists for how hair should pack: the errors are \
the ratios to the grid-off row, oriented so that lower is better, against the kernels' goal: \
`volume packing` = 99th percentile / the off row's (goal <= 0.5; an integer count, 6 off, so \
it moves in steps of 1/6), `volume cells` = the off row's cells / the row's (goal <= 0.625, \
i.e. 1.6x the cells), `volume settling` = the fastest vertex speed after 3 s in m/s; the \
setting names the absolute 99th percentile and cells. Settings: stiffness 0 (friction 0: the \
grid off, the default), 0.25, 0.5, 1 with `hair_friction` 1 at the default 1.5 cm cell, and \
cells of 0.75 and 3 cm at stiffness 1; ns per vertex-step of the step (grid included), one \
thread, the median step of each of three runs.
- **hair friction** (`hair friction relative`, `hair friction momentum`): the hair grid's \
friction (`hair_friction`, volume off) on a lock of 64 strands of 20 cm (8 x 8 roots 3 mm \
apart) kicked at (1, 0, 0) m/s plus a random velocity of up to 0.5 m/s per axis per strand, \
run for 0.1 s (6 steps); errors: the RMS velocity relative to the lock's mean after 0.1 s as \
a fraction of the kick's (what friction has not yet removed), and the largest \
|mean velocity / the frictionless lock's - 1| over the 6 steps (the common motion friction \
should keep; 0 at friction 0, the reference); the setting names the share kept after 0.1 s. \
Settings: friction 0 (the default), 0.25, 0.5, 1; ns per vertex-step, one thread, the median \
step of each run, 15 runs: the lock has 1,344 vertices, so the grid's fixed costs weigh more \
than on a head.
- **refinement**: segments per span; ns per guide (input) vertex; largest chord error.
- **fits**: controls x smoothing; ns per strand; RMS distance to the noise-free curve \
(scalar only: faer's Cholesky).
- **interpolation**: the share of render hairs drawn (the distance-LOD prefix, widened to \
keep coverage: 100, 50, 25, 12.5 %); ns per output vertex of the full density (the same \
unit at every setting, so the time thinning saves shows; divide by the share for the time \
per vertex written); relative RMS difference of \
per-pixel optical depth (projected hair area per pixel) against all hairs, on the built-in \
head from the default camera at 64 x 64 pixels. The default is what the pipeline draws at \
its default settings.
- **shading**: Kajiya-Kay, Marschner direct and tables (error against direct), pbrt far \
field per quadrature order and tables (error against a 4x-order far field), every model \
against pbrt's far field (`models vs pbrt`); ns per sample.
- **pbrt exact**: the exact per-h model averaged over 1, 4, 16, 64 stratified (jittered) \
offsets h per shading point, the Monte Carlo estimate pbrt makes with one random h per \
camera ray; ns per shading point (all its offsets); error against the same 4x-order far \
field and direction samples as the pbrt rows. Scalar only: there is no SIMD path.
- **multiple scattering** (`multiple scattering <colour>`, `... <colour> marschner`, `... path \
tracer`, `... path tracer furnace`; blond, brown and dark: pbrt-v3 eumelanin 0.3, 1.3, 8.0): \
single scattering with the exact shadow and dual scattering (pbrt table 64 and \
`DualScattering::from_pbrt`, default densities 0.4) against the Monte Carlo path tracer through \
explicit fibres; error the relative RMS of patch means (1.5 mm patches of camera rays, first \
hits shaded with the exact fibre count and visibility toward the light) over a set: held-out \
tufts (light (-0.4, 0.5, 0.8), volume fractions 0.1 and 0.25, 5 mm thick, three views), the \
training tufts the densities were fitted on (20 patches), and a region of Sintel's groom (her \
guides within a 20 mm ball at the crown, fibre radius chosen for a volume fraction of 0.12, \
stated in the setting; lit from above, two views); the setting names the tracer's relative \
standard error on the set. ns per sample of the method's shading (2,048 samples in cache, the \
table and `shade_simd` fused per block; scalar twin per sample). The `marschner` kernels: \
Marschner's table 128 (absorption halved) and `from_marschner` against the same tracer, which \
is pbrt's model, so their error mixes the models' difference with multiple scattering. `path \
tracer`: the reference's relative standard error per set against ns per path (thread time); \
`path tracer furnace`: sigma_a = 0, environment 1, no light, a tuft of volume fraction 0.25: \
|mean - 1| against ns per path.
- **shadow maps**: slices 4-64 and deep opacity 2-4 layers; build per segment, lookup per \
sample; error against the exact footprint transmittance.
- **patch**: constraint sweeps of a cloth patch (a 16 x 32 flag circling past a sphere); ns per particle-step; RMS per-step distance to a 256-sweep step, and as its own kernel (`patch stretch`) the largest structural edge stretch after a step.

";

/// The summary; `plots` lists (kernel, file name) of the SVG plots.
pub fn to_markdown(rows: &[Row], plots: &[(String, String)], machine: &str) -> String {
    let mut md = String::from("# Time against error, every kernel\n\n");
    md += &format!(
        "Measured by `cargo run --release -p coif-report` on {machine}. Time is the median over \
repeated runs of a whole batch, per element, with the fastest and slowest run; the machine \
was shared with other work, so absolute times are noisy (compare within a table). A setting \
is on the Pareto front if no other setting of the same kernel and path is both faster and \
more accurate. Defaults are the settings the library or the frame pipeline uses.\n\n"
    );
    md += MEASURED;
    md += &defaults_off_front(rows);
    md += &speedup_table(rows);
    for k in &kernels(rows) {
        let plot = plots
            .iter()
            .find(|(name, _)| name == k)
            .map(|(_, f)| f.as_str());
        md += &kernel_section(rows, k, plot);
    }
    md
}

/// The defaults not on the Pareto front, each with the settings that beat it.
fn defaults_off_front(rows: &[Row]) -> String {
    let mut md = String::from("## Defaults not on the Pareto front\n\n");
    let off: Vec<&Row> = rows
        .iter()
        .filter(|r| r.is_default && !on_pareto_front(rows, r))
        .collect();
    if off.is_empty() {
        return md + "Every default is on the Pareto front of its kernel and path.\n\n";
    }
    for r in off {
        let better: Vec<&str> = rows
            .iter()
            .filter(|o| {
                o.kernel == r.kernel
                    && o.path == r.path
                    && o.time.median < r.time.median
                    && o.error < r.error
            })
            .map(|o| o.setting.as_str())
            .collect();
        md += &format!(
            "- **{}**, {} ({}): {} ns, error {:.3e}; faster and more accurate: {}\n",
            r.kernel,
            r.setting,
            r.path.name(),
            fmt_ns(r.time.median),
            r.error,
            better.join(", ")
        );
    }
    md + "\n"
}

/// The SIMD speed-up of every kernel: at the default and over settings.
fn speedup_table(rows: &[Row]) -> String {
    let mut md = String::from(
        "## SIMD speed-up (scalar median / SIMD median)\n\n| kernel | at the default | range over settings |\n|---|---|---|\n",
    );
    for k in &kernels(rows) {
        let s = speedups(rows, k);
        if s.is_empty() {
            md += &format!("| {k} | no SIMD path | |\n");
            continue;
        }
        let at_default = s
            .iter()
            .find(|x| x.2)
            .map_or("-".to_string(), |x| format!("{:.1}x ({})", x.1, x.0));
        let lo = s.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
        let hi = s.iter().map(|x| x.1).fold(0.0, f64::max);
        md += &format!("| {k} | {at_default} | {lo:.1}x - {hi:.1}x |\n");
    }
    md + "\n"
}

/// One kernel's section: its units, its plot (`plot`, a file name) and a
/// table of every row.
fn kernel_section(rows: &[Row], kernel: &str, plot: Option<&str>) -> String {
    let of: Vec<&Row> = rows.iter().filter(|r| r.kernel == kernel).collect();
    let first = of[0];
    let mut md = format!(
        "## {kernel}\n\nTime in ns per {}; error: {}.\n\n",
        first.element, first.error_metric
    );
    if let Some(file) = plot {
        md += &format!("![{kernel}: time against error]({file})\n\n");
    }
    md += "| setting | path | ns median | ns min - max | error | default | Pareto |\n|---|---|---|---|---|---|---|\n";
    for r in of {
        md += &format!(
            "| {} | {} | {} | {} - {} | {:.3e} | {} | {} |\n",
            r.setting,
            r.path.name(),
            fmt_ns(r.time.median),
            fmt_ns(r.time.min),
            fmt_ns(r.time.max),
            r.error,
            if r.is_default { "**yes**" } else { "" },
            if on_pareto_front(rows, r) {
                "front"
            } else {
                ""
            },
        );
    }
    md + "\n"
}
