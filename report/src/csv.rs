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
