//! How steep the built grid is: per block of the far map, a bound of the
//! looked-up field's slope, which the strand step's lookup cache relies on
//! (`SdfLane::clear_radius2`).
//!
//! The exact signed distance changes by at most the distance moved. The
//! built grid does not everywhere: its exact region is, but the propagated
//! values beyond it are distances to *some* triangle (never below the
//! nearest one, sometimes above it), and the sign by winding number flips
//! far from the surface across a hole (the bust's open chest), where the
//! grid jumps from `+d` to `-d` between two nodes. Measured on the bust at
//! 4 mm: 1 % of the axis edges differ by more than a cell, the worst by 38
//! cells. So no global bound holds, and none is enforced (a pass that
//! scaled opposite-sign jumps down to a cell was tried: it pulled values
//! near the box boundary below half the true distance, and the
//! outside-the-box tests of `tests/sdf.rs` failed); the bound is local.
//!
//! **[`block_slopes`]**: per block of the far map (`FAR_BLOCK^3` cells), the
//! largest axis-edge difference `R` (in cells) over the block grown by one
//! whole block on every side (clamped to the grid). A trilinear cell whose
//! edges differ by at most `R` cells has every partial derivative at most
//! `R` (`dv/dx` is a bilinear blend of the cell's four x-edge differences),
//! so the interpolant's slope is at most `sqrt(3) R`; outside the box the
//! lookup adds the distance to the box (`lookup.rs`), whose gradient is a
//! unit vector along the clamped axes, where the trilinear term is
//! constant: the slope there is at most `sqrt(3 R^2 + 1)`
//! ([`slope_bound`]). The value is continuous, so along any path that stays
//! (after clamping to the box, which only shortens it) in the grown block
//! it changes by at most that bound times the path's length.

use glam::UVec3;

/// The slope bound of a region whose axis edges differ by at most `r`
/// cells: `sqrt(3 r^2 + 1)` (per metre moved; the module's argument).
pub(crate) fn slope_bound(r: f32) -> f32 {
    (3.0 * r * r + 1.0).sqrt()
}

/// Per block of `block` cells a side (`blocks` of them per axis, x
/// fastest): the largest axis-edge difference, in cells, over every edge
/// with both ends in the block or in one of its 26 neighbours (the block
/// grown by one block, clamped to the grid). NaN edges count as infinite.
pub(crate) fn block_slopes(
    values: &[f32],
    dims: UVec3,
    cell: f32,
    block: u32,
    blocks: UVec3,
) -> Vec<f32> {
    let (nx, ny, nz) = (dims.x as usize, dims.y as usize, dims.z as usize);
    let plane = nx * ny;
    // Per node: the largest difference along its edges toward +x, +y, +z,
    // a row at a time (the inner loops vectorise).
    let mut node = vec![0.0f32; values.len()];
    let edge = |a: f32, b: f32| {
        let d = (a - b).abs();
        if d.is_nan() {
            f32::INFINITY
        } else {
            d
        }
    };
    for z in 0..nz {
        for y in 0..ny {
            let row = (z * ny + y) * nx;
            let here = &values[row..row + nx];
            let out = &mut node[row..row + nx];
            for (o, w) in out.iter_mut().zip(here.windows(2)) {
                *o = edge(w[0], w[1]);
            }
            for next in [
                (y + 1 < ny).then_some(row + nx),
                (z + 1 < nz).then_some(row + plane),
            ]
            .into_iter()
            .flatten()
            {
                let there = &values[next..next + nx];
                for (o, (&a, &b)) in out.iter_mut().zip(here.iter().zip(there)) {
                    *o = o.max(edge(a, b));
                }
            }
        }
    }
    // Per block: the nodes of its closed range `[b block, (b + 1) block]`
    // (every edge with both ends in the range starts at one of them; the
    // edges leaving it at the upper faces only add to the bound).
    let (bx, by, bz) = (blocks.x as usize, blocks.y as usize, blocks.z as usize);
    let b = block as usize;
    let mut own = vec![0.0f32; bx * by * bz];
    for k in 0..bz {
        for j in 0..by {
            for i in 0..bx {
                let mut m = 0.0f32;
                for z in k * b..((k + 1) * b + 1).min(nz) {
                    for y in j * b..((j + 1) * b + 1).min(ny) {
                        let row = (z * ny + y) * nx;
                        let lo = row + i * b;
                        let hi = row + ((i + 1) * b + 1).min(nx);
                        for &e in &node[lo..hi] {
                            m = m.max(e);
                        }
                    }
                }
                own[(k * by + j) * bx + i] = m;
            }
        }
    }
    // Grown by one block: the maximum over the 3 x 3 x 3 neighbours, one
    // axis at a time.
    let mut grown = own;
    for (stride, count) in [(1, bx), (bx, by), (bx * by, bz)] {
        let src = grown.clone();
        for (i, g) in grown.iter_mut().enumerate() {
            let c = (i / stride) % count;
            let mut m = src[i];
            if c > 0 {
                m = m.max(src[i - stride]);
            }
            if c + 1 < count {
                m = m.max(src[i + stride]);
            }
            *g = m;
        }
    }
    // In cells, rounded up a little (the bound must not round below the
    // largest difference).
    let inv = 1.0 / cell * (1.0 + 1.0e-5);
    for g in &mut grown {
        *g *= inv;
    }
    grown
}

#[cfg(test)]
mod tests {
    use super::super::build::FAR_BLOCK;
    use super::super::{Sdf, SdfLane};
    use crate::lanes::V3;
    use coif_base::rng::SplitMix64;
    use coif_testkit::meshes::{icosphere, open_sphere};
    use glam::{UVec3, Vec3};

    /// A closed sphere and one with its cap cut off (across the hole the
    /// sign flips far from the surface: `+d` beside `-d`), 10 cm, 1 cm cells.
    fn fields() -> Vec<Sdf> {
        [icosphere(3, 0.1), open_sphere(3, 0.1, 0.06)]
            .iter()
            .map(|m| Sdf::from_mesh(&m.0, &m.1, 0.01).unwrap())
            .collect()
    }

    /// The slope bound stored for the block of `p` (mesh frame).
    fn slope_at(sdf: &Sdf, p: Vec3) -> f32 {
        1.0 / <f32 as SdfLane>::block_entry(sdf, V3::from_vec3(p)).abs()
    }

    /// By brute force: every block's stored `1 / L` is at most
    /// `1 / sqrt(3 R^2 + 1)`, `R` the largest axis-edge difference (cells)
    /// over the block grown by one block; and the open sphere has edges
    /// far steeper than a cell (so the bound is tested where it matters).
    #[test]
    fn every_block_bounds_the_edges_of_its_grown_block() {
        for (m, sdf) in fields().iter().enumerate() {
            let g = &sdf.grid;
            let dims = g.dims;
            let blocks = (dims - UVec3::ONE) / FAR_BLOCK;
            assert_eq!(blocks * FAR_BLOCK, dims - UVec3::ONE, "whole blocks");
            assert_eq!(g.far.len(), (blocks.x * blocks.y * blocks.z) as usize);
            let value = |x: u32, y: u32, z: u32| sdf.node_value(x, y, z).unwrap();
            let mut steepest = 0.0f32;
            for bz in 0..blocks.z {
                for by in 0..blocks.y {
                    for bx in 0..blocks.x {
                        let b = UVec3::new(bx, by, bz);
                        let lo = (b * FAR_BLOCK).saturating_sub(UVec3::splat(FAR_BLOCK));
                        let hi = ((b + UVec3::splat(2)) * FAR_BLOCK).min(dims - UVec3::ONE);
                        let mut r = 0.0f32;
                        for z in lo.z..=hi.z {
                            for y in lo.y..=hi.y {
                                for x in lo.x..=hi.x {
                                    let v = value(x, y, z);
                                    if x < hi.x {
                                        r = r.max((v - value(x + 1, y, z)).abs());
                                    }
                                    if y < hi.y {
                                        r = r.max((v - value(x, y + 1, z)).abs());
                                    }
                                    if z < hi.z {
                                        r = r.max((v - value(x, y, z + 1)).abs());
                                    }
                                }
                            }
                        }
                        let r = r / g.cell;
                        steepest = steepest.max(r);
                        let i = ((bz * blocks.y + by) * blocks.x + bx) as usize;
                        let l = 1.0 / g.far[i].abs();
                        assert!(
                            l >= (3.0 * r * r + 1.0).sqrt(),
                            "mesh {m} block {b}: L {l} for R {r}"
                        );
                    }
                }
            }
            eprintln!("mesh {m}: steepest edge {steepest} cells");
            if m == 1 {
                assert!(
                    steepest > 4.0,
                    "the open sphere's steepest edge: {steepest}"
                );
            }
        }
    }

    /// Random pairs of points less than a block width apart, in and
    /// around the grid box: the looked-up field changes by at most the
    /// first point's block's `L` times the distance (plus rounding).
    #[test]
    fn the_field_changes_by_at_most_the_slope_bound() {
        let mut rng = SplitMix64::new(7);
        for sdf in fields() {
            let (lo, hi) = sdf.bounds();
            let width = FAR_BLOCK as f32 * sdf.cell();
            let f = |p: Vec3| <f32 as SdfLane>::sample(&sdf, V3::from_vec3(p)).0;
            let mut tight = 0.0f32;
            for k in 0..40_000 {
                let t = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let p = lo - Vec3::splat(0.05) + (hi - lo + Vec3::splat(0.1)) * t;
                let dir = Vec3::new(
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                )
                .normalize_or(Vec3::X);
                // Some moves just under the cap, the rest anywhere below.
                let len = width * if k % 4 == 0 { 0.998 } else { rng.next_f32() };
                let q = p + dir * len;
                let (a, b) = (f(p), f(q));
                let l = slope_at(&sdf, p);
                let bound = l * (q - p).length();
                let rounding = 1.0e-6 + 1.0e-5 * a.abs().max(b.abs());
                assert!(
                    (a - b).abs() <= bound + rounding,
                    "{p} -> {q}: {a} -> {b}, L {l}"
                );
                if bound > 0.0 {
                    tight = tight.max((a - b).abs() / bound);
                }
            }
            eprintln!("largest change over its bound: {tight}");
        }
    }

    /// Every point of a clear ball (`SdfLane::clear_radius2`) looks up at
    /// least the skin's reach, for skins thinner and thicker than a cell,
    /// free and pinned vertices, with the value looked up or the far
    /// clearance in far blocks; and balls are not rare.
    #[test]
    fn no_point_of_a_clear_ball_is_within_the_skin() {
        let mut rng = SplitMix64::new(11);
        for sdf in fields() {
            let (lo, hi) = sdf.bounds();
            let f = |p: Vec3| <f32 as SdfLane>::sample(&sdf, V3::from_vec3(p)).0;
            let mut balls = 0;
            for k in 0..20_000 {
                let t = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let p = lo - Vec3::splat(0.05) + (hi - lo + Vec3::splat(0.1)) * t;
                let skin = [0.0005, 0.002, 0.006][k % 3];
                let off = if k % 7 == 0 { f32::INFINITY } else { 0.0 };
                let pv = V3::from_vec3(p);
                let entry = <f32 as SdfLane>::block_entry(&sdf, pv);
                let far = <f32 as SdfLane>::far(entry, pv) && skin < sdf.far_clearance();
                let d = if far { sdf.far_clearance() } else { f(p) };
                let r2 = <f32 as SdfLane>::clear_radius2(&sdf, pv, d, (d + off) - skin, entry);
                if r2 <= 0.0 {
                    assert!(r2 == -1.0);
                    continue;
                }
                balls += 1;
                let r = r2.sqrt();
                assert!(r <= FAR_BLOCK as f32 * sdf.cell());
                for j in 0..8 {
                    let dir = Vec3::new(
                        rng.next_f32() - 0.5,
                        rng.next_f32() - 0.5,
                        rng.next_f32() - 0.5,
                    )
                    .normalize_or(Vec3::Y);
                    let len = r * if j < 4 { 0.999_999 } else { rng.next_f32() };
                    let q = p + dir * len;
                    assert!(
                        f(q) + off >= skin,
                        "{p} (d {d}, ball {r}) -> {q}: {} below the skin {skin}",
                        f(q)
                    );
                }
            }
            assert!(balls > 5_000, "only {balls} balls");
        }
    }
}
