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
pub fn on_pareto_front(rows: &[Row], row: &Row) -> bool {
    !rows.iter().any(|o| {
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

/// The summary; `plots` lists (kernel, file name) of the SVG plots.
pub fn to_markdown(rows: &[Row], plots: &[(String, String)], machine: &str) -> String {
    let mut md = String::from("# Time against error, every kernel\n\n");
    md += &format!(
        "Measured by `cargo run --release --bin report` on {machine}. Time is the median over \
repeated runs of a whole batch, per element, with the fastest and slowest run; the machine \
was shared with other work, so absolute times are noisy (compare within a table). A setting \
is on the Pareto front if no other setting of the same kernel and path is both faster and \
more accurate. Defaults are the settings the library or the frame pipeline uses.\n\n"
    );
    let names = kernels(rows);

    md += "## Defaults not on the Pareto front\n\n";
    let off: Vec<&Row> = rows
        .iter()
        .filter(|r| r.is_default && !on_pareto_front(rows, r))
        .collect();
    if off.is_empty() {
        md += "Every default is on the Pareto front of its kernel and path.\n\n";
    } else {
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
        md += "\n";
    }

    md += "## SIMD speed-up (scalar median / SIMD median)\n\n| kernel | at the default | range over settings |\n|---|---|---|\n";
    for k in &names {
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
    md += "\n";

    for k in &names {
        let of: Vec<&Row> = rows.iter().filter(|r| &r.kernel == k).collect();
        let first = of[0];
        md += &format!(
            "## {k}\n\nTime in ns per {}; error: {}.\n\n",
            first.element, first.error_metric
        );
        if let Some((_, file)) = plots.iter().find(|(name, _)| name == k) {
            md += &format!("![{k}: time against error]({file})\n\n");
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
        md += "\n";
    }
    md
}
