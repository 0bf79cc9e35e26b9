//! Multiple scattering in hair by dual scattering (Zinke et al. 2008,
//! `coif_shading::dual_scattering`): tables built once from a Marschner or
//! pbrt table handle, then shading calls that take, per vertex, the number
//! of fibres between it and the light, optionally the number of fibres
//! behind it (between it and the far side of the hair along the light),
//! and the fraction of the light that reaches it unscattered (all from the
//! engine's shadowing: an opacity shadow map's hair count, its last
//! layer's count minus the vertex's, and its transmittance, say).

use crate::shading::{shade, CoifMarschnerLut, CoifPbrtTable};
use crate::CoifRenderVertex;
use crate::{guard, handle, new_handle, set_last_error, CoifExecutor, CoifStatus};
use coif_base::lanes::load_padded;
use coif_base::Vec3Lanes;
use coif_shading::dual_scattering::{DualScattering, DualScatteringSettings};

/// Density and quality settings of dual scattering; the fields of
/// `coif_shading::dual_scattering::DualScatteringSettings`. Start from
/// `coif_dual_scattering_settings_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoifDualScatteringSettings {
    /// Density factor of forward scattering `d_f` in (0, 1] (default 0.4, fitted against
    /// the path tracer; the paper's 0.7).
    pub forward_density: f32,
    /// Density factor of backward scattering `d_b` in [0, 1] (default 0.35, fitted against
    /// the path tracer; the paper's 0.7).
    pub backward_density: f32,
    /// Table entries over the light's longitudinal angle, 2..=4096
    /// (default 64).
    pub resolution: usize,
}

/// Densities 0.4 and 0.35 (fitted against the path tracer through explicit
/// fibres) and 64 entries (`DualScatteringSettings::default()`).
#[no_mangle]
pub extern "C" fn coif_dual_scattering_settings_default() -> CoifDualScatteringSettings {
    let s = DualScatteringSettings::default();
    CoifDualScatteringSettings {
        forward_density: s.forward_density,
        backward_density: s.backward_density,
        resolution: s.resolution,
    }
}

impl From<&CoifDualScatteringSettings> for DualScatteringSettings {
    fn from(c: &CoifDualScatteringSettings) -> DualScatteringSettings {
        DualScatteringSettings {
            forward_density: c.forward_density,
            backward_density: c.backward_density,
            resolution: c.resolution,
        }
    }
}

/// The model a `CoifDualScattering` was built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Model {
    Marschner,
    Pbrt,
}

impl Model {
    fn name(self) -> &'static str {
        match self {
            Model::Marschner => "Marschner tables",
            Model::Pbrt => "pbrt tables",
        }
    }
}

/// Opaque dual scattering tables of one material (created by
/// `coif_dual_scattering_from_marschner_lut` or
/// `coif_dual_scattering_from_pbrt_table`, freed by
/// `coif_dual_scattering_free`).
pub struct CoifDualScattering {
    ds: DualScattering,
    model: Model,
}

/// Builds the dual scattering tables (the fibre's forward and backward
/// attenuations, shifts and widths over the light's angle) of the
/// material in `lut` (`DualScattering::from_marschner`). Made once per
/// material, after its tables; about `resolution x 9,216` table lookups.
/// The handle does not keep `lut`: either may be freed first.
///
/// Errors: `COIF_ERROR_NULL`, `COIF_ERROR_NON_FINITE` (a NaN density),
/// `COIF_ERROR_INVALID_ARGUMENT` (a density or the resolution out of
/// range; `coif_last_error_message` names it). `*out` is NULL on error.
///
/// # Safety
/// `lut` is NULL or a live handle; `settings` is NULL or readable; `out`
/// is NULL or points to a writable `CoifDualScattering *`.
#[no_mangle]
pub unsafe extern "C" fn coif_dual_scattering_from_marschner_lut(
    lut: *const CoifMarschnerLut,
    settings: *const CoifDualScatteringSettings,
    out: *mut *mut CoifDualScattering,
) -> CoifStatus {
    guard(|| {
        // SAFETY: the pointers are NULL or valid (the caller's contract).
        unsafe {
            new_handle(out, || {
                let lut = &handle(lut)?.lut;
                let settings = DualScatteringSettings::from(handle(settings)?);
                Ok(CoifDualScattering {
                    ds: DualScattering::from_marschner(lut, settings)?,
                    model: Model::Marschner,
                })
            })
        }
    })
}

/// As `coif_dual_scattering_from_marschner_lut`, for pbrt-v3's hair BSDF
/// in `table` (`DualScattering::from_pbrt`).
///
/// Errors: as `coif_dual_scattering_from_marschner_lut`.
///
/// # Safety
/// `table` is NULL or a live handle; the rest as
/// `coif_dual_scattering_from_marschner_lut`.
#[no_mangle]
pub unsafe extern "C" fn coif_dual_scattering_from_pbrt_table(
    table: *const CoifPbrtTable,
    settings: *const CoifDualScatteringSettings,
    out: *mut *mut CoifDualScattering,
) -> CoifStatus {
    guard(|| {
        // SAFETY: the pointers are NULL or valid (the caller's contract).
        unsafe {
            new_handle(out, || {
                let table = &handle(table)?.table;
                let settings = DualScatteringSettings::from(handle(settings)?);
                Ok(CoifDualScattering {
                    ds: DualScattering::from_pbrt(table, settings)?,
                    model: Model::Pbrt,
                })
            })
        }
    })
}

/// Frees tables made by `coif_dual_scattering_from_*`. NULL is fine.
///
/// # Safety
/// `ds` is NULL or a handle from `coif_dual_scattering_from_*` not freed
/// before.
#[no_mangle]
pub unsafe extern "C" fn coif_dual_scattering_free(ds: *mut CoifDualScattering) {
    // SAFETY: the caller's contract.
    unsafe { crate::free_handle(ds) }
}

/// `coif_shade_marschner_lut` with multiple scattering: per vertex `k`,
/// the single scattering of `lut` is turned into dual scattering's `F`
/// (`DualScattering::shade_layered_simd`, the same numbers as
/// `DualScattering::shade_layered` vertex by vertex given
/// `Lut::scattering_batch`'s single scattering) from `fibres[k]`, the
/// number of hair fibres between the vertex and the light (>= 0,
/// fractional is fine), `behind[k]`, the
/// number of hair fibres between the vertex and the far side of the hair
/// along the light (>= 0, fractional is fine; an opacity shadow map's last
/// layer's hair count minus the vertex's count), and `direct[k]`, the
/// fraction of the light reaching it unscattered (in [0, 1]; a shadow
/// map's transmittance). The local backscatter comes from the hair behind
/// the vertex: a vertex with nothing behind it gets none. `behind` NULL is
/// infinitely deep hair behind every vertex (`DualScattering::shade_simd`,
/// the same numbers as `DualScattering::shade_batch` given
/// `Lut::scattering_batch`'s single scattering). The result replaces
/// `single * direct` in the lighting (like Marschner's single scattering,
/// it is without the cosine of the light's angle). `ds` must have been
/// built from Marschner tables (`coif_dual_scattering_from_marschner_lut`),
/// best from `lut` itself. Allocates nothing.
///
/// Errors: as `coif_shade_marschner_lut`, and `COIF_ERROR_NULL` (`ds`,
/// `fibres` or `direct`), `COIF_ERROR_NON_FINITE` (a NaN or infinite fibre
/// count, count behind or fraction), `COIF_ERROR_INVALID_ARGUMENT` (a
/// negative fibre count or count behind, a fraction outside [0, 1], `ds`
/// built from pbrt tables; `coif_last_error_message` names the index).
/// Nothing is written.
///
/// # Safety
/// `lut` and `ds` are NULL or live handles; `fibres`, `behind` and
/// `direct` are NULL or point to `count` readable floats; the rest as
/// `coif_shade_marschner_lut`.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_marschner_lut_dual(
    lut: *const CoifMarschnerLut,
    ds: *const CoifDualScattering,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    fibres: *const f32,
    behind: *const f32,
    direct: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_shade_marschner_lut_dual_with(
            lut,
            ds,
            vertices,
            count,
            light_dir,
            eye,
            fibres,
            behind,
            direct,
            out_rgb,
            capacity,
            std::ptr::null(),
        )
    }
}

/// `coif_shade_marschner_lut_dual` with runs of vertices handed out as
/// tasks to `executor` (as `coif_shade_kajiya_kay_with`). The same bytes.
///
/// Errors: as `coif_shade_marschner_lut_dual`, and those of the executor
/// as `coif_shade_kajiya_kay_with`.
///
/// # Safety
/// As `coif_shade_marschner_lut_dual`; `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_marschner_lut_dual_with(
    lut: *const CoifMarschnerLut,
    ds: *const CoifDualScattering,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    fibres: *const f32,
    behind: *const f32,
    direct: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or live handles.
        let lut = &unsafe { handle(lut) }?.lut;
        // SAFETY: as above.
        let ds = unsafe { dual(ds, Model::Marschner) }?;
        // SAFETY: the buffers as the caller's contract says.
        unsafe {
            shade_dual(
                ds,
                vertices,
                count,
                light_dir,
                eye,
                fibres,
                behind,
                direct,
                out_rgb,
                capacity,
                executor,
                &|t, wi, wo| lut.scattering_simd(t, wi, wo),
            )
        }
    })
}

/// `coif_shade_pbrt_table` with multiple scattering, as
/// `coif_shade_marschner_lut_dual`, `fibres`, `behind` and `direct` as
/// there (`behind[k]` the hair fibres between vertex `k` and the far side
/// of the hair along the light: an opacity shadow map's last layer's hair
/// count minus the vertex's; NULL for infinitely deep hair, the same
/// numbers as `DualScattering::shade_batch` given
/// `Table::scattering_batch`'s single scattering). Like pbrt-v3's single
/// scattering the result includes the cosine of the light's angle. `ds`
/// must have been built from pbrt tables
/// (`coif_dual_scattering_from_pbrt_table`), best from `table` itself.
/// Allocates nothing.
///
/// Errors: as `coif_shade_marschner_lut_dual` (`ds` built from Marschner
/// tables is `COIF_ERROR_INVALID_ARGUMENT`).
///
/// # Safety
/// As `coif_shade_marschner_lut_dual`, with `table` for `lut`.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_pbrt_table_dual(
    table: *const CoifPbrtTable,
    ds: *const CoifDualScattering,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    fibres: *const f32,
    behind: *const f32,
    direct: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
) -> CoifStatus {
    // SAFETY: the caller's contract; a NULL executor is the calling thread.
    unsafe {
        coif_shade_pbrt_table_dual_with(
            table,
            ds,
            vertices,
            count,
            light_dir,
            eye,
            fibres,
            behind,
            direct,
            out_rgb,
            capacity,
            std::ptr::null(),
        )
    }
}

/// `coif_shade_pbrt_table_dual` with runs of vertices handed out as tasks
/// to `executor` (as `coif_shade_kajiya_kay_with`). The same bytes.
///
/// Errors: as `coif_shade_marschner_lut_dual_with`.
///
/// # Safety
/// As `coif_shade_pbrt_table_dual`; `executor` as `coif_step_with` says.
#[no_mangle]
pub unsafe extern "C" fn coif_shade_pbrt_table_dual_with(
    table: *const CoifPbrtTable,
    ds: *const CoifDualScattering,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    fibres: *const f32,
    behind: *const f32,
    direct: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
) -> CoifStatus {
    guard(|| {
        // SAFETY: NULL or live handles.
        let table = &unsafe { handle(table) }?.table;
        // SAFETY: as above.
        let ds = unsafe { dual(ds, Model::Pbrt) }?;
        // SAFETY: the buffers as the caller's contract says.
        unsafe {
            shade_dual(
                ds,
                vertices,
                count,
                light_dir,
                eye,
                fibres,
                behind,
                direct,
                out_rgb,
                capacity,
                executor,
                &|t, wi, wo| table.scattering_simd(t, wi, wo),
            )
        }
    })
}

/// The tables behind `ds`, refused unless they were built for `model`.
///
/// # Safety
/// `ds` is NULL or a live handle not written during `'a`.
unsafe fn dual<'a>(
    ds: *const CoifDualScattering,
    model: Model,
) -> Result<&'a DualScattering, CoifStatus> {
    // SAFETY: the caller's contract.
    let h = unsafe { handle(ds) }?;
    if h.model != model {
        set_last_error(&format_args!(
            "the dual scattering tables were built from {}, not {}",
            h.model.name(),
            model.name()
        ));
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    Ok(&h.ds)
}

/// Checks `fibres`, `behind` (NULL: infinitely deep hair) and `direct`
/// (after the checks of [`shade`]), then shades with `single` followed by
/// `ds`.
///
/// # Safety
/// As the public dual shading calls.
#[allow(clippy::too_many_arguments)]
unsafe fn shade_dual(
    ds: &DualScattering,
    vertices: *const CoifRenderVertex,
    count: usize,
    light_dir: *const f32,
    eye: *const f32,
    fibres: *const f32,
    behind: *const f32,
    direct: *const f32,
    out_rgb: *mut f32,
    capacity: usize,
    executor: *const CoifExecutor,
    single: &(dyn Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes + Sync),
) -> Result<(), CoifStatus> {
    if fibres.is_null() || direct.is_null() {
        return Err(CoifStatus::COIF_ERROR_NULL);
    }
    // SAFETY: the caller's contract: `count` readable floats each.
    let (fibres, direct) = unsafe { (crate::input(fibres, count)?, crate::input(direct, count)?) };
    // NULL: infinitely deep hair behind every vertex.
    let behind = if behind.is_null() {
        None
    } else {
        // SAFETY: as above.
        Some(unsafe { crate::input(behind, count) }?)
    };
    let counts = |name: &str, values: &[f32]| {
        for (k, &n) in values.iter().enumerate() {
            if !n.is_finite() || n < 0.0 {
                set_last_error(&format_args!(
                    "{name}[{k}] = {n} (expected a finite fibre count >= 0)"
                ));
                return Err(if n.is_finite() {
                    CoifStatus::COIF_ERROR_INVALID_ARGUMENT
                } else {
                    CoifStatus::COIF_ERROR_NON_FINITE
                });
            }
        }
        Ok(())
    };
    let check = || {
        counts("fibres", fibres)?;
        if let Some(behind) = behind {
            counts("behind", behind)?;
        }
        for (k, &d) in direct.iter().enumerate() {
            if !(0.0..=1.0).contains(&d) {
                set_last_error(&format_args!(
                    "direct[{k}] = {d} (expected a fraction in [0, 1])"
                ));
                return Err(if d.is_finite() {
                    CoifStatus::COIF_ERROR_INVALID_ARGUMENT
                } else {
                    CoifStatus::COIF_ERROR_NON_FINITE
                });
            }
        }
        Ok(())
    };
    let kernel = |first: usize, t, wi, wo| {
        let s = single(t, wi, wo);
        let behind = match behind {
            Some(behind) => load_padded(&behind[first..], 0.0),
            // Every lane infinity: infinitely deep hair (`shade_simd`).
            None => load_padded(&[], f32::INFINITY),
        };
        ds.shade_layered_simd(
            s,
            t,
            wi,
            wo,
            load_padded(&fibres[first..], 0.0),
            behind,
            load_padded(&direct[first..], 0.0),
        )
    };
    // SAFETY: the caller's contract on every pointer.
    unsafe {
        shade(
            vertices, count, light_dir, eye, out_rgb, capacity, executor, &check, &kernel,
        )
    }
}
