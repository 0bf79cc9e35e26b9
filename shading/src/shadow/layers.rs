//! The depth axis of one texel: where its planes lie, which interval a depth
//! falls in, and the piecewise-linear opacity between planes.
//!
//! Each texel holds `L` cumulative opacities `S[0..L]` at plane depths
//! `base + D_1 < ... < base + D_L`; depth `base` itself (`D_0 = 0`) has
//! opacity 0. Between planes opacity is linear in depth (Kim & Neumann
//! 2001, section 3): for `D_i <= x = z - base <= D_(i+1)`,
//! `sigma = S[i-1] + (x - D_i) / (D_(i+1) - D_i) (S[i] - S[i-1])`
//! with `S[-1] = 0`; in front of `base` sigma is 0 and behind the last plane
//! it stays `S[L-1]`.
//!
//! * Slices (OSM): `base = near` for every texel and even spacing
//!   `D_i = i (far - near) / L`.
//! * Deep: `base = z0(x, y)` and `D_i = s (far - near) (i / L)^2` with
//!   `s = DEEP_SPAN = 1/2`: thin layers at the lit surface, thicker ones
//!   deeper in, where the opacity has saturated and changes slowly; hair
//!   more than `s (far - near)` behind `z0` falls in the last layer (as in
//!   Yuksel & Keyser, whose last layer extends to infinity).
//!
//! Measured on a draped head (1024 strands, 128^2 map, footprint reference,
//! see SHADOWS.md), mean |T error| of deep mode at 3 / 8 / 16 layers:
//! even spacing over the full depth 0.110 / 0.090 / 0.073, quadratic over the
//! full depth 0.094 / 0.063 / 0.058, quadratic over half of it 0.082 / 0.066
//! / 0.063, over a quarter 0.082 / 0.074 / 0.073. Half is the best at the
//! small layer counts deep maps are for.

use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::LANES;

/// The share of the hair's depth range that deep mode's layers span.
pub const DEEP_SPAN: f32 = 0.5;

/// Up to this many quadratic layers (deep maps use 3) the interval index
/// `min(floor(sqrt q), L - 1)` is found without a square root, as the
/// number of `k` in `1..L` with `q >= k^2`: the same integer, since a
/// correctly rounded square root is monotonic and exact at the perfect
/// squares `k^2` (so `sqrt q >= k` exactly when `q >= k^2`; tested next to
/// every `k^2`). A vector square root costs more than three compares. The
/// fraction's `/ (2 i + 1)` is then a multiply by
/// [`ODD_RECIPROCALS`]`[i]` (within one rounding of the division).
pub const FEW: usize = 4;

/// `1 / (2 i + 1)` for the intervals `i < FEW`, rounded to `f32`.
pub const ODD_RECIPROCALS: [f32; FEW] = [1.0, 1.0 / 3.0, 1.0 / 5.0, 1.0 / 7.0];

/// How a texel's planes are spaced; see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layering {
    /// `L`, the number of planes.
    pub count: usize,
    /// `L / (far - near)` (even) or `L^2 / (far - near)` (quadratic).
    pub scale: f32,
    /// `D_i` grows as `i^2` (deep mode) rather than as `i`.
    pub quadratic: bool,
}

impl Layering {
    /// Even spacing of `count` planes over `depth`.
    pub fn even(count: usize, depth: f32) -> Layering {
        Layering {
            count,
            scale: count as f32 / depth.max(1.0e-6),
            quadratic: false,
        }
    }

    /// Quadratic spacing `D_i = depth (i / count)^2`.
    pub fn quadratic(count: usize, depth: f32) -> Layering {
        Layering {
            count,
            scale: (count * count) as f32 / depth.max(1.0e-6),
            quadratic: true,
        }
    }

    /// The interval `i` in `0..L` holding `x = z - base` (`D_i <= x <
    /// D_(i+1)`, clamped: in front of `base` gives 0, behind the last plane
    /// `L - 1`) and the fraction of the way from `D_i` to `D_(i+1)`, clamped
    /// to [0, 1]. `x` must not be NaN.
    ///
    /// Even: `c = x L / depth`, `i = floor(c)`, `f = c - i`. Quadratic:
    /// `q = x L^2 / depth`, `i = floor(sqrt q)`, `f = (q - i^2) / (2 i + 1)`
    /// (up to [`FEW`] layers by comparisons and a reciprocal table).
    #[inline(always)]
    pub fn locate(&self, x: f32) -> (usize, f32) {
        let last = (self.count - 1) as f32;
        let q = x.max(0.0) * self.scale;
        if self.quadratic {
            if self.count <= FEW {
                // floor(sqrt q) clamped, by comparisons, and 1 / (2 i + 1)
                // from a table (see `FEW`).
                let mut i = 0.0;
                for k in 1..self.count {
                    i += (q >= (k * k) as f32) as u32 as f32;
                }
                let f = ((q - i * i) * ODD_RECIPROCALS[i as usize]).min(1.0);
                return (i as usize, f);
            }
            let i = q.sqrt().floor().min(last);
            let f = ((q - i * i) / (2.0 * i + 1.0)).min(1.0);
            (i as usize, f)
        } else {
            let i = q.floor().min(last);
            let f = (q - i).min(1.0);
            (i as usize, f)
        }
    }

    /// The interval index of [`Layering::locate`] on eight depths, with the
    /// same operations in the same order (`max`, multiply, then `sqrt`,
    /// `floor`, `min`, or the comparisons up to [`FEW`] quadratic layers:
    /// each correctly rounded, so every lane equals the scalar index).
    /// `x` must not be NaN.
    #[inline(always)]
    pub fn interval_simd(&self, x: F32Lanes) -> [usize; LANES] {
        self.interval_i32x8(x).to_array().map(|i| i as usize)
    }

    /// [`Layering::interval_simd`] as `i32` lanes (for index arithmetic in
    /// SIMD registers).
    #[inline(always)]
    pub fn interval_i32x8(&self, x: F32Lanes) -> I32Lanes {
        self.interval_f32x8(x).fast_trunc_int()
    }

    /// Up to [`FEW`] quadratic layers: the thresholds `k^2` for `k` in
    /// `1..FEW`, `+inf` from `k = L` on (never reached by a finite `q`),
    /// splatted, for [`Layering::interval_few_i32x8`]; `None` otherwise.
    pub fn few_thresholds(&self) -> Option<[F32Lanes; FEW - 1]> {
        (self.quadratic && self.count <= FEW).then(|| {
            std::array::from_fn(|j| {
                let k = j + 1;
                F32Lanes::splat(if k < self.count {
                    (k * k) as f32
                } else {
                    f32::INFINITY
                })
            })
        })
    }

    /// [`Layering::interval_i32x8`] for up to [`FEW`] quadratic layers with
    /// the thresholds of [`Layering::few_thresholds`]: always `FEW - 1`
    /// comparisons, no branch on the layer count; the same index (a
    /// comparison with `+inf` adds nothing for finite `q`).
    #[inline(always)]
    pub fn interval_few_i32x8(&self, thresholds: &[F32Lanes; FEW - 1], x: F32Lanes) -> I32Lanes {
        let q = x.fast_max(F32Lanes::ZERO) * F32Lanes::splat(self.scale);
        let mut i = F32Lanes::ZERO;
        for t in thresholds {
            i += q.simd_ge(*t) & F32Lanes::ONE;
        }
        i.fast_trunc_int()
    }

    /// [`Layering::interval_simd`] as `f32` lanes (exact small integers).
    /// `x` must not be NaN (a NaN lane gives some index in `0..L`:
    /// `fast_max(x, 0)` returns 0 for it).
    #[inline(always)]
    pub fn interval_f32x8(&self, x: F32Lanes) -> F32Lanes {
        let last = F32Lanes::splat((self.count - 1) as f32);
        let q = x.fast_max(F32Lanes::ZERO) * F32Lanes::splat(self.scale);
        if self.quadratic && self.count <= FEW {
            // The scalar's comparisons, in the same order.
            let mut i = F32Lanes::ZERO;
            for k in 1..self.count {
                i += q.simd_ge(F32Lanes::splat((k * k) as f32)) & F32Lanes::ONE;
            }
            i
        } else {
            let i = if self.quadratic { q.sqrt() } else { q };
            i.floor().fast_min(last)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comparisons give `min(floor(sqrt q), L - 1)` next to every
    /// perfect square they test (a thousand floats either side of `k^2`),
    /// and the eight-lane index equals the scalar one.
    #[test]
    fn few_layer_index_equals_the_square_root_floor() {
        for count in 1..=FEW {
            let ly = Layering::quadratic(count, count as f32);
            assert_eq!(ly.scale, count as f32, "q = x * L here");
            let last = (count - 1) as f32;
            for k in 1..=count + 1 {
                let square = (k * k) as f32;
                let mut below = square;
                let mut above = square;
                for _ in 0..1000 {
                    for q in [below, above] {
                        let x = q / ly.scale;
                        let q = x * ly.scale;
                        let want = q.sqrt().floor().min(last) as usize;
                        let (i, f) = ly.locate(x);
                        assert_eq!(i, want, "L {count} q {q}");
                        let i = i as f32;
                        let divided = ((q - i * i) / (2.0 * i + 1.0)).min(1.0);
                        assert!((f - divided).abs() <= f32::EPSILON, "L {count} q {q}");
                        let lanes = ly.interval_simd(F32Lanes::splat(x));
                        assert_eq!(lanes, [want; LANES], "L {count} q {q}");
                        let few = ly.few_thresholds().expect("quadratic, few layers");
                        let lanes = ly.interval_few_i32x8(&few, F32Lanes::splat(x));
                        assert_eq!(lanes.to_array(), [want as i32; LANES], "L {count} q {q}");
                    }
                    below = f32::from_bits(below.to_bits() - 1);
                    above = f32::from_bits(above.to_bits() + 1);
                }
            }
        }
    }
}
