//! A flattened binary bounding-volume hierarchy over axis-aligned boxes,
//! built by median split (the primitives' centroids split at the median
//! along the axis of largest centroid extent, `select_nth_unstable`), with
//! up to [`LEAF_SIZE`] primitives per leaf.
//!
//! The build is iterative (an explicit work list) and the median split
//! halves every range, so the depth is at most `ceil(log2(n / LEAF_SIZE)) + 1`
//! (16 for 100,000 primitives): traversal uses a fixed stack of 64 entries,
//! enough for any `n` that fits in memory. Children of an interior node are
//! stored next to each other (`first` and `first + 1`).

use glam::Vec3;

/// Most primitives in one leaf.
pub(crate) const LEAF_SIZE: usize = 4;

/// Traversal stack depth (the tree is at most about 40 levels deep for
/// 2^32 primitives).
pub(crate) const STACK: usize = 64;

#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub min: Vec3,
    pub max: Vec3,
    /// Leaf: first index into `Bvh::prims`. Interior: the left child (the
    /// right one is `first + 1`).
    pub first: u32,
    /// Primitives in a leaf; 0 for an interior node.
    pub count: u32,
}

#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    pub nodes: Vec<Node>,
    /// Primitive indices, leaf ranges contiguous.
    pub prims: Vec<u32>,
}

fn bounds_of(prims: &[u32], boxes: &[(Vec3, Vec3)]) -> (Vec3, Vec3) {
    prims.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| {
            let (a, b) = boxes[p as usize];
            (lo.min(a), hi.max(b))
        },
    )
}

impl Bvh {
    /// Builds over `boxes` (min, max), which must be non-empty and have
    /// fewer than 2^31 entries (the caller checks). Infinite or NaN box
    /// coordinates do not panic (`total_cmp`); such boxes are simply never hit.
    pub fn build(boxes: &[(Vec3, Vec3)]) -> Bvh {
        let n = boxes.len();
        let mut prims: Vec<u32> = (0..n as u32).collect();
        let centroid = |p: u32| {
            let (a, b) = boxes[p as usize];
            0.5 * (a + b)
        };
        let mut nodes = Vec::with_capacity(2 * n / LEAF_SIZE + 1);
        let (lo, hi) = bounds_of(&prims, boxes);
        nodes.push(Node {
            min: lo,
            max: hi,
            first: 0,
            count: n as u32,
        });
        // (node, begin, end)
        let mut work = vec![(0usize, 0usize, n)];
        while let Some((node, begin, end)) = work.pop() {
            if end - begin <= LEAF_SIZE {
                nodes[node].first = begin as u32;
                nodes[node].count = (end - begin) as u32;
                continue;
            }
            let slice = &mut prims[begin..end];
            let (clo, chi) = slice.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), &p| (lo.min(centroid(p)), hi.max(centroid(p))),
            );
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = slice.len() / 2;
            slice.select_nth_unstable_by(mid, |&p, &q| {
                centroid(p)[axis].total_cmp(&centroid(q)[axis])
            });
            let left = nodes.len();
            for (b, e) in [(begin, begin + mid), (begin + mid, end)] {
                let (lo, hi) = bounds_of(&prims[b..e], boxes);
                nodes.push(Node {
                    min: lo,
                    max: hi,
                    first: 0,
                    count: 0,
                });
                work.push((nodes.len() - 1, b, e));
            }
            nodes[node].first = left as u32;
            nodes[node].count = 0;
        }
        Bvh { nodes, prims }
    }

    /// Visits the leaves' primitives whose boxes the ray `origin + t dir`,
    /// `t` in `[0, t_max]`, may cross, nearer child first. `visit(prim)`
    /// returns the new `t_max` (the closest hit so far, or the old value) or
    /// `None` to stop the traversal.
    #[inline]
    pub fn traverse(
        &self,
        origin: Vec3,
        dir: Vec3,
        mut t_max: f32,
        mut visit: impl FnMut(u32) -> Option<f32>,
    ) {
        let inv = dir.recip();
        let mut stack = [0u32; STACK];
        let mut top = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                let first = n.first as usize;
                for &p in &self.prims[first..first + n.count as usize] {
                    match visit(p) {
                        Some(t) => t_max = t,
                        None => return,
                    }
                }
            } else {
                let l = n.first as usize;
                let (tl, tr) = (
                    slab(&self.nodes[l], origin, inv, t_max),
                    slab(&self.nodes[l + 1], origin, inv, t_max),
                );
                match (tl, tr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, l + 1) } else { (l + 1, l) };
                        if top < STACK {
                            stack[top] = far as u32;
                            top += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = l + 1;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            node = stack[top] as usize;
        }
    }
}

/// Entry distance of the ray into the node's box if it meets it within
/// `[0, t_max]` (slab test; NaN from 0 * inf is ignored by `max`/`min`).
#[inline]
fn slab(n: &Node, origin: Vec3, inv: Vec3, t_max: f32) -> Option<f32> {
    let t0 = (n.min - origin) * inv;
    let t1 = (n.max - origin) * inv;
    let near = t0.min(t1);
    let far = t0.max(t1);
    let enter = near.x.max(near.y).max(near.z).max(0.0);
    let exit = far.x.min(far.y).min(far.z).min(t_max);
    (enter <= exit).then_some(enter)
}
