// hang.cpp: the core of hang.c in C++17, with every handle owned by a
// std::unique_ptr whose deleter is the matching coif_*_free (RAII); then
// the engine calls of engine.c (refinement, render hairs, shading, and a
// groom from the file named by argv[1], if any) in the same style, and
// coif_step_with on a pool of std::thread workers against coif_step.
//
// Build (from the workspace root, after cargo build --release -p coif-capi):
//   c++ -std=c++17 -Wall -Wextra -pthread capi/examples/hang.cpp -Icapi/include
//       target/release/libcoif_capi.a -lm -lpthread -ldl -o hang_cpp
//   ./hang_cpp shared/data/grooms/sintel_lite.tfx

#include "coif.h"

#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Deleter {
    void operator()(CoifStrands *s) const noexcept { coif_strands_free(s); }
    void operator()(CoifGroom *g) const noexcept { coif_groom_free(g); }
    void operator()(CoifHairs *h) const noexcept { coif_hairs_free(h); }
    void operator()(CoifMarschnerLut *l) const noexcept { coif_marschner_lut_free(l); }
    void operator()(CoifPatch *p) const noexcept { coif_patch_free(p); }
    void operator()(CoifPbrtTable *t) const noexcept { coif_pbrt_table_free(t); }
};
using StrandsPtr = std::unique_ptr<CoifStrands, Deleter>;
using GroomPtr = std::unique_ptr<CoifGroom, Deleter>;
using HairsPtr = std::unique_ptr<CoifHairs, Deleter>;
using LutPtr = std::unique_ptr<CoifMarschnerLut, Deleter>;
using PatchPtr = std::unique_ptr<CoifPatch, Deleter>;
using TablePtr = std::unique_ptr<CoifPbrtTable, Deleter>;

static_assert(sizeof(CoifRenderVertex) == 32, "one render vertex is 32 bytes");

void ok(CoifStatus status, const char *what) {
    if (status != COIF_OK) {
        throw std::runtime_error(std::string(what) + ": " + coif_status_message(status));
    }
}

StrandsPtr make_strands(const std::vector<float> &xyz, std::size_t verts) {
    CoifStrands *raw = nullptr;
    ok(coif_strands_new(xyz.data(), xyz.size() / 3, verts, &raw), "coif_strands_new");
    return StrandsPtr(raw);
}

void require(bool ok, const char *what) {
    if (!ok) throw std::runtime_error(what);
}

// Refinement, render hairs on the 8 x 8 grid's triangles, both shaders.
void engine_calls(CoifStrands *hair, int grid) {
    std::vector<float> refined(coif_refine_bound(hair, 3) * 3);
    ok(coif_refine(hair, 3, refined.data(), nullptr, refined.size() / 3), "coif_refine");
    std::vector<std::uint32_t> triangles;
    for (int j = 0; j + 1 < grid; j++) {
        for (int i = 0; i + 1 < grid; i++) {
            std::uint32_t k = j * grid + i, g = grid;
            triangles.insert(triangles.end(), {k, k + 1, k + g, k + 1, k + g + 1, k + g});
        }
    }
    CoifHairSettings settings = coif_hair_settings_default();
    settings.hairs_per_cm2 = 10.0f;  // the roots are 2 cm apart: 196 cm^2
    CoifHairs *raw_hairs = nullptr;
    ok(coif_hairs_new(hair, triangles.data(), triangles.size() / 3, &settings, &raw_hairs),
       "coif_hairs_new");
    HairsPtr hairs(raw_hairs);
    std::vector<CoifRenderVertex> vertices(coif_hairs_vertex_bound(hairs.get(), 4, SIZE_MAX));
    std::size_t written = 0;
    ok(coif_hairs_write_vertices(hairs.get(), hair, 4, SIZE_MAX, 1.0f, vertices.data(),
                                 vertices.size(), &written),
       "coif_hairs_write_vertices");
    require(written == vertices.size() && written > 0, "every hair written");

    CoifMarschnerParams params = coif_marschner_params_default();
    CoifMarschnerLut *raw_lut = nullptr;
    ok(coif_marschner_lut_new(&params, 32, &raw_lut), "coif_marschner_lut_new");
    LutPtr lut(raw_lut);
    const float light[3] = {0.0f, 1.0f, 1.0f}, eye[3] = {0.0f, 0.0f, 2.0f};
    std::vector<float> rgb(3 * written);
    CoifKajiyaKay kk = coif_kajiya_kay_default();
    ok(coif_shade_kajiya_kay(&kk, vertices.data(), written, light, eye, rgb.data(), written),
       "Kajiya-Kay");
    for (float c : rgb) require(std::isfinite(c) && c >= 0.0f, "Kajiya-Kay colour");
    ok(coif_shade_marschner_lut(lut.get(), vertices.data(), written, light, eye, rgb.data(),
                                written),
       "Marschner");
    for (float c : rgb) require(std::isfinite(c), "Marschner colour");
    CoifPbrtParams pp = coif_pbrt_params_default();
    CoifPbrtTable *raw_table = nullptr;
    ok(coif_pbrt_table_new(&pp, 16, &raw_table), "coif_pbrt_table_new");
    TablePtr table(raw_table);
    ok(coif_shade_pbrt_table(table.get(), vertices.data(), written, light, eye, rgb.data(),
                             written),
       "pbrt");
    for (float c : rgb) require(std::isfinite(c), "pbrt colour");
    require(coif_shade_marschner_lut(lut.get(), vertices.data(), written, light, eye, rgb.data(),
                                     written - 1) == COIF_ERROR_BUFFER_TOO_SMALL,
            "a too-small colour buffer was accepted");
    std::printf("hang.cpp: %zu render vertices shaded\n", written);
}

// A 3 x 8 cloth patch pinned at its top row, stepped, blended.
void cloth_calls() {
    constexpr int rows = 3, cols = 8;
    std::vector<float> grid;
    std::vector<std::uint8_t> pinned;
    for (int k = 0; k < rows * cols; k++) {
        grid.insert(grid.end(), {0.02f * (k % cols), 1.5f - 0.02f * (k / cols), 0.0f});
        pinned.push_back(k < cols ? 1 : 0);
    }
    CoifPatch *raw = nullptr;
    ok(coif_patch_new(grid.data(), rows, cols, pinned.data(), &raw), "coif_patch_new");
    PatchPtr patch(raw);
    CoifSimParams params = coif_sim_params_default();
    for (int step = 0; step < 30; step++) {
        ok(coif_patch_set_skinned(patch.get(), grid.data(), rows * cols), "patch skin");
        ok(coif_patch_step(patch.get(), &params, nullptr, 0), "patch step");
    }
    std::vector<float> out(3 * coif_patch_particle_count(patch.get()));
    ok(coif_patch_blended(patch.get(), out.data(), out.size() / 3), "patch blended");
    for (float c : out) require(std::isfinite(c), "patch finite");
    std::printf("hang.cpp: cloth blended, %d particles\n", rows * cols);
}

// A groom from a file: strands in metres, stepped; a truncated copy refused.
void groom_calls(const char *path) {
    std::ifstream file(path, std::ios::binary);
    require(file.good(), "cannot open the groom");
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                                    std::istreambuf_iterator<char>());
    CoifGroom *raw = nullptr;
    ok(coif_groom_load(bytes.data(), bytes.size(), &raw), "coif_groom_load");
    GroomPtr groom(raw);
    CoifStrands *raw_strands = nullptr;
    ok(coif_strands_from_groom(groom.get(), 20, 12, 0.01f, &raw_strands),
       "coif_strands_from_groom");
    StrandsPtr strands(raw_strands);
    CoifSimParams params = coif_sim_params_default();
    for (int step = 0; step < 30; step++) ok(coif_step(strands.get(), &params, nullptr, 0), "step");
    CoifGroom *bad = nullptr;
    require(coif_groom_load(bytes.data(), bytes.size() / 2, &bad) == COIF_ERROR_BAD_DATA &&
                bad == nullptr,
            "a truncated groom was accepted");
    std::printf("hang.cpp: groom of %zu strands, %zu guides stepped\n",
                coif_groom_strand_count(groom.get()), coif_strands_strand_count(strands.get()));
}

// A fixed pool of std::thread workers taking indices from a shared counter;
// the calling thread works too while it waits (jobs.c's pool in C++17).
class Pool {
  public:
    explicit Pool(unsigned workers) {
        for (unsigned i = 0; i < workers; i++) threads_.emplace_back([this] { work(); });
    }
    ~Pool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread &t : threads_) t.join();
    }
    Pool(const Pool &) = delete;
    Pool &operator=(const Pool &) = delete;

    CoifExecutor executor() { return CoifExecutor{this, threads_.size() + 1, &Pool::run}; }

  private:
    // CoifExecutor::run: publish the job, work on it, wait for the rest.
    static void run(void *ctx, std::size_t count, CoifTaskFn task, void *task_ctx) {
        Pool &p = *static_cast<Pool *>(ctx);
        std::unique_lock<std::mutex> lock(p.mutex_);
        p.task_ = task;
        p.task_ctx_ = task_ctx;
        p.count_ = count;
        p.next_ = 0;
        p.finished_ = 0;
        p.wake_.notify_all();
        while (p.next_ < p.count_) {
            std::size_t i = p.next_++;
            lock.unlock();
            task(task_ctx, i);
            lock.lock();
            p.finished_++;
        }
        p.done_.wait(lock, [&p] { return p.finished_ == p.count_; });
        p.task_ = nullptr;
    }

    void work() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            wake_.wait(lock, [this] { return stop_ || (task_ != nullptr && next_ < count_); });
            if (stop_) return;
            std::size_t i = next_++;
            CoifTaskFn task = task_;
            void *ctx = task_ctx_;
            lock.unlock();
            task(ctx, i);
            lock.lock();
            if (++finished_ == count_) done_.notify_one();
        }
    }

    std::vector<std::thread> threads_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    CoifTaskFn task_ = nullptr;
    void *task_ctx_ = nullptr;
    std::size_t count_ = 0, next_ = 0, finished_ = 0;
    bool stop_ = false;
};

// The same strands stepped by coif_step and by coif_step_with on the pool,
// with sleeping on and swinging roots: equal bit for bit.
void job_calls(const std::vector<float> &xyz, std::size_t verts) {
    Pool pool(3);
    CoifExecutor exec = pool.executor();
    StrandsPtr serial = make_strands(xyz, verts), pooled = make_strands(xyz, verts);
    std::size_t strands = coif_strands_strand_count(serial.get());
    CoifSimParams params = coif_sim_params_default();
    std::vector<float> roots(3 * strands);
    for (int step = 0; step < 120; step++) {
        float shift = step < 30 ? 0.01f * std::sin(0.2f * static_cast<float>(step)) : 0.0f;
        for (std::size_t i = 0; i < strands; i++) {
            roots[3 * i + 0] = xyz[3 * i * verts + 0] + shift;
            roots[3 * i + 1] = xyz[3 * i * verts + 1];
            roots[3 * i + 2] = xyz[3 * i * verts + 2];
        }
        ok(coif_strands_set_roots(serial.get(), roots.data(), strands), "roots");
        ok(coif_strands_set_roots(pooled.get(), roots.data(), strands), "roots");
        ok(coif_step(serial.get(), &params, nullptr, 0), "coif_step");
        ok(coif_step_with(pooled.get(), &params, nullptr, 0, &exec), "coif_step_with");
        require(coif_strands_awake_strands(serial.get()) ==
                    coif_strands_awake_strands(pooled.get()),
                "awake counts differ");
    }
    std::vector<float> a(3 * strands * verts), b(a.size());
    ok(coif_strands_positions(serial.get(), a.data(), a.size() / 3), "positions");
    ok(coif_strands_positions(pooled.get(), b.data(), b.size() / 3), "positions");
    require(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0,
            "coif_step_with on std::thread differs from coif_step");
    std::printf("hang.cpp: %zu strands on std::thread workers = coif_step bit for bit\n", strands);
}

}  // namespace

int main(int argc, char **argv) {
    constexpr int strands = 64, verts = 16;
    constexpr float segment = 0.01f;
    std::vector<float> xyz;
    for (int i = 0; i < strands; i++) {
        for (int v = 0; v < verts; v++) {
            xyz.insert(xyz.end(), {0.02f * (i % 8), 1.5f - segment * v, 0.02f * (i / 8)});
        }
    }
    try {
        StrandsPtr hair = make_strands(xyz, verts);
        CoifSimParams params = coif_sim_params_default();
        for (int step = 0; step < 600; step++) {
            ok(coif_step(hair.get(), &params, nullptr, 0), "coif_step");
        }
        std::vector<float> out(coif_strands_point_count(hair.get()) * 3);
        ok(coif_strands_positions(hair.get(), out.data(), out.size() / 3), "positions");
        float worst = 0.0f;
        for (int i = 0; i < strands; i++) {
            const float *r = &out[3 * (i * verts)];
            const float *t = &out[3 * (i * verts + verts - 1)];
            for (int k = 0; k < 3 * verts; k++) {
                if (!std::isfinite(r[k])) throw std::runtime_error("non-finite point");
            }
            worst = std::fmax(worst, std::hypot(t[0] - r[0], t[2] - r[2]));
        }
        if (!(worst < 0.001f)) throw std::runtime_error("a tip left the vertical");
        if (coif_strands_positions(hair.get(), out.data(), 1) != COIF_ERROR_BUFFER_TOO_SMALL) {
            throw std::runtime_error("a too-small buffer was accepted");
        }
        engine_calls(hair.get(), 8);
        cloth_calls();
        job_calls(xyz, verts);
        if (argc > 1) groom_calls(argv[1]);
        std::printf("hang.cpp: 600 steps, tip sideways %.3g m: all checks passed\n",
                    static_cast<double>(worst));
    } catch (const std::exception &e) {
        std::fprintf(stderr, "FAIL: %s\n", e.what());
        return 1;
    }
    return 0;
}
