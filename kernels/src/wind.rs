//! Gusts: a deterministic turbulent wind field in space and time, added to
//! [`crate::SimParams::wind`] where [`crate::SimParams::turbulence`] > 0.
//!
//! The field is a sum of [`GUST_MODES`] travelling transverse waves (a
//! random Fourier field; Shinozuka and Deodatis 1991 simulate wind this way):
//!
//! `u(x, t) = sum_k e_k s(k_k . x - w_k t + phi_k)`,
//!
//! with wave vectors `k_k` of random direction and length
//! `2 pi / turbulence_scale` times a factor in [0.5, 1.5], frequencies
//! `w_k = 2 pi / turbulence_period` times a factor in [0.5, 1.5], amplitudes
//! `e_k` perpendicular to `k_k` (each wave, and so the field, is
//! divergence-free, as air at low Mach number is) and scaled so the field's
//! RMS speed is `turbulence`; `s` is a smooth periodic stand-in for the
//! sine (a parabola pair with one correction, within 0.001 of `sin`). The
//! modes come from a fixed seed, so the field is the same for every run,
//! thread count and path; it is evaluated in world coordinates (the phase
//! takes the strands' local origin in `f64`), so rebasing does not move it.
//! Neighbouring strands a `turbulence_scale` apart feel unrelated gusts;
//! strands much closer move together, as hair in real wind does.
//!
//! Cost: the field is sampled once per step per vertex (at the step's start
//! position) and held over its substeps: 8 waves of about 16 lane
//! operations each.

use crate::fused::madd;
use crate::lanes::{Lane, V3};
use crate::SimParams;
use coif_base::rng::SplitMix64;
use glam::{DVec3, Vec3};

/// Waves in the gust field.
pub const GUST_MODES: usize = 8;

/// The seed of the waves (any thread count and run gives the same field).
const GUST_SEED: u64 = 0x6f1f_57a1_d5e2_0b3d;

/// One wave at one step: `k / 2 pi` (cycles per metre), its phase in
/// cycles (world origin and time folded in, wrapped to [-0.5, 0.5]) and
/// its amplitude, premultiplied by `drag h^2` (a position offset per
/// substep).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Wave {
    cycles: Vec3,
    phase: f32,
    offset: Vec3,
}

/// The gust field's waves at one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Gusts {
    waves: [Wave; GUST_MODES],
}

impl Gusts {
    /// The field at simulation time `time` for strands whose local origin is
    /// `origin`, premultiplied by `drag h^2`; None when there are no gusts
    /// (`turbulence` or `drag` zero, or parameters out of range).
    pub(crate) fn new(p: &SimParams, drag: f32, h: f32, time: f64, origin: DVec3) -> Option<Gusts> {
        let ok = p.turbulence > 0.0
            && p.turbulence.is_finite()
            && drag > 0.0
            && p.turbulence_scale > 0.0
            && p.turbulence_scale.is_finite()
            && p.turbulence_period > 0.0
            && p.turbulence_period.is_finite();
        if !ok {
            return None;
        }
        let mut rng = SplitMix64::new(GUST_SEED);
        // Each wave's amplitude so that the RMS speed is `turbulence`: a
        // sine of amplitude A has mean square A^2 / 2 per wave.
        let amplitude = p.turbulence * (2.0 / GUST_MODES as f32).sqrt();
        let scale = drag * h * h * amplitude;
        let waves = std::array::from_fn(|_| {
            let dir = rng.unit_vector();
            let cycles = dir * (rng.range(0.5, 1.5) / p.turbulence_scale);
            let helper = if dir.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
            let e1 = dir.cross(helper).normalize();
            let e2 = dir.cross(e1);
            let angle = rng.range(0.0, std::f32::consts::TAU);
            let e = e1 * angle.cos() + e2 * angle.sin();
            let freq = rng.range(0.5, 1.5) as f64 / p.turbulence_period as f64;
            let phi = rng.next_f32() as f64;
            let phase = cycles.as_dvec3().dot(origin) - freq * time + phi;
            Wave {
                cycles,
                phase: (phase - phase.round()) as f32,
                offset: e * scale,
            }
        });
        Some(Gusts { waves })
    }

    /// The gusts' pull over one substep at local point `x`:
    /// `drag h^2 u(x, t)`.
    #[inline(always)]
    pub(crate) fn offset<T: Lane>(&self, x: V3<T>) -> V3<T> {
        let mut sum = V3::zero();
        for w in &self.waves {
            let c = V3::<T>::splat(w.cycles);
            let arg =
                c.x.mul_add(x.x, c.y.mul_add(x.y, c.z.mul_add(x.z, T::splat(w.phase))));
            sum = madd(V3::splat(w.offset), sine_cycles(arg), sum);
        }
        sum
    }
}

/// `sin(2 pi f)` within 0.001, for any `f` (cycles): `f` is reduced to
/// [-0.5, 0.5] by rounding with the `1.5 2^23` trick (IEEE adds, the same in
/// every width), then `y = 8 f (1 - 2|f|)` (the parabola through the
/// sine's zeros and extremes) and `y + 0.225 (y |y| - y)`.
#[inline(always)]
pub(crate) fn sine_cycles<T: Lane>(f: T) -> T {
    let magic = T::splat(12_582_912.0);
    let near = (f + magic) - magic;
    let r = f - near;
    let y = T::splat(8.0) * r * (T::splat(1.0) - T::splat(2.0) * r.abs());
    (y * y.abs() - y).mul_add(T::splat(0.225), y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use coif_base::lanes::F32Lanes;

    #[test]
    fn the_sine_stand_in_is_within_a_thousandth_and_the_twins_agree() {
        let mut worst: f32 = 0.0;
        for i in -40_000..40_000 {
            let f = i as f32 * 1.37e-4;
            let s = sine_cycles(f);
            worst = worst.max((s - (std::f32::consts::TAU * f as f64 as f32).sin()).abs());
            let lanes = sine_cycles(F32Lanes::splat(f)).to_array();
            assert!(lanes.iter().all(|&l| l.to_bits() == s.to_bits()), "{f}");
        }
        assert!(worst < 1.1e-3, "{worst}");
    }

    #[test]
    fn the_field_has_the_asked_rms_speed_and_varies_over_its_scale() {
        let p = SimParams {
            turbulence: 2.0,
            turbulence_scale: 0.2,
            ..Default::default()
        };
        // drag h^2 = 1: offsets are the field itself.
        let g = Gusts::new(&p, 1.0, 1.0, 3.0, DVec3::ZERO).unwrap();
        let mut rng = SplitMix64::new(5);
        let (mut sq, mut near_diff, n) = (0.0f64, 0.0f64, 20_000);
        for _ in 0..n {
            let x = Vec3::new(
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
            );
            let u = g.offset(V3::<f32>::from_vec3(x)).to_vec3();
            let v = g
                .offset(V3::<f32>::from_vec3(x + Vec3::X * 0.005))
                .to_vec3();
            sq += u.length_squared() as f64;
            near_diff += (u - v).length_squared() as f64;
        }
        let rms = (sq / n as f64).sqrt();
        assert!((rms - 2.0).abs() < 0.15, "RMS {rms} m/s");
        // 5 mm apart: nearly the same wind (smooth); the scale apart: not.
        assert!((near_diff / n as f64).sqrt() < 0.15 * rms, "not smooth");
        let u = g.offset(V3::<f32>::from_vec3(Vec3::ZERO)).to_vec3();
        let w = g.offset(V3::<f32>::from_vec3(Vec3::X * 0.2)).to_vec3();
        assert!((u - w).length() > 0.1, "{u} {w}");
        // Rebasing does not move the field: origin + local is what counts.
        let o = DVec3::new(1000.0, -20.0, 3.0);
        let h = Gusts::new(&p, 1.0, 1.0, 3.0, o).unwrap();
        let x = Vec3::new(0.3, 0.1, -0.2);
        let a = g.offset(V3::<f32>::from_vec3((o.as_vec3()) + x)).to_vec3();
        let b = h.offset(V3::<f32>::from_vec3(x)).to_vec3();
        assert!((a - b).length() < 1e-2 * rms as f32, "{a} {b}");
    }
}
