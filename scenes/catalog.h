// The scenes Plausible ships, in one explicit ordered table with a
// one-sentence description each. Every consumer (run, check, video, view,
// report, tests) builds its scene from here. (Scene files, scenes/*.toml,
// replace the C++ builders when the scene loader lands.)
#pragma once

#include "sim/analytic.h"
#include "sim/world.h"

#include <functional>
#include <optional>
#include <string_view>
#include <vector>

namespace scenes {

// A closed-form trajectory for one particle of a scene: what the "ghost"
// shows and what run summaries measure the error against.
struct Reference {
    std::size_t particle = 0;
    std::function<sim::analytic::PointState(double t)> exact;
};

struct Scene {
    sim::ParticleModel model;
    sim::StepSettings step;
    int frames = 600;  // frame steps the scene runs by default
    std::optional<Reference> reference;
};

struct SceneInfo {
    std::string_view name;
    std::string_view description;  // one sentence
    Scene (*build)();
};

// The ordered table; the first scene is the default (`make demo`).
const std::vector<SceneInfo>& catalog();
const SceneInfo* find_scene(std::string_view name);

}  // namespace scenes
