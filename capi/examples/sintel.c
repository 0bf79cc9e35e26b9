/* sintel.c: groom file to shaded render-hair buffers through the C
 * interface, over a head turn, with timings (C11: the timer is C11's
 * timespec_get, which C99 lacks; tests/c_examples.rs compiles it with
 * -std=c11). The C twin of examples/engine.rs: load a .tfx (any vertex
 * counts: resampled), fit the head, triangulate the scalp, make render
 * hairs, then per frame one head pose, one step, the render vertices and
 * their Kajiya-Kay colours into buffers sized once. Usage: sintel
 * GROOM.tfx (the test passes the project's shipped
 * assets/sintel/sintel_lite.tfx). */
#include "checks.h"

#include <math.h>
#include <stdlib.h>
#include <time.h>

static double seconds(void) {
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Reads a whole file; NULL on failure. */
static uint8_t *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *bytes = n > 0 ? malloc((size_t)n) : NULL;
    if (bytes && fread(bytes, 1, (size_t)n, f) != (size_t)n) { free(bytes); bytes = NULL; }
    fclose(f);
    *len = (size_t)n;
    return bytes;
}

/* A turn of `yaw` radians about the vertical through `pivot`, as the 12
 * floats (3 rows of 4) coif_strands_set_head_pose takes. */
static void turn(float yaw, const float pivot[3], float m[12]) {
    float c = cosf(yaw), s = sinf(yaw);
    float r[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
    for (int i = 0; i < 3; i++) {
        m[4 * i + 0] = r[3 * i + 0];
        m[4 * i + 1] = r[3 * i + 1];
        m[4 * i + 2] = r[3 * i + 2];
        m[4 * i + 3] = pivot[i] - (r[3 * i] * pivot[0] + r[3 * i + 1] * pivot[1] + r[3 * i + 2] * pivot[2]);
    }
}

int main(int argc, char **argv) {
    if (argc < 2) { fprintf(stderr, "usage: sintel GROOM.tfx\n"); return 2; }
    size_t len = 0;
    uint8_t *bytes = read_file(argv[1], &len);
    if (!bytes) { fprintf(stderr, "sintel: cannot read %s\n", argv[1]); return 1; }

    /* Once: the groom, its guides resampled to 24 points in metres. */
    double t0 = seconds();
    CoifGroom *groom = NULL;
    expect(coif_groom_load(bytes, len, &groom), COIF_OK, "coif_groom_load");
    free(bytes);
    CoifStrands *hair = NULL;
    expect(coif_strands_from_groom(groom, 1, 24, 0.01f, &hair), COIF_OK, "coif_strands_from_groom");
    /* The head proxy and the scalp: a first call sizes the buffer. */
    CoifSphere head;
    expect(coif_fit_head_sphere(hair, &head), COIF_OK, "coif_fit_head_sphere");
    size_t triangle_count = 0;
    expect(coif_scalp_triangles(hair, head.center, NULL, 0, &triangle_count),
           COIF_ERROR_BUFFER_TOO_SMALL, "coif_scalp_triangles sizes its buffer");
    uint32_t *triangles = malloc(3 * triangle_count * sizeof *triangles);
    expect(coif_scalp_triangles(hair, head.center, triangles, triangle_count, &triangle_count),
           COIF_OK, "coif_scalp_triangles");
    CoifHairSettings settings = coif_hair_settings_default();
    settings.hairs_per_cm2 = 20.0f;
    settings.max_segments_per_span = 3;
    CoifHairs *hairs = NULL;
    expect(coif_hairs_new(hair, triangles, triangle_count, &settings, &hairs), COIF_OK,
           "coif_hairs_new");
    size_t groups = coif_hairs_group_count(hairs);
    size_t capacity = coif_hairs_vertex_bound(hairs, 3, groups);
    CoifRenderVertex *vertices = malloc(capacity * sizeof *vertices);
    float *rgb = malloc(3 * capacity * sizeof *rgb);
    CoifSimParams params = coif_sim_params_default();
    params.local_shape_stiffness = 1.0f; /* a groom keeps its style */
    CoifKajiyaKay model = coif_kajiya_kay_default();
    printf("sintel.c: %zu strands, %zu scalp triangles, %zu render hairs; setup %.0f ms\n",
           coif_strands_strand_count(hair), triangle_count, coif_hairs_hair_count(hairs),
           1e3 * (seconds() - t0));

    /* Per frame: a 60 degree turn and back over 2 s at 60 Hz. */
    const float pivot[3] = {head.center[0], head.center[1] - head.radius, head.center[2]};
    const float light[3] = {-0.5f, 0.7f, 0.5f};
    double step_s = 0, vertices_s = 0, shade_s = 0;
    size_t written = 0;
    for (int f = 0; f < 120; f++) {
        float m[12];
        float s = sinf(3.14159265f * (float)f / 60.0f);
        turn(1.0471976f * (s > 0 ? s : 0), pivot, m);
        double a = seconds();
        expect(coif_strands_set_head_pose(hair, m), COIF_OK, "coif_strands_set_head_pose");
        expect(coif_step(hair, &params, NULL, 0), COIF_OK, "coif_step");
        double b = seconds();
        expect(coif_hairs_write_vertices(hairs, hair, 3, groups, 1.0f, vertices, capacity, &written),
               COIF_OK, "coif_hairs_write_vertices");
        double c = seconds();
        /* The eye in the vertices' space: relative to the guides' origin. */
        double origin[3];
        expect(coif_strands_origin(hair, origin), COIF_OK, "coif_strands_origin");
        float eye[3] = {(float)(head.center[0] - 0.3 - origin[0]), (float)(head.center[1] + 0.05 - origin[1]),
                        (float)(head.center[2] + 0.7 - origin[2])};
        expect(coif_shade_kajiya_kay(&model, vertices, written, light, eye, rgb, capacity), COIF_OK,
               "coif_shade_kajiya_kay");
        double d = seconds();
        step_s += b - a;
        vertices_s += c - b;
        shade_s += d - c;
    }
    check(written > 100000, "render vertices written");
    int lit = 0;
    for (size_t i = 0; i < 3 * written; i++) lit += rgb[i] > 0.0f && isfinite(rgb[i]);
    check(lit > (int)written, "shaded colours");
    printf("sintel.c: per frame: step %.2f ms, vertices %.2f ms, shade %.2f ms; %zu vertices\n",
           1e3 * step_s / 120, 1e3 * vertices_s / 120, 1e3 * shade_s / 120, written);

    /* A bad pose is refused with a message, and changes nothing. */
    float scaled[12] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0};
    expect(coif_strands_set_head_pose(hair, scaled), COIF_ERROR_INVALID_ARGUMENT,
           "a scaled pose is refused");
    printf("sintel.c: a scaled pose: %s\n", coif_last_error_message());

    free(vertices);
    free(rgb);
    free(triangles);
    coif_hairs_free(hairs);
    coif_strands_free(hair);
    coif_groom_free(groom);
    if (failures == 0) printf("sintel.c: all checks passed\n");
    return failures == 0 ? 0 : 1;
}
