// hang.cpp: the core of hang.c in C++17, with the handle owned by a
// std::unique_ptr whose deleter is coif_strands_free (RAII).
//
// Build (from the workspace root, after cargo build --release -p coif-capi):
//   c++ -std=c++17 -Wall -Wextra capi/examples/hang.cpp -Icapi/include
//       target/release/libcoif_capi.a -lm -lpthread -ldl -o hang_cpp

#include "coif.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct StrandsDeleter {
    void operator()(CoifStrands *s) const noexcept { coif_strands_free(s); }
};
using StrandsPtr = std::unique_ptr<CoifStrands, StrandsDeleter>;

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

}  // namespace

int main() {
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
        std::printf("hang.cpp: 600 steps, tip sideways %.3g m: all checks passed\n",
                    static_cast<double>(worst));
    } catch (const std::exception &e) {
        std::fprintf(stderr, "FAIL: %s\n", e.what());
        return 1;
    }
    return 0;
}
