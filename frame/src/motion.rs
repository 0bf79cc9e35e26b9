//! Head motion: rigid poses of the head about a pivot.

use glam::{Affine3A, Quat, Vec3};
use std::f32::consts::PI;

/// The rigid transform that turns the head by `yaw` (about +y) and then
/// nods it by `pitch` (about +x, positive tips the face down for a head
/// facing +z) about `pivot`, and moves it by `translation`.
pub fn head_pose(pivot: Vec3, yaw: f32, pitch: f32, translation: Vec3) -> Affine3A {
    let rotation = Quat::from_rotation_y(yaw) * Quat::from_rotation_x(pitch);
    Affine3A::from_translation(pivot + translation)
        * Affine3A::from_quat(rotation)
        * Affine3A::from_translation(-pivot)
}

/// The built-in motion at time `t` seconds: a turn to one side and back
/// (0-2 s, 40 degrees), then a nod (2-3 s, 20 degrees), at rest after 3 s.
/// Smooth (C1) throughout.
pub fn turn_and_nod(t: f32, pivot: Vec3) -> Affine3A {
    let yaw = 40f32.to_radians() * bump(t, 0.0, 2.0);
    let pitch = 20f32.to_radians() * bump(t, 2.0, 1.0);
    head_pose(pivot, yaw, pitch, Vec3::ZERO)
}

/// A smooth bump: 0 outside `[start, start + length]`, rising to 1 at its
/// middle and back (`(1 - cos 2 pi s) / 2`), C1.
fn bump(t: f32, start: f32, length: f32) -> f32 {
    let s = (t - start) / length;
    if (0.0..=1.0).contains(&s) {
        0.5 - 0.5 * (2.0 * PI * s).cos()
    } else {
        0.0
    }
}

/// The character's motion at time `t` seconds: a turn of the head (and
/// the bust it rides on) 40 degrees to one side and back, about the
/// vertical through `pivot` (0-2 s), at rest after. Smooth (C1).
pub fn turn(t: f32, pivot: Vec3) -> Affine3A {
    head_pose(
        pivot,
        40f32.to_radians() * bump(t, 0.5, 2.0),
        0.0,
        Vec3::ZERO,
    )
}

/// The air's velocity at the height of [`gust`] in the scenes with a body
/// (m/s: from the front and a little from the side, so that the hair blows
/// back and aside), pulling the hair through [`GUST_DRAG`], with
/// [`GUST_TURBULENCE`].
pub const GUST_WIND: Vec3 = Vec3::new(6.0, 1.0, 0.0);
/// Air drag of the scenes with a body (`SimParams::drag`, per second): a
/// 5 m/s gust pulls the hair at about 0.8 g.
pub const GUST_DRAG: f32 = 2.0;
/// Turbulence of the scenes with a body at the gust's peak
/// (`SimParams::turbulence`, m/s, [`gust_turbulence`]): neighbouring
/// locks move apart. A quarter of [`GUST_WIND`]'s 6.1 m/s, as gusty wind
/// near the ground has.
pub const GUST_TURBULENCE: f32 = 1.5;

/// A gust at time `t` seconds: the air's velocity `peak * bump`, rising
/// from 1.6 s, strongest at 2.3 s, still by 3 s (the wind of
/// [`crate::FramePipeline::set_wind`]).
pub fn gust(t: f32, peak: Vec3) -> Vec3 {
    peak * bump(t, 1.6, 1.4)
}

/// The gusts' RMS speed at time `t` seconds (m/s, `SimParams::turbulence`
/// through [`crate::FramePipeline::set_turbulence`]): `peak` times the
/// same bump as [`gust`], so that the turbulence rises and falls with the
/// wind and the air is calm when the wind is. (A turbulence that stayed
/// on at rest kept blowing the hair: measured on Sintel's groom with the
/// body scene's simulation at rest, `examples/style.rs`, a constant
/// 1.5 m/s left the vertices 15.7 mm from the groom (p95) at local shape
/// 0.7 and 153 mm at 0.3, 5 % of them kinked, against 0.7 and 2.3 mm
/// without it.)
pub fn gust_turbulence(t: f32, peak: f32) -> f32 {
    peak * bump(t, 1.6, 1.4)
}

/// Linear blend of two rigid poses (slerp of the rotation, lerp of the
/// translation), for fixed substeps inside one frame.
pub fn blend_poses(a: &Affine3A, b: &Affine3A, s: f32) -> Affine3A {
    let (_, ra, ta) = a.to_scale_rotation_translation();
    let (_, rb, tb) = b.to_scale_rotation_translation();
    Affine3A::from_rotation_translation(ra.slerp(rb, s), ta.lerp(tb, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_keep_the_pivot_and_the_motion_returns_to_rest() {
        let pivot = Vec3::new(0.0, 1.5, 0.1);
        let m = head_pose(pivot, 0.4, 0.2, Vec3::ZERO);
        assert!((m.transform_point3(pivot) - pivot).length() < 1e-5);
        let p = pivot + Vec3::new(0.1, 0.2, 0.0);
        assert!(((m.transform_point3(p) - pivot).length() - (p - pivot).length()).abs() < 1e-5);
        let rest = turn_and_nod(3.5, pivot);
        assert!((rest.transform_point3(p) - p).length() < 1e-6);
        let turned = turn_and_nod(1.0, pivot);
        assert!((turned.transform_point3(p) - p).length() > 0.05);
        let half = blend_poses(&Affine3A::IDENTITY, &turned, 0.5);
        let (q, r) = (half.transform_point3(p), half.transform_point3(pivot));
        assert!(
            ((q - r).length() - (p - pivot).length()).abs() < 1e-5,
            "rigid"
        );
        let end = blend_poses(&Affine3A::IDENTITY, &turned, 1.0);
        assert!((end.transform_point3(p) - turned.transform_point3(p)).length() < 1e-5);
    }
}
