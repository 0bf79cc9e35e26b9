//! Scalar twin of the broad phase's block box (`crate::collide::broad_phase`).

use crate::collide::broad_phase::Aabb;
use crate::lanes::{Vec3Lanes, LANES};
use glam::Vec3;

/// The box of [`crate::collide::broad_phase::block_aabb`], one lane and one vertex at
/// a time: the lanes `0 .. lanes` are the active ones (the scalar twin).
pub(crate) fn block_aabb(pos: &[Vec3Lanes], lanes: usize) -> Aabb {
    let mut b = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };
    for l in 0..lanes.min(LANES) {
        for p in pos {
            let q = p.lane(l);
            b.min = Vec3::new(b.min.x.min(q.x), b.min.y.min(q.y), b.min.z.min(q.z));
            b.max = Vec3::new(b.max.x.max(q.x), b.max.y.max(q.y), b.max.z.max(q.z));
        }
    }
    b
}

/// The scalar twin of [`crate::collide::broad_phase::block_sweep_aabb`]: the same
/// points in the same arithmetic order, lane by lane (the real lanes of
/// `lanes`).
pub(crate) fn block_sweep_aabb(
    pos: &[Vec3Lanes],
    prev: &[Vec3Lanes],
    g_dt2: Vec3,
    lanes: std::ops::Range<usize>,
) -> Aabb {
    let mut b = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };
    for l in lanes.start..lanes.end.min(LANES) {
        let root_move = pos[0].lane(l) - prev[0].lane(l);
        for (x, p) in pos.iter().zip(prev) {
            let (x, p) = (x.lane(l), p.lane(l));
            let ahead = x + (x - p) + g_dt2 + root_move;
            for q in [x, ahead] {
                b.min = Vec3::new(b.min.x.min(q.x), b.min.y.min(q.y), b.min.z.min(q.z));
                b.max = Vec3::new(b.max.x.max(q.x), b.max.y.max(q.y), b.max.z.max(q.z));
            }
        }
    }
    b
}
