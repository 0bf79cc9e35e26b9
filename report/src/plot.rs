//! Time-against-error plots as SVG, written by hand (a few dozen shapes
//! per plot; no plotting dependency, no fonts needed at build time: the
//! viewer renders the `<text>` elements).
//!
//! Both axes are logarithmic: x is nanoseconds per element, y the error.
//! One colour per path; the Pareto front of each path is joined by a line
//! and its points filled; other points are hollow; the default setting
//! gets a red ring. Errors of exactly 0 (a reference measured against
//! itself) are drawn on the bottom edge and labelled so. Setting labels
//! are placed greedily (default first, then the Pareto front) at the first
//! free spot around their point; a label that would overlap another label
//! or a point is left out, and the legend says how many were.

use super::summary::on_pareto_front;
use super::{Path, Row};
use std::fmt::Write;

const W: f64 = 720.0;
const H: f64 = 480.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 170.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 60.0;

/// A file name for a kernel: lower case, spaces and punctuation as `-`.
pub fn file_stem(kernel: &str) -> String {
    kernel
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

fn colour(path: Path) -> &'static str {
    match path {
        Path::Simd => "#1f77b4",
        Path::Scalar => "#ff7f0e",
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Values closer than this (in decades) to a whole decade get one more
/// decade of room, so points do not sit on the frame where their labels
/// cannot be placed.
const EDGE_ROOM: f64 = 0.15;

/// Decade range `[floor(log lo - room), ceil(log hi + room)]` (as
/// exponents) of the positive values, with `room` = [`EDGE_ROOM`].
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let (a, mut b) = (
        (lo.log10() - EDGE_ROOM).floor(),
        (hi.log10() + EDGE_ROOM).ceil(),
    );
    if b <= a {
        b = a + 1.0;
    }
    (a, b)
}

/// The plot of one kernel's rows (all with the same kernel name).
pub fn svg(kernel: &str, rows: &[&Row]) -> String {
    let all: Vec<Row> = rows.iter().map(|r| (*r).clone()).collect();
    let (x0, x1) = decades(rows.iter().map(|r| r.time.median));
    let (mut y0, y1) = decades(rows.iter().map(|r| r.error));
    let has_zero = rows.iter().any(|r| r.error <= 0.0);
    if has_zero {
        y0 -= 1.0;
    }
    let pw = W - LEFT - RIGHT;
    let ph = H - TOP - BOTTOM;
    let px = |ns: f64| LEFT + (ns.max(1e-30).log10() - x0) / (x1 - x0) * pw;
    let py = |e: f64| {
        let l = if e > 0.0 { e.log10().max(y0) } else { y0 };
        TOP + ph - (l - y0) / (y1 - y0) * ph
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="{W}" height="{H}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" font-size="15" text-anchor="middle">{}: time against error</text>"#,
        LEFT + pw / 2.0,
        escape(kernel)
    );
    // Grid and decade ticks.
    for d in (x0 as i32)..=(x1 as i32) {
        let x = px(10f64.powi(d));
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">1e{d}</text>"##,
            TOP + ph,
            TOP + ph + 16.0
        );
    }
    for d in (y0 as i32)..=(y1 as i32) {
        let y = TOP + ph - (d as f64 - y0) / (y1 - y0) * ph;
        let label = if has_zero && d as f64 == y0 {
            "0".to_string()
        } else {
            format!("1e{d}")
        };
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{label}</text>"##,
            LEFT + pw,
            LEFT - 6.0,
            y + 4.0
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="black"/>"#
    );
    let element = rows.first().map_or("element", |r| r.element);
    let metric = rows.first().map_or("error", |r| r.error_metric);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">ns per {} (median, log scale)</text>"#,
        LEFT + pw / 2.0,
        H - 18.0,
        escape(element)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{} (log scale)</text>"#,
        TOP + ph / 2.0,
        escape(metric)
    );
    // Per path: front line and points; labels placed after all points.
    let mut labels: Vec<Label> = Vec::new();
    let mut legend_y = TOP + 10.0;
    for path in [Path::Simd, Path::Scalar] {
        let of: Vec<&Row> = rows.iter().copied().filter(|r| r.path == path).collect();
        if of.is_empty() {
            continue;
        }
        let c = colour(path);
        let mut front: Vec<&Row> = of
            .iter()
            .copied()
            .filter(|r| on_pareto_front(&all, r))
            .collect();
        front.sort_by(|a, b| a.time.median.total_cmp(&b.time.median));
        if front.len() > 1 {
            let pts: Vec<String> = front
                .iter()
                .map(|r| format!("{:.1},{:.1}", px(r.time.median), py(r.error)))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.5" stroke-dasharray="5 3"/>"#,
                pts.join(" ")
            );
        }
        for r in &of {
            let (x, y) = (px(r.time.median), py(r.error));
            // Spread of the timing as a horizontal bar.
            let _ = writeln!(
                s,
                r#"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{c}" stroke-opacity="0.5"/>"#,
                px(r.time.min),
                px(r.time.max)
            );
            let fill = if on_pareto_front(&all, r) { c } else { "white" };
            let _ = writeln!(
                s,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="4" fill="{fill}" stroke="{c}" stroke-width="1.5"/>"#
            );
            if r.is_default {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{x:.1}" cy="{y:.1}" r="8" fill="none" stroke="red" stroke-width="2"/>"#
                );
            }
            let priority = if r.is_default {
                0
            } else if on_pareto_front(&all, r) {
                1
            } else {
                2
            };
            labels.push(Label {
                x,
                y,
                text: &r.setting,
                priority,
            });
        }
        let lx = LEFT + pw + 12.0;
        let _ = writeln!(
            s,
            r#"<circle cx="{lx}" cy="{legend_y}" r="4" fill="{c}" stroke="{c}"/><text x="{}" y="{}">{}</text>"#,
            lx + 10.0,
            legend_y + 4.0,
            path.name()
        );
        legend_y += 18.0;
    }
    let plot_area = Rect {
        x0: LEFT,
        y0: TOP,
        x1: LEFT + pw,
        y1: TOP + ph,
    };
    let omitted = place_labels(&mut s, &mut labels, plot_area);
    let lx = LEFT + pw + 12.0;
    let _ = writeln!(
        s,
        r#"<circle cx="{lx}" cy="{legend_y}" r="4" fill="gray"/><text x="{}" y="{}">on Pareto front</text>"#,
        lx + 10.0,
        legend_y + 4.0
    );
    legend_y += 18.0;
    let _ = writeln!(
        s,
        r#"<circle cx="{lx}" cy="{legend_y}" r="4" fill="white" stroke="gray"/><text x="{}" y="{}">dominated</text>"#,
        lx + 10.0,
        legend_y + 4.0
    );
    legend_y += 18.0;
    let _ = writeln!(
        s,
        r#"<circle cx="{lx}" cy="{legend_y}" r="8" fill="none" stroke="red" stroke-width="2"/><text x="{}" y="{}">default</text>"#,
        lx + 14.0,
        legend_y + 4.0
    );
    legend_y += 18.0;
    let _ = writeln!(
        s,
        r#"<text x="{lx}" y="{}" font-size="9">bars: fastest-slowest run</text>"#,
        legend_y + 4.0
    );
    if omitted > 0 {
        legend_y += 14.0;
        let _ = writeln!(
            s,
            r#"<text x="{lx}" y="{}" font-size="9">{omitted} label{} left out where</text><text x="{lx}" y="{}" font-size="9">they would overlap (see</text><text x="{lx}" y="{}" font-size="9">the table in summary.md)</text>"#,
            legend_y + 4.0,
            if omitted == 1 { "" } else { "s" },
            legend_y + 16.0,
            legend_y + 28.0
        );
    }
    s += "</svg>\n";
    s
}

/// A point's setting label waiting to be placed.
struct Label<'a> {
    x: f64,
    y: f64,
    text: &'a str,
    /// 0: the default, 1: on the Pareto front, 2: dominated; lower first.
    priority: u8,
}

/// An axis-aligned box in SVG coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Rect {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Rect {
    fn overlaps(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    fn grown(&self, by: f64) -> Rect {
        Rect {
            x0: self.x0 - by,
            y0: self.y0 - by,
            x1: self.x1 + by,
            y1: self.y1 + by,
        }
    }

    fn inside(&self, o: &Rect) -> bool {
        self.x0 >= o.x0 && self.x1 <= o.x1 && self.y0 >= o.y0 && self.y1 <= o.y1
    }
}

/// Font size of the point labels and the width of one character at it
/// (an estimate for sans-serif digits and lower case).
const LABEL_SIZE: f64 = 9.0;
const LABEL_CHAR_WIDTH: f64 = 5.2;
/// Least space between two labels.
const LABEL_GAP: f64 = 3.0;

/// Writes the labels that fit: in order of priority (default, Pareto
/// front, dominated; left to right within each), each at the first of
/// eight positions around its point where its box stays inside `area`,
/// keeps [`LABEL_GAP`] from every placed label and overlaps no point
/// marker (the default's ring included). Labels with
/// no such position are left out; returns how many.
fn place_labels(s: &mut String, labels: &mut [Label], area: Rect) -> usize {
    labels.sort_by(|a, b| a.priority.cmp(&b.priority).then(a.x.total_cmp(&b.x)));
    // A point's marker: radius 4, or the default's ring of radius 8.
    let points: Vec<Rect> = labels
        .iter()
        .map(|l| {
            let r = if l.priority == 0 { 9.0 } else { 4.0 };
            Rect {
                x0: l.x - r,
                y0: l.y - r,
                x1: l.x + r,
                y1: l.y + r,
            }
        })
        .collect();
    let mut placed: Vec<Rect> = Vec::new();
    let mut omitted = 0;
    for l in labels.iter() {
        let w = LABEL_CHAR_WIDTH * l.text.chars().count() as f64;
        let h = LABEL_SIZE;
        // Clear of the point's own marker (radius 4, the default's ring 9).
        let r = if l.priority == 0 { 9.0 } else { 4.0 };
        let (dx, dy) = (r + 2.0, r + 1.0);
        // Top-left corners: right above, right below, left above, left
        // below, centred above and below, then level on the right and left.
        let candidates = [
            (l.x + dx, l.y - dy - h),
            (l.x + dx, l.y + dy),
            (l.x - dx - w, l.y - dy - h),
            (l.x - dx - w, l.y + dy),
            (l.x - 0.5 * w, l.y - dy - 2.0 - h),
            (l.x - 0.5 * w, l.y + dy + 2.0),
            (l.x + dx, l.y - 0.5 * h),
            (l.x - dx - w, l.y - 0.5 * h),
        ];
        let spot = candidates.iter().map(|&(x0, y0)| Rect {
            x0,
            y0,
            x1: x0 + w,
            y1: y0 + h,
        });
        let free = spot.into_iter().find(|r| {
            let padded = r.grown(LABEL_GAP);
            r.inside(&area)
                && !placed.iter().any(|p| p.overlaps(&padded))
                && !points.iter().any(|p| p.overlaps(r))
        });
        match free {
            Some(r) => {
                // The baseline sits about 2 px above the box's bottom.
                let _ = writeln!(
                    s,
                    r##"<text x="{:.1}" y="{:.1}" font-size="{LABEL_SIZE}" fill="#333">{}</text>"##,
                    r.x0,
                    r.y1 - 2.0,
                    escape(l.text)
                );
                placed.push(r);
            }
            None => omitted += 1,
        }
    }
    omitted
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(x: f64, y: f64, text: &str, priority: u8) -> Label<'_> {
        Label {
            x,
            y,
            text,
            priority,
        }
    }

    #[test]
    fn placed_labels_do_not_overlap_and_the_default_is_kept() {
        let area = Rect {
            x0: 0.0,
            y0: 0.0,
            x1: 400.0,
            y1: 300.0,
        };
        // Six points on top of each other and one far away.
        let mut labels = vec![
            label(100.0, 100.0, "iterations=1 pearls=0", 2),
            label(101.0, 100.0, "iterations=1 pearls=1", 1),
            label(102.0, 100.0, "iterations=1 pearls=2", 2),
            label(103.0, 101.0, "iterations=2 pearls=0", 2),
            label(103.0, 101.0, "iterations=2 pearls=1", 0),
            label(104.0, 100.0, "iterations=2 pearls=2", 2),
            label(300.0, 200.0, "alone", 2),
        ];
        let mut svg = String::new();
        let omitted = place_labels(&mut svg, &mut labels, area);
        let texts: Vec<&str> = svg.lines().collect();
        assert_eq!(texts.len() + omitted, 7);
        assert!(omitted > 0, "not all of six stacked labels fit");
        assert!(svg.contains(">iterations=2 pearls=1<"), "default kept");
        assert!(svg.contains(">alone<"));
        // Recover each placed box from its text line and check pairwise.
        let boxes: Vec<Rect> = texts
            .iter()
            .map(|t| {
                let num = |key: &str| -> f64 {
                    let rest = &t[t.find(key).unwrap() + key.len()..];
                    rest[..rest.find('"').unwrap()].parse().unwrap()
                };
                let text = &t[t.find('>').unwrap() + 1..t.rfind('<').unwrap()];
                let (x, base) = (num("x=\""), num("y=\""));
                Rect {
                    x0: x,
                    y0: base + 2.0 - LABEL_SIZE,
                    x1: x + LABEL_CHAR_WIDTH * text.len() as f64,
                    y1: base + 2.0,
                }
            })
            .collect();
        for (i, a) in boxes.iter().enumerate() {
            assert!(a.inside(&area));
            for b in &boxes[i + 1..] {
                assert!(!a.grown(LABEL_GAP - 0.1).overlaps(b), "{a:?} touches {b:?}");
            }
        }
    }
}
