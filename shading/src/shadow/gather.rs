//! Eight-lane gathers from a slice of `f32`: `values[index[l]]` per lane,
//! read lane by lane (scalar loads). An AVX2 `vgatherdps` was measured
//! slower on the development machine (an AMD EPYC: 20 against 17.5 ns per
//! shadow lookup for the first-depth reads), so none is used. Indices are
//! clamped into the slice, so a gather never reads outside it whatever the
//! caller passes (callers pass in-range indices).

use coif_base::lanes::{F32Lanes, I32Lanes};
use coif_base::LANES;

/// `values[clamp(index[l], 0, len - 1)]` per lane; 0 in every lane when
/// `values` is empty.
#[inline(always)]
pub(crate) fn gather(values: &[f32], index: I32Lanes) -> F32Lanes {
    let Some(last) = values.len().checked_sub(1) else {
        return F32Lanes::ZERO;
    };
    let index = index.max(I32Lanes::ZERO).to_array();
    F32Lanes::new(std::array::from_fn::<f32, LANES, _>(|l| {
        values[(index[l] as usize).min(last)]
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gathers_the_indexed_values_and_clamps_out_of_range_lanes() {
        let values: Vec<f32> = (0..37).map(|i| i as f32 * 1.5 - 3.0).collect();
        let (raw, clamped) = (
            [0, 36, 5, -4, 1000, 17, 17, 2],
            [0, 36, 5, 0, 36, 17, 17, 2],
        );
        let index = I32Lanes::new(std::array::from_fn(|l| raw[l % 8]));
        let got = gather(&values, index).to_array();
        for (l, g) in got.iter().enumerate() {
            assert_eq!(*g, values[clamped[l % 8]], "lane {l}");
        }
        assert_eq!(gather(&[], index).to_array(), [0.0; LANES]);
    }
}
