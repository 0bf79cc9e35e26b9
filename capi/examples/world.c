/* world.c: hair in the world around it, from C99. 24 strands hang from a
 * line; wind blows them (+x) over a capsule (a shoulder) onto a mesh given
 * as vertex and index arrays (an octahedron, built here into a signed
 * distance field and placed by a rigid transform that turns it each
 * frame). Checks: the tips end downwind, no vertex is inside the capsule
 * or the field; then the bad inputs of the new calls.
 *
 * Build (from the workspace root, after cargo build --release -p coif-capi):
 *   cc -std=c99 -Wall -Wextra capi/examples/world.c -Icapi/include
 *      target/release/libcoif_capi.a -lm -lpthread -ldl -o world
 */

#include "checks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STRANDS 24
#define VERTS 12
#define POINTS (STRANDS * VERTS)

/* An octahedron of half-diagonal r about the origin: 6 vertices, 8
 * triangles counter-clockwise seen from outside. */
static void octahedron(float r, float xyz[18], uint32_t idx[24]) {
    static const uint32_t tris[24] = {0, 2, 4, 1, 4, 2, 0, 4, 3, 1, 3, 4,
                                      0, 5, 2, 1, 2, 5, 0, 3, 5, 1, 5, 3};
    int i;
    memset(xyz, 0, 18 * sizeof(float));
    for (i = 0; i < 3; i++) {
        xyz[(2 * i) * 3 + i] = r;      /* +axis */
        xyz[(2 * i + 1) * 3 + i] = -r; /* -axis */
    }
    memcpy(idx, tris, sizeof tris);
}

/* The field's pose at `frame`: turned by 0.02 rad per frame about y, at
 * (0.13, 1.43, 0); 3x4 row-major (x' = m0 x + m1 y + m2 z + m3). */
static void field_pose(int frame, float m[12]) {
    float a = 0.02f * (float)frame, c = cosf(a), s = sinf(a);
    float pose[12] = {c, 0, s, 0.13f, 0, 1, 0, 1.43f, -s, 0, c, 0.0f};
    memcpy(m, pose, sizeof pose);
}

/* Distance from p to the capsule's surface (negative inside). */
static float capsule_distance(const CoifCapsule *cap, const float *p) {
    float ab[3], ap[3], t = 0, len2 = 0, d2 = 0;
    int i;
    for (i = 0; i < 3; i++) {
        ab[i] = cap->b[i] - cap->a[i];
        ap[i] = p[i] - cap->a[i];
        len2 += ab[i] * ab[i];
        t += ap[i] * ab[i];
    }
    t = len2 > 0 ? t / len2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    for (i = 0; i < 3; i++) {
        float e = ap[i] - t * ab[i];
        d2 += e * e;
    }
    return sqrtf(d2) - cap->radius;
}

int main(void) {
    static float xyz[POINTS * 3], roots[STRANDS * 3], out[POINTS * 3], before[POINTS * 3];
    float mesh[18], m[12];
    uint32_t idx[24];
    CoifStrands *hair = NULL;
    CoifSdf *field = NULL;
    CoifSdfSet *fields = NULL;
    CoifSimParams params = coif_sim_params_default();
    CoifCapsule shoulder = {{0.05f, 1.5f, -0.2f}, {0.05f, 1.5f, 0.2f}, 0.03f};
    int s, v, frame;
    float tip_dx = 0, worst_capsule = 1e9f, worst_field = 1e9f;
    size_t index = 99;
    CoifStatus st;

    for (s = 0; s < STRANDS; s++) {
        for (v = 0; v < VERTS; v++) {
            float *p = &xyz[(s * VERTS + v) * 3];
            p[0] = -0.01f;
            p[1] = 1.6f - 0.02f * (float)v;
            p[2] = -0.115f + 0.01f * (float)s;
        }
        memcpy(&roots[s * 3], &xyz[s * VERTS * 3], 3 * sizeof(float));
    }
    expect(coif_strands_new(xyz, POINTS, VERTS, &hair), COIF_OK, "coif_strands_new");

    /* The field: built once from the caller's arrays, then moved into a set
     * that the step borrows (the set owns it from then on). */
    octahedron(0.05f, mesh, idx);
    expect(coif_sdf_set_new(&fields), COIF_OK, "coif_sdf_set_new");
    st = coif_sdf_new(mesh, 6, idx, 8, 0.01f, &field);
    if (st != COIF_OK) {
        fprintf(stderr, "world: coif_sdf_new: %s\n", coif_status_message(st));
        coif_sdf_set_free(fields);
        coif_strands_free(hair);
        return 1;
    }
    field_pose(0, m);
    expect(coif_sdf_set_transform(field, m), COIF_OK, "coif_sdf_set_transform");
    expect(coif_sdf_set_add(fields, &field, &index), COIF_OK, "coif_sdf_set_add");
    check(field == NULL && index == 0, "the set took the field at index 0");
    printf("world: field of 8 triangles built, in a set of %u\n",
           (unsigned)coif_sdf_set_count(fields));

    /* Wind along +x with drag (1/s) and light gusts; Coulomb friction. */
    params.wind[0] = 2.5f;
    params.drag = 5.0f;
    params.turbulence = 0.3f;
    params.friction = 0.4f;
    params.static_friction = 0.8f;
    /* Hair against hair: volume and friction through the hair grid. */
    params.volume_stiffness = 1.0f;
    params.hair_friction = 1.0f;
    for (frame = 0; frame < 240; frame++) {
        field_pose(frame, m);
        expect(coif_sdf_set_transform_at(fields, 0, m), COIF_OK, "set_transform_at");
        expect(coif_strands_set_roots(hair, roots, STRANDS), COIF_OK, "set_roots");
        st = coif_step_colliders(hair, &params, NULL, 0, &shoulder, 1, fields);
        expect(st, COIF_OK, "coif_step_colliders");
    }
    expect(coif_strands_positions(hair, out, POINTS), COIF_OK, "positions");
    for (s = 0; s < STRANDS; s++) {
        tip_dx += (out[(s * VERTS + VERTS - 1) * 3] - out[s * VERTS * 3]) / STRANDS;
    }
    for (v = 0; v < POINTS; v++) {
        float d = capsule_distance(&shoulder, &out[v * 3]);
        worst_capsule = d < worst_capsule ? d : worst_capsule;
        expect(coif_sdf_set_distance_at(fields, 0, &out[v * 3], &d), COIF_OK, "distance_at");
        worst_field = d < worst_field ? d : worst_field;
    }
    check(tip_dx > 0.03f, "the tips end downwind");
    check(worst_capsule > -0.001f, "no vertex inside the capsule");
    check(worst_field > -0.001f, "no vertex inside the field");
    printf("world: tips %.3f m downwind; nearest vertex %.4f m from the capsule\n", tip_dx,
           worst_capsule);
    printf("world: nearest vertex %.4f m from the field\n", worst_field);

    /* Bad inputs: refused, nothing changes. */
    memcpy(before, out, sizeof out);
    {
        CoifSimParams bad = params;
        CoifCapsule thin = shoulder;
        CoifSdf *bad_field = (CoifSdf *)&index; /* must be overwritten with NULL */
        uint32_t bad_idx[24];
        float scaled[12] = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        float p[3] = {0, 0, 0}, d = 0;
        bad.wind[1] = NAN;
        expect(coif_step_colliders(hair, &bad, NULL, 0, &shoulder, 1, fields),
               COIF_ERROR_NON_FINITE, "NaN wind");
        bad = params;
        bad.drag = -1.0f;
        expect(coif_step_colliders(hair, &bad, NULL, 0, &shoulder, 1, fields),
               COIF_ERROR_INVALID_ARGUMENT, "negative drag");
        bad = params;
        bad.turbulence_scale = 0.0f;
        expect(coif_sim_params_validate(&bad), COIF_ERROR_INVALID_ARGUMENT, "turbulence_scale 0");
        thin.radius = -0.01f;
        expect(coif_step_colliders(hair, &params, NULL, 0, &thin, 1, fields),
               COIF_ERROR_INVALID_ARGUMENT, "negative capsule radius");
        expect(coif_step_colliders(hair, &params, NULL, 0, NULL, 1, fields), COIF_ERROR_NULL,
               "NULL capsules with a count");
        memcpy(bad_idx, idx, sizeof idx);
        bad_idx[7] = 6;
        expect(coif_sdf_new(mesh, 6, bad_idx, 8, 0.01f, &bad_field), COIF_ERROR_INVALID_ARGUMENT,
               "an index past the vertices");
        check(bad_field == NULL, "a refused field leaves *out NULL");
        expect(coif_sdf_new(mesh, 6, idx, 8, 0.0f, &bad_field), COIF_ERROR_INVALID_ARGUMENT,
               "cell 0");
        expect(coif_sdf_new(NULL, 6, idx, 8, 0.01f, &bad_field), COIF_ERROR_NULL, "NULL vertices");
        expect(coif_sdf_set_transform_at(fields, 5, m), COIF_ERROR_INVALID_ARGUMENT,
               "an index past the set");
        expect(coif_sdf_set_transform_at(fields, 0, scaled), COIF_ERROR_INVALID_ARGUMENT,
               "a scaling transform");
        expect(coif_sdf_distance(NULL, p, &d), COIF_ERROR_NULL, "NULL field");
        expect(coif_strands_positions(hair, out, POINTS), COIF_OK, "positions");
        check(memcmp(before, out, sizeof out) == 0, "refused calls changed nothing");
    }

    coif_sdf_set_free(fields);
    coif_sdf_free(field); /* NULL: the set owned it */
    coif_strands_free(hair);
    if (failures) {
        fprintf(stderr, "world: %d checks failed\n", failures);
        return 1;
    }
    printf("world: all checks passed\n");
    return 0;
}
