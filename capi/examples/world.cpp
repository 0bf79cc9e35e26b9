// world.cpp: world.c in C++17, with every handle in a std::unique_ptr
// whose deleter is the matching coif_*_free: 32 strands in a gusty wind,
// a swinging capsule (an arm) and a box-like field (an octahedron built
// here from vertex and index arrays, moved into a CoifSdfSet); the same
// steps on a CoifExecutor of std::thread workers give the bytes of the
// serial coif_step_colliders. Checks: tips downwind, no vertex inside
// the capsule or the field, bad inputs refused.
//
// Build (from the workspace root, after cargo build --release -p coif-capi):
//   c++ -std=c++17 -Wall -Wextra -pthread capi/examples/world.cpp -Icapi/include
//       target/release/libcoif_capi.a -lm -lpthread -ldl -o world_cpp

#include "coif.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Deleter {
    void operator()(CoifStrands *s) const noexcept { coif_strands_free(s); }
    void operator()(CoifSdf *f) const noexcept { coif_sdf_free(f); }
    void operator()(CoifSdfSet *f) const noexcept { coif_sdf_set_free(f); }
};
using StrandsPtr = std::unique_ptr<CoifStrands, Deleter>;
using SdfPtr = std::unique_ptr<CoifSdf, Deleter>;
using SdfSetPtr = std::unique_ptr<CoifSdfSet, Deleter>;

constexpr std::size_t kStrands = 32, kVerts = 12, kPoints = kStrands * kVerts;

void ok(CoifStatus status, const char *what) {
    if (status != COIF_OK) {
        throw std::runtime_error(std::string(what) + ": " + coif_status_message(status));
    }
}

void require(bool cond, const char *what) {
    if (!cond) throw std::runtime_error(what);
}

void refused(CoifStatus got, CoifStatus want, const char *what) {
    if (got != want) {
        throw std::runtime_error(std::string(what) + ": got " + coif_status_message_code(got) +
                                 ", want " + coif_status_message(want));
    }
}

// An executor on fresh std::threads: each run spawns `threads` workers that
// take indices from a shared counter, and joins them before returning.
void run_on_threads(void *ctx, std::size_t count, CoifTaskFn task, void *task_ctx) {
    std::size_t workers = *static_cast<std::size_t *>(ctx);
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (std::size_t w = 0; w < workers; w++) {
        pool.emplace_back([&] {
            for (std::size_t i; (i = next.fetch_add(1)) < count;) task(task_ctx, i);
        });
    }
    for (auto &t : pool) t.join();
}

StrandsPtr make_hair() {
    std::vector<float> xyz;
    for (std::size_t s = 0; s < kStrands; s++) {
        for (std::size_t v = 0; v < kVerts; v++) {
            xyz.insert(xyz.end(), {-0.01f + 0.002f * std::sin(0.7f * v), 1.6f - 0.02f * v,
                                   -0.155f + 0.01f * s});
        }
    }
    CoifStrands *raw = nullptr;
    ok(coif_strands_new(xyz.data(), kPoints, kVerts, &raw), "coif_strands_new");
    return StrandsPtr(raw);
}

std::vector<float> positions(CoifStrands *hair) {
    std::vector<float> out(kPoints * 3);
    ok(coif_strands_positions(hair, out.data(), kPoints), "coif_strands_positions");
    return out;
}

// 3x4 row-major rigid transform: a turn about y and a translation.
std::array<float, 12> pose(int frame) {
    float a = 0.02f * frame, c = std::cos(a), s = std::sin(a);
    return {c, 0, s, 0.13f, 0, 1, 0, 1.43f, -s, 0, c, 0.01f * std::sin(0.05f * frame)};
}

CoifCapsule arm(int frame) {
    float swing = 0.03f * std::sin(0.08f * frame);
    return CoifCapsule{{0.05f + swing, 1.5f, -0.2f}, {0.05f + swing, 1.5f, 0.2f}, 0.03f};
}

float capsule_distance(const CoifCapsule &cap, const float *p) {
    float ab[3], ap[3], t = 0, len2 = 0, d2 = 0;
    for (int i = 0; i < 3; i++) {
        ab[i] = cap.b[i] - cap.a[i];
        ap[i] = p[i] - cap.a[i];
        len2 += ab[i] * ab[i];
        t += ap[i] * ab[i];
    }
    t = std::clamp(len2 > 0 ? t / len2 : 0.0f, 0.0f, 1.0f);
    for (int i = 0; i < 3; i++) d2 += (ap[i] - t * ab[i]) * (ap[i] - t * ab[i]);
    return std::sqrt(d2) - cap.radius;
}

}  // namespace

int main() {
    try {
        // The mesh: an octahedron of half-diagonal 5 cm, counter-clockwise
        // from outside; indices are 3 uint32_t per triangle.
        const float r = 0.05f;
        const std::vector<float> mesh = {r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r};
        const std::vector<std::uint32_t> idx = {0, 2, 4, 1, 4, 2, 0, 4, 3, 1, 3, 4,
                                                0, 5, 2, 1, 2, 5, 0, 3, 5, 1, 5, 3};
        CoifSdfSet *raw_set = nullptr;
        ok(coif_sdf_set_new(&raw_set), "coif_sdf_set_new");
        SdfSetPtr fields(raw_set);
        CoifSdf *raw_field = nullptr;
        ok(coif_sdf_new(mesh.data(), mesh.size() / 3, idx.data(), idx.size() / 3, 0.01f,
                        &raw_field),
           "coif_sdf_new");
        SdfPtr field(raw_field);
        // Ownership moves into the set: release, and take it back only if
        // the set refused it.
        CoifSdf *moving = field.release();
        std::size_t index = 0;
        CoifStatus st = coif_sdf_set_add(fields.get(), &moving, &index);
        field.reset(moving);  // NULL on success
        ok(st, "coif_sdf_set_add");
        require(!field && index == 0, "the set took the field");
        std::printf("world.cpp: field of 8 triangles built, in a set of %zu\n",
                    coif_sdf_set_count(fields.get()));

        CoifSimParams params = coif_sim_params_default();
        params.wind[0] = 2.5f;
        params.wind[2] = 0.3f;
        params.drag = 4.0f;
        params.turbulence = 0.5f;
        params.turbulence_scale = 0.1f;
        params.friction = 0.5f;
        params.volume_stiffness = 1.0f; // hair against hair, through the hair grid
        params.hair_friction = 1.0f;
        params.static_friction = 0.9f;

        StrandsPtr serial = make_hair(), threaded = make_hair();
        std::size_t workers = 3;
        CoifExecutor exec{&workers, workers, run_on_threads};
        CoifCapsule cap{};
        for (int frame = 0; frame < 240; frame++) {
            cap = arm(frame);
            auto m = pose(frame);
            ok(coif_sdf_set_transform_at(fields.get(), 0, m.data()), "set_transform_at");
            ok(coif_step_colliders(serial.get(), &params, nullptr, 0, &cap, 1, fields.get()),
               "coif_step_colliders");
            ok(coif_step_colliders_with(threaded.get(), &params, nullptr, 0, &cap, 1,
                                        fields.get(), &exec),
               "coif_step_colliders_with");
        }
        std::vector<float> out = positions(serial.get());
        require(std::memcmp(out.data(), positions(threaded.get()).data(),
                            out.size() * sizeof(float)) == 0,
                "the executor's step differs from the serial step");
        std::printf("world.cpp: on 3 std::thread workers = coif_step_colliders bit for bit\n");

        float tip_dx = 0, near_cap = 1e9f, near_field = 1e9f;
        for (std::size_t s = 0; s < kStrands; s++) {
            tip_dx += (out[(s * kVerts + kVerts - 1) * 3] - out[s * kVerts * 3]) / kStrands;
        }
        for (std::size_t v = 0; v < kPoints; v++) {
            near_cap = std::min(near_cap, capsule_distance(cap, &out[v * 3]));
            float d = 0;
            ok(coif_sdf_set_distance_at(fields.get(), 0, &out[v * 3], &d), "distance_at");
            near_field = std::min(near_field, d);
        }
        require(tip_dx > 0.03f, "the tips end downwind");
        require(near_cap > -0.001f, "a vertex is inside the capsule");
        require(near_field > -0.001f, "a vertex is inside the field");
        std::printf("world.cpp: tips %.3f m downwind; nearest vertex %.4f m from the capsule\n",
                    tip_dx, near_cap);
        std::printf("world.cpp: nearest vertex %.4f m from the field\n", near_field);

        // Bad inputs: refused, nothing moves.
        CoifSimParams bad = params;
        bad.static_friction = -1.0f;
        refused(coif_step_colliders(serial.get(), &bad, nullptr, 0, &cap, 1, fields.get()),
                COIF_ERROR_INVALID_ARGUMENT, "negative static friction");
        bad = params;
        bad.turbulence_period = INFINITY;
        refused(coif_sim_params_validate(&bad), COIF_ERROR_NON_FINITE, "infinite period");
        CoifCapsule nan_cap = cap;
        nan_cap.b[1] = NAN;
        refused(coif_step_colliders(serial.get(), &params, nullptr, 0, &nan_cap, 1, fields.get()),
                COIF_ERROR_NON_FINITE, "NaN capsule");
        CoifExecutor no_run{nullptr, 2, nullptr};
        refused(coif_step_colliders_with(serial.get(), &params, nullptr, 0, &cap, 1, fields.get(),
                                         &no_run),
                COIF_ERROR_NULL, "an executor without run");
        CoifSdf *none = nullptr;
        refused(coif_sdf_set_add(fields.get(), &none, nullptr), COIF_ERROR_NULL, "adding NULL");
        refused(coif_sdf_new(mesh.data(), mesh.size() / 3, idx.data(), 0, 0.01f, &none),
                COIF_ERROR_INVALID_ARGUMENT, "no triangles");
        require(none == nullptr, "a refused field leaves *out NULL");
        std::vector<float> again = positions(serial.get());
        require(again == out, "refused calls changed the hair");
    } catch (const std::exception &e) {
        std::fprintf(stderr, "world.cpp: FAIL: %s\n", e.what());
        return 1;
    }
    std::printf("world.cpp: all checks passed\n");
    return 0;
}
