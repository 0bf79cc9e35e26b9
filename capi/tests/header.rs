//! The committed header `include/coif.h` is what cbindgen generates from
//! `src/lib.rs` with `cbindgen.toml` now (a header check in the manner of
//! hyper's C API). `COIF_BLESS=1` rewrites the header instead of failing.
//! (cbindgen's `style = "both"` spells the uses `struct CoifStrands *`,
//! `enum CoifStatus`: the same C types as the typedef names.)

use std::path::Path;

fn generate() -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen generates the header");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("UTF-8 header")
}

#[test]
fn header_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/coif.h");
    let generated = generate();
    if std::env::var_os("COIF_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write include/coif.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "capi/include/coif.h differs from what cbindgen generates from capi/src/lib.rs.\n\
         Regenerate it with:\n    COIF_BLESS=1 cargo test -p coif-capi --release --test header\n\
         and commit the result."
    );
}

#[test]
fn header_declares_the_c_names() {
    let h = generate();
    for name in [
        "typedef struct CoifStrands CoifStrands;",
        "typedef enum CoifStatus",
        "COIF_OK = 0",
        "COIF_ERROR_NULL",
        "COIF_ERROR_INVALID_ARGUMENT",
        "COIF_ERROR_NON_FINITE",
        "COIF_ERROR_BUFFER_TOO_SMALL",
        "COIF_ERROR_COUNT_MISMATCH",
        "COIF_ERROR_PANIC",
        "typedef struct CoifSimParams",
        "typedef struct CoifSphere",
        "struct CoifSimParams coif_sim_params_default(void);",
        "enum CoifStatus coif_strands_new(const float *xyz,",
        "void coif_strands_free(struct CoifStrands *s);",
        "size_t coif_strands_strand_count(const struct CoifStrands *s);",
        "enum CoifStatus coif_strands_set_roots(struct CoifStrands *s, const float *xyz, size_t root_count);",
        "enum CoifStatus coif_step(struct CoifStrands *s,",
        "enum CoifStatus coif_strands_positions(const struct CoifStrands *s,",
        "const char *coif_status_message(enum CoifStatus status);",
        "const char *coif_status_message_code(int32_t code);",
        "COIF_ERROR_BAD_DATA = 7",
        "typedef struct CoifGroom CoifGroom;",
        "typedef struct CoifHairs CoifHairs;",
        "typedef struct CoifMarschnerLut CoifMarschnerLut;",
        "typedef struct CoifRenderVertex {",
        "enum CoifStatus coif_groom_load(const uint8_t *bytes, size_t len, struct CoifGroom **out);",
        "size_t coif_refine_bound(const struct CoifStrands *s, size_t segments_per_span);",
        "size_t coif_hairs_vertex_bound(const struct CoifHairs *h,",
        "enum CoifStatus coif_hairs_write_vertices(struct CoifHairs *h,",
        "enum CoifStatus coif_shade_kajiya_kay(const struct CoifKajiyaKay *model,",
        "enum CoifStatus coif_shade_marschner_lut(const struct CoifMarschnerLut *lut,",
        "static_assert(sizeof(CoifRenderVertex) == 32",
        "typedef struct CoifPatch CoifPatch;",
        "typedef struct CoifPbrtTable CoifPbrtTable;",
        "enum CoifStatus coif_shade_pbrt_table(const struct CoifPbrtTable *table,",
        "typedef struct CoifDualScattering CoifDualScattering;",
        "typedef struct CoifDualScatteringSettings {",
        "struct CoifDualScatteringSettings coif_dual_scattering_settings_default(void);",
        "enum CoifStatus coif_dual_scattering_from_marschner_lut(const struct CoifMarschnerLut *lut,",
        "enum CoifStatus coif_dual_scattering_from_pbrt_table(const struct CoifPbrtTable *table,",
        "void coif_dual_scattering_free(struct CoifDualScattering *ds);",
        "enum CoifStatus coif_shade_marschner_lut_dual(const struct CoifMarschnerLut *lut,",
        "enum CoifStatus coif_shade_marschner_lut_dual_with(const struct CoifMarschnerLut *lut,",
        "enum CoifStatus coif_shade_pbrt_table_dual(const struct CoifPbrtTable *table,",
        "enum CoifStatus coif_shade_pbrt_table_dual_with(const struct CoifPbrtTable *table,",
        "enum CoifStatus coif_patch_step(struct CoifPatch *p,",
        "enum CoifStatus coif_patch_blended(const struct CoifPatch *p,",
        "typedef char coif_render_vertex_is_32_bytes[sizeof(CoifRenderVertex) == 32 ? 1 : -1];",
        "typedef struct CoifCapsule {",
        "typedef struct CoifSdf CoifSdf;",
        "typedef struct CoifSdfSet CoifSdfSet;",
        "float wind[3];",
        "float static_friction;",
        "float turbulence_period;",
        "float root_exit;",
        "float volume_stiffness;",
        "float hair_friction;",
        "enum CoifStatus coif_sdf_new(const float *xyz,",
        "void coif_sdf_free(struct CoifSdf *sdf);",
        "enum CoifStatus coif_sdf_set_transform(struct CoifSdf *sdf, const float *world_from_mesh);",
        "enum CoifStatus coif_sdf_distance(const struct CoifSdf *sdf, const float *p, float *out);",
        "enum CoifStatus coif_sdf_set_new(struct CoifSdfSet **out);",
        "enum CoifStatus coif_sdf_set_add(struct CoifSdfSet *set, struct CoifSdf **sdf, size_t *out_index);",
        "enum CoifStatus coif_step_colliders(struct CoifStrands *s,",
        "enum CoifStatus coif_step_colliders_with(struct CoifStrands *s,",
        "typedef struct CoifGpuGuideVertex {",
        "typedef struct CoifGpuRenderHair {",
        "typedef struct CoifGpuHairView {",
        "float clip_from_world[4][4];",
        "struct CoifGpuHairView coif_gpu_hair_view_default(void);",
        "enum CoifStatus coif_gpu_pack_guides(const struct CoifStrands *s,",
        "enum CoifStatus coif_gpu_pack_hairs(const struct CoifHairs *h,",
        "size_t coif_gpu_render_hair_count(const struct CoifHairs *h, size_t groups_drawn);",
        "static_assert(sizeof(CoifGpuHairView) == 192",
        "typedef char coif_gpu_hair_view_is_192_bytes[sizeof(CoifGpuHairView) == 192 ? 1 : -1];",
        "#ifndef COIF_H",
        "extern \"C\" {",
        "#include <stdint.h>",
        "#include <stddef.h>",
    ] {
        assert!(h.contains(name), "coif.h lacks `{name}`:\n{h}");
    }
}

#[test]
fn dual_shading_takes_the_counts_behind_after_the_fibres() {
    let h = generate();
    for name in [
        "coif_shade_marschner_lut_dual(",
        "coif_shade_marschner_lut_dual_with(",
        "coif_shade_pbrt_table_dual(",
        "coif_shade_pbrt_table_dual_with(",
    ] {
        let start = h.find(&format!("enum CoifStatus {name}")).expect(name);
        let end = start + h[start..].find(");").expect("the declaration ends");
        let params: Vec<&str> = h[start + 16 + name.len()..end]
            .split(',')
            .map(str::trim)
            .collect();
        let at = params
            .iter()
            .position(|p| *p == "const float *fibres")
            .expect("fibres");
        assert_eq!(
            params[at..at + 3],
            [
                "const float *fibres",
                "const float *behind",
                "const float *direct"
            ],
            "{name}"
        );
    }
}
