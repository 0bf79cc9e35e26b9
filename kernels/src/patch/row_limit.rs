//! The row strain limit: Provot's deformation limit along each row, in
//! Follow-The-Leader order from a root column outward.
//!
//! Columns have a natural leader (the particle above, toward the pins), rows
//! do not. A row is limited from its root column `m` outward (the pinned
//! particle nearest the middle column, as on a flag's pole, or the middle
//! column `cols / 2` when the row has no pin, as on a ribbon hung by row 0):
//! columns `m + 1, m + 2, ...` are each pulled toward their left neighbour,
//! columns `m - 1, m - 2, ...` toward their right one, until
//! `|x_c - x_leader| <= (1 + max_stretch) l` (Provot 1995; Muller et al.
//! 2012's FTL order, which needs no second pass because a leader is final
//! before its follower moves). Pinned particles are not moved. A particle
//! that the column limit has just placed (one whose shortest path to the
//! pins goes through the particle above) is moved to the nearest point that
//! satisfies both limits, so the row limit does not undo the column's.
//!
//! The chain is serial across lanes (each column follows the one just
//! moved), so there is nothing for eight lanes to do together: the SIMD
//! step and the scalar twin both call this one function, lane by lane, and
//! so agree bit for bit. It runs once per row, in the last round of the
//! alternation with the collisions, after the column limit and before the
//! max distance and the push-out. (Running it in both rounds measured 2.1 %
//! worst stretch instead of 2.3 % over the stability matrix, for 22 % more
//! instructions per step.)

use super::grid::Patch;
use crate::lanes::{inv_sqrt, LANES};
use glam::Vec3;

/// Limits the horizontal edges of row `r` to `factor` times their rest
/// length, from the row's root column outward.
pub(crate) fn limit_row(p: &mut Patch, r: usize, factor: f32) {
    let (rows, cols) = (p.rows, p.cols);
    let root = p.row_root[r];
    let slot = |c: usize| ((c / LANES) * rows + r, c % LANES);
    // Rest length of edge (c, c + 1): the colour-(c mod 2) pair data,
    // stored in column c's slot.
    let rest = |p: &Patch, c: usize| {
        let (i, l) = slot(c);
        p.horiz[c % 2].rest[i].as_array()[l]
    };
    let (i, l) = slot(root);
    let start = p.pos[i].lane(l);
    let mut lead = start;
    for c in root + 1..cols {
        let limit = rest(p, c - 1) * factor;
        lead = follow(p, slot(c), lead, limit, factor);
    }
    lead = start;
    for c in (0..root).rev() {
        let limit = rest(p, c) * factor;
        lead = follow(p, slot(c), lead, limit, factor);
    }
}

/// Moves the free particle in `slot` to the nearest point within `limit` of
/// `lead` (its row leader's position) that stays within the column limit
/// of its parent (the particle above, when the particle's shortest path to
/// the pins goes through it): the projection onto the intersection of the
/// two balls. When the balls do not meet, the column wins (the point of the
/// parent's ball nearest the leader), as columns carry the weight. Returns
/// the particle's position (the next leader).
#[inline]
fn follow(p: &mut Patch, (i, l): (usize, usize), lead: Vec3, limit: f32, factor: f32) -> Vec3 {
    let x = p.pos[i].lane(l);
    if p.inv_mass[i].as_array()[l] <= 0.0 {
        return x;
    }
    let d = x - lead;
    let d2 = dot(d, d);
    if d2 <= limit * limit {
        return x;
    }
    let on_row_ball = lead + d * (limit * inv_sqrt(d2));
    let moved = if p.parent_up[i].as_array()[l].to_bits() == 0 {
        on_row_ball
    } else {
        // parent_up is never set in row 0, so `i - 1` is the row above.
        let parent = p.pos[i - 1].lane(l);
        let reach = p.vert_rest[i - 1].as_array()[l] * factor;
        let e = on_row_ball - parent;
        if dot(e, e) <= reach * reach {
            on_row_ball
        } else {
            nearest_on_lens(x, parent, reach, lead, limit)
        }
    };
    p.pos[i].set_lane(l, moved);
    moved
}

/// The point of `ball(c1, r1) ∩ ball(c2, r2)` nearest `x`, for `x` outside
/// the second ball whose projection onto it leaves the first: the projection
/// onto the first ball if that lies in the second, else a point of the
/// circle where the two spheres meet (centre `c1 + a n`, radius
/// `sqrt(r1^2 - a^2)`, `a = (d^2 + r1^2 - r2^2) / 2d`, `n` the unit vector
/// from `c1` to `c2`, `d` their distance). If the balls do not meet, the
/// point of the first ball nearest `c2`.
fn nearest_on_lens(x: Vec3, c1: Vec3, r1: f32, c2: Vec3, r2: f32) -> Vec3 {
    let between = c2 - c1;
    let d2 = dot(between, between).max(1e-14);
    let inv_d = inv_sqrt(d2);
    let d = d2 * inv_d;
    let n = between * inv_d;
    if d >= r1 + r2 {
        return c1 + n * r1;
    }
    // Outside the first ball too: its projection onto the first ball, if
    // that lies in the second.
    let from1 = x - c1;
    let e2 = dot(from1, from1);
    if e2 > r1 * r1 {
        let on1 = c1 + from1 * (r1 * inv_sqrt(e2));
        let f = on1 - c2;
        if dot(f, f) <= r2 * r2 {
            return on1;
        }
    }
    let a = (d2 + r1 * r1 - r2 * r2) * (0.5 * inv_d);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let centre = c1 + n * a;
    let off = x - centre;
    let t = off - n * dot(off, n);
    let t2 = dot(t, t);
    if t2 < 1e-20 {
        return centre;
    }
    centre + t * (h * inv_sqrt(t2))
}

#[inline]
fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// The lens point lies in both balls, and no point of the intersection
    /// found by brute force (rejection sampling) is nearer to `x`.
    #[test]
    fn nearest_on_lens_is_the_nearest_point_of_both_balls() {
        let mut rng = SplitMix64::new(7);
        let mut checked = 0;
        for _ in 0..200 {
            let c1 = Vec3::ZERO;
            let r1 = rng.range(0.5, 1.5);
            let c2 = rng.unit_vector() * rng.range(0.2, 2.0);
            let r2 = rng.range(0.5, 1.5);
            let x = rng.unit_vector() * rng.range(0.0, 3.0);
            let in_both = |p: Vec3| p.distance(c1) <= r1 * 1.0001 && p.distance(c2) <= r2 * 1.0001;
            // The case the function is called for: outside ball 2, and its
            // projection onto ball 2 leaves ball 1.
            let on2 = c2 + (x - c2).normalize() * r2;
            if x.distance(c2) <= r2 || on2.distance(c1) <= r1 || c1.distance(c2) >= r1 + r2 {
                continue;
            }
            checked += 1;
            let y = nearest_on_lens(x, c1, r1, c2, r2);
            assert!(in_both(y), "{y} outside a ball");
            for _ in 0..2000 {
                let q = c1 + rng.unit_vector() * (r1 * rng.next_f32().cbrt());
                if in_both(q) {
                    assert!(
                        q.distance(x) >= y.distance(x) - 1e-4,
                        "{q} is nearer to {x} than {y}"
                    );
                }
            }
        }
        assert!(checked > 20, "only {checked} configurations exercised");
    }

    /// Balls that do not meet: the column (first ball) wins.
    #[test]
    fn disjoint_balls_keep_the_first() {
        let y = nearest_on_lens(
            Vec3::new(5.0, 1.0, 0.0),
            Vec3::ZERO,
            1.0,
            Vec3::new(3.0, 0.0, 0.0),
            1.0,
        );
        assert!(y.distance(Vec3::X) < 1e-6, "{y}");
    }
}
