//! Dense render hair interpolated from guide strands (Nalu, Nguyen & Donnelly
//! 2005, GPU Gems 2 ch. 23; NVIDIA HairWorks).
//!
//! Render hair `k` lies in a scalp triangle whose corners are the roots of
//! guides `(A, B, C)`, with barycentric weights `b >= 0`, `sum b = 1`, drawn
//! uniformly over the triangle (Osada et al. 2002, "Shape distributions",
//! section 4.2):
//!
//! ```text
//! b_A = 1 - sqrt(u),   b_B = sqrt(u) (1 - v),   b_C = sqrt(u) v,   u, v ~ U[0, 1)
//! ```
//!
//! and every one of its vertices is `P = b_A A + b_B B + b_C C` of the three
//! guides' refined vertices. Positions are metres; density is in hairs per
//! square centimetre (1 cm^2 = 1e-4 m^2; real scalps: 120-200).
//!
//! Layout: hairs come in groups of up to eight ([`GROUP_LANES`]) hairs of
//! one triangle, so a group's guides are shared by its lanes and the SIMD
//! batch loads each guide vertex once (a broadcast) for eight hairs. The
//! groups are eight hairs wide at both widths, so that both make the same
//! hairs in the same groups and draw the same ones at every LOD (the hairs'
//! bytes do not depend on the width). [`interpolate`] writes a group per
//! register of [`LANES`] lanes (in a 16-lane build the upper eight lanes
//! are padding); [`Interpolation::groups_blend`] fills a register with
//! [`GROUPS_PER_BLOCK`] groups, one per eight lanes, for fused passes.
//! Groups are stored in a
//! shuffled order: drawing a prefix of groups is an even random thinning of
//! the whole scalp (see [`crate::distance_lod`]). Padding lanes repeat the
//! group's last real hair.
//!
//! Steps, in both twins ([`interpolate`] here, eight hairs of a group per
//! instruction, and [`crate::scalar::interpolate`], one hair at a time):
//!
//! 1. Skip the groups past the distance-LOD prefix, culled, or whose guide
//!    blocks were not refined.
//! 2. Per refined vertex: `P = b_A A + b_B B + b_C C` (with [`blend`]).
//! 3. With tangents: the same blend of the guides' unit tangents,
//!    normalised (or `+Y`).

use crate::culling::Visibility;
use crate::refine_batch::unit_or_y_simd;
use crate::refine_batch::RefinedGuides;
use crate::Error;
use coif_base::lanes::F32Lanes;
use coif_base::lanes::Lane;
use coif_base::lanes::{from_groups, groups as groups_of, F32Group, GROUPS_PER_BLOCK, GROUP_LANES};
use coif_base::rng::SplitMix64;
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

/// Square metres per square centimetre.
pub const M2_PER_CM2: f32 = 1e-4;

/// Upper bound on the number of render hairs one [`Interpolation`] may hold:
/// 2^20 = 1,048,576, ten times a real head's hair count (a frame pipeline
/// holds about 11 KB per render hair, so this keeps a bad density to about
/// 12 GB instead of the hundreds that 2^24 allowed).
pub const MAX_RENDER_HAIRS: usize = 1 << 20;

/// Up to eight ([`GROUP_LANES`]) render hairs sharing one scalp triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HairGroup {
    /// Index of the scalp triangle.
    pub triangle: u32,
    /// The triangle's corner guides `(A, B, C)`.
    pub guides: [u32; 3],
    /// Real hairs in this group (1 ..= 8); the other lanes are padding.
    pub hairs: u32,
}

/// Where render hairs sit: groups of hairs per scalp triangle with their
/// barycentric weights, in shuffled group order. Built once per groom.
#[derive(Clone, Debug)]
pub struct Interpolation {
    guide_count: usize,
    hair_count: usize,
    scalp_area_m2: f64,
    pub(crate) groups: Vec<HairGroup>,
    /// Per group: (b_A, b_B, b_C) lanes.
    pub(crate) weights: Vec<[F32Lanes; 3]>,
}

impl Interpolation {
    /// Places render hairs on the scalp triangles `triangles` (indices into
    /// `guide_roots`, one root per guide strand, metres) at `hairs_per_cm2`,
    /// reproducibly from `seed`.
    ///
    /// Triangle `t` of area `a_t` gets `floor(a_t rho)` hairs plus one more
    /// with probability `frac(a_t rho)`, so the expected count is exact.
    ///
    /// # Errors
    ///
    /// [`Error::NonFinite`] on a non-finite root, [`Error::GuideOutOfRange`]
    /// on a guide index out of range, [`Error::InvalidParameter`] on a
    /// negative or non-finite density or more than [`MAX_RENDER_HAIRS`] hairs.
    pub fn new(
        guide_roots: &[Vec3],
        triangles: &[[u32; 3]],
        hairs_per_cm2: f32,
        seed: u64,
    ) -> Result<Interpolation, Error> {
        Interpolation::build(guide_roots, triangles, hairs_per_cm2, seed, 1)
    }

    /// As [`Interpolation::new`], but every triangle gets a whole number of
    /// full groups: `8 floor(m / 8)` hairs plus 8 more with probability
    /// `frac(m / 8)`, for a mean of `m = a_t rho`. The expected count (and
    /// so the density over many triangles) is unchanged, no lane of an
    /// eight-lane block is padding, and the batch does about `1 / lane use` less work; the price
    /// is a coarser hair count per triangle (steps of 8), so use it when
    /// triangles hold many hairs each. The step is eight at every lane
    /// width ([`GROUP_LANES`]), so that 8- and 16-lane builds make the same
    /// hairs; in a 16-lane build a triangle with an odd number of groups
    /// pads half a block.
    ///
    /// # Errors
    ///
    /// As [`Interpolation::new`].
    pub fn with_whole_groups(
        guide_roots: &[Vec3],
        triangles: &[[u32; 3]],
        hairs_per_cm2: f32,
        seed: u64,
    ) -> Result<Interpolation, Error> {
        Interpolation::build(guide_roots, triangles, hairs_per_cm2, seed, GROUP_LANES)
    }

    /// Hair counts per triangle are rounded stochastically to multiples of `step`.
    fn build(
        guide_roots: &[Vec3],
        triangles: &[[u32; 3]],
        hairs_per_cm2: f32,
        seed: u64,
        step: usize,
    ) -> Result<Interpolation, Error> {
        if !(hairs_per_cm2.is_finite() && hairs_per_cm2 >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "hairs_per_cm2",
                value: hairs_per_cm2 as f64,
                expected: "finite and >= 0",
            });
        }
        if let Some(index) = guide_roots.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        let mut total = 0.0f64;
        let mut areas = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&guide) = tri.iter().find(|&&g| g as usize >= guide_roots.len()) {
                return Err(Error::GuideOutOfRange { triangle: t, guide });
            }
            let [a, b, c] = tri.map(|g| guide_roots[g as usize].as_dvec3());
            let area = 0.5 * (b - a).cross(c - a).length();
            total += area;
            areas.push(area);
        }
        let expected = total / M2_PER_CM2 as f64 * hairs_per_cm2 as f64;
        if expected > MAX_RENDER_HAIRS as f64 {
            return Err(Error::InvalidParameter {
                name: "hairs_per_cm2",
                value: hairs_per_cm2 as f64,
                expected: "a density giving at most 1,048,576 (2^20, MAX_RENDER_HAIRS) hairs on this scalp",
            });
        }

        let mut rng = SplitMix64::new(seed);
        let mut groups = Vec::new();
        let mut weights = Vec::new();
        let mut hair_count = 0;
        for (t, (tri, &area)) in triangles.iter().zip(&areas).enumerate() {
            let mean = area / M2_PER_CM2 as f64 * hairs_per_cm2 as f64 / step as f64;
            let mut count = mean.floor() as usize;
            if (rng.next_f32() as f64) < mean - mean.floor() {
                count += 1;
            }
            count *= step;
            hair_count += count;
            let mut left = count;
            while left > 0 {
                let hairs = left.min(GROUP_LANES);
                let mut lanes = [[0.0f32; LANES]; 3];
                for l in 0..LANES {
                    if l < hairs {
                        let b = barycentric(rng.next_f32(), rng.next_f32());
                        for (lane, w) in lanes.iter_mut().zip(b) {
                            lane[l] = w;
                        }
                    } else {
                        for lane in lanes.iter_mut() {
                            lane[l] = lane[hairs - 1];
                        }
                    }
                }
                groups.push(HairGroup {
                    triangle: t as u32,
                    guides: *tri,
                    hairs: hairs as u32,
                });
                weights.push(lanes.map(F32Lanes::new));
                left -= hairs;
            }
        }
        // Fisher-Yates shuffle of whole groups: any prefix is a uniform
        // random subset of groups, i.e. an even thinning over the scalp.
        for i in (1..groups.len()).rev() {
            let j = rng.below(i + 1);
            groups.swap(i, j);
            weights.swap(i, j);
        }
        Ok(Interpolation {
            guide_count: guide_roots.len(),
            hair_count,
            scalp_area_m2: total,
            groups,
            weights,
        })
    }

    /// Number of guide strands the triangles index into.
    pub fn guide_count(&self) -> usize {
        self.guide_count
    }

    /// Number of real render hairs.
    pub fn hair_count(&self) -> usize {
        self.hair_count
    }

    /// Number of groups (SIMD blocks) of render hairs.
    pub fn group_count(&self) -> usize {
        self.groups.len()
    }

    /// Total scalp area of the triangles, in square metres.
    pub fn scalp_area_m2(&self) -> f64 {
        self.scalp_area_m2
    }

    /// The groups, in draw (shuffled) order.
    pub fn groups(&self) -> &[HairGroup] {
        &self.groups
    }

    /// Barycentric weights `(b_A, b_B, b_C)` of lane `lane` of group `g`.
    ///
    /// # Panics
    ///
    /// If `g >= group_count()` or `lane >= LANES` (as slice indexing does).
    pub fn weights(&self, g: usize, lane: usize) -> [f32; 3] {
        self.weights[g].map(|w| w.as_array()[lane])
    }

    /// [`Interpolation::weights`], or `None` for a hair that does not exist.
    pub fn get_weights(&self, g: usize, lane: usize) -> Option<[f32; 3]> {
        (g < self.weights.len() && lane < LANES).then(|| self.weights(g, lane))
    }

    /// How much of the hair each guide stands for: per guide, the sum of its
    /// barycentric weights over every real render hair (a guide at the
    /// corner of many large triangles carries much), scaled so that the
    /// mean over the guides in some triangle is 1; a guide in no triangle
    /// gets 1. What `coif_kernels::Strands::set_hair_shares` takes.
    ///
    /// ```
    /// use coif_lod::Interpolation;
    /// use glam::Vec3;
    /// let roots = [Vec3::ZERO, Vec3::X * 0.01, Vec3::Z * 0.01, Vec3::ONE];
    /// let interp = Interpolation::new(&roots, &[[0, 1, 2]], 150.0, 7).unwrap();
    /// let shares = interp.guide_shares();
    /// assert_eq!(shares.len(), 4);
    /// assert!((shares[..3].iter().sum::<f32>() / 3.0 - 1.0).abs() < 1e-5);
    /// assert_eq!(shares[3], 1.0);
    /// ```
    pub fn guide_shares(&self) -> Vec<f32> {
        let mut sum = vec![0.0f64; self.guide_count];
        for (g, group) in self.groups.iter().enumerate() {
            for lane in 0..(group.hairs as usize).min(LANES) {
                for (k, &guide) in group.guides.iter().enumerate() {
                    if let Some(s) = sum.get_mut(guide as usize) {
                        *s += self.weights[g][k].as_array()[lane] as f64;
                    }
                }
            }
        }
        let used: Vec<f64> = sum.iter().copied().filter(|s| *s > 0.0).collect();
        let mean = used.iter().sum::<f64>() / used.len().max(1) as f64;
        sum.iter()
            .map(|&s| {
                if s > 0.0 && mean > 0.0 {
                    (s / mean) as f32
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// Real hairs in the first `groups` groups (the drawn prefix).
    pub fn hairs_in_prefix(&self, groups: usize) -> usize {
        self.groups
            .iter()
            .take(groups)
            .map(|g| g.hairs as usize)
            .sum()
    }
}

/// Uniform barycentric weights in a triangle from two uniform numbers:
/// `(1 - sqrt(u), sqrt(u) (1 - v), sqrt(u) v)`.
#[inline]
pub fn barycentric(u: f32, v: f32) -> [f32; 3] {
    let s = u.sqrt();
    let b = s * (1.0 - v);
    let c = s * v;
    // b_A from the other two keeps the sum at 1 to the last bit we can.
    [(1.0 - b - c).max(0.0), b, c]
}

/// Caller-owned output of [`interpolate`]: every render hair's vertices
/// (positions relative to the guides' `Strands::origin`, and unit tangents),
/// in group layout: vertex `r` of group `g` is `positions[g * R + r]`, lane
/// `l` = hair `l` of that group. Sized once for the largest level.
#[derive(Clone, Debug)]
pub struct RenderHairs {
    groups: usize,
    pub(crate) verts: usize,
    capacity: usize,
    pub(crate) positions: Vec<Vec3Lanes>,
    pub(crate) tangents: Vec<Vec3Lanes>,
    pub(crate) written: Vec<bool>,
    has_tangents: bool,
}

impl RenderHairs {
    /// A buffer for the hairs of `interpolation`, large enough for `guides`
    /// at its maximum segments per span.
    pub fn new(interpolation: &Interpolation, guides: &RefinedGuides) -> RenderHairs {
        let max_verts = crate::bspline::refined_len(
            guides.control_verts_per_strand(),
            guides.max_segments_per_span(),
        );
        RenderHairs::with_capacity(interpolation.group_count(), max_verts)
    }

    /// A buffer for `groups` groups of up to `max_verts_per_hair` vertices.
    ///
    /// # Panics
    ///
    /// If `groups * max_verts_per_hair` overflows or the buffers exceed
    /// `isize::MAX` bytes (as `Vec::with_capacity` does).
    pub fn with_capacity(groups: usize, max_verts_per_hair: usize) -> RenderHairs {
        let capacity = groups
            .checked_mul(max_verts_per_hair)
            .expect("RenderHairs capacity overflows usize");
        RenderHairs {
            groups,
            verts: 0,
            capacity,
            positions: vec![Vec3Lanes::ZERO; capacity],
            tangents: vec![Vec3Lanes::ZERO; capacity],
            written: vec![false; groups],
            has_tangents: false,
        }
    }

    /// `Vec3Lanes` entries per output array: `groups * verts_per_hair`.
    pub fn buffer_len(groups: usize, verts_per_hair: usize) -> usize {
        groups * verts_per_hair
    }

    /// Number of hair groups (up to eight hairs of one triangle each).
    pub fn group_count(&self) -> usize {
        self.groups
    }

    /// Vertices per render hair written by the last [`interpolate`].
    pub fn verts_per_hair(&self) -> usize {
        self.verts
    }

    /// Whether the last interpolation wrote group `g` (false: culled, past
    /// the drawn prefix, or its guides were not refined).
    pub fn is_group_written(&self, g: usize) -> bool {
        self.written.get(g).copied().unwrap_or(false)
    }

    /// Whether the last pass wrote tangents ([`interpolate`]) or not
    /// ([`interpolate_positions`]).
    pub fn has_tangents(&self) -> bool {
        self.has_tangents
    }

    /// Group `g`'s positions, `R` entries of eight hairs; empty for a
    /// group past the end.
    pub fn group_positions(&self, g: usize) -> &[Vec3Lanes] {
        crate::refine_batch::block_slice(&self.positions, g, self.verts)
    }

    /// Group `g`'s unit tangents, `R` entries of eight hairs; empty for a
    /// group past the end.
    pub fn group_tangents(&self, g: usize) -> &[Vec3Lanes] {
        crate::refine_batch::block_slice(&self.tangents, g, self.verts)
    }

    /// [`RenderHairs::position`], or `None` for a vertex that does not
    /// exist.
    pub fn get_position(&self, g: usize, lane: usize, r: usize) -> Option<Vec3> {
        (g < self.groups && lane < LANES && r < self.verts).then(|| self.position(g, lane, r))
    }

    /// [`RenderHairs::tangent`], or `None` for a vertex that does not exist.
    pub fn get_tangent(&self, g: usize, lane: usize, r: usize) -> Option<Vec3> {
        (g < self.groups && lane < LANES && r < self.verts).then(|| self.tangent(g, lane, r))
    }

    /// Vertex `r` of hair `lane` of group `g`.
    ///
    /// # Panics
    ///
    /// If `g >= group_count()`, `lane >= LANES` or `r >= verts_per_hair()`
    /// (as slice indexing does).
    pub fn position(&self, g: usize, lane: usize, r: usize) -> Vec3 {
        self.check_vertex(g, lane, r);
        self.positions[g * self.verts + r].lane(lane)
    }

    /// Unit tangent at vertex `r` of hair `lane` of group `g`.
    ///
    /// # Panics
    ///
    /// If `g >= group_count()`, `lane >= LANES` or `r >= verts_per_hair()`
    /// (as slice indexing does).
    pub fn tangent(&self, g: usize, lane: usize, r: usize) -> Vec3 {
        self.check_vertex(g, lane, r);
        self.tangents[g * self.verts + r].lane(lane)
    }

    /// Panics unless vertex `r` of lane `lane` of group `g` exists (an `r`
    /// past the end would otherwise read the next group's vertices).
    fn check_vertex(&self, g: usize, lane: usize, r: usize) {
        assert!(
            g < self.groups && lane < LANES && r < self.verts,
            "render vertex ({g}, {lane}, {r}) out of range: {} groups of {} vertices",
            self.groups,
            self.verts
        );
    }

    /// Prepares for a pass: checks that the buffer takes it (nothing is
    /// marked written otherwise), then marks every group unwritten.
    pub(crate) fn begin(
        &mut self,
        interpolation: &Interpolation,
        guides: &RefinedGuides,
        with_tangents: bool,
    ) -> Result<(), Error> {
        if interpolation.group_count() != self.groups {
            return Err(Error::CountMismatch {
                what: "hair groups (RenderHairs made for another Interpolation)",
                expected: interpolation.group_count(),
                got: self.groups,
            });
        }
        if interpolation.guide_count() != guides.strand_count() {
            return Err(Error::CountMismatch {
                what: "guide strands (RefinedGuides made for another set than the Interpolation)",
                expected: interpolation.guide_count(),
                got: guides.strand_count(),
            });
        }
        let verts = guides.verts_per_strand();
        let needed = self.groups.saturating_mul(verts);
        if needed > self.capacity {
            return Err(Error::BufferTooSmall {
                needed,
                got: self.capacity,
            });
        }
        self.has_tangents = with_tangents;
        self.written.iter_mut().for_each(|w| *w = false);
        self.verts = verts;
        Ok(())
    }
}

/// Whether group `g` is drawn this frame and its guides hold fresh data.
pub(crate) fn group_drawn(
    g: usize,
    group: &HairGroup,
    groups_drawn: usize,
    visibility: Option<&Visibility>,
    guides: &RefinedGuides,
) -> bool {
    g < groups_drawn
        && visibility.is_none_or(|v| v.group_visible(g))
        && group
            .guides
            .iter()
            .all(|&s| guides.is_block_refined(s as usize / LANES))
}

/// Writes every drawn render hair's vertices `b_A A + b_B B + b_C C` (and
/// the normalised blend of the guides' tangents) from the refined guides into
/// `out` (SIMD path: eight hairs of one group per instruction, each guide
/// vertex loaded once as a broadcast).
///
/// Only the first `groups_drawn` groups (the distance-LOD prefix) that
/// `visibility` (if given) marks visible and whose guide blocks were refined
/// are written. Returns the number of groups written. Allocates nothing.
///
/// # Errors
///
/// Nothing is written (and `out` keeps its last pass) on:
/// - [`Error::CountMismatch`]: `out` was made for an interpolation with
///   another group count, or `guides` holds another number of strands than
///   `interpolation` indexes;
/// - [`Error::BufferTooSmall`]: `out` cannot hold the hairs at the guides'
///   current level (it was made for a lower maximum level), `needed` and
///   `got` in `Vec3Lanes` entries.
pub fn interpolate(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
) -> Result<usize, Error> {
    interpolate_groups(interpolation, guides, visibility, groups_drawn, out, true)
}

/// [`interpolate`] without tangents: positions only, half the memory
/// traffic (for renderers that derive tangents from neighbouring vertices,
/// as [`crate::write_render_vertices`] then does). Scalar twin:
/// [`crate::scalar::interpolate_positions`].
///
/// # Errors
///
/// As [`interpolate`].
pub fn interpolate_positions(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
) -> Result<usize, Error> {
    interpolate_groups(interpolation, guides, visibility, groups_drawn, out, false)
}

fn interpolate_groups(
    interpolation: &Interpolation,
    guides: &RefinedGuides,
    visibility: Option<&Visibility>,
    groups_drawn: usize,
    out: &mut RenderHairs,
    with_tangents: bool,
) -> Result<usize, Error> {
    out.begin(interpolation, guides, with_tangents)?;
    let r_len = out.verts;
    let mut count = 0;
    for (g, group) in interpolation.groups.iter().enumerate() {
        // 1. Skip the groups not drawn.
        if !group_drawn(g, group, groups_drawn, visibility, guides) {
            continue;
        }
        out.written[g] = true;
        count += 1;
        let [wa, wb, wc] = interpolation.weights[g];
        let [(ba, la), (bb, lb), (bc, lc)] = group
            .guides
            .map(|s| (s as usize / LANES, s as usize % LANES));
        // 2. Positions.
        let rows = g * r_len..(g + 1) * r_len;
        let (pa, pb, pc) = (
            guides.block_positions(ba),
            guides.block_positions(bb),
            guides.block_positions(bc),
        );
        for (((p, a), b), c) in out.positions[rows.clone()]
            .iter_mut()
            .zip(pa)
            .zip(pb)
            .zip(pc)
        {
            *p = blend_simd(wa, wb, wc, a, la, b, lb, c, lc);
        }
        // 3. Tangents.
        if with_tangents {
            let (ta, tb, tc) = (
                guides.block_tangents(ba),
                guides.block_tangents(bb),
                guides.block_tangents(bc),
            );
            for (((t, a), b), c) in out.tangents[rows].iter_mut().zip(ta).zip(tb).zip(tc) {
                *t = unit_or_y_simd(blend_simd(wa, wb, wc, a, la, b, lb, c, lc));
            }
        }
    }
    Ok(count)
}

/// `wa A + wb B + wc C` with A, B, C broadcast from one lane each:
/// [`blend`] on each coordinate.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn blend_simd(
    wa: F32Lanes,
    wb: F32Lanes,
    wc: F32Lanes,
    a: &Vec3Lanes,
    la: usize,
    b: &Vec3Lanes,
    lb: usize,
    c: &Vec3Lanes,
    lc: usize,
) -> Vec3Lanes {
    let s = |v: &F32Lanes, l: usize| F32Lanes::splat(v.as_array()[l]);
    let w = [wa, wb, wc];
    Vec3Lanes {
        x: blend(w, s(&a.x, la), s(&b.x, lb), s(&c.x, lc)),
        y: blend(w, s(&a.y, la), s(&b.y, lb), s(&c.y, lc)),
        z: blend(w, s(&a.z, la), s(&b.z, lb), s(&c.z, lc)),
    }
}

/// `wa a + wb b + wc c`, fused multiply-adds left to right: one body for a
/// coordinate of one hair (`f32`, the scalar twin) and of eight (`F32Lanes`).
#[inline(always)]
pub(crate) fn blend<L: Lane>(w: [L; 3], a: L, b: L, c: L) -> L {
    let [wa, wb, wc] = w;
    wc.mul_add(c, wb.mul_add(b, wa * a))
}

impl Interpolation {
    /// Whether group `g` is drawn this frame: inside the distance-LOD prefix
    /// of `groups_drawn` groups, visible in `visibility` (if given), and its
    /// three guides' blocks refined in `guides` (step 1 of [`interpolate`]).
    pub fn is_group_drawn(
        &self,
        g: usize,
        groups_drawn: usize,
        visibility: Option<&Visibility>,
        guides: &RefinedGuides,
    ) -> bool {
        self.groups
            .get(g)
            .is_some_and(|group| group_drawn(g, group, groups_drawn, visibility, guides))
    }

    /// The blend of group `g` over `guides`, for passes that interpolate one
    /// group at a time and use its vertices at once (a fused prepare pass:
    /// the group's hairs stay in registers and L1 instead of a frame-sized
    /// [`RenderHairs`]). `None` if `g` is out of range or a guide does not
    /// fit `guides`. The rows are the same numbers [`interpolate`] writes.
    /// The group fills the first [`GROUP_LANES`] lanes; in a 16-lane build
    /// the others repeat it and hold no hair (see
    /// [`Interpolation::groups_blend`] to fill them).
    pub fn group_blend<'a>(&self, guides: &'a RefinedGuides, g: usize) -> Option<GroupBlend<'a>> {
        self.groups_blend(guides, &[g])
    }

    /// The blend of up to [`GROUPS_PER_BLOCK`] groups in one block's lanes:
    /// group `groups[k]` in lanes `8 k .. 8 k + 8` (its hairs first, then
    /// its last hair repeated), so that a 16-lane build interpolates two
    /// groups per instruction and an 8-lane build one, each lane the same
    /// numbers as [`Interpolation::group_blend`] of its group. Slots past
    /// `groups.len()` repeat the first group and hold no hair. `None` if
    /// `groups` is empty or longer than [`GROUPS_PER_BLOCK`], a group is out
    /// of range, or a guide does not fit `guides`.
    pub fn groups_blend<'a>(
        &self,
        guides: &'a RefinedGuides,
        groups: &[usize],
    ) -> Option<GroupBlend<'a>> {
        if groups.is_empty()
            || groups.len() > GROUPS_PER_BLOCK
            || self.guide_count != guides.strand_count()
        {
            return None;
        }
        let mut slots = [None; GROUPS_PER_BLOCK];
        // The first group's weights, padding lanes included (an empty slot
        // keeps them, so `group_blend` has `interpolate`'s padding); each
        // further group's eight lanes in its slot.
        let mut weights = self.weights.get(groups[0])?.map(groups_of);
        for (k, &g) in groups.iter().enumerate() {
            let group = self.groups.get(g)?;
            let blocks = group.guides.map(|s| s as usize / LANES);
            if blocks.iter().any(|&b| b >= guides.block_count()) {
                return None;
            }
            for (w, gw) in weights.iter_mut().zip(&self.weights[g]) {
                w[k] = groups_of(*gw)[0];
            }
            slots[k] = Some(BlendSlot {
                lanes: group.guides.map(|s| s as usize % LANES),
                positions: blocks.map(|b| guides.block_positions(b)),
                tangents: blocks.map(|b| guides.block_tangents(b)),
                hairs: group.hairs as usize,
            });
        }
        let first = slots[0]?;
        Some(GroupBlend {
            weights: weights.map(from_groups),
            slots: slots.map(|s| s.unwrap_or(BlendSlot { hairs: 0, ..first })),
        })
    }
}

/// One group of a [`GroupBlend`]: its guides' lanes and rows, and its hairs.
#[derive(Clone, Copy, Debug)]
struct BlendSlot<'a> {
    lanes: [usize; 3],
    positions: [&'a [Vec3Lanes]; 3],
    tangents: [&'a [Vec3Lanes]; 3],
    hairs: usize,
}

/// Interpolation of up to [`GROUPS_PER_BLOCK`] hair groups, row by row (see
/// [`Interpolation::group_blend`] and [`Interpolation::groups_blend`]):
/// `position_simd(r)` is vertex `r` of the block's lanes, `P = b_A A + b_B B
/// + b_C C` (step 2 of [`interpolate`]) with each group's guides broadcast
/// to its eight lanes, `tangent_simd(r)` the normalised blend of the guides'
/// tangents (step 3). The scalar twins `position(lane, r)` and
/// `tangent(lane, r)` run the same blend on one hair (the scalar
/// interpolation's arithmetic): positions agree bit for bit, tangents to
/// a few ulp (rsqrt + Newton against `1 / sqrt`).
#[derive(Clone, Copy, Debug)]
pub struct GroupBlend<'a> {
    weights: [F32Lanes; 3],
    slots: [BlendSlot<'a>; GROUPS_PER_BLOCK],
}

impl GroupBlend<'_> {
    /// Vertices per hair (the refined guides' `R`).
    pub fn verts(&self) -> usize {
        self.slots[0].positions[0].len()
    }

    /// Real hairs in all the blend's groups.
    pub fn hairs(&self) -> usize {
        self.slots.iter().map(|s| s.hairs.min(GROUP_LANES)).sum()
    }

    /// Real hairs of the group in lanes `8 k .. 8 k + 8` (0 for an empty
    /// slot or `k >= GROUPS_PER_BLOCK`).
    pub fn group_hairs(&self, k: usize) -> usize {
        self.slots.get(k).map_or(0, |s| s.hairs.min(GROUP_LANES))
    }

    /// The lanes holding a real hair, as bits (bit `l` for lane `l`): the
    /// first `group_hairs(k)` lanes of each group of eight.
    pub fn hair_bits(&self) -> u32 {
        self.slots
            .iter()
            .enumerate()
            .map(|(k, s)| ((1u32 << s.hairs.min(GROUP_LANES)) - 1) << (k * GROUP_LANES))
            .fold(0, |a, b| a | b)
    }

    /// Vertex `r` of the block's lanes.
    ///
    /// # Panics
    ///
    /// If `r >= verts()` (as slice indexing does).
    #[inline(always)]
    pub fn position_simd(&self, r: usize) -> Vec3Lanes {
        blend_rows(
            self.weights,
            self.broadcast(0, r, false),
            self.broadcast(1, r, false),
            self.broadcast(2, r, false),
        )
    }

    /// Unit tangent at vertex `r` of the block's lanes (or `+Y`).
    ///
    /// # Panics
    ///
    /// If `r >= verts()` (as slice indexing does).
    #[inline(always)]
    pub fn tangent_simd(&self, r: usize) -> Vec3Lanes {
        unit_or_y_simd(blend_rows(
            self.weights,
            self.broadcast(0, r, true),
            self.broadcast(1, r, true),
            self.broadcast(2, r, true),
        ))
    }

    /// Guide `i`'s (0, 1, 2: A, B, C) vertex `r` (or tangent) of each
    /// group, broadcast to the group's eight lanes. Plain loops over the
    /// groups: this runs per row of the prepare pass and must inline.
    #[inline(always)]
    fn broadcast(&self, i: usize, r: usize, tangent: bool) -> Vec3Lanes {
        let mut x = [F32Group::ZERO; GROUPS_PER_BLOCK];
        let mut y = x;
        let mut z = x;
        for k in 0..GROUPS_PER_BLOCK {
            let slot = &self.slots[k];
            let rows = if tangent {
                slot.tangents[i]
            } else {
                slot.positions[i]
            };
            let (v, l) = (&rows[r], slot.lanes[i]);
            x[k] = F32Group::splat(v.x.as_array()[l]);
            y[k] = F32Group::splat(v.y.as_array()[l]);
            z[k] = F32Group::splat(v.z.as_array()[l]);
        }
        Vec3Lanes {
            x: from_groups(x),
            y: from_groups(y),
            z: from_groups(z),
        }
    }

    /// Scalar twin of [`GroupBlend::position_simd`] for one lane (`lane` is
    /// taken modulo [`LANES`]).
    ///
    /// # Panics
    ///
    /// If `r >= verts()` (as slice indexing does).
    pub fn position(&self, lane: usize, r: usize) -> Vec3 {
        let (w, slot) = self.lane_weights(lane);
        blend_lanes(w, slot.positions.map(|p| p[r]), slot.lanes)
    }

    /// Scalar twin of [`GroupBlend::tangent_simd`] for one lane (`lane` is
    /// taken modulo [`LANES`]).
    ///
    /// # Panics
    ///
    /// If `r >= verts()` (as slice indexing does).
    pub fn tangent(&self, lane: usize, r: usize) -> Vec3 {
        let (w, slot) = self.lane_weights(lane);
        crate::scalar::unit_or_y(blend_lanes(w, slot.tangents.map(|t| t[r]), slot.lanes))
    }

    /// The weights of lane `lane % LANES` and its group.
    fn lane_weights(&self, lane: usize) -> ([f32; 3], &BlendSlot<'_>) {
        let lane = lane % LANES;
        (
            self.weights.map(|w| w.as_array()[lane]),
            &self.slots[lane / GROUP_LANES],
        )
    }

    /// [`GroupBlend::position`], or `None` for `r >= verts()`.
    pub fn get_position(&self, lane: usize, r: usize) -> Option<Vec3> {
        (r < self.verts()).then(|| self.position(lane, r))
    }

    /// [`GroupBlend::tangent`], or `None` for `r >= verts()`.
    pub fn get_tangent(&self, lane: usize, r: usize) -> Option<Vec3> {
        (r < self.verts()).then(|| self.tangent(lane, r))
    }
}

/// `wa A + wb B + wc C` of already broadcast guide rows: [`blend`] on each
/// coordinate.
#[inline(always)]
fn blend_rows(w: [F32Lanes; 3], a: Vec3Lanes, b: Vec3Lanes, c: Vec3Lanes) -> Vec3Lanes {
    Vec3Lanes {
        x: blend(w, a.x, b.x, c.x),
        y: blend(w, a.y, b.y, c.y),
        z: blend(w, a.z, b.z, c.z),
    }
}

/// [`blend`] per coordinate of lane `lanes[i]` of `v[i]`, one hair.
fn blend_lanes(w: [f32; 3], v: [Vec3Lanes; 3], lanes: [usize; 3]) -> Vec3 {
    let [a, b, c] = [0, 1, 2].map(|i| v[i].lane(lanes[i]));
    Vec3::new(
        blend(w, a.x, b.x, c.x),
        blend(w, a.y, b.y, c.y),
        blend(w, a.z, b.z, c.z),
    )
}
