//! Back-to-front order of hair strands.
//!
//! Blending `c <- c + alpha (colour - c)` is order dependent: the result is
//! correct only if farther hair is blended first. Like Alice: Madness
//! Returns, we sort whole **strands**, not segments, by the view depth of
//! their middle vertex: one key per strand (tens of thousands, not millions
//! of segments), and a strand's segments stay together. The price is that a
//! long strand crossing others in depth is blended at one depth; for hair
//! hanging around a head, strands' depth ranges are short next to the
//! head, and errors are where many thin, similar-coloured strands overlap,
//! where they are least visible.

use super::{Camera, ShadedVertex};
use coif_lod::RenderVertex;
use glam::Vec3;

/// A vertex with a position: what [`DepthOrder::sort`] reads.
pub trait Positioned {
    /// Position in the camera's space.
    fn position(&self) -> Vec3;
}

impl Positioned for RenderVertex {
    #[inline]
    fn position(&self) -> Vec3 {
        Vec3::from(self.position)
    }
}

impl Positioned for ShadedVertex {
    #[inline]
    fn position(&self) -> Vec3 {
        Vec3::from(self.position)
    }
}

/// Orders below this many strands use a comparison sort; above, a radix
/// sort (same order, fewer passes over the keys).
const RADIX_FROM: usize = 1024;

/// Caller-owned sort keys `(depth, strand)` and the radix sort's scratch,
/// sized once for `capacity` strands.
#[derive(Clone, Debug, Default)]
pub struct DepthOrder {
    keys: Vec<(f32, u32)>,
    scratch: Vec<(u32, u32)>,
    radix: Vec<(u32, u32)>,
}

impl DepthOrder {
    /// An empty order with room for `strands` strands (sorting then allocates nothing).
    pub fn with_capacity(strands: usize) -> DepthOrder {
        DepthOrder {
            keys: Vec::with_capacity(strands),
            scratch: Vec::with_capacity(strands),
            radix: Vec::with_capacity(strands),
        }
    }

    /// Strand indices, farthest first, after [`DepthOrder::sort`].
    pub fn strands(&self) -> impl ExactSizeIterator<Item = usize> + '_ {
        self.keys.iter().map(|&(_, s)| s as usize)
    }

    /// The `i`-th strand of the order (farthest first); `i < len()`.
    #[inline]
    pub fn strand(&self, i: usize) -> usize {
        self.keys[i].1 as usize
    }

    /// Number of strands ordered.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Whether no strand is ordered.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Orders the strands of `vertices` (`verts_per_strand` each, strand
    /// after strand) farthest first by the view depth of their middle
    /// vertex (ties by index; a non-finite depth sorts as farthest). At most
    /// the capacity's worth of strands is kept, so nothing is allocated.
    pub fn sort<V: Positioned>(
        &mut self,
        camera: &Camera,
        vertices: &[V],
        verts_per_strand: usize,
    ) {
        self.keys.clear();
        if verts_per_strand == 0 {
            return;
        }
        let forward = camera.forward();
        let eye = camera.eye();
        let room = self.keys.capacity();
        for (s, strand) in vertices
            .chunks_exact(verts_per_strand)
            .take(room)
            .enumerate()
        {
            let mid = strand[verts_per_strand / 2].position();
            let depth = (mid - eye).dot(forward);
            let depth = if depth.is_finite() {
                depth
            } else {
                f32::INFINITY
            };
            self.keys.push((depth, s as u32));
        }
        self.order_keys();
    }

    /// Orders strands `0..count` by the given depths (farthest first); for
    /// tests and callers with their own depth measure.
    pub fn sort_by_depths(&mut self, depths: impl IntoIterator<Item = f32>) {
        self.keys.clear();
        let room = self.keys.capacity();
        for (s, d) in depths.into_iter().take(room).enumerate() {
            self.keys
                .push((if d.is_finite() { d } else { f32::INFINITY }, s as u32));
        }
        self.order_keys();
    }

    /// Sorts the keys farthest first, ties by strand index: a comparison
    /// sort for short orders, else [`DepthOrder::radix_sort`] (the same
    /// order, proven by a test).
    fn order_keys(&mut self) {
        if self.keys.len() < RADIX_FROM {
            self.comparison_sort();
        } else {
            self.radix_sort();
        }
    }

    /// The reference order: `total_cmp` on the depths, descending, ties by index.
    fn comparison_sort(&mut self) {
        self.keys
            .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    }

    /// The same order by a least-significant-digit radix sort (three
    /// passes of 11 bits) over `u32` keys whose unsigned order is the
    /// depths' `total_cmp` order reversed (the sign bit flipped for
    /// positive floats, every bit for negative ones, then all inverted).
    /// Each pass is stable and the keys start in index order, so ties
    /// stay in index order, as in the comparison sort.
    fn radix_sort(&mut self) {
        let descending = |d: f32| {
            let bits = d.to_bits();
            !(if bits >> 31 == 1 {
                !bits
            } else {
                bits | 1 << 31
            })
        };
        self.radix.clear();
        self.radix
            .extend(self.keys.iter().map(|&(d, s)| (descending(d), s)));
        self.scratch.clear();
        self.scratch.resize(self.radix.len(), (0, 0));
        let (mut from, mut to) = (&mut self.radix, &mut self.scratch);
        for shift in [0u32, 11, 22] {
            let mut counts = [0u32; 2048];
            for &(k, _) in from.iter() {
                counts[(k >> shift) as usize & 2047] += 1;
            }
            let mut sum = 0;
            for c in counts.iter_mut() {
                (*c, sum) = (sum, sum + *c);
            }
            for &(k, s) in from.iter() {
                let c = &mut counts[(k >> shift) as usize & 2047];
                to[*c as usize] = (k, s);
                *c += 1;
            }
            std::mem::swap(&mut from, &mut to);
        }
        // Three passes: the sorted keys are in `from`; back to depths.
        let depth = |k: u32| {
            let o = !k;
            f32::from_bits(if o >> 31 == 1 { o & !(1 << 31) } else { !o })
        };
        for (dst, &(k, s)) in self.keys.iter_mut().zip(from.iter()) {
            *dst = (depth(k), s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use coif_base::SplitMix64;

    #[test]
    fn the_radix_sort_gives_the_comparison_sorts_order() {
        let mut rng = SplitMix64::new(17);
        // Ties (a few distinct depths), signed zeros, negative depths,
        // infinities and NaN (sorted as farthest).
        let special = [
            0.0f32,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -1.5,
            1e-30,
        ];
        let depths: Vec<f32> = (0..5000)
            .map(|k| match k % 5 {
                0 => special[(k / 5) % special.len()],
                1 => (rng.range(0.0, 8.0)).floor() * 0.25,
                _ => rng.range(-3.0, 3.0),
            })
            .collect();
        let mut radix = DepthOrder::with_capacity(depths.len());
        radix.sort_by_depths(depths.iter().copied());
        assert!(radix.len() >= RADIX_FROM, "the radix path ran");
        let mut comparison = DepthOrder::with_capacity(depths.len());
        comparison.sort_by_depths(depths.iter().copied());
        comparison.comparison_sort();
        assert_eq!(radix.keys.len(), comparison.keys.len());
        for (a, b) in radix.keys.iter().zip(&comparison.keys) {
            assert_eq!((a.0.to_bits(), a.1), (b.0.to_bits(), b.1));
        }
        // Farthest first: the NaN and +inf strands lead.
        assert!(radix.keys[0].0 == f32::INFINITY);
    }
}
