//! Skipping work the frame does not need: frustum culling of guide blocks
//! and render-hair groups by bounding box, and distance LOD (a prefix of the
//! shuffled hair order, widened to keep coverage; TressFX, Frostbite).
//!
//! Bounds: a uniform cubic B-spline span lies in the convex hull of its four
//! control points (the weights are >= 0 and sum to 1), so a strand's refined
//! curve lies in the bounding box of its control points and the two phantom
//! ends. An interpolated hair's vertices are convex combinations of its three
//! guides' refined vertices, so it lies in the box around the three guides'
//! boxes. Culled guide blocks are not refined and culled groups are not
//! interpolated (nor, downstream, shaded).

use crate::interpolation::Interpolation;
use crate::Error;
use coif_base::{StrandBlocks, Vec3Lanes, LANES};
use glam::{DVec3, Mat4, Vec3, Vec4};

/// A convex view volume: six planes `(n, d)` with the inside where
/// `n . p + d >= 0`, normalised so that `|n| = 1` (distances in metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    planes: [Vec4; 6],
}

impl Frustum {
    /// From six inside-facing planes `(n.x, n.y, n.z, d)`; each is normalised
    /// (a plane with a zero normal accepts everything).
    pub fn from_planes(planes: [Vec4; 6]) -> Frustum {
        Frustum {
            planes: planes.map(|p| {
                let len = p.truncate().length();
                if len > 0.0 && len.is_finite() {
                    p / len
                } else {
                    Vec4::new(0.0, 0.0, 0.0, 1.0)
                }
            }),
        }
    }

    /// The world-space frustum of a view-projection matrix with clip depth
    /// in `[0, 1]` (glam's `perspective_*`, Vulkan, D3D, wgpu), by Gribb and
    /// Hartmann (2001): with rows `r0..r3`, the planes are `r3 + r0`,
    /// `r3 - r0`, `r3 + r1`, `r3 - r1`, `r2` (near) and `r3 - r2` (far).
    pub fn from_view_projection(view_projection: Mat4) -> Frustum {
        let r = |i| view_projection.row(i);
        Frustum::from_planes([
            r(3) + r(0),
            r(3) - r(0),
            r(3) + r(1),
            r(3) - r(1),
            r(2),
            r(3) - r(2),
        ])
    }

    /// The six planes `(n, d)`, `n . p + d >= 0` inside (Gribb & Hartmann 2001).
    pub fn planes(&self) -> &[Vec4; 6] {
        &self.planes
    }

    /// The same frustum in coordinates relative to `origin` (world position
    /// of local zero), computed in f64 so that far-from-origin scenes keep
    /// their precision.
    pub fn relative_to(&self, origin: DVec3) -> Frustum {
        Frustum {
            planes: self.planes.map(|p| {
                let d = p.w as f64 + p.truncate().as_dvec3().dot(origin);
                Vec4::new(p.x, p.y, p.z, d as f32)
            }),
        }
    }

    /// Whether the box `[min, max]` grown by `margin` may intersect the
    /// frustum (the "positive vertex" test: conservative, never culls a box
    /// that intersects). Empty or NaN boxes are kept (never culled).
    pub fn intersects_box(&self, min: Vec3, max: Vec3, margin: f32) -> bool {
        self.planes.iter().all(|p| {
            let n = p.truncate();
            let corner = Vec3::select(n.cmpge(Vec3::ZERO), max, min);
            // NaN distances compare as not-less: NaN boxes are kept.
            (n.dot(corner) + p.w + margin).partial_cmp(&0.0) != Some(std::cmp::Ordering::Less)
        })
    }
}

/// Which guide blocks must be refined and which render-hair groups drawn
/// this frame; filled by [`cull`] into caller-owned storage.
#[derive(Clone, Debug)]
pub struct Visibility {
    guide_blocks: Vec<bool>,
    groups: Vec<bool>,
    strand_min: Vec<Vec3>,
    strand_max: Vec<Vec3>,
}

impl Visibility {
    /// Storage for `guide_count` guides and `group_count` render groups
    /// (0 if there is no interpolation). Everything starts visible.
    ///
    /// # Panics
    ///
    /// Only as an allocation does, for counts whose flags and boxes cannot
    /// be allocated.
    pub fn new(guide_count: usize, group_count: usize) -> Visibility {
        let blocks = guide_count.div_ceil(LANES);
        Visibility {
            guide_blocks: vec![true; blocks],
            groups: vec![true; group_count],
            strand_min: vec![Vec3::ZERO; blocks * LANES],
            strand_max: vec![Vec3::ZERO; blocks * LANES],
        }
    }

    /// Whether guide block `b` must be refined (true if out of range).
    pub fn guide_block_needed(&self, b: usize) -> bool {
        self.guide_blocks.get(b).copied().unwrap_or(true)
    }

    /// Whether render group `g` is visible (true if out of range).
    pub fn group_visible(&self, g: usize) -> bool {
        self.groups.get(g).copied().unwrap_or(true)
    }

    /// Guide blocks that the last [`crate::cull`] marked as needed.
    pub fn guide_blocks_needed(&self) -> usize {
        self.guide_blocks.iter().filter(|&&b| b).count()
    }

    /// Hair groups that the last [`crate::cull`] marked as visible.
    pub fn groups_visible(&self) -> usize {
        self.groups.iter().filter(|&&g| g).count()
    }

    /// Bounding box (local coordinates) of guide strand `i`'s refined curve
    /// as of the last [`cull`].
    ///
    /// # Panics
    ///
    /// If `i` is past the last block's lanes (as slice indexing does).
    pub fn strand_bounds(&self, i: usize) -> (Vec3, Vec3) {
        (self.strand_min[i], self.strand_max[i])
    }

    /// [`Visibility::strand_bounds`], or `None` past the last block's lanes.
    pub fn get_strand_bounds(&self, i: usize) -> Option<(Vec3, Vec3)> {
        Some((*self.strand_min.get(i)?, *self.strand_max.get(i)?))
    }
}

/// Fills `out` for this frame (`frustum` in world space, `margin` in metres,
/// e.g. the hair width).
///
/// Without `interpolation`, a guide block is needed when its box meets the
/// frustum. With it, group `g` is visible when `g < groups_drawn` (the
/// distance-LOD prefix) and the box around its three guides' boxes meets the
/// frustum, and a guide block is needed exactly when a visible group uses one
/// of its strands. Allocates nothing.
///
/// # Errors
///
/// Nothing is written on:
/// - [`Error::CountMismatch`]: `out` was made for another number of guide
///   blocks or groups (make it with `Visibility::new(strand_count,
///   group_count)`), or `interpolation` indexes another number of guides
///   than `strands` holds;
/// - [`Error::InvalidParameter`]: `strands` has fewer than 2 vertices per
///   strand (and at least one strand).
pub fn cull(
    strands: StrandBlocks<'_>,
    interpolation: Option<&Interpolation>,
    groups_drawn: usize,
    frustum: &Frustum,
    margin: f32,
    out: &mut Visibility,
) -> Result<(), Error> {
    let blocks = strands.block_count();
    let groups = interpolation.map_or(0, |i| i.group_count());
    if out.guide_blocks.len() != blocks {
        return Err(Error::CountMismatch {
            what: "guide blocks (Visibility made for another set)",
            expected: blocks,
            got: out.guide_blocks.len(),
        });
    }
    if out.groups.len() != groups {
        return Err(Error::CountMismatch {
            what: "hair groups (Visibility made for another Interpolation)",
            expected: groups,
            got: out.groups.len(),
        });
    }
    if let Some(i) = interpolation.filter(|i| i.guide_count() != strands.strand_count()) {
        return Err(Error::CountMismatch {
            what: "guide strands (the Interpolation was made for another set)",
            expected: i.guide_count(),
            got: strands.strand_count(),
        });
    }
    if blocks > 0 && strands.verts_per_strand() < 2 {
        return Err(Error::InvalidParameter {
            name: "verts_per_strand",
            value: strands.verts_per_strand() as f64,
            expected: ">= 2",
        });
    }
    let local = frustum.relative_to(strands.origin());
    let verts = strands.verts_per_strand();
    for b in 0..blocks {
        let p = strands.block_positions_local(b);
        let first = p[0] + p[0] - p[1];
        let last = p[verts - 1] + p[verts - 1] - p[verts - 2];
        let (mut lo, mut hi) = (first.min(last), first.max(last));
        for v in p {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        for l in 0..LANES {
            out.strand_min[b * LANES + l] = lo.lane(l);
            out.strand_max[b * LANES + l] = hi.lane(l);
        }
    }
    match interpolation {
        None => {
            for b in 0..blocks {
                let (lo, hi) = block_box(out, b, strands.lanes_in_block(b));
                out.guide_blocks[b] = local.intersects_box(lo, hi, margin);
            }
        }
        Some(interp) => {
            out.guide_blocks.iter_mut().for_each(|b| *b = false);
            for (g, group) in interp.groups().iter().enumerate() {
                let [a, b, c] = group.guides.map(|s| s as usize);
                let lo = out.strand_min[a]
                    .min(out.strand_min[b])
                    .min(out.strand_min[c]);
                let hi = out.strand_max[a]
                    .max(out.strand_max[b])
                    .max(out.strand_max[c]);
                let visible = g < groups_drawn && local.intersects_box(lo, hi, margin);
                out.groups[g] = visible;
                if visible {
                    for s in [a, b, c] {
                        out.guide_blocks[s / LANES] = true;
                    }
                }
            }
        }
    }
    Ok(())
}

fn block_box(v: &Visibility, b: usize, lanes: usize) -> (Vec3, Vec3) {
    let s = b * LANES;
    let lo = v.strand_min[s..s + lanes]
        .iter()
        .fold(Vec3::INFINITY, |m, p| m.min(*p));
    let hi = v.strand_max[s..s + lanes]
        .iter()
        .fold(Vec3::NEG_INFINITY, |m, p| m.max(*p));
    (lo, hi)
}

/// Lane-wise min / max helpers on [`Vec3Lanes`].
trait MinMax {
    fn min(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
}

impl MinMax for Vec3Lanes {
    #[inline(always)]
    fn min(self, o: Vec3Lanes) -> Vec3Lanes {
        Vec3Lanes::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    #[inline(always)]
    fn max(self, o: Vec3Lanes) -> Vec3Lanes {
        Vec3Lanes::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
}

/// What distance LOD draws this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceLod {
    /// Draw (and interpolate) groups `0 .. groups_drawn` of the shuffled order.
    pub groups_drawn: usize,
    /// Real hairs in that prefix.
    pub hairs_drawn: usize,
    /// Multiply hair width by this to keep coverage: `hair_count / hairs_drawn`
    /// (coverage of thin, sparse hair is proportional to count x width).
    pub width_factor: f32,
}

/// Distance LOD from the projected width of one hair in pixels: draw the
/// fraction `clamp(width_px, min_fraction, 1)` of the hair (all of it while
/// a hair is at least a pixel wide; below that, fewer and wider hairs so each
/// drawn hair stays about a pixel wide), rounded up to whole groups.
/// `min_fraction` is clamped to `(0, 1]`; NaN inputs draw everything.
pub fn distance_lod(
    interpolation: &Interpolation,
    hair_width_px: f32,
    min_fraction: f32,
) -> DistanceLod {
    let min_fraction = if min_fraction > 0.0 {
        min_fraction.min(1.0)
    } else {
        1e-3
    };
    let fraction = if hair_width_px.is_nan() {
        1.0
    } else {
        hair_width_px.clamp(min_fraction, 1.0)
    };
    let groups = interpolation.group_count();
    let groups_drawn =
        ((fraction as f64 * groups as f64).ceil() as usize).clamp(groups.min(1), groups);
    let hairs_drawn = interpolation.hairs_in_prefix(groups_drawn);
    let width_factor = if hairs_drawn > 0 {
        interpolation.hair_count() as f32 / hairs_drawn as f32
    } else {
        1.0
    };
    DistanceLod {
        groups_drawn,
        hairs_drawn,
        width_factor,
    }
}
