//! The ribbon stage of a frame: silk ribbons hanging from the head,
//! simulated as cloth patches (`coif::kernels::patch`), blended with their
//! rigidly skinned rest grids, shaded per vertex and drawn as opaque
//! triangles before the hair.
//!
//! Per fixed substep (inside [`super::FramePipeline::simulate`]):
//! `skinned = pose_k * rest grid` (an engine's rigid skinning to the head
//! bone) -> `Patch::set_skinned` -> `patch::step` against the posed rig.
//! After the substeps: `Patch::write_blended` (`lerp(skinned, simulated,
//! weight)`, weight 0 on the attached row) and `patch::grid_normals`.
//!
//! **Clearance.** The ribbons are tied over the hair, not under it: they
//! are built on the head sphere grown by [`RIBBON_CLEARANCE`] (a hair
//! layer's thickness) and collide with the hair's rig spheres grown by the
//! same amount, since a patch does not collide with the hair itself.
//!
//! **Shading** (per vertex, two-sided: the normal is flipped toward the
//! eye): Lambert plus a Blinn-Phong highlight (Blinn 1977),
//!
//! ```text
//! L = albedo (ambient + E max(n.l, 0) V) + k_s E max(n.h, 0)^s V [n.l > 0],
//! h = normalize(l + v),   V = T_shadow(p) [ray to the light misses the head]
//! ```
//!
//! with `T_shadow` the hair's opacity shadow map (a ribbon under hair is
//! darker). **Order**: the ribbon is opaque, so it is drawn after the head
//! with the depth test and writes its depth (`render::triangle`); the hair
//! is then blended back to front and hidden where the ribbon or the head is
//! nearer, exactly as the head already hid it. Hair in front of the ribbon
//! blends over it.

use super::shadow::ShadowStage;
use super::{Error, HairScene, Light};
use coif_base::tasks::{Executor, Serial};
use coif_kernels::patch::{self, grid_normals, ribbon_on_sphere, Patch, Ribbon};
use coif_kernels::{SimParams, Sphere};
use coif_render::grid::draw_grid;
use coif_render::head::occluded;
use coif_render::{Camera, Framebuffer};
use glam::{Affine3A, Vec3};

/// Dark red silk (linear RGB diffuse albedo).
pub const RIBBON_ALBEDO: Vec3 = Vec3::new(0.42, 0.03, 0.045);
/// Strength `k_s` and exponent `s` of the ribbon's highlight.
pub const RIBBON_SPECULAR: (f32, f32) = (0.25, 40.0);
/// How far above the head sphere a ribbon lies and collides (metres): the
/// hair layer it is tied over.
pub const RIBBON_CLEARANCE: f32 = 0.012;
/// Grid of each ribbon: rows along its length, columns across (one SIMD
/// block of 8 columns).
pub const RIBBON_GRID: (usize, usize) = (18, 8);

/// A bow's two tails tied to `head` at unit direction `attach` from its
/// centre: two ribbons 3.5 cm wide, 30 and 26 cm long, their tops a few
/// centimetres apart across the head, on the sphere grown by
/// [`RIBBON_CLEARANCE`] (see [`ribbon_on_sphere`]).
pub fn bow_tails(head: &Sphere, attach: Vec3) -> Vec<Ribbon> {
    let n = attach.try_normalize().unwrap_or(Vec3::NEG_Z);
    let across = Vec3::Y.cross(n).try_normalize().unwrap_or(Vec3::X);
    let grown = Sphere {
        center: head.center,
        radius: head.radius + RIBBON_CLEARANCE,
    };
    let (rows, cols) = RIBBON_GRID;
    [(0.22f32, 0.30f32), (-0.22, 0.26)]
        .iter()
        .map(|&(side, length)| {
            ribbon_on_sphere(&grown, n + across * side, 0.035, length, rows, cols)
        })
        .collect()
}

/// Colour of a two-sided silk point `p` with unit normal `n` (either side),
/// seen from `eye`, lit by `light` with visibility `visible` in [0, 1]
/// (shadows): the module doc's Lambert + Blinn-Phong, with the normal
/// turned toward the eye, so the side away from the light gets the ambient
/// term only. Non-finite input or output gives the ambient colour.
pub fn shade_silk(p: Vec3, n: Vec3, eye: Vec3, light: &Light, visible: f32) -> Vec3 {
    let ambient = RIBBON_ALBEDO * light.ambient;
    if !(p.is_finite() && n.is_finite() && eye.is_finite()) {
        return ambient;
    }
    let (k_s, exponent) = RIBBON_SPECULAR;
    let l = light.to_light;
    let v = (eye - p).normalize_or_zero();
    let n = if n.dot(v) < 0.0 { -n } else { n };
    let n_dot_l = n.dot(l);
    let direct = if n_dot_l > 0.0 {
        light.irradiance * visible.clamp(0.0, 1.0)
    } else {
        Vec3::ZERO
    };
    let h = (l + v).normalize_or_zero();
    let highlight = k_s * n.dot(h).max(0.0).powf(exponent);
    let c = ambient + RIBBON_ALBEDO * direct * n_dot_l.max(0.0) + direct * highlight;
    if c.is_finite() {
        c
    } else {
        ambient
    }
}

/// One simulated ribbon and its per-frame buffers (sized once).
struct RibbonState {
    rows: usize,
    cols: usize,
    /// Rest grid (world space at rest, head pose = identity).
    rest: Vec<Vec3>,
    /// This substep's skinned grid: head pose applied to `rest`.
    skinned: Vec<Vec3>,
    /// Blended positions (world) and their normals.
    blended: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// Blended positions relative to the render origin, and their colours.
    local: Vec<Vec3>,
    colors: Vec<Vec3>,
}

/// Constraint sweeps per step of the ribbons' cloth patches. The hair's
/// `iterations` counts projections per substep of its direct solver (1);
/// a patch relaxes its grid by Gauss-Seidel sweeps, and 4 per step is what
/// its stretch and penetration figures were measured at.
pub const RIBBON_SWEEPS: u32 = 4;

/// Owns the ribbons' patches, their rig and every buffer: cloth patches
/// tied to the head, stepped with the hair's parameters (but
/// [`RIBBON_SWEEPS`] sweeps).
pub struct RibbonStage {
    /// One cloth patch per ribbon (apart, for `patch::step_all`).
    patches: Vec<Patch>,
    ribbons: Vec<RibbonState>,
    rest_rig: Vec<Sphere>,
    rig: Vec<Sphere>,
    params: SimParams,
}

impl RibbonStage {
    /// The ribbons of `scene` (none if it has none), settled for
    /// `settle_steps` fixed steps at rest.
    pub fn new(
        scene: &HairScene,
        params: &SimParams,
        settle_steps: usize,
    ) -> Result<RibbonStage, Error> {
        let rest_rig: Vec<Sphere> = scene
            .rig
            .iter()
            .map(|s| Sphere {
                center: s.center,
                radius: s.radius + RIBBON_CLEARANCE,
            })
            .collect();
        let mut ribbons = Vec::with_capacity(scene.ribbons.len());
        let mut patches = Vec::with_capacity(scene.ribbons.len());
        for ribbon in &scene.ribbons {
            let mut patch = ribbon.patch()?;
            // Diagonals keep the silk from shearing into a parallelogram.
            patch.set_shear_stiffness(0.5)?;
            let n = ribbon.points.len();
            patches.push(patch);
            ribbons.push(RibbonState {
                rows: ribbon.rows,
                cols: ribbon.cols,
                rest: ribbon.points.clone(),
                skinned: ribbon.points.clone(),
                blended: ribbon.points.clone(),
                normals: vec![Vec3::ZERO; n],
                local: vec![Vec3::ZERO; n],
                colors: vec![Vec3::ZERO; n],
            });
        }
        let mut stage = RibbonStage {
            patches,
            ribbons,
            rig: rest_rig.clone(),
            rest_rig,
            params: SimParams {
                iterations: RIBBON_SWEEPS,
                ..params.clone()
            },
        };
        for _ in 0..settle_steps {
            stage.step(&Serial);
        }
        stage.finish();
        Ok(stage)
    }

    /// Number of ribbons.
    pub fn len(&self) -> usize {
        self.ribbons.len()
    }

    /// Whether the scene has no ribbon.
    pub fn is_empty(&self) -> bool {
        self.ribbons.is_empty()
    }

    /// Moves the skin and the rig with the rigid head pose `pose` and hands
    /// the skin to the patches (`Patch::set_skinned`).
    pub fn place(&mut self, pose: &Affine3A) {
        for (dst, s) in self.rig.iter_mut().zip(&self.rest_rig) {
            dst.center = pose.transform_point3(s.center);
        }
        for (r, patch) in self.ribbons.iter_mut().zip(&mut self.patches) {
            for (dst, p) in r.skinned.iter_mut().zip(&r.rest) {
                *dst = pose.transform_point3(*p);
            }
            // Finite by construction (finite rest grid, pose checked by
            // the caller); a refused skin keeps the previous one.
            let _ = patch.set_skinned(&r.skinned);
        }
    }

    /// One fixed step of every ribbon (SIMD `patch::step_all`: runs of
    /// patches as tasks on `executor`; the same bytes on any executor).
    pub fn step(&mut self, executor: &dyn Executor) {
        patch::step_all(&mut self.patches, &self.params, &self.rig, executor);
    }

    /// Blended positions and their normals, after the substeps of a frame.
    pub fn finish(&mut self) {
        for (r, patch) in self.ribbons.iter_mut().zip(&self.patches) {
            // Counts match by construction.
            let _ = patch.write_blended(&mut r.blended);
            let _ = grid_normals(&r.blended, r.rows, r.cols, &mut r.normals);
        }
    }

    /// Colours of every vertex (see the module doc), for positions taken
    /// relative to `origin` (the render space), seen from `eye` (render
    /// space), lit by `light`, shadowed by the hair's `shadow` map and the
    /// `head` spheres (render space).
    pub fn shade(
        &mut self,
        origin: Vec3,
        eye: Vec3,
        light: &Light,
        head: &[Sphere],
        shadow: &ShadowStage,
    ) {
        let l = light.to_light;
        for r in &mut self.ribbons {
            for k in 0..r.blended.len() {
                let p = r.blended[k] - origin;
                r.local[k] = p;
                let facing = r.normals[k].dot(l) * r.normals[k].dot(eye - p) > 0.0;
                let visible = if facing && !occluded(p, l, head, 1e-3) {
                    shadow.transmittance_at(p)
                } else {
                    0.0
                };
                r.colors[k] = shade_silk(p, r.normals[k], eye, light, visible);
            }
        }
    }

    /// Draws every ribbon (render-space positions of the last
    /// [`RibbonStage::shade`]) with `camera` (render space); returns the
    /// pixels written.
    pub fn draw(&self, frame: &mut Framebuffer, camera: &Camera) -> usize {
        self.ribbons
            .iter()
            .map(|r| draw_grid(frame, camera, &r.local, &r.colors, r.rows, r.cols))
            .sum()
    }

    /// Blended world positions of ribbon `i` after the last frame
    /// (row-major, `rows x cols`).
    pub fn blended(&self, i: usize) -> &[Vec3] {
        &self.ribbons[i].blended
    }

    /// Skinned world positions of ribbon `i` (the last substep's).
    pub fn skinned(&self, i: usize) -> &[Vec3] {
        &self.ribbons[i].skinned
    }

    /// `(rows, cols)` of ribbon `i`.
    pub fn grid(&self, i: usize) -> (usize, usize) {
        (self.ribbons[i].rows, self.ribbons[i].cols)
    }

    /// Final linear-RGB colour of every vertex of ribbon `i`.
    pub fn colors(&self, i: usize) -> &[Vec3] {
        &self.ribbons[i].colors
    }

    /// The ribbons' collision spheres as posed in the last substep.
    pub fn rig(&self) -> &[Sphere] {
        &self.rig
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn silk_is_lit_on_the_side_facing_the_light_from_either_side() {
        let light = Light {
            to_light: Vec3::Z,
            irradiance: Vec3::ONE,
            ambient: Vec3::splat(0.1),
        };
        let ambient = RIBBON_ALBEDO * light.ambient;
        // Light and eye on the same side: lit, whichever way n points.
        let front = shade_silk(Vec3::ZERO, Vec3::Z, Vec3::Z, &light, 1.0);
        let flipped = shade_silk(Vec3::ZERO, -Vec3::Z, Vec3::Z, &light, 1.0);
        assert_eq!(front, flipped);
        // Head-on: Lambert 1 plus the full highlight k_s.
        let expected = RIBBON_ALBEDO * (light.ambient + Vec3::ONE) + Vec3::splat(RIBBON_SPECULAR.0);
        assert!((front - expected).length() < 1e-5, "{front} vs {expected}");
        // The eye behind the ribbon sees its unlit side: ambient only.
        let back = shade_silk(Vec3::ZERO, Vec3::Z, -Vec3::Z, &light, 1.0);
        assert_eq!(back, ambient);
        // In shadow: ambient only; half shadow: between.
        assert_eq!(
            shade_silk(Vec3::ZERO, Vec3::Z, Vec3::Z, &light, 0.0),
            ambient
        );
        let half = shade_silk(Vec3::ZERO, Vec3::Z, Vec3::Z, &light, 0.5);
        assert!(half.x > ambient.x && half.x < front.x);
        // Grazing light: darker than head-on, highlight off the mirror direction.
        let oblique = Light {
            to_light: Vec3::new(0.8, 0.0, 0.6),
            ..light
        };
        let side = shade_silk(
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(-0.8, 0.0, 0.6),
            &oblique,
            1.0,
        );
        let off = shade_silk(Vec3::ZERO, Vec3::Z, Vec3::Z, &oblique, 1.0);
        assert!(
            side.y > off.y,
            "mirror view shows the highlight: {side} vs {off}"
        );
        assert!(off.x < front.x);
        // NaN in, the ambient colour out.
        assert_eq!(
            shade_silk(Vec3::NAN, Vec3::Z, Vec3::Z, &light, 1.0),
            ambient
        );
        assert_eq!(
            shade_silk(Vec3::ZERO, Vec3::NAN, Vec3::Z, &light, 1.0),
            ambient
        );
    }
}
