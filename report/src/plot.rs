//! Time-against-error plots, one SVG per kernel, drawn with `plotters`.
//!
//! x is the error, y the nanoseconds per element (median), both on
//! logarithmic axes with a tick per decade. One colour per path (SIMD,
//! scalar), side by side in the same chart. Points on the Pareto front of
//! their path are filled and joined by a line; dominated points are
//! hollow; the default setting has a red ring; a vertical bar spans the
//! fastest to the slowest timed run. Every point carries the number of its
//! setting, and the key beside the chart lists the settings by number, so
//! every setting stays readable however close the points are.
//!
//! Errors of 0 or below (a reference measured against itself) have no
//! place on a log axis: they are drawn as crosses at the axis minimum, one
//! decade below the smallest positive error, whose tick reads `≤ 0`, and
//! the key says so. Rows whose time or error is not finite, or whose time is
//! not positive, cannot be drawn at all: the key lists them by name.

use super::summary::on_pareto_front;
use super::{Path, Row};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io;

/// Size of the whole picture in pixels.
const SIZE: (u32, u32) = (960, 540);
/// Width of the key (setting numbers and notes) right of the chart.
const KEY_WIDTH: u32 = 270;
/// Font of the axis labels, point numbers and key.
const FONT: &str = "sans-serif";
/// Characters per line of the key's notes (about 6 px each: plotters
/// writes SVG font sizes at 1 / 1.24 of the size asked for).
const KEY_CHARS: usize = 40;
/// Values closer than this (in decades) to a whole decade get one more
/// decade of room, so points do not sit on the frame.
const EDGE_ROOM: f64 = 0.15;

/// The chart type: log error (x) against log time (y), on an SVG.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;
/// What a drawing step returns.
type Drawn = Result<(), DrawingAreaErrorKind<io::Error>>;

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

/// The plot of one kernel's rows (all with the same kernel name) as SVG.
pub fn svg(kernel: &str, rows: &[&Row]) -> io::Result<String> {
    let layout = Layout::new(rows);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        draw(&root, kernel, rows, &layout).map_err(|e| io::Error::other(e.to_string()))?;
    }
    Ok(out)
}

/// The colour of a path's points and front line.
fn colour(path: Path) -> RGBColor {
    match path {
        Path::Simd => RGBColor(31, 119, 180),
        Path::Scalar => RGBColor(255, 127, 14),
    }
}

/// Axis ranges, where non-positive errors go, and the setting numbers.
struct Layout {
    /// Error axis, `[10^a, 10^b]`.
    x: (f64, f64),
    /// Time axis, `[10^a, 10^b]`.
    y: (f64, f64),
    /// The error axis minimum where errors `<= 0` are drawn, if any are.
    clamp: Option<f64>,
    /// Settings in order of first appearance; a point's number is its
    /// index here plus one.
    settings: Vec<String>,
}

impl Layout {
    fn new(rows: &[&Row]) -> Layout {
        let drawn = || rows.iter().filter(|r| drawable(r));
        let (mut x0, x1) = decades(drawn().map(|r| r.error));
        let clamped = drawn().any(|r| r.error <= 0.0);
        if clamped {
            x0 -= 1.0;
        }
        let (y0, y1) = decades(drawn().flat_map(|r| [r.time.min, r.time.median, r.time.max]));
        let mut settings: Vec<String> = Vec::new();
        for r in rows {
            if !settings.contains(&r.setting) {
                settings.push(r.setting.clone());
            }
        }
        Layout {
            x: widened(x0, x1),
            y: widened(y0, y1),
            clamp: clamped.then(|| 10f64.powf(x0)),
            settings,
        }
    }

    /// The point of a drawable row: errors `<= 0` at the axis minimum.
    fn point(&self, r: &Row) -> (f64, f64) {
        match self.clamp {
            Some(c) if r.error <= 0.0 => (c, r.time.median),
            _ => (r.error, r.time.median),
        }
    }

    /// The 1-based number of a setting.
    fn number(&self, setting: &str) -> usize {
        self.settings
            .iter()
            .position(|s| s == setting)
            .map_or(0, |i| i + 1)
    }

    /// Decades spanned by an axis (at least 1).
    fn decades((lo, hi): (f64, f64)) -> usize {
        ((hi / lo).log10().round() as usize).max(1)
    }
}

/// Whether a row has a place in the chart: finite positive time, finite
/// error (errors `<= 0` are clamped, not dropped).
fn drawable(r: &Row) -> bool {
    r.time.median.is_finite() && r.time.median > 0.0 && r.error.is_finite()
}

/// Decade range `[floor(log lo - room), ceil(log hi + room)]` (as
/// exponents) of the positive finite values, with `room` = [`EDGE_ROOM`];
/// `(0, 1)` if there are none.
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let a = (lo.log10() - EDGE_ROOM).floor();
    let b = (hi.log10() + EDGE_ROOM).ceil().max(a + 1.0);
    (a, b)
}

/// The axis range `[10^a, 10^b]`, a hair wider so that rounding in
/// plotters' `log10` of the ends keeps both end decades as ticks.
fn widened(a: f64, b: f64) -> (f64, f64) {
    (10f64.powf(a) * (1.0 - 1e-9), 10f64.powf(b) * (1.0 + 1e-9))
}

/// A tick label: `≤ 0` at the clamp position, else `1e-3` style.
fn tick(v: f64, clamp: Option<f64>) -> String {
    match clamp {
        Some(c) if (v / c - 1.0).abs() < 1e-9 => "≤ 0".into(),
        _ => format!("{v:.0e}"),
    }
}

/// The whole picture: the chart on the left, the key on the right.
fn draw(
    root: &DrawingArea<SVGBackend, Shift>,
    kernel: &str,
    rows: &[&Row],
    layout: &Layout,
) -> Drawn {
    root.fill(&WHITE)?;
    let (chart_area, key_area) = root.split_horizontally(SIZE.0 - KEY_WIDTH);
    let mut chart = axes(&chart_area, kernel, rows, layout)?;
    for path in [Path::Simd, Path::Scalar] {
        let of: Vec<&Row> = rows
            .iter()
            .copied()
            .filter(|r| r.path == path && drawable(r))
            .collect();
        if of.is_empty() {
            continue;
        }
        spread_bars(&mut chart, &of, layout)?;
        front_line(&mut chart, path, &of, layout)?;
        points(&mut chart, path, &of, layout)?;
    }
    defaults(&mut chart, rows, layout)?;
    numbers(&mut chart, rows, layout)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font((FONT, 14))
        .draw()?;
    key(&key_area, rows, layout)
}

/// Title, log axes with a tick per decade, grid and axis descriptions.
fn axes<'a, 'b: 'a>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    kernel: &str,
    rows: &[&Row],
    layout: &Layout,
) -> Result<Chart<'a, 'b>, DrawingAreaErrorKind<io::Error>> {
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{kernel}: time against error"), (FONT, 24))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(
            (layout.x.0..layout.x.1).log_scale(),
            (layout.y.0..layout.y.1).log_scale(),
        )?;
    let element = rows.first().map_or("element", |r| r.element);
    let metric = rows.first().map_or("error", |r| r.error_metric);
    let clamp = layout.clamp;
    let x_tick = move |v: &f64| tick(*v, clamp);
    let y_tick = |v: &f64| tick(*v, None);
    chart
        .configure_mesh()
        .x_labels(Layout::decades(layout.x) + 1)
        .y_labels(Layout::decades(layout.y) + 1)
        .x_label_formatter(&x_tick)
        .y_label_formatter(&y_tick)
        .x_desc(format!("{metric} (log scale)"))
        .y_desc(format!("ns per {element} (median, log scale)"))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()?;
    Ok(chart)
}

/// The fastest-to-slowest run of every point as a vertical bar.
fn spread_bars<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, rows: &[&Row], layout: &Layout) -> Drawn {
    let style = colour(rows[0].path).mix(0.5);
    let (lo, hi) = layout.y;
    chart.draw_series(rows.iter().map(|r| {
        let (x, y) = layout.point(r);
        let clip = |t: f64| if t.is_finite() { t.clamp(lo, hi) } else { y };
        ErrorBar::new_vertical(x, clip(r.time.min), y, clip(r.time.max), style, 6)
    }))?;
    Ok(())
}

/// The Pareto front of one path, joined in order of error.
fn front_line<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    path: Path,
    rows: &[&Row],
    layout: &Layout,
) -> Drawn {
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| on_pareto_front(rows.iter().copied(), r))
        .map(|r| layout.point(r))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    let c = colour(path);
    chart
        .draw_series(LineSeries::new(front, c.stroke_width(2)))?
        .label(format!("{}: Pareto front", path.name()))
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(-10, 0), (10, 0)], c.stroke_width(2))
                + Circle::new((0, 0), 4, c.filled())
        });
    Ok(())
}

/// One path's points: filled on the front, hollow if dominated, a cross
/// where the error is `<= 0` (clamped to the axis minimum).
fn points<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    path: Path,
    rows: &[&Row],
    layout: &Layout,
) -> Drawn {
    let c = colour(path);
    let on_front = |r: &Row| on_pareto_front(rows.iter().copied(), r);
    let (front, dominated): (Vec<&Row>, Vec<&Row>) = rows
        .iter()
        .copied()
        .filter(|r| r.error > 0.0)
        .partition(|r| on_front(r));
    chart.draw_series(
        front
            .iter()
            .map(|r| Circle::new(layout.point(r), 4, c.filled())),
    )?;
    if !dominated.is_empty() {
        chart
            .draw_series(dominated.iter().map(|r| {
                EmptyElement::at(layout.point(r))
                    + Circle::new((0, 0), 4, WHITE.filled())
                    + Circle::new((0, 0), 4, c.stroke_width(2))
            }))?
            .label(format!("{}: dominated", path.name()))
            .legend(move |(x, y)| Circle::new((x, y), 4, c.stroke_width(2)));
    }
    let clamped: Vec<&Row> = rows.iter().copied().filter(|r| r.error <= 0.0).collect();
    if !clamped.is_empty() {
        chart
            .draw_series(
                clamped
                    .iter()
                    .map(|r| Cross::new(layout.point(r), 5, c.stroke_width(2))),
            )?
            .label(format!("{}: error ≤ 0, at the axis minimum", path.name()))
            .legend(move |(x, y)| Cross::new((x, y), 5, c.stroke_width(2)));
    }
    Ok(())
}

/// A red ring around the default setting's points.
fn defaults<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, rows: &[&Row], layout: &Layout) -> Drawn {
    let of: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| r.is_default && drawable(r))
        .collect();
    if of.is_empty() {
        return Ok(());
    }
    chart
        .draw_series(
            of.iter()
                .map(|r| Circle::new(layout.point(r), 8, RED.stroke_width(2))),
        )?
        .label("default setting")
        .legend(|(x, y)| Circle::new((x, y), 6, RED.stroke_width(2)));
    Ok(())
}

/// Every point's setting number, right of the point, moved up or down
/// where it would cover another number ([`label_offsets`]).
fn numbers<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, rows: &[&Row], layout: &Layout) -> Drawn {
    let drawn: Vec<&Row> = rows.iter().copied().filter(|r| drawable(r)).collect();
    let texts: Vec<String> = drawn
        .iter()
        .map(|r| layout.number(&r.setting).to_string())
        .collect();
    let at: Vec<(i32, i32)> = drawn
        .iter()
        .map(|r| chart.backend_coord(&layout.point(r)))
        .collect();
    let offsets = label_offsets(&at, &texts);
    let style = (FONT, 13).into_font().color(&RGBColor(51, 51, 51));
    chart.draw_series(drawn.iter().zip(texts).zip(offsets).map(|((r, t), dy)| {
        EmptyElement::at(layout.point(r)) + Text::new(t, (11, dy), style.clone())
    }))?;
    Ok(())
}

/// Height of a point number's box in pixels, and the width of one digit.
const NUMBER_BOX: (i32, i32) = (12, 7);

/// Vertical offsets (from the point, in pixels, to the top of the text)
/// for labels `texts` right of the points `at`: plotters places text
/// where it is told, so labels of points that crowd together (settings
/// of nearly equal error and time) would print over one another. Each
/// label, in order of its point's height, takes the first of a few
/// offsets, alternating down and up from level, whose box clears the
/// labels placed before; if none does, it stays level.
fn label_offsets(at: &[(i32, i32)], texts: &[String]) -> Vec<i32> {
    let (h, digit) = NUMBER_BOX;
    let boxed = |i: usize, dy: i32| {
        let (x, y) = (at[i].0 + 11, at[i].1 + dy);
        (x, y, x + digit * texts[i].len() as i32, y + h)
    };
    let clear = |a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)| {
        a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1
    };
    let mut order: Vec<usize> = (0..at.len()).collect();
    order.sort_by_key(|&i| (at[i].1, at[i].0));
    let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
    let mut offsets = vec![-h / 2; at.len()];
    for i in order {
        let level = -h / 2;
        let candidates =
            (0..9).map(|k| level + (h + 1) * if k % 2 == 0 { k / 2 } else { -(k + 1) / 2 });
        let dy = candidates
            .into_iter()
            .find(|&dy| placed.iter().all(|&p| clear(boxed(i, dy), p)))
            .unwrap_or(level);
        offsets[i] = dy;
        placed.push(boxed(i, dy));
    }
    offsets
}

/// The key: settings by number (the default marked), then notes on the
/// run spread, clamped errors and rows that could not be drawn.
fn key(area: &DrawingArea<SVGBackend, Shift>, rows: &[&Row], layout: &Layout) -> Drawn {
    let mut lines: Vec<(String, u32)> = vec![("Settings (point numbers)".into(), 16)];
    for (i, s) in layout.settings.iter().enumerate() {
        let default = rows.iter().any(|r| &r.setting == s && r.is_default);
        let mark = if default { "  (default)" } else { "" };
        lines.push((format!("{:>2}  {s}{mark}", i + 1), 13));
    }
    lines.push((String::new(), 13));
    let mut notes = vec!["Bars: fastest to slowest timed run.".to_string()];
    if let Some(c) = layout.clamp {
        let n = rows
            .iter()
            .filter(|r| drawable(r) && r.error <= 0.0)
            .count();
        notes.push(format!(
            "Crosses: {n} point(s) with error ≤ 0 (no place on a log axis), drawn at the axis minimum {c:.0e}."
        ));
    }
    for r in rows.iter().filter(|r| !drawable(r)) {
        notes.push(format!(
            "Not drawn: {} ({}), time {} ns, error {} (not finite or not positive).",
            r.setting,
            r.path.name(),
            r.time.median,
            r.error
        ));
    }
    for note in notes {
        lines.extend(wrap(&note, KEY_CHARS).into_iter().map(|l| (l, 13)));
    }
    let mut y = 48;
    for (text, size) in lines {
        area.draw(&Text::new(text, (8, y), (FONT, size)))?;
        y += size as i32 + 4;
    }
    Ok(())
}

/// Words of `text` in lines of at most `width` characters (longer words
/// on a line of their own).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Timing;

    fn row(setting: &str, path: Path, ns: f64, error: f64) -> Row {
        Row {
            kernel: "k".into(),
            setting: setting.into(),
            path,
            element: "sample",
            time: Timing {
                median: ns,
                min: 0.9 * ns,
                max: 1.2 * ns,
            },
            error_metric: "test error",
            error,
            is_default: setting == "b",
        }
    }

    #[test]
    fn zero_errors_are_clamped_and_unplottable_rows_are_named() {
        let rows = [
            row("a", Path::Simd, 2.0, 0.0),
            row("b", Path::Simd, 1.0, 1e-3),
            row("c", Path::Scalar, 20.0, 1e-2),
            row("d", Path::Scalar, f64::NAN, 1e-2),
        ];
        let refs: Vec<&Row> = rows.iter().collect();
        let layout = Layout::new(&refs);
        // 1e-3 .. 1e-2 widened to 1e-4 .. 1e-1 for edge room, then one
        // decade more below for the zero error.
        assert_eq!(layout.clamp, Some(1e-5));
        assert!((layout.x.0 / 1e-5 - 1.0).abs() < 1e-6, "{:?}", layout.x);
        assert_eq!(layout.point(&rows[0]), (1e-5, 2.0));
        let svg = svg("k", &refs).expect("drawn");
        assert!(svg.contains("≤ 0"), "clamped tick");
        assert!(svg.contains("error ≤ 0, at the axis minimum"), "legend");
        assert!(
            svg.contains("Not drawn: d (scalar)"),
            "unplottable row named"
        );
        for s in ["a", "b", "c", "d"] {
            assert!(svg.contains(&format!("{}  {s}", layout.number(s))), "{s}");
        }
        assert!(svg.contains("b  (default)"));
    }

    #[test]
    fn crowded_point_numbers_do_not_overlap() {
        // Five points a pixel apart, one far away.
        let at = [
            (100, 100),
            (101, 101),
            (100, 102),
            (102, 103),
            (100, 104),
            (300, 300),
        ];
        let texts: Vec<String> = ["1", "12", "3", "14", "5", "6"].map(String::from).into();
        let dy = label_offsets(&at, &texts);
        let (h, digit) = NUMBER_BOX;
        let boxes: Vec<(i32, i32, i32, i32)> = (0..at.len())
            .map(|i| {
                let (x, y) = (at[i].0 + 11, at[i].1 + dy[i]);
                (x, y, x + digit * texts[i].len() as i32, y + h)
            })
            .collect();
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[i + 1..] {
                let apart = a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1;
                assert!(apart, "{a:?} overlaps {b:?}");
            }
        }
        assert_eq!(dy[5], -h / 2, "a lone point's number stays level");
    }

    #[test]
    fn notes_wrap_at_word_boundaries() {
        let lines = wrap("one two three four", 9);
        assert_eq!(lines, ["one two", "three", "four"]);
        assert!(wrap("", 9).is_empty());
    }
}
