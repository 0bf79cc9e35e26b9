/* hang.c: 64 strands of 16 vertices (1 cm segments) hang straight down from
 * an 8 x 8 grid of roots; 600 steps with the default parameters. Checks that
 * every point stays finite, that each tip stays within 1 mm (sideways) of
 * directly below its root and within the strain limit of its rest length,
 * and that bad input returns an error status and changes nothing.
 *
 * Build (from the workspace root, after cargo build --release -p coif-capi):
 *   cc -std=c99 -Wall -Wextra capi/examples/hang.c -Icapi/include \
 *      target/release/libcoif_capi.a -lm -lpthread -ldl -o hang
 * Exit code 0 only if every check passes. */

#include "coif.h"
#include "checks.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STRANDS 64
#define VERTS 16
#define POINTS (STRANDS * VERTS)
#define SEGMENT 0.01f

static float points[POINTS * 3];
static float roots[STRANDS * 3];
static float before[POINTS * 3];
static float after[POINTS * 3];

/* Positions now equal `before` bit for bit (a failed call changed nothing). */
static void expect_unchanged(const CoifStrands *s, const char *what) {
    expect(coif_strands_positions(s, after, POINTS), COIF_OK, "positions after a failed call");
    check(memcmp(before, after, sizeof before) == 0, what);
}

int main(void) {
    for (int i = 0; i < STRANDS; i++) {
        float x = 0.02f * (float)(i % 8), z = 0.02f * (float)(i / 8), y = 1.5f;
        roots[3 * i + 0] = x;
        roots[3 * i + 1] = y;
        roots[3 * i + 2] = z;
        for (int v = 0; v < VERTS; v++) {
            float *p = &points[3 * (i * VERTS + v)];
            p[0] = x;
            p[1] = y - SEGMENT * (float)v;
            p[2] = z;
        }
    }

    CoifStrands *s = NULL;
    expect(coif_strands_new(points, POINTS, VERTS, &s), COIF_OK, "coif_strands_new");
    if (s == NULL) {
        fprintf(stderr, "FAIL: no handle\n");
        return 1;
    }
    check(coif_strands_strand_count(s) == STRANDS, "strand count");
    check(coif_strands_point_count(s) == POINTS, "point count");

    CoifSimParams params = coif_sim_params_default();
    expect(coif_sim_params_validate(&params), COIF_OK, "default params validate");
    CoifSphere head = {{0.07f, 1.0f, 0.07f}, 0.05f}; /* far below the tips */
    for (int step = 0; step < 600; step++) {
        expect(coif_step(s, &params, &head, 1), COIF_OK, "coif_step");
    }
    expect(coif_strands_positions(s, before, POINTS), COIF_OK, "coif_strands_positions");

    int finite = 1;
    float worst_side = 0.0f, worst_stretch = 0.0f;
    for (int k = 0; k < POINTS * 3; k++) {
        finite &= isfinite(before[k]) ? 1 : 0;
    }
    for (int i = 0; i < STRANDS; i++) {
        const float *r = &before[3 * (i * VERTS)];
        const float *t = &before[3 * (i * VERTS + VERTS - 1)];
        float side = hypotf(t[0] - r[0], t[2] - r[2]);
        float stretch = fabsf((r[1] - t[1]) - SEGMENT * (VERTS - 1)) / (SEGMENT * (VERTS - 1));
        if (side > worst_side) worst_side = side;
        if (stretch > worst_stretch) worst_stretch = stretch;
        /* Positions are kept relative to the mean root: world coordinates
           come back within float rounding. */
        check(fabsf(r[0] - roots[3 * i]) < 1e-6f && fabsf(r[1] - roots[3 * i + 1]) < 1e-6f &&
                  fabsf(r[2] - roots[3 * i + 2]) < 1e-6f,
              "roots stay pinned");
    }
    check(finite, "every point finite after 600 steps");
    check(worst_side < 0.001f, "every tip within 1 mm sideways of below its root");
    check(worst_stretch <= 0.0101f, "every strand within the 1 % strain limit");
    printf("hang: 64 strands x 16 vertices, 600 steps: tip sideways %.3g m, stretch %.3g\n",
           (double)worst_side, (double)worst_stretch);

    /* Bad input: an error status, and nothing changes. */
    CoifStrands *bad = s;
    expect(coif_strands_new(NULL, POINTS, VERTS, &bad), COIF_ERROR_NULL, "new: NULL xyz");
    check(bad == NULL, "new: *out NULL on error");
    expect(coif_strands_new(points, POINTS, VERTS, NULL), COIF_ERROR_NULL, "new: NULL out");
    expect(coif_strands_new(points, POINTS - 1, VERTS, &bad), COIF_ERROR_COUNT_MISMATCH,
           "new: points not a whole number of strands");
    check(bad == NULL, "new: *out NULL on count mismatch");
    expect(coif_strands_new(points, POINTS, 1, &bad), COIF_ERROR_INVALID_ARGUMENT,
           "new: one vertex per strand");
    expect(coif_strands_new(points, 0, VERTS, &bad), COIF_ERROR_INVALID_ARGUMENT, "new: no points");
    float saved = points[7];
    points[7] = NAN;
    expect(coif_strands_new(points, POINTS, VERTS, &bad), COIF_ERROR_NON_FINITE, "new: NaN point");
    check(bad == NULL, "new: *out NULL on NaN");
    points[7] = saved;

    expect(coif_strands_positions(NULL, after, POINTS), COIF_ERROR_NULL, "positions: NULL handle");
    expect(coif_strands_positions(s, NULL, POINTS), COIF_ERROR_NULL, "positions: NULL buffer");
    memset(after, 0, sizeof after);
    expect(coif_strands_positions(s, after, POINTS - 1), COIF_ERROR_BUFFER_TOO_SMALL,
           "positions: buffer one point short");
    {
        int untouched = 1;
        for (int k = 0; k < POINTS * 3; k++) untouched &= after[k] == 0.0f;
        check(untouched, "positions: nothing written into a too-small buffer");
    }

    expect(coif_strands_set_roots(s, roots, STRANDS - 1), COIF_ERROR_COUNT_MISMATCH,
           "set_roots: one root short");
    expect_unchanged(s, "set_roots with a wrong count changed nothing");
    expect(coif_strands_set_roots(s, NULL, STRANDS), COIF_ERROR_NULL, "set_roots: NULL xyz");
    expect(coif_strands_set_roots(NULL, roots, STRANDS), COIF_ERROR_NULL, "set_roots: NULL handle");
    saved = roots[5];
    roots[5] = NAN;
    expect(coif_strands_set_roots(s, roots, STRANDS), COIF_ERROR_NON_FINITE, "set_roots: NaN root");
    roots[5] = saved;
    expect_unchanged(s, "set_roots with a NaN changed nothing");

    CoifSimParams nan_params = params;
    nan_params.dt = NAN;
    expect(coif_sim_params_validate(&nan_params), COIF_ERROR_NON_FINITE, "validate: NaN dt");
    expect(coif_step(s, &nan_params, NULL, 0), COIF_ERROR_NON_FINITE, "step: NaN dt");
    nan_params = params;
    nan_params.gravity[1] = NAN;
    expect(coif_step(s, &nan_params, NULL, 0), COIF_ERROR_NON_FINITE, "step: NaN gravity");
    nan_params = params;
    nan_params.damping = 2.0f;
    expect(coif_step(s, &nan_params, NULL, 0), COIF_ERROR_INVALID_ARGUMENT, "step: damping 2");
    expect(coif_step(s, NULL, NULL, 0), COIF_ERROR_NULL, "step: NULL params");
    expect(coif_step(NULL, &params, NULL, 0), COIF_ERROR_NULL, "step: NULL handle");
    expect(coif_step(s, &params, NULL, 1), COIF_ERROR_NULL, "step: NULL spheres");
    CoifSphere nan_sphere = {{0.0f, NAN, 0.0f}, 0.1f};
    expect(coif_step(s, &params, &nan_sphere, 1), COIF_ERROR_NON_FINITE, "step: NaN sphere");
    expect_unchanged(s, "failed steps changed nothing");

    float shear[12] = {1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    expect(coif_strands_teleport(s, shear), COIF_ERROR_INVALID_ARGUMENT, "teleport: a shear");
    shear[3] = NAN;
    expect(coif_strands_teleport(s, shear), COIF_ERROR_NON_FINITE, "teleport: NaN");
    expect(coif_strands_teleport(s, NULL), COIF_ERROR_NULL, "teleport: NULL");
    expect_unchanged(s, "failed teleports changed nothing");

    /* A valid teleport moves everything by the translation. */
    const float move[12] = {1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0};
    expect(coif_strands_teleport(s, move), COIF_OK, "teleport: 2 m along x");
    expect(coif_strands_positions(s, after, POINTS), COIF_OK, "positions after teleport");
    check(fabsf(after[0] - before[0] - 2.0f) < 1e-5f, "teleport moved the first root by 2 m");
    expect(coif_strands_reset_to_rest(s), COIF_OK, "reset_to_rest");
    expect(coif_strands_reset_to_rest(NULL), COIF_ERROR_NULL, "reset_to_rest: NULL");

    check(coif_strands_strand_count(NULL) == 0, "strand_count(NULL) is 0");
    check(coif_strands_point_count(NULL) == 0, "point_count(NULL) is 0");
    check(coif_status_message(COIF_ERROR_PANIC) != NULL, "status message never NULL");
    coif_strands_free(s);
    coif_strands_free(NULL);

    if (failures != 0) {
        fprintf(stderr, "hang: %d checks failed\n", failures);
        return 1;
    }
    printf("hang: all checks passed\n");
    return 0;
}
