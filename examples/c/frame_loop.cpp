// An engine's frame loop with gnomon from C++: the scene made once, a box moved each frame
// (the kiosk of blocks.toml drives along the street), the sun's cascades set up again each
// frame into a result the engine owns, their float matrices copied to the uniform buffer.
//
//   cargo build --release -p gnomon-c
//   c++ -std=c++17 -I crates/gnomon-c/include examples/c/frame_loop.cpp
//       target/release/libgnomon_c.a -lm -lpthread -ldl -o frame_loop   (one line)
//   ./frame_loop 120
//
// It prints frame 0's cascades as JSON (what `gnomon setup --json --scene-file
// examples/c/blocks.toml --view street --technique cascades` prints, in part), one line per
// frame after it, and checks that the kiosk driven back to its start gives frame 0's
// matrices again (the moved hierarchies refitted, not rebuilt, give the same answer).
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gnomon.h"

namespace {

// Throws with gnomon's message where a call fails.
void check(int status) {
    if (status != GNOMON_OK) {
        throw std::runtime_error(gnomon_last_error_message());
    }
}

struct SceneDeleter {
    void operator()(GnomonScene *scene) const { gnomon_scene_free(scene); }
};
using Scene = std::unique_ptr<GnomonScene, SceneDeleter>;

// What the engine uploads per cascade: the float matrix and the depth row.
struct CascadeUniform {
    std::array<float, 16> light_clip_from_world;
    std::array<float, 4> depth_from_world;
    float far_view_depth;
};

class ShadowSystem {
  public:
    ShadowSystem(std::vector<GnomonBox> casters, std::vector<GnomonBox> receivers)
        : casters_(std::move(casters)), receivers_(std::move(receivers)) {
        GnomonScene *scene = nullptr;
        check(gnomon_scene_new(casters_.data(), casters_.size(), receivers_.data(),
                               receivers_.size(), &scene));
        scene_.reset(scene);
    }

    // Moves caster i (and its receiver copy) to x offset dx from where it started.
    void move_caster(size_t i, const GnomonBox &start, double dx) {
        GnomonBox moved = start;
        moved.min[0] += dx;
        moved.max[0] += dx;
        casters_[i] = moved;
        receivers_[i + 1] = moved;
        check(gnomon_scene_move(scene_.get(), casters_.data(), casters_.size(), receivers_.data(),
                                receivers_.size()));
    }

    // Sets up the cascades for this frame's camera and fills the uniforms.
    const GnomonSetupResult &update(const GnomonCamera &camera, const GnomonLight &sun) {
        check(gnomon_setup(scene_.get(), &camera, &sun, "cascades", "--cascades 4", 2048,
                           &result_));
        uniforms_.resize(result_.map_count);
        for (uint32_t i = 0; i < result_.map_count; i++) {
            const GnomonMap &map = result_.maps[i];
            std::memcpy(uniforms_[i].light_clip_from_world.data(), map.clip_from_world_f32,
                        sizeof map.clip_from_world_f32);
            std::memcpy(uniforms_[i].depth_from_world.data(), map.depth_from_world_f32,
                        sizeof map.depth_from_world_f32);
            uniforms_[i].far_view_depth = static_cast<float>(map.view_depth_range[1]);
        }
        return result_;
    }

    const std::vector<CascadeUniform> &uniforms() const { return uniforms_; }

  private:
    std::vector<GnomonBox> casters_;
    std::vector<GnomonBox> receivers_;
    Scene scene_;
    GnomonSetupResult result_{};
    std::vector<CascadeUniform> uniforms_;
};

void print_numbers(const char *key, const double *values, int count) {
    std::printf("\"%s\": [", key);
    for (int i = 0; i < count; i++) {
        std::printf("%s%.17g", i ? ", " : "", values[i]);
    }
    std::printf("]");
}

void print_frame_zero(const GnomonSetupResult &result) {
    std::printf("{\"technique\": \"cascades\", \"maps\": [");
    for (uint32_t i = 0; i < result.map_count; i++) {
        std::printf("%s{", i ? ", " : "");
        print_numbers("clip_from_world", result.maps[i].clip_from_world, 16);
        std::printf(", ");
        print_numbers("view_depth_range", result.maps[i].view_depth_range, 2);
        std::printf("}");
    }
    std::printf("]}\n");
}

}  // namespace

int main(int argc, char **argv) {
    const int frames = argc > 1 ? std::atoi(argv[1]) : 60;
    if (frames < 2) {
        std::fprintf(stderr, "error: give at least 2 frames\n");
        return 2;
    }
    const std::vector<GnomonBox> blocks = {
        {{-20, 0, -26}, {20, 16, -14}}, {{20, 0, 4}, {28, 40, 12}}, {{-23, 0, 3}, {-13, 8, 17}},
        {{-30, 0, 29.5}, {30, 4, 30.5}}, {{2.5, 0, 4.5}, {5.5, 3, 7.5}},
    };
    std::vector<GnomonBox> receivers = {{{-100, -5, -100}, {100, 0, 100}}};
    receivers.insert(receivers.end(), blocks.begin(), blocks.end());
    const size_t kiosk = 4;
    const GnomonCamera camera = {{-30, 2, 60}, {10, 4, -10}, {0, 1, 0}, 60, 16.0 / 9.0, 1, 300};
    const GnomonLight sun = {GNOMON_LIGHT_SUN, {0, 0, 0}, {0.4, -0.8, -0.45}, 0, 0};
    try {
        ShadowSystem shadows(blocks, receivers);
        const GnomonSetupResult first = shadows.update(camera, sun);
        print_frame_zero(first);
        for (int frame = 1; frame < frames; frame++) {
            // There and back again: the last frame has the kiosk where it started.
            const double dx = 20.0 * (frame < frames / 2 ? frame : frames - 1 - frame) / frames;
            shadows.move_caster(kiosk, blocks[kiosk], dx);
            const GnomonSetupResult &now = shadows.update(camera, sun);
            std::printf("frame %d: kiosk at x + %.3f, %u cascades, fallback %s, far %.2f\n",
                        frame, dx, now.map_count, gnomon_fallback_name(now.fallback),
                        shadows.uniforms().back().far_view_depth);
        }
        const GnomonSetupResult &last = shadows.update(camera, sun);
        bool same = last.map_count == first.map_count;
        for (uint32_t i = 0; same && i < first.map_count; i++) {
            same = std::memcmp(last.maps[i].clip_from_world, first.maps[i].clip_from_world,
                               sizeof first.maps[i].clip_from_world) == 0 &&
                   std::memcmp(last.maps[i].depth_from_world, first.maps[i].depth_from_world,
                               sizeof first.maps[i].depth_from_world) == 0;
        }
        if (!same) {
            std::fprintf(stderr, "error: the kiosk back at its start gives other matrices\n");
            return 1;
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
