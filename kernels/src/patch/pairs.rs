//! Constraints between neighbouring lanes: partner permutations and the
//! per-lane constraint data of a colour pass.
//!
//! Columns live in lanes, so a horizontal edge `(c, c + s)` (`s = 1`:
//! structural, `s = 2`: bending) joins two lanes. The edges of a row are
//! split into two colours so that no particle appears twice in a pass:
//! colour `k` pairs column `c` with `c + s` where `(c / s) mod 2 = k`, and
//! with `c - s` otherwise. Within a pass every lane then has at most one
//! partner, `partner` is an involution, and each lane can apply its own half
//! of the constraint from the pre-pass positions (a Jacobi update that equals
//! Gauss-Seidel because the pairs are disjoint). The two halves of an edge
//! compute `|delta|^2` from `delta` and `-delta`, which square to the same
//! bits, so they agree exactly with the scalar twin, which visits each edge
//! once and moves both ends.
//!
//! Shear edges pair row `r`, column `c` with row `r + 1`, column
//! `partner(c, 1, k)`: colour 0 covers both diagonals of the quads that start
//! at even columns, colour 1 those at odd columns.

use crate::lanes::{Vec3Lanes, LANES};
use coif_base::lanes::F32Lanes;

/// The partner column of padded column `c` in colour `colour` of stride `s`,
/// or `None` past either end of the padded row (`lanes` columns).
#[inline(always)]
pub(crate) fn partner(c: usize, s: usize, colour: usize, lanes: usize) -> Option<usize> {
    if (c / s) % 2 == colour {
        (c + s < lanes).then_some(c + s)
    } else {
        c.checked_sub(s)
    }
}

/// One kind of lane-pair constraint in one colour, per particle (indexed like
/// positions): rest distance to the partner, the particle's mass share
/// `w / (w + w_partner)`, and the partner's inverse mass. All zero where the
/// particle has no partner (grid edge, padding) or both ends are pinned.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairSet {
    pub rest: Vec<F32Lanes>,
    pub share: Vec<F32Lanes>,
    pub partner_w: Vec<F32Lanes>,
}

impl PairSet {
    pub(crate) fn zeros(n: usize) -> Self {
        PairSet {
            rest: vec![F32Lanes::ZERO; n],
            share: vec![F32Lanes::ZERO; n],
            partner_w: vec![F32Lanes::ZERO; n],
        }
    }
}

/// Mass share of a particle with inverse mass `w` in a pair with `other`.
pub(crate) fn mass_share(w: f32, other: f32) -> f32 {
    if w + other > 0.0 {
        w / (w + other)
    } else {
        0.0
    }
}

/// One block of a row's partner positions for stride `S`, colour `C`:
/// lane `l` receives the position of its partner column, taken from the
/// block itself or its left/right neighbour; lanes without a partner receive
/// their own position. The lane pattern is a compile-time constant.
#[inline(always)]
fn gather_block<const S: usize, const C: usize>(
    left: Option<Vec3Lanes>,
    cur: Vec3Lanes,
    right: Option<Vec3Lanes>,
) -> Vec3Lanes {
    #[inline(always)]
    fn axis<const S: usize, const C: usize>(
        left: Option<F32Lanes>,
        cur: F32Lanes,
        right: Option<F32Lanes>,
    ) -> F32Lanes {
        let c = cur.to_array();
        let l = left.map(|v| v.to_array());
        let r = right.map(|v| v.to_array());
        F32Lanes::new(std::array::from_fn(|lane| {
            if (lane / S) % 2 == C {
                let src = lane + S;
                if src < LANES {
                    c[src]
                } else {
                    r.map_or(c[lane], |r| r[src - LANES])
                }
            } else if lane >= S {
                c[lane - S]
            } else {
                l.map_or(c[lane], |l| l[lane + LANES - S])
            }
        }))
    }
    Vec3Lanes {
        x: axis::<S, C>(left.map(|v| v.x), cur.x, right.map(|v| v.x)),
        y: axis::<S, C>(left.map(|v| v.y), cur.y, right.map(|v| v.y)),
        z: axis::<S, C>(left.map(|v| v.z), cur.z, right.map(|v| v.z)),
    }
}

/// Writes into `out[b]` (one entry per column block) the partner positions
/// of row `r` of `pos` (block-major, `rows` particles per block).
pub(crate) fn gather_row(
    pos: &[Vec3Lanes],
    rows: usize,
    r: usize,
    stride: usize,
    colour: usize,
    out: &mut [Vec3Lanes],
) {
    match (stride, colour) {
        (1, 0) => gather_row_with::<1, 0>(pos, rows, r, out),
        (1, _) => gather_row_with::<1, 1>(pos, rows, r, out),
        (_, 0) => gather_row_with::<2, 0>(pos, rows, r, out),
        _ => gather_row_with::<2, 1>(pos, rows, r, out),
    }
}

#[inline(always)]
fn gather_row_with<const S: usize, const C: usize>(
    pos: &[Vec3Lanes],
    rows: usize,
    r: usize,
    out: &mut [Vec3Lanes],
) {
    let blocks = out.len();
    for (b, slot) in out.iter_mut().enumerate() {
        let left = (b > 0).then(|| pos[(b - 1) * rows + r]);
        let right = (b + 1 < blocks).then(|| pos[(b + 1) * rows + r]);
        *slot = gather_block::<S, C>(left, pos[b * rows + r], right);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn gather_matches_the_partner_rule_and_is_an_involution() {
        let (rows, blocks) = (2, 3);
        let lanes = blocks * LANES;
        let mut pos = vec![Vec3Lanes::ZERO; rows * blocks];
        for b in 0..blocks {
            for r in 0..rows {
                for l in 0..LANES {
                    let c = b * LANES + l;
                    pos[b * rows + r].set_lane(l, Vec3::new(c as f32, r as f32, -(c as f32)));
                }
            }
        }
        let mut out = vec![Vec3Lanes::ZERO; blocks];
        for s in [1, 2] {
            for colour in [0, 1] {
                gather_row(&pos, rows, 1, s, colour, &mut out);
                for c in 0..lanes {
                    let got = out[c / LANES].lane(c % LANES);
                    let want = partner(c, s, colour, lanes).unwrap_or(c);
                    assert_eq!(got, Vec3::new(want as f32, 1.0, -(want as f32)));
                    if let Some(p) = partner(c, s, colour, lanes) {
                        assert_eq!(partner(p, s, colour, lanes), Some(c));
                        assert_eq!(p.abs_diff(c), s);
                    }
                }
            }
        }
    }
}
