//! Polylines resampled by arc length.

use glam::Vec3;

/// Writes `out.len()` points spaced uniformly in arc length along the
/// polyline `strand`, from its first to its last point (the first and last
/// exactly; arc lengths summed in f64). A one-point or zero-length strand
/// gives `out.len()` copies of its first point; an empty one writes
/// nothing.
///
/// ```
/// use coif_base::polyline::arc_length_samples;
/// use glam::Vec3;
/// let bent = [Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y];
/// let mut out = [Vec3::ZERO; 5];
/// arc_length_samples(&bent, &mut out);
/// assert_eq!(out[2], Vec3::X);
/// assert_eq!(out[3], Vec3::new(1.0, 0.5, 0.0));
/// ```
pub fn arc_length_samples(strand: &[Vec3], out: &mut [Vec3]) {
    let m = out.len();
    if m == 0 || strand.is_empty() {
        return;
    }
    let total: f64 = strand
        .windows(2)
        .map(|w| (w[1] - w[0]).length() as f64)
        .sum();
    if strand.len() == 1 || total <= 0.0 {
        out.iter_mut().for_each(|o| *o = strand[0]);
        return;
    }
    let mut seg = 0;
    let mut seg_start = 0.0f64;
    let mut seg_len = (strand[1] - strand[0]).length() as f64;
    for (k, o) in out.iter_mut().enumerate() {
        let target = if m > 1 {
            total * k as f64 / (m - 1) as f64
        } else {
            0.0
        };
        while seg + 2 < strand.len() && seg_start + seg_len < target {
            seg_start += seg_len;
            seg += 1;
            seg_len = (strand[seg + 1] - strand[seg]).length() as f64;
        }
        let t = if seg_len > 0.0 {
            ((target - seg_start) / seg_len).clamp(0.0, 1.0) as f32
        } else {
            0.0
        };
        *o = strand[seg].lerp(strand[seg + 1], t);
    }
    out[m - 1] = strand[strand.len() - 1];
}
