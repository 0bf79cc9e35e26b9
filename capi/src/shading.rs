//! Hair shading of caller vertices into caller RGB buffers: Kajiya-Kay with
//! two shifted highlights (`coif_shading::kajiya_kay`), Marschner 2003
//! from its lookup tables (`coif_shading::marschner::Lut`) and pbrt-v3's
//! hair BSDF from its far-field tables (`coif_shading::pbrt::Table`), eight
//! vertices per SIMD step (`shade_simd` / `scattering_simd`, the kernels of the
//! Rust batch paths).

use crate::lod::CoifRenderVertex;
use crate::tasks::{self, per_task};
use crate::{guard, handle, input, new_handle, output, vec3_arg, CoifExecutor, CoifStatus};
use coif_base::tasks::{for_each_chunk_mut, Executor};
use coif_base::{Vec3Lanes, LANES};
use coif_shading::kajiya_kay::{Highlight, KajiyaKay};
use coif_shading::marschner::{self, Lut, RootSolver};
use coif_shading::pbrt::{self, Table};
use glam::Vec3;

/// Kajiya-Kay (1989) diffuse plus Scheuermann's (2004) two shifted
/// specular highlights; the fields of `coif_shading::kajiya_kay::KajiyaKay`.
/// Start from `coif_kajiya_kay_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifKajiyaKay {
    /// Diffuse colour K_d (linear RGB, >= 0).
    pub diffuse: [f32; 3],
    /// Primary highlight colour (>= 0), shifted toward the tip.
    pub primary_color: [f32; 3],
    /// Primary highlight exponent (>= 0).
    pub primary_exponent: f32,
    /// Primary tangent shift along the normal (e.g. 0.1).
    pub primary_shift: f32,
    /// Secondary highlight colour (>= 0), shifted toward the root.
    pub secondary_color: [f32; 3],
    /// Secondary highlight exponent (>= 0).
    pub secondary_exponent: f32,
    /// Secondary tangent shift (e.g. -0.1).
    pub secondary_shift: f32,
}

/// Scheuermann-style brown hair (`KajiyaKay::default()`).
#[no_mangle]
pub extern "C" fn coif_kajiya_kay_default() -> CoifKajiyaKay {
    let k = KajiyaKay::default();
    CoifKajiyaKay {
        diffuse: k.diffuse.to_array(),
        primary_color: k.primary.color.to_array(),
        primary_exponent: k.primary.exponent,
        primary_shift: k.primary.shift,
        secondary_color: k.secondary.color.to_array(),
        secondary_exponent: k.secondary.exponent,
        secondary_shift: k.secondary.shift,
    }
}

impl TryFrom<&CoifKajiyaKay> for KajiyaKay {
    type Error = CoifStatus;
    fn try_from(c: &CoifKajiyaKay) -> Result<KajiyaKay, CoifStatus> {
        let colours = [c.diffuse, c.primary_color, c.secondary_color];
        let scalars = [
            c.primary_exponent,
            c.primary_shift,
            c.secondary_exponent,
            c.secondary_shift,
        ];
        let all = colours.iter().flatten().chain(scalars.iter());
        if !all.clone().all(|v| v.is_finite()) {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        let negative = colours.iter().flatten().any(|v| *v < 0.0)
            || c.primary_exponent < 0.0
            || c.secondary_exponent < 0.0;
        if negative {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        Ok(KajiyaKay {
            diffuse: Vec3::from_array(c.diffuse),
            primary: Highlight {
                color: Vec3::from_array(c.primary_color),
                exponent: c.primary_exponent,
                shift: c.primary_shift,
            },
            secondary: Highlight {
                color: Vec3::from_array(c.secondary_color),
                exponent: c.secondary_exponent,
                shift: c.secondary_shift,
            },
        })
    }
}

/// Parameters of Marschner et al. 2003 (table 1 of the paper); the fields
/// of `coif_shading::marschner::Params`, angles in radians. Start from
/// `coif_marschner_params_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifMarschnerParams {
    /// Index of refraction (> 1; paper 1.55).
    pub eta: f32,
    /// Longitudinal shift of the R lobe, radians (paper -10 to -5 degrees).
    pub alpha_r: f32,
    /// Longitudinal width of the R lobe, radians (> 0; paper 5 to 10 degrees).
    pub beta_r: f32,
    /// Absorption per unit fibre radius, per RGB channel (>= 0).
    pub absorption: [f32; 3],
    /// Minor over major axis of the cross section (0.1..=10; paper 0.85 to 1).
    pub eccentricity: f32,
    /// Scale of the TRT glints (>= 0; paper 0.5 to 5).
    pub glint_scale: f32,
    /// Azimuthal width of the caustic, radians (> 0; paper 10 to 25 degrees).
    pub caustic_width: f32,
    /// Range of eta' over which the glints fade (> 0; paper 0.2 to 0.4).
    pub caustic_fade_range: f32,
    /// Largest h-interval a caustic gathers (>= 0; paper 0.5).
    pub caustic_limit: f32,
    /// 0: exact roots of the azimuthal equation (default); 1: the paper's
    /// cubic approximation.
    pub cubic_roots: u32,
}

/// The paper's typical values (`marschner::Params::default()`).
#[no_mangle]
pub extern "C" fn coif_marschner_params_default() -> CoifMarschnerParams {
    let p = marschner::Params::default();
    CoifMarschnerParams {
        eta: p.eta,
        alpha_r: p.alpha_r,
        beta_r: p.beta_r,
        absorption: p.absorption.to_array(),
        eccentricity: p.eccentricity,
        glint_scale: p.glint_scale,
        caustic_width: p.caustic_width,
        caustic_fade_range: p.caustic_fade_range,
        caustic_limit: p.caustic_limit,
        cubic_roots: u32::from(p.roots == RootSolver::Cubic),
    }
}

impl TryFrom<&CoifMarschnerParams> for marschner::Params {
    type Error = CoifStatus;
    fn try_from(c: &CoifMarschnerParams) -> Result<marschner::Params, CoifStatus> {
        let scalars = [
            c.eta,
            c.alpha_r,
            c.beta_r,
            c.eccentricity,
            c.glint_scale,
            c.caustic_width,
            c.caustic_fade_range,
            c.caustic_limit,
        ];
        if !scalars
            .iter()
            .chain(c.absorption.iter())
            .all(|v| v.is_finite())
        {
            return Err(CoifStatus::COIF_ERROR_NON_FINITE);
        }
        let in_range = c.eta > 1.0
            && c.beta_r > 0.0
            && c.absorption.iter().all(|a| *a >= 0.0)
            && (0.1..=10.0).contains(&c.eccentricity)
            && c.glint_scale >= 0.0
            && c.caustic_width > 0.0
            && c.caustic_fade_range > 0.0
            && c.caustic_limit >= 0.0
            && c.cubic_roots <= 1;
        if !in_range {
            return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
        }
        Ok(marschner::Params {
            eta: c.eta,
            alpha_r: c.alpha_r,
            beta_r: c.beta_r,
            absorption: Vec3::from_array(c.absorption),
            eccentricity: c.eccentricity,
            glint_scale: c.glint_scale,
            caustic_width: c.caustic_width,
            caustic_fade_range: c.caustic_fade_range,
            caustic_limit: c.caustic_limit,
            roots: if c.cubic_roots == 1 {
                RootSolver::Cubic
            } else {
                RootSolver::Exact
            },
        })
    }
}

/// An opaque pair of Marschner lookup tables (created by
/// `coif_marschner_lut_new`, freed by `coif_marschner_lut_free`).
pub struct CoifMarschnerLut {
    pub(crate) lut: Lut,
}

/// Tabulates Marschner's factored scattering function (`marschner::Lut`,
/// default layout) at `resolution` x `resolution` texels per table
/// (2..=1024; 64 to 256 are usual; 48 bytes a texel pair). Made once per
/// material; this is where the time goes (seconds at 256).
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (a parameter or the resolution out of range).
///
/// # Safety
/// `params` is NULL or readable; `out` is NULL or points to a writable
/// `CoifMarschnerLut *`.
#[no_mangle]
pub unsafe extern "C" fn coif_marschner_lut_new(
    params: *const CoifMarschnerParams,
    resolution: usize,
    out: *mut *mut CoifMarschnerLut,
) -> CoifStatus {
    guard(|| {
        // SAFETY: the pointers are NULL or valid (the caller's contract).
        unsafe {
            new_handle(out, || {
                let p = marschner::Params::try_from(handle(params)?)?;
                let range = marschner::lut::MIN_RESOLUTION..=marschner::lut::MAX_RESOLUTION;
                if !range.contains(&resolution) {
                    return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
                }
                Ok(CoifMarschnerLut {
                    lut: Lut::new(&p, resolution),
                })
            })
        }
    })
}

/// Frees tables made by `coif_marschner_lut_new`. NULL is fine.
///
/// # Safety
/// `lut` is NULL or a handle from `coif_marschner_lut_new` not freed before.
#[no_mangle]
pub unsafe extern "C" fn coif_marschner_lut_free(lut: *mut CoifMarschnerLut) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(lut) }
}

impl From<coif_shading::Error> for CoifStatus {
    fn from(e: coif_shading::Error) -> CoifStatus {
        crate::set_last_error(&e);
        match e {
            coif_shading::Error::InvalidParameter { value, .. } if !value.is_finite() => {
                CoifStatus::COIF_ERROR_NON_FINITE
            }
            coif_shading::Error::CountMismatch { .. } => CoifStatus::COIF_ERROR_COUNT_MISMATCH,
            _ => CoifStatus::COIF_ERROR_INVALID_ARGUMENT,
        }
    }
}

/// pbrt-v3's hair material (Chiang et al. 2016 as pbrt-v3 implements it);
/// the fields of `coif_shading::pbrt::Params`. Start from
/// `coif_pbrt_params_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifPbrtParams {
    /// Index of refraction (> 1; default 1.55).
    pub eta: f32,
    /// Longitudinal roughness in (0, 1] (default 0.3).
    pub beta_m: f32,
    /// Azimuthal roughness in (0, 1] (default 0.3).
    pub beta_n: f32,
    /// Cuticle scale tilt, radians, |alpha| < pi/4 (default 2 degrees).
    pub alpha: f32,
    /// Absorption per unit radius, RGB (>= 0; default eumelanin 1.3).
    pub sigma_a: [f32; 3],
}

/// pbrt-v3's defaults (`pbrt::Params::default()`).
#[no_mangle]
pub extern "C" fn coif_pbrt_params_default() -> CoifPbrtParams {
    let p = pbrt::Params::default();
    CoifPbrtParams {
        eta: p.eta,
        beta_m: p.beta_m,
        beta_n: p.beta_n,
        alpha: p.alpha,
        sigma_a: p.sigma_a.to_array(),
    }
}

/// An opaque pair of pbrt far-field tables (created by
/// `coif_pbrt_table_new`, freed by `coif_pbrt_table_free`).
pub struct CoifPbrtTable {
    pub(crate) table: Table,
}

/// Tabulates pbrt-v3's hair BSDF in the far field (`pbrt::Table::new`) at
/// `resolution` x `resolution` cells per table (2..=1024). Made once per
/// material.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE`,
/// `COIF_ERROR_INVALID_ARGUMENT` (a parameter or the resolution out of range).
///
/// # Safety
/// `params` is NULL or readable; `out` is NULL or points to a writable
/// `CoifPbrtTable *`.
#[no_mangle]
pub unsafe extern "C" fn coif_pbrt_table_new(
    params: *const CoifPbrtParams,
    resolution: usize,
    out: *mut *mut CoifPbrtTable,
) -> CoifStatus {
    guard(|| {
        // SAFETY: the pointers are NULL or valid (the caller's contract).
        unsafe {
            new_handle(out, || {
                let c = handle(params)?;
                let p = pbrt::Params {
                    eta: c.eta,
                    beta_m: c.beta_m,
                    beta_n: c.beta_n,
                    alpha: c.alpha,
                    sigma_a: Vec3::from_array(c.sigma_a),
                };
                p.validate()?;
                if !(2..=1024).contains(&resolution) {
                    return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
                }
                Ok(CoifPbrtTable {
                    table: Table::new(&p, resolution)?,
                })
            })
        }
    })
}

/// Frees tables made by `coif_pbrt_table_new`. NULL is fine.
///
/// # Safety
/// `table` is NULL or a handle from `coif_pbrt_table_new` not freed before.
#[no_mangle]
pub unsafe extern "C" fn coif_pbrt_table_free(table: *mut CoifPbrtTable) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(table) }
}

/// As `coif_shade_kajiya_kay`, with pbrt-v3's hair BSDF from the tables
/// `table` (`Table::scattering_simd`, the same numbers as
/// `Table::scattering_batch`). Allocates nothing.
///
/// Errors: as `coif_shade_kajiya_kay`.
///
/// # Safety
/// `table` is NULL or a live handle; the rest as `coif_shade_kajiya_kay`.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_pbrt_table(
    table: *const CoifPbrtTable,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_shade_pbrt_table_with(
            table,
            vertices,
            count,
            light_dir,
            eye,
            out_rgb,
            capacity,
            std::ptr::null(),
        )
    }
}

/// `coif_shade_pbrt_table` with runs of vertices handed out as tasks to
/// `executor` (as `coif_shade_kajiya_kay_with`). The same bytes.
///
/// Errors: as `coif_shade_kajiya_kay_with`.
///
/// # Safety
/// As `coif_shade_pbrt_table`; `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_pbrt_table_with(
    table: *const CoifPbrtTable,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle.
        let table = &unsafe { handle(table) }?.table;
        // SAFETY: the buffers as the caller's contract says.
        unsafe {
            shade(
                vertices,
                count,
                light_dir,
                eye,
                out_rgb,
                capacity,
                executor,
                &|| Ok(()),
                &|_, t, wi, wo| table.scattering_simd(t, wi, wo),
            )
        }
    })
}

/// Shades `count` vertices with Kajiya-Kay: per vertex, `wi` is
/// `light_dir` normalised (the direction toward a distant light), `wo` is
/// `normalize(eye - position)` (the direction toward the eye, whose
/// position is in the vertices' coordinates: subtract `coif_strands_origin`
/// for render vertices), `t` the vertex tangent; writes `K_d s_i` plus both
/// highlights (linear RGB, without light colour) as 3 floats per vertex into
/// `out_rgb`, which holds `capacity` vertices (at least `count`). The same
/// numbers, bit for bit, as `KajiyaKay::shade_batch` on those samples.
/// Allocates nothing.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a NaN or infinite
/// parameter, direction, eye or vertex), `COIF_ERROR_INVALID_ARGUMENT` (a
/// negative colour or exponent, a zero light direction),
/// `COIF_ERROR_BUFFER_TOO_SMALL` (nothing written).
///
/// # Safety
/// `model`, `light_dir` (3 floats) and `eye` (3 floats) are NULL or
/// readable; `vertices` is NULL or points to `count` readable vertices;
/// `out_rgb` is NULL or points to `3 * capacity` writable floats.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_kajiya_kay(
    model: *const CoifKajiyaKay,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_shade_kajiya_kay_with(
            model,
            vertices,
            count,
            light_dir,
            eye,
            out_rgb,
            capacity,
            std::ptr::null(),
        )
    }
}

/// `coif_shade_kajiya_kay` with runs of vertices (whole groups of 8, at
/// most 64 runs) handed out as tasks to `executor`; each task shades and
/// writes only its own run, so the output is the same bytes as
/// `coif_shade_kajiya_kay` with any executor and task order. NULL
/// `executor` runs them on the calling thread. Every check runs before
/// `run` is called. Allocates nothing.
///
/// Errors: as `coif_shade_kajiya_kay`, and `COIF_ERROR_NULL` for an
/// executor whose `run` is NULL.
///
/// # Safety
/// As `coif_shade_kajiya_kay`; `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_kajiya_kay_with(
    model: *const CoifKajiyaKay,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or readable (the caller's contract).
        let kk = KajiyaKay::try_from(unsafe { handle(model) }?)?;
        // SAFETY: the buffers as the caller's contract says.
        unsafe {
            shade(
                vertices,
                count,
                light_dir,
                eye,
                out_rgb,
                capacity,
                executor,
                &|| Ok(()),
                &|_, t, wi, wo| kk.shade_simd(t, wi, wo),
            )
        }
    })
}

/// As `coif_shade_kajiya_kay`, with Marschner's scattering function from
/// the tables `lut` (`Lut::scattering_simd`, the same numbers as
/// `Lut::scattering_batch`). Allocates nothing.
///
/// Errors: as `coif_shade_kajiya_kay`.
///
/// # Safety
/// `lut` is NULL or a live handle; the rest as `coif_shade_kajiya_kay`.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_marschner_lut(
    lut: *const CoifMarschnerLut,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_shade_marschner_lut_with(
            lut,
            vertices,
            count,
            light_dir,
            eye,
            out_rgb,
            capacity,
            std::ptr::null(),
        )
    }
}

/// `coif_shade_marschner_lut` with runs of vertices handed out as tasks to
/// `executor` (as `coif_shade_kajiya_kay_with`). The same bytes.
///
/// Errors: as `coif_shade_kajiya_kay_with`.
///
/// # Safety
/// As `coif_shade_marschner_lut`; `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_marschner_lut_with(
    lut: *const CoifMarschnerLut,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or a live handle.
        let lut = &unsafe { handle(lut) }?.lut;
        // SAFETY: the buffers as the caller's contract says.
        unsafe {
            shade(
                vertices,
                count,
                light_dir,
                eye,
                out_rgb,
                capacity,
                executor,
                &|| Ok(()),
                &|_, t, wi, wo| lut.scattering_simd(t, wi, wo),
            )
        }
    })
}

/// A shading kernel: the index of the block's first vertex, then its `t`,
/// `wi`, `wo` lanes.
pub(crate) type Kernel<'a> =
    dyn Fn(usize, Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes + Sync + 'a;

/// Checks the inputs, then shades eight vertices at a time with `kernel`
/// (`t`, `wi`, `wo` lanes; lanes past the end padded as
/// `ShadingSamples::load_block` pads them: t = x, wi = wo = y), runs of
/// whole groups of eight as tasks on `executor`. `extra` runs after the
/// interface's checks and before `run` is called (the checks of the
/// callers' own per-vertex inputs).
///
/// # Safety
/// As the public shading calls.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn shade(
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
    extra: &dyn Fn() -> Result<(), CoifStatus>,
    kernel: &Kernel,
) -> Result<(), CoifStatus> {
    // SAFETY: the caller's contract on every pointer.
    let (light, eye) = unsafe { (vec3_arg(light_dir)?, vec3_arg(eye)?) };
    if vertices.is_null() {
        return Err(CoifStatus::COIF_ERROR_NULL);
    }
    // SAFETY: as above.
    let verts = unsafe { input(vertices, count) }?;
    let out = unsafe { output(out_rgb.cast::<Vec3>(), count, capacity) }?;
    let finite = |v: &CoifRenderVertex| {
        v.position
            .iter()
            .chain(v.tangent.iter())
            .all(|c| c.is_finite())
    };
    if !verts.iter().all(finite) {
        return Err(CoifStatus::COIF_ERROR_NON_FINITE);
    }
    let wi = light.normalize_or_zero();
    if wi == Vec3::ZERO {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    extra()?;
    // SAFETY: the caller's contract on `executor`.
    let exec = unsafe { tasks::executor(executor) }?;
    let exec: &dyn Executor = exec.get();
    let per = per_task(count, exec, LANES);
    for_each_chunk_mut(exec, out, per, &|i, run| {
        let start = i * per;
        shade_run(
            start,
            &verts[start..start + run.len()],
            eye,
            wi,
            kernel,
            run,
        );
    });
    Ok(())
}

/// One task of [`shade`]: `verts` (vertex `first` on) into `out`, eight at
/// a time (`first` is a multiple of eight, so the groups are those of one
/// serial pass).
fn shade_run(
    first: usize,
    verts: &[CoifRenderVertex],
    eye: Vec3,
    wi: Vec3,
    kernel: &Kernel,
    out: &mut [Vec3],
) {
    let blocks = verts.chunks(LANES).zip(out.chunks_mut(LANES));
    for (b, (block, rgb)) in blocks.enumerate() {
        let (mut t, mut wo) = (Vec3Lanes::splat(Vec3::X), Vec3Lanes::splat(Vec3::Y));
        let mut wi_simd = Vec3Lanes::splat(Vec3::Y);
        for (l, v) in block.iter().enumerate() {
            t.set_lane(l, Vec3::from_array(v.tangent));
            wo.set_lane(l, view_direction(eye, v));
            wi_simd.set_lane(l, wi);
        }
        let c = kernel(first + b * LANES, t, wi_simd, wo);
        for (l, o) in rgb.iter_mut().enumerate() {
            *o = c.lane(l);
        }
    }
}

/// `normalize(eye - position)`, zero when the eye is at the vertex.
pub(crate) fn view_direction(eye: Vec3, v: &CoifRenderVertex) -> Vec3 {
    (eye - Vec3::from_array(v.position)).normalize_or_zero()
}
