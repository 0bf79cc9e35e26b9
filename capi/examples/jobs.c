/* jobs.c: coif's tasks on an engine's job system. A tiny pthread job
 * system (a fixed pool of workers and a shared counter of the next index;
 * the calling thread works too while it waits) is handed to coif as a
 * CoifExecutor. 72 strands (9 blocks of 8) swing on moving roots, fall
 * asleep and are woken by a sphere; every step runs through
 * coif_step_with on the pool and on a second executor that runs the
 * indices backwards, and through coif_step alone: the three sets must
 * stay equal bit for bit, with the same awake counts. Then cloth patches
 * through coif_patch_step_all and Kajiya-Kay shading through
 * coif_shade_kajiya_kay_with, each against its serial call, and an
 * executor without a run function refused.
 *
 * Build (from the workspace root, after cargo build --release -p coif-capi):
 *   cc -std=c99 -Wall -Wextra -pthread capi/examples/jobs.c -Icapi/include \
 *      target/release/libcoif_capi.a -lm -lpthread -ldl -o jobs
 * Exit code 0 only if every check passes. */

#define _POSIX_C_SOURCE 200809L

#include "coif.h"
#include "checks.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the job system: a fixed pool, one parallel-for at a time ---- */

#define WORKERS 3

typedef struct Pool {
    pthread_t threads[WORKERS];
    pthread_mutex_t lock;
    pthread_cond_t wake; /* workers: a job has indices left, or stop */
    pthread_cond_t done; /* the caller: every index of the job finished */
    CoifTaskFn task;     /* the current job (NULL: none) */
    void *task_ctx;
    size_t count, next, finished;
    size_t by_workers; /* indices the workers ran (statistics only) */
    int stop;
} Pool;

/* Takes the next index of the current job under the lock, runs it outside. */
static void *worker(void *arg) {
    Pool *p = (Pool *)arg;
    pthread_mutex_lock(&p->lock);
    for (;;) {
        while (!p->stop && (p->task == NULL || p->next >= p->count)) {
            pthread_cond_wait(&p->wake, &p->lock);
        }
        if (p->stop) break;
        size_t i = p->next++;
        CoifTaskFn task = p->task;
        void *ctx = p->task_ctx;
        pthread_mutex_unlock(&p->lock);
        task(ctx, i);
        pthread_mutex_lock(&p->lock);
        p->by_workers++;
        if (++p->finished == p->count) pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

/* The CoifExecutor's run: publish the job, work on it too, wait for the rest. */
static void pool_run(void *ctx, size_t count, CoifTaskFn task, void *task_ctx) {
    Pool *p = (Pool *)ctx;
    pthread_mutex_lock(&p->lock);
    p->task = task;
    p->task_ctx = task_ctx;
    p->count = count;
    p->next = 0;
    p->finished = 0;
    pthread_cond_broadcast(&p->wake);
    while (p->next < p->count) {
        size_t i = p->next++;
        pthread_mutex_unlock(&p->lock);
        task(task_ctx, i);
        pthread_mutex_lock(&p->lock);
        p->finished++;
    }
    while (p->finished < p->count) pthread_cond_wait(&p->done, &p->lock);
    p->task = NULL;
    pthread_mutex_unlock(&p->lock);
}

static int pool_start(Pool *p) {
    memset(p, 0, sizeof *p);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int i = 0; i < WORKERS; i++) {
        if (pthread_create(&p->threads[i], NULL, worker, p) != 0) return 0;
    }
    return 1;
}

static void pool_stop(Pool *p) {
    pthread_mutex_lock(&p->lock);
    p->stop = 1;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
    for (int i = 0; i < WORKERS; i++) pthread_join(p->threads[i], NULL);
    pthread_cond_destroy(&p->done);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
}

/* A second executor: every index, backwards, on the calling thread. */
static void backwards_run(void *ctx, size_t count, CoifTaskFn task, void *task_ctx) {
    (void)ctx;
    for (size_t i = count; i > 0; i--) task(task_ctx, i - 1);
}

/* ---- the checks ---- */

#define STRANDS 72
#define VERTS 12
#define POINTS (STRANDS * VERTS)
#define FRAMES 300

static float points[POINTS * 3], roots[STRANDS * 3];
static float serial_out[POINTS * 3], pool_out[POINTS * 3], back_out[POINTS * 3];

static CoifStrands *make_strands(void) {
    CoifStrands *s = NULL;
    expect(coif_strands_new(points, POINTS, VERTS, &s), COIF_OK, "coif_strands_new");
    return s;
}

static void strands_calls(const CoifExecutor *pool, const CoifExecutor *back) {
    for (int i = 0; i < STRANDS; i++) {
        float a = 0.09f * (float)i;
        for (int v = 0; v < VERTS; v++) {
            float *p = &points[3 * (i * VERTS + v)];
            p[0] = 0.1f * cosf(a) + 0.003f * sinf(0.7f * (float)v);
            p[1] = 1.7f - 0.012f * (float)v;
            p[2] = 0.1f * sinf(a);
        }
    }
    CoifStrands *serial = make_strands(), *pooled = make_strands(), *backed = make_strands();
    if (!serial || !pooled || !backed) return;
    CoifSimParams params = coif_sim_params_default(); /* sleeping on (sleep_speed 0.02) */
    size_t fewest_awake = STRANDS, woken = 0;
    for (int f = 0; f < FRAMES; f++) {
        /* roots swing for half a second, then stay; a sphere arrives at frame 200 */
        float t = (float)(f < 30 ? f : 30) / 30.0f;
        for (int i = 0; i < STRANDS; i++) {
            roots[3 * i + 0] = points[3 * i * VERTS + 0] + 0.01f * sinf(3.0f * t);
            roots[3 * i + 1] = points[3 * i * VERTS + 1];
            roots[3 * i + 2] = points[3 * i * VERTS + 2];
        }
        CoifSphere rig = {{f < 200 ? 1.0f : 0.5f - 0.01f * (float)(f - 200), 1.6f, 0.0f}, 0.05f};
        expect(coif_strands_set_roots(serial, roots, STRANDS), COIF_OK, "roots");
        expect(coif_strands_set_roots(pooled, roots, STRANDS), COIF_OK, "roots");
        expect(coif_strands_set_roots(backed, roots, STRANDS), COIF_OK, "roots");
        expect(coif_step(serial, &params, &rig, 1), COIF_OK, "coif_step");
        expect(coif_step_with(pooled, &params, &rig, 1, pool), COIF_OK, "coif_step_with pool");
        expect(coif_step_with(backed, &params, &rig, 1, back), COIF_OK, "coif_step_with back");
        size_t awake = coif_strands_awake_strands(serial);
        check(coif_strands_awake_strands(pooled) == awake, "awake: pool = serial");
        check(coif_strands_awake_strands(backed) == awake, "awake: backwards = serial");
        if (awake < fewest_awake) fewest_awake = awake;
        if (f > 200 && awake > 0 && awake < STRANDS) woken = awake;
        if (f % 50 == 49 || f == FRAMES - 1) {
            expect(coif_strands_positions(serial, serial_out, POINTS), COIF_OK, "positions");
            expect(coif_strands_positions(pooled, pool_out, POINTS), COIF_OK, "positions");
            expect(coif_strands_positions(backed, back_out, POINTS), COIF_OK, "positions");
            check(memcmp(serial_out, pool_out, sizeof pool_out) == 0, "pool = serial, bit for bit");
            check(memcmp(serial_out, back_out, sizeof back_out) == 0, "backwards = serial");
        }
    }
    check(fewest_awake < STRANDS, "some blocks slept");
    check(woken > 0, "the sphere woke some blocks and not all");

    /* A refused step: an executor without run; nothing changes. */
    CoifExecutor no_run = *pool;
    no_run.run = NULL;
    expect(coif_step_with(pooled, &params, NULL, 0, &no_run), COIF_ERROR_NULL, "run NULL");
    expect(coif_strands_positions(pooled, pool_out, POINTS), COIF_OK, "positions");
    check(memcmp(serial_out, pool_out, sizeof pool_out) == 0, "a refused step changed nothing");
    printf("jobs: %d strands, %d steps on the pool = coif_step bit for bit; "
           "fewest awake %zu, woken %zu\n",
           STRANDS, FRAMES, fewest_awake, woken);
    coif_strands_free(serial);
    coif_strands_free(pooled);
    coif_strands_free(backed);
}

#define PATCHES 5
#define ROWS 4
#define COLS 9

static void patch_calls(const CoifExecutor *pool) {
    float grid[ROWS * COLS * 3];
    uint8_t pinned[ROWS * COLS];
    CoifPatch *alone[PATCHES], *tasked[PATCHES];
    for (int k = 0; k < PATCHES; k++) {
        for (int i = 0; i < ROWS * COLS; i++) {
            grid[3 * i + 0] = 0.3f * (float)k + 0.02f * (float)(i % COLS);
            grid[3 * i + 1] = 1.5f - 0.02f * (float)(i / COLS);
            grid[3 * i + 2] = 0.0f;
            pinned[i] = i < COLS;
        }
        alone[k] = tasked[k] = NULL;
        expect(coif_patch_new(grid, ROWS, COLS, pinned, &alone[k]), COIF_OK, "patch");
        expect(coif_patch_new(grid, ROWS, COLS, pinned, &tasked[k]), COIF_OK, "patch");
        if (!alone[k] || !tasked[k]) return;
    }
    CoifSimParams params = coif_sim_params_default();
    CoifSphere rig = {{0.05f, 1.47f, 0.01f}, 0.03f};
    for (int f = 0; f < 40; f++) {
        for (int k = 0; k < PATCHES; k++) {
            expect(coif_patch_step(alone[k], &params, &rig, 1), COIF_OK, "patch step");
        }
        expect(coif_patch_step_all(tasked, PATCHES, &params, &rig, 1, pool), COIF_OK,
               "coif_patch_step_all");
    }
    float a[ROWS * COLS * 3], b[ROWS * COLS * 3];
    for (int k = 0; k < PATCHES; k++) {
        expect(coif_patch_positions(alone[k], a, ROWS * COLS), COIF_OK, "patch positions");
        expect(coif_patch_positions(tasked[k], b, ROWS * COLS), COIF_OK, "patch positions");
        check(memcmp(a, b, sizeof a) == 0, "coif_patch_step_all = coif_patch_step");
    }
    CoifPatch *twice[2] = {tasked[0], tasked[0]};
    expect(coif_patch_step_all(twice, 2, &params, &rig, 1, pool), COIF_ERROR_INVALID_ARGUMENT,
           "a patch listed twice");
    printf("jobs: %d patches stepped on the pool = alone\n", PATCHES);
    for (int k = 0; k < PATCHES; k++) {
        coif_patch_free(alone[k]);
        coif_patch_free(tasked[k]);
    }
}

#define SHADED 1003

static void shading_calls(const CoifExecutor *pool) {
    static CoifRenderVertex verts[SHADED];
    static float serial_rgb[SHADED * 3], pool_rgb[SHADED * 3];
    for (int i = 0; i < SHADED; i++) {
        float a = 0.037f * (float)i;
        CoifRenderVertex v = {{0.01f * sinf(a), -0.0005f * (float)i, 0.02f * cosf(a)},
                              6e-5f,
                              {cosf(a), 0.0f, sinf(a)},
                              (float)(i % 17) / 16.0f};
        verts[i] = v;
    }
    CoifKajiyaKay kk = coif_kajiya_kay_default();
    float light[3] = {0.3f, 1.0f, 0.5f}, eye[3] = {0.0f, 0.1f, 1.5f};
    expect(coif_shade_kajiya_kay(&kk, verts, SHADED, light, eye, serial_rgb, SHADED), COIF_OK,
           "shade");
    expect(coif_shade_kajiya_kay_with(&kk, verts, SHADED, light, eye, pool_rgb, SHADED, pool),
           COIF_OK, "shade on the pool");
    check(memcmp(serial_rgb, pool_rgb, sizeof pool_rgb) == 0, "shading: pool = serial");
    printf("jobs: %d vertices shaded on the pool = serial\n", SHADED);
}

int main(void) {
    Pool pool;
    if (!pool_start(&pool)) {
        fprintf(stderr, "FAIL: no threads\n");
        return 1;
    }
    CoifExecutor on_pool = {&pool, WORKERS + 1, pool_run};
    CoifExecutor on_back = {NULL, 1, backwards_run};
    strands_calls(&on_pool, &on_back);
    patch_calls(&on_pool);
    shading_calls(&on_pool);
    pool_stop(&pool);
    printf("jobs: workers ran %zu tasks\n", pool.by_workers);
    if (failures) {
        fprintf(stderr, "jobs: %d checks failed\n", failures);
        return 1;
    }
    printf("jobs: all checks passed\n");
    return 0;
}
