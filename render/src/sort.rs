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

use super::Camera;
use coif_lod::RenderVertex;
use glam::Vec3;

/// Caller-owned sort keys `(depth, strand)`, sized once for `capacity`
/// strands.
#[derive(Clone, Debug, Default)]
pub struct DepthOrder {
    keys: Vec<(f32, u32)>,
}

impl DepthOrder {
    /// An empty order with room for `strands` strands (sorting then allocates nothing).
    pub fn with_capacity(strands: usize) -> DepthOrder {
        DepthOrder {
            keys: Vec::with_capacity(strands),
        }
    }

    /// Strand indices, farthest first, after [`DepthOrder::sort`].
    pub fn strands(&self) -> impl ExactSizeIterator<Item = usize> + '_ {
        self.keys.iter().map(|&(_, s)| s as usize)
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
    pub fn sort(&mut self, camera: &Camera, vertices: &[RenderVertex], verts_per_strand: usize) {
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
            let mid = Vec3::from(strand[verts_per_strand / 2].position);
            let depth = (mid - eye).dot(forward);
            let depth = if depth.is_finite() {
                depth
            } else {
                f32::INFINITY
            };
            self.keys.push((depth, s as u32));
        }
        self.keys
            .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
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
        self.keys
            .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    }
}
