//! The rows as CSV (`results.csv`).

use super::Row;

/// Header of [`to_csv`].
pub const HEADER: &str = "kernel,setting,path,element,ns_per_element_median,ns_min,ns_max,ns_spread,error_metric,error,is_default";

fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One line per row after [`HEADER`].
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = format!("{HEADER}\n");
    for r in rows {
        out += &format!(
            "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{},{:.6e},{}\n",
            field(&r.kernel),
            field(&r.setting),
            r.path.name(),
            field(r.element),
            r.time.median,
            r.time.min,
            r.time.max,
            r.time.spread(),
            field(r.error_metric),
            r.error,
            r.is_default
        );
    }
    out
}

/// The fields of one CSV line (quotes as [`to_csv`] writes them).
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().expect("one field").push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            (c, _) => out.last_mut().expect("one field").push(c),
        }
    }
    out
}

/// A `&'static str` for a parsed name: the element and error-metric
/// names of [`Row`] are static, so each distinct one read from a file is
/// leaked once (a few dozen bytes per report).
fn interned(s: &str, seen: &mut Vec<&'static str>) -> &'static str {
    if let Some(&known) = seen.iter().find(|&&k| k == s) {
        return known;
    }
    let leaked: &'static str = Box::leak(s.to_string().into_boxed_str());
    seen.push(leaked);
    leaked
}

/// The rows of a `results.csv` written by [`to_csv`] (the spread column
/// is recomputed, not read), so plots and the summary can be redrawn
/// without measuring again.
pub fn from_csv(text: &str) -> Result<Vec<Row>, String> {
    use super::{Path, Timing};
    let mut lines = text.lines();
    if lines.next() != Some(HEADER) {
        return Err(format!("the first line is not the header {HEADER:?}"));
    }
    let mut names = Vec::new();
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.is_empty()) {
        let f = fields(line);
        let at = |what: &str| format!("line {}: {what} in {line:?}", i + 2);
        if f.len() != HEADER.split(',').count() {
            return Err(at("wrong number of fields"));
        }
        let number = |k: usize| f[k].parse::<f64>().map_err(|_| at("not a number"));
        let path = match f[2].as_str() {
            "simd" => Path::Simd,
            "scalar" => Path::Scalar,
            _ => return Err(at("unknown path")),
        };
        rows.push(Row {
            kernel: f[0].clone(),
            setting: f[1].clone(),
            path,
            element: interned(&f[3], &mut names),
            time: Timing {
                median: number(4)?,
                min: number(5)?,
                max: number(6)?,
            },
            error_metric: interned(&f[8], &mut names),
            error: number(9)?,
            is_default: f[10] == "true",
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn committed_csv_reads_back_to_the_same_text() {
        let text = include_str!("../../docs/report/results.csv");
        let rows = from_csv(text).expect("parsed");
        assert_eq!(rows.len(), text.lines().count() - 1);
        // Every column but the spread, which is recomputed from the
        // rounded min and max and may differ in its last digit.
        let without_spread = |t: &str| -> Vec<Vec<String>> {
            t.lines()
                .map(|l| {
                    let mut f = fields(l);
                    f.remove(7);
                    f
                })
                .collect()
        };
        assert_eq!(without_spread(&to_csv(&rows)), without_spread(text));
    }

    #[test]
    fn quoted_fields_keep_commas_and_quotes() {
        assert_eq!(fields(r#"a,"b, ""c""",d"#), ["a", r#"b, "c""#, "d"]);
    }
}
