/* engine.c: what an engine does with coif each frame, in C99.
 *
 * 1. Guides: 36 strands of 8 vertices on a 6 x 6 grid of roots 1 cm apart,
 *    stepped under gravity; scalp triangles over the grid.
 * 2. LOD: B-spline refinement into a caller buffer (bound first), render
 *    hairs interpolated from the guides into CoifRenderVertex buffers
 *    (distance LOD, bound first).
 * 3. Shading: Kajiya-Kay, Marschner tables and pbrt tables, linear RGB
 *    per vertex; the tables again with dual scattering (multiple
 *    scattering from per-vertex fibre counts and direct fractions).
 * 4. A cloth patch (a 4 x 9 ribbon pinned at its top row) following a
 *    moving skin, blended half and half at its free end.
 * 5. A groom from memory (argv[1], a TressFX .tfx or cyHair .hair file, if
 *    given): counts, a strand's points, simulation strands in metres, and
 *    corrupted copies of its bytes (truncated, lying counts) refused.
 * Every call is checked, and bad input must give its error status and
 * change nothing.
 *
 * Build (from the workspace root, after cargo build --release -p coif-capi):
 *   cc -std=c99 -Wall -Wextra capi/examples/engine.c -Icapi/include \
 *      target/release/libcoif_capi.a -lm -lpthread -ldl -o engine
 *   ./engine shared/data/grooms/sintel_lite.tfx
 * Exit code 0 only if every check passes. */

#include "coif.h"
#include "checks.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GRID 6
#define STRANDS (GRID * GRID)
#define VERTS 8

static void *xmalloc(size_t bytes) {
    void *p = malloc(bytes > 0 ? bytes : 1);
    if (p == NULL) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return p;
}

/* All `n` floats are finite. */
static int all_finite(const float *v, size_t n) {
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(v[k])) return 0;
    }
    return 1;
}

/* All `n` floats equal `value` (a buffer a failed call must not touch). */
static int all_equal(const float *v, size_t n, float value) {
    for (size_t k = 0; k < n; k++) {
        if (v[k] != value) return 0;
    }
    return 1;
}

static CoifStrands *make_guides(void) {
    static float xyz[STRANDS * VERTS * 3];
    for (int j = 0; j < GRID; j++) {
        for (int i = 0; i < GRID; i++) {
            for (int v = 0; v < VERTS; v++) {
                float *p = &xyz[3 * ((j * GRID + i) * VERTS + v)];
                p[0] = 0.01f * (float)i + 0.002f * sinf((float)(v + i));
                p[1] = 1.6f - 0.015f * (float)v;
                p[2] = 0.01f * (float)j + 0.001f * (float)v;
            }
        }
    }
    CoifStrands *s = NULL;
    expect(coif_strands_new(xyz, STRANDS * VERTS, VERTS, &s), COIF_OK, "coif_strands_new");
    return s;
}

static void lod_and_shading(CoifStrands *guides) {
    CoifSimParams params = coif_sim_params_default();
    for (int step = 0; step < 30; step++) {
        expect(coif_step(guides, &params, NULL, 0), COIF_OK, "coif_step");
    }

    /* Refinement: bound, then write. The ends stay the guides' own points. */
    size_t refined = coif_refine_bound(guides, 4);
    check(refined == STRANDS * ((VERTS - 1) * 4 + 1), "refine bound");
    float *xyz = xmalloc(refined * 3 * sizeof(float));
    float *tangents = xmalloc(refined * 3 * sizeof(float));
    float points[STRANDS * VERTS * 3];
    expect(coif_refine(guides, 4, xyz, tangents, refined), COIF_OK, "coif_refine");
    expect(coif_strands_positions(guides, points, STRANDS * VERTS), COIF_OK, "positions");
    check(all_finite(xyz, refined * 3) && all_finite(tangents, refined * 3), "refined finite");
    check(memcmp(&xyz[0], &points[0], 3 * sizeof(float)) == 0, "refined root is the root");
    size_t r = refined / STRANDS;
    check(memcmp(&xyz[3 * (r - 1)], &points[3 * (VERTS - 1)], 3 * sizeof(float)) == 0,
          "refined tip is the tip");
    float len = sqrtf(tangents[0] * tangents[0] + tangents[1] * tangents[1] +
                      tangents[2] * tangents[2]);
    check(fabsf(len - 1.0f) < 1e-5f, "refined tangents are unit");
    for (size_t k = 0; k < refined * 3; k++) xyz[k] = -1.0f;
    expect(coif_refine(guides, 4, xyz, NULL, refined - 1), COIF_ERROR_BUFFER_TOO_SMALL,
           "refine: buffer one point short");
    check(all_equal(xyz, refined * 3, -1.0f), "refine: nothing written into a short buffer");
    expect(coif_refine(guides, 0, xyz, NULL, refined), COIF_ERROR_INVALID_ARGUMENT,
           "refine: 0 segments per span");
    expect(coif_refine(NULL, 4, xyz, NULL, refined), COIF_ERROR_NULL, "refine: NULL handle");
    check(coif_refine_bound(guides, 300) == 0, "refine bound of a level out of range is 0");
    free(xyz);
    free(tangents);

    /* Render hairs on the grid's triangles. */
    uint32_t triangles[(GRID - 1) * (GRID - 1) * 6];
    size_t t = 0;
    for (uint32_t j = 0; j + 1 < GRID; j++) {
        for (uint32_t i = 0; i + 1 < GRID; i++) {
            uint32_t k = j * GRID + i;
            uint32_t tri[6] = {k, k + 1, k + GRID, k + 1, k + GRID + 1, k + GRID};
            memcpy(&triangles[t], tri, sizeof tri);
            t += 6;
        }
    }
    size_t triangle_count = t / 3;
    CoifHairSettings settings = coif_hair_settings_default();
    settings.hairs_per_cm2 = 40.0f;
    settings.max_segments_per_span = 8;
    CoifHairs *hairs = NULL;
    expect(coif_hairs_new(guides, triangles, triangle_count, &settings, &hairs), COIF_OK,
           "coif_hairs_new");
    if (hairs == NULL) return;
    size_t hair_count = coif_hairs_hair_count(hairs);
    check(hair_count > 500 && hair_count < 1500, "about 40 hairs per cm^2 over 25 cm^2");

    size_t groups = 0;
    float width_factor = 0.0f;
    expect(coif_hairs_distance_lod(hairs, 0.5f, 0.1f, &groups, &width_factor), COIF_OK,
           "distance LOD");
    check(groups > 0 && groups < coif_hairs_group_count(hairs), "half a pixel: fewer groups");
    check(width_factor > 1.0f, "fewer hairs, wider");

    size_t bound = coif_hairs_vertex_bound(hairs, 8, groups);
    CoifRenderVertex *vertices = xmalloc(bound * sizeof(CoifRenderVertex));
    size_t written = 0;
    expect(coif_hairs_write_vertices(hairs, guides, 8, groups, width_factor, vertices, bound,
                                     &written),
           COIF_OK, "coif_hairs_write_vertices");
    check(written == bound && written % (7 * 8 + 1) == 0, "whole hairs of 57 vertices");
    int vertices_ok = 1;
    for (size_t k = 0; k < written; k++) {
        const CoifRenderVertex *v = &vertices[k];
        float tl = sqrtf(v->tangent[0] * v->tangent[0] + v->tangent[1] * v->tangent[1] +
                         v->tangent[2] * v->tangent[2]);
        vertices_ok &= all_finite(v->position, 3) && fabsf(tl - 1.0f) < 1e-4f &&
                       v->width > 0.0f && v->strand_parameter >= 0.0f &&
                       v->strand_parameter <= 1.0f;
    }
    check(vertices_ok, "render vertices finite, unit tangents, widths > 0, s in [0, 1]");
    check(vertices[0].strand_parameter == 0.0f && vertices[56].strand_parameter == 1.0f,
          "s runs from 0 at the root to 1 at the tip");
    double origin[3];
    expect(coif_strands_origin(guides, origin), COIF_OK, "origin");
    check(fabs(origin[1] - 1.6) < 1e-6, "origin at the mean root");

    size_t saved_written = written;
    expect(coif_hairs_write_vertices(hairs, guides, 8, groups, width_factor, vertices,
                                     bound - 1, &written),
           COIF_ERROR_BUFFER_TOO_SMALL, "vertices: buffer one vertex short");
    check(written == saved_written, "written untouched on error");
    expect(coif_hairs_write_vertices(hairs, guides, 9, groups, width_factor, vertices, bound,
                                     NULL),
           COIF_ERROR_INVALID_ARGUMENT, "vertices: level above the settings' maximum");
    expect(coif_hairs_write_vertices(hairs, guides, 8, groups, NAN, vertices, bound, NULL),
           COIF_ERROR_NON_FINITE, "vertices: NaN width factor");
    uint32_t bad_triangle[3] = {0, 1, STRANDS};
    CoifHairs *bad = hairs;
    expect(coif_hairs_new(guides, bad_triangle, 1, &settings, &bad), COIF_ERROR_INVALID_ARGUMENT,
           "hairs: a triangle naming a guide that does not exist");
    check(bad == NULL, "hairs: *out NULL on error");

    /* Shading: a light above and in front, the eye in front (vertex frame). */
    float light[3] = {0.3f, 1.0f, 0.6f};
    float eye[3] = {0.02f, 0.0f, 1.0f};
    float *rgb = xmalloc(written * 3 * sizeof(float));
    CoifKajiyaKay kk = coif_kajiya_kay_default();
    expect(coif_shade_kajiya_kay(&kk, vertices, written, light, eye, rgb, written), COIF_OK,
           "Kajiya-Kay");
    int lit = 0, shading_ok = all_finite(rgb, written * 3);
    for (size_t k = 0; k < written * 3; k++) {
        shading_ok &= rgb[k] >= 0.0f;
        lit |= rgb[k] > 0.0f;
    }
    check(shading_ok && lit, "Kajiya-Kay colours finite, >= 0, some lit");
    CoifMarschnerParams mp = coif_marschner_params_default();
    CoifMarschnerLut *lut = NULL;
    expect(coif_marschner_lut_new(&mp, 32, &lut), COIF_OK, "Marschner tables");
    expect(coif_shade_marschner_lut(lut, vertices, written, light, eye, rgb, written), COIF_OK,
           "Marschner");
    check(all_finite(rgb, written * 3), "Marschner colours finite");
    CoifPbrtParams pp = coif_pbrt_params_default();
    CoifPbrtTable *table = NULL;
    expect(coif_pbrt_table_new(&pp, 16, &table), COIF_OK, "pbrt tables");
    expect(coif_shade_pbrt_table(table, vertices, written, light, eye, rgb, written), COIF_OK,
           "pbrt");
    check(all_finite(rgb, written * 3), "pbrt colours finite");

    /* Dual scattering: tables once per material; per vertex the fibres
     * between it and the light, the fibres behind it (between it and the
     * far side of the hair; NULL for infinitely deep hair) and the light
     * reaching it unscattered (an engine takes all three from its opacity
     * shadow map: the vertex's hair count, the last layer's count minus
     * the vertex's, the transmittance). */
    CoifDualScatteringSettings ds_settings = coif_dual_scattering_settings_default();
    ds_settings.resolution = 16;
    CoifDualScattering *ds_lut = NULL, *ds_table = NULL;
    expect(coif_dual_scattering_from_marschner_lut(lut, &ds_settings, &ds_lut), COIF_OK,
           "dual scattering tables (Marschner)");
    expect(coif_dual_scattering_from_pbrt_table(table, &ds_settings, &ds_table), COIF_OK,
           "dual scattering tables (pbrt)");
    float *fibres = xmalloc(written * sizeof(float));
    float *behind = xmalloc(written * sizeof(float));
    float *direct = xmalloc(written * sizeof(float));
    float *rgb_deep = xmalloc(written * 3 * sizeof(float));
    for (size_t k = 0; k < written; k++) {
        fibres[k] = (float)(k % 20);           /* deeper into the hair */
        behind[k] = 19.0f - fibres[k];         /* the last layer holds 19 */
        direct[k] = expf(-0.3f * fibres[k]);   /* the map's transmittance */
    }
    expect(coif_shade_marschner_lut_dual(lut, ds_lut, vertices, written, light, eye, fibres,
                                         behind, direct, rgb, written),
           COIF_OK, "Marschner + dual scattering");
    check(all_finite(rgb, written * 3), "Marschner + dual scattering colours finite");
    expect(coif_shade_marschner_lut_dual(lut, ds_lut, vertices, written, light, eye, fibres,
                                         NULL, direct, rgb_deep, written),
           COIF_OK, "Marschner + dual scattering, deep hair");
    int shallower = 1;
    for (size_t k = 0; k < written * 3; k++) shallower &= rgb[k] <= rgb_deep[k];
    check(shallower, "dual: no more backscatter than infinitely deep hair");
    expect(coif_shade_pbrt_table_dual(table, ds_table, vertices, written, light, eye, fibres,
                                      behind, direct, rgb, written),
           COIF_OK, "pbrt + dual scattering");
    check(all_finite(rgb, written * 3), "pbrt + dual scattering colours finite");
    for (size_t k = 0; k < written * 3; k++) rgb[k] = -1.0f;
    expect(coif_shade_pbrt_table_dual(table, ds_lut, vertices, written, light, eye, fibres,
                                      behind, direct, rgb, written),
           COIF_ERROR_INVALID_ARGUMENT, "dual: tables of another model");
    behind[0] = -1.0f;
    expect(coif_shade_pbrt_table_dual(table, ds_table, vertices, written, light, eye, fibres,
                                      behind, direct, rgb, written),
           COIF_ERROR_INVALID_ARGUMENT, "dual: a negative count behind");
    check(strstr(coif_last_error_message(), "behind[0]") != NULL,
          "dual: the message names the count behind");
    behind[0] = 0.0f;
    direct[written - 1] = 1.5f;
    expect(coif_shade_marschner_lut_dual(lut, ds_lut, vertices, written, light, eye, fibres,
                                         behind, direct, rgb, written),
           COIF_ERROR_INVALID_ARGUMENT, "dual: a direct fraction above 1");
    check(strstr(coif_last_error_message(), "direct[") != NULL, "dual: the message names it");
    expect(coif_shade_marschner_lut_dual(lut, ds_lut, vertices, written, light, eye, NULL,
                                         behind, direct, rgb, written),
           COIF_ERROR_NULL, "dual: NULL fibres");
    check(all_equal(rgb, written * 3, -1.0f), "dual: nothing written by failed calls");
    ds_settings.forward_density = 0.0f;
    CoifDualScattering *bad_ds = ds_lut;
    expect(coif_dual_scattering_from_marschner_lut(lut, &ds_settings, &bad_ds),
           COIF_ERROR_INVALID_ARGUMENT, "dual scattering tables: forward density 0");
    check(bad_ds == NULL, "dual scattering tables: *out NULL on error");
    check(strstr(coif_last_error_message(), "forward_density") != NULL,
          "dual scattering tables: the message names the setting");
    coif_dual_scattering_free(ds_lut);
    coif_dual_scattering_free(ds_table);
    free(fibres);
    free(behind);
    free(direct);
    free(rgb_deep);
    pp.beta_n = 2.0f;
    CoifPbrtTable *bad_table = table;
    expect(coif_pbrt_table_new(&pp, 16, &bad_table), COIF_ERROR_INVALID_ARGUMENT,
           "pbrt tables: beta_n 2");
    check(bad_table == NULL, "pbrt tables: *out NULL on error");
    coif_pbrt_table_free(table);

    for (size_t k = 0; k < written * 3; k++) rgb[k] = -1.0f;
    float nan_light[3] = {0.0f, NAN, 1.0f};
    float zero_light[3] = {0.0f, 0.0f, 0.0f};
    expect(coif_shade_kajiya_kay(&kk, vertices, written, nan_light, eye, rgb, written),
           COIF_ERROR_NON_FINITE, "shade: NaN light");
    expect(coif_shade_kajiya_kay(&kk, vertices, written, zero_light, eye, rgb, written),
           COIF_ERROR_INVALID_ARGUMENT, "shade: zero light direction");
    expect(coif_shade_marschner_lut(lut, vertices, written, light, eye, rgb, written - 1),
           COIF_ERROR_BUFFER_TOO_SMALL, "shade: buffer one vertex short");
    expect(coif_shade_marschner_lut(lut, NULL, written, light, eye, rgb, written),
           COIF_ERROR_NULL, "shade: NULL vertices");
    vertices[3].tangent[0] = NAN;
    expect(coif_shade_kajiya_kay(&kk, vertices, written, light, eye, rgb, written),
           COIF_ERROR_NON_FINITE, "shade: a NaN tangent");
    check(all_equal(rgb, written * 3, -1.0f), "shade: nothing written by failed calls");
    mp.eta = 0.5f;
    CoifMarschnerLut *bad_lut = lut;
    expect(coif_marschner_lut_new(&mp, 32, &bad_lut), COIF_ERROR_INVALID_ARGUMENT,
           "tables: eta below 1");
    check(bad_lut == NULL, "tables: *out NULL on error");

    printf("engine: %zu hairs, %zu of %zu groups drawn, %zu vertices shaded\n", hair_count,
           groups, coif_hairs_group_count(hairs), written);
    coif_marschner_lut_free(lut);
    free(rgb);
    free(vertices);
    coif_hairs_free(hairs);
}

#define PATCH_ROWS 4
#define PATCH_COLS 9
#define PATCH_N (PATCH_ROWS * PATCH_COLS)

static void cloth(void) {
    float grid[PATCH_N * 3], skin[PATCH_N * 3], blended[PATCH_N * 3], weights[PATCH_N];
    uint8_t pinned[PATCH_N];
    for (int k = 0; k < PATCH_N; k++) {
        int r = k / PATCH_COLS, c = k % PATCH_COLS;
        grid[3 * k + 0] = 0.02f * (float)c;
        grid[3 * k + 1] = 1.5f - 0.02f * (float)r;
        grid[3 * k + 2] = 0.0f;
        pinned[k] = r == 0;
        weights[k] = r == PATCH_ROWS - 1 ? 0.5f : 1.0f;
    }
    CoifPatch *patch = NULL;
    expect(coif_patch_new(grid, PATCH_ROWS, PATCH_COLS, pinned, &patch), COIF_OK,
           "coif_patch_new");
    if (patch == NULL) return;
    check(coif_patch_particle_count(patch) == PATCH_N, "patch particle count");
    expect(coif_patch_set_weights(patch, weights, PATCH_N), COIF_OK, "patch weights");
    float reach[PATCH_N];
    for (int k = 0; k < PATCH_N; k++) reach[k] = k % 2 == 0 ? 0.05f : INFINITY;
    expect(coif_patch_set_max_distances(patch, reach, PATCH_N), COIF_OK, "patch max distances");
    expect(coif_patch_set_shear_stiffness(patch, 0.1f), COIF_OK, "patch shear");
    CoifSimParams params = coif_sim_params_default();
    CoifSphere body = {{0.08f, 1.3f, 0.05f}, 0.05f};
    for (int frame = 0; frame < 60; frame++) {
        memcpy(skin, grid, sizeof skin);
        for (int k = 0; k < PATCH_N; k++) skin[3 * k + 2] = 0.001f * (float)frame;
        expect(coif_patch_set_skinned(patch, skin, PATCH_N), COIF_OK, "patch skin");
        expect(coif_patch_step(patch, &params, &body, 1), COIF_OK, "patch step");
    }
    expect(coif_patch_blended(patch, blended, PATCH_N), COIF_OK, "patch blended");
    check(all_finite(blended, PATCH_N * 3), "patch finite");
    check(memcmp(blended, skin, 3 * PATCH_COLS * sizeof(float)) == 0,
          "pinned row on the skin exactly");
    check(blended[3 * (PATCH_N - 1) + 1] < grid[3 * (PATCH_N - 1) + 1] + 1e-3f,
          "the free end does not rise");

    float before[PATCH_N * 3];
    memcpy(before, blended, sizeof before);
    weights[5] = 2.0f;
    expect(coif_patch_set_weights(patch, weights, PATCH_N), COIF_ERROR_INVALID_ARGUMENT,
           "patch: weight 2");
    expect(coif_patch_set_skinned(patch, skin, PATCH_N - 1), COIF_ERROR_COUNT_MISMATCH,
           "patch: one skinned point short");
    skin[4] = NAN;
    expect(coif_patch_set_skinned(patch, skin, PATCH_N), COIF_ERROR_NON_FINITE, "patch: NaN skin");
    expect(coif_patch_blended(patch, blended, PATCH_N - 1), COIF_ERROR_BUFFER_TOO_SMALL,
           "patch: buffer one point short");
    expect(coif_patch_blended(patch, blended, PATCH_N), COIF_OK, "patch blended again");
    check(memcmp(before, blended, sizeof before) == 0, "patch: failed calls changed nothing");
    expect(coif_patch_set_shear_stiffness(patch, 1.5f), COIF_ERROR_INVALID_ARGUMENT,
           "patch: shear 1.5");
    reach[3] = -1.0f;
    expect(coif_patch_set_max_distances(patch, reach, PATCH_N), COIF_ERROR_INVALID_ARGUMENT,
           "patch: negative max distance");
    expect(coif_patch_reset_to_skin(patch), COIF_OK, "patch reset to skin");
    expect(coif_patch_positions(patch, blended, PATCH_N), COIF_OK, "patch positions");
    skin[4] = grid[4];
    check(memcmp(blended, skin, sizeof blended) == 0, "after a reset the patch is its skin");
    CoifPatch *bad = patch;
    expect(coif_patch_new(grid, 1, PATCH_N, pinned, &bad), COIF_ERROR_INVALID_ARGUMENT,
           "patch: one row");
    check(bad == NULL, "patch: *out NULL on error");
    printf("cloth: %d x %d patch, 60 steps\n", PATCH_ROWS, PATCH_COLS);
    coif_patch_free(patch);
}

static void groom_from_file(const char *path) {
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "FAIL: cannot open %s\n", path);
        failures++;
        return;
    }
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *bytes = xmalloc((size_t)size);
    size_t len = fread(bytes, 1, (size_t)size, f);
    fclose(f);

    CoifGroom *groom = NULL;
    expect(coif_groom_load(bytes, len, &groom), COIF_OK, "coif_groom_load");
    if (groom == NULL) {
        free(bytes);
        return;
    }
    size_t strands = coif_groom_strand_count(groom);
    size_t vertices = coif_groom_vertex_count(groom);
    check(strands > 0 && vertices >= 2 * strands, "groom counts");
    size_t n = coif_groom_strand_vertex_count(groom, 0);
    float *points = xmalloc(n * 3 * sizeof(float));
    expect(coif_groom_strand_points(groom, 0, points, n), COIF_OK, "groom strand points");
    check(all_finite(points, n * 3), "groom points finite");
    expect(coif_groom_strand_points(groom, strands, points, n), COIF_ERROR_INVALID_ARGUMENT,
           "groom: strand out of range");
    free(points);

    /* Every 10th strand as a guide of 16 vertices, centimetres to metres. */
    CoifStrands *hair = NULL;
    expect(coif_strands_from_groom(groom, 10, 16, 0.01f, &hair), COIF_OK,
           "coif_strands_from_groom");
    coif_groom_free(groom); /* the strands do not need the groom */
    if (hair != NULL) {
        size_t guides = coif_strands_strand_count(hair);
        check(guides == (strands + 9) / 10, "one guide per 10 strands");
        CoifSimParams params = coif_sim_params_default();
        for (int step = 0; step < 60; step++) {
            expect(coif_step(hair, &params, NULL, 0), COIF_OK, "groom step");
        }
        size_t count = coif_strands_point_count(hair);
        float *xyz = xmalloc(count * 3 * sizeof(float));
        expect(coif_strands_positions(hair, xyz, count), COIF_OK, "groom positions");
        check(all_finite(xyz, count * 3), "groom strands finite after 60 steps");
        printf("groom: %zu strands, %zu vertices; %zu guides of 16 stepped 60 times\n", strands,
               vertices, guides);
        free(xyz);
        coif_strands_free(hair);
    }

    /* Corrupted copies: refused, *out NULL. */
    CoifGroom *bad = (CoifGroom *)1;
    /* (Cut in half: a file may carry data after the points, so one byte less may still load.) */
    expect(coif_groom_load(bytes, len / 2, &bad), COIF_ERROR_BAD_DATA, "groom: truncated");
    check(bad == NULL, "groom: *out NULL on error");
    expect(coif_groom_load(bytes, 100, &bad), COIF_ERROR_BAD_DATA, "groom: cut in the header");
    uint8_t saved[4];
    memcpy(saved, bytes + 4, 4);
    memset(bytes + 4, 0xff, 4); /* TressFX: strand count 2^32 - 1 */
    expect(coif_groom_load(bytes, len, &bad), COIF_ERROR_BAD_DATA, "groom: lying strand count");
    memcpy(bytes + 4, saved, 4);
    memset(bytes, 0, 4); /* neither TressFX 4 nor cyHair */
    expect(coif_groom_load(bytes, len, &bad), COIF_ERROR_BAD_DATA, "groom: unknown format");
    expect(coif_groom_load(NULL, len, &bad), COIF_ERROR_NULL, "groom: NULL bytes");
    check(bad == NULL, "groom: *out NULL after every error");
    free(bytes);
}

int main(int argc, char **argv) {
    check(sizeof(CoifRenderVertex) == 32, "CoifRenderVertex is 32 bytes");
    CoifStrands *guides = make_guides();
    if (guides == NULL) return 1;
    lod_and_shading(guides);
    coif_strands_free(guides);
    cloth();
    if (argc > 1) {
        groom_from_file(argv[1]);
    } else {
        printf("groom: no file given, skipped\n");
    }
    check(strcmp(coif_status_message_code(12345), "unknown status") == 0,
          "a status outside the enum has a message");
    check(coif_status_message_code(COIF_ERROR_BAD_DATA) == coif_status_message(COIF_ERROR_BAD_DATA),
          "a status inside the enum has its own message");
    if (failures != 0) {
        fprintf(stderr, "engine: %d checks failed\n", failures);
        return 1;
    }
    printf("engine: all checks passed\n");
    return 0;
}
