// The `plausible` command (DESIGN.md, "The command"). Exit codes: 0 ok,
// 1 a simulation exploded, 2 bad input.
#include "scenes/catalog.h"
#include "sim/error.h"
#include "sim/state_hash.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace {

constexpr int kExitOk = 0;
constexpr int kExitExploded = 1;
constexpr int kExitBadInput = 2;

struct RunOptions {
    std::string scene;
    std::optional<int> frames;
    std::optional<std::string> integrator;
    std::optional<double> dt;
    std::optional<int> substeps;
    bool json = false;
};

struct EnergyStats {
    double initial = 0, final = 0;
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    void add(double e) {
        final = e;
        min = std::min(min, e);
        max = std::max(max, e);
    }
};

bool state_is_finite(const sim::ParticleState& s) {
    for (double value : s.x.raw()) {
        if (!std::isfinite(value)) return false;
    }
    for (double value : s.v.raw()) {
        if (!std::isfinite(value)) return false;
    }
    return true;
}

std::string json_number(double value) {
    if (!std::isfinite(value)) return "null";
    return sim::format_value(value);
}

int run(const RunOptions& options) {
    const scenes::SceneInfo* info = scenes::find_scene(options.scene);
    if (info == nullptr) {
        std::string names;
        for (const auto& s : scenes::catalog()) names += (names.empty() ? "" : ", ") + std::string(s.name);
        throw sim::InputError("unknown scene '" + options.scene + "' (scenes: " + names + ")");
    }
    scenes::Scene scene = info->build();
    if (options.integrator) {
        const auto id = sim::integrator_from_name(*options.integrator);
        if (!id) {
            throw sim::InputError("--integrator: unknown integrator '" + *options.integrator +
                                  "' (expected one of: " + sim::integrator_names() + ")");
        }
        scene.step.integrator = *id;
    }
    if (options.dt) scene.step.dt = *options.dt;
    if (options.substeps) scene.step.substeps = *options.substeps;
    if (options.frames) {
        if (*options.frames < 0) {
            throw sim::InputError("--frames must be >= 0 (got " + std::to_string(*options.frames) + ")");
        }
        scene.frames = *options.frames;
    }
    sim::validate(scene.step);

    sim::World world(scene.model);
    EnergyStats energy;
    energy.initial = world.energy();
    energy.add(energy.initial);
    int exploded_at = -1;
    const auto start = std::chrono::steady_clock::now();
    for (int frame = 1; frame <= scene.frames; ++frame) {
        world.step(scene.step);
        energy.add(world.energy());
        if (!state_is_finite(world.state())) {
            exploded_at = frame;
            break;
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double ms_per_step = world.steps() ? 1e3 * seconds / static_cast<double>(world.steps()) : 0.0;
    const sim::ParticleState& s = world.state();
    const std::string integrator(sim::integrator_info(scene.step.integrator).name);

    std::optional<double> position_error;
    if (scene.reference) {
        const auto exact = scene.reference->exact(s.t);
        position_error = (s.x.get(scene.reference->particle) - exact.x).norm();
    }
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016" PRIx64, sim::state_hash(s));

    if (options.json) {
        std::ostringstream out;
        out << "{\"scene\":\"" << info->name << "\",\"integrator\":\"" << integrator
            << "\",\"dt\":" << json_number(scene.step.dt) << ",\"substeps\":" << scene.step.substeps
            << ",\"steps\":" << world.steps() << ",\"sim_time\":" << json_number(s.t)
            << ",\"systems\":[\"particles\"],\"state_hash\":\"" << hash
            << "\",\"energy\":{\"initial\":" << json_number(energy.initial)
            << ",\"final\":" << json_number(energy.final) << ",\"min\":" << json_number(energy.min)
            << ",\"max\":" << json_number(energy.max) << "},\"verdict\":";
        if (exploded_at < 0) {
            out << "{\"status\":\"ok\"}";
        } else {
            out << "{\"status\":\"exploded\",\"frame\":" << exploded_at << ",\"quantity\":\"non-finite state\"}";
        }
        out << ",\"ms_per_step\":{\"particles\":" << json_number(ms_per_step)
            << ",\"total\":" << json_number(ms_per_step) << "}";
        if (position_error) out << ",\"position_error\":" << json_number(*position_error);
        out << ",\"force_evaluations\":" << json_number(world.force_evaluations()) << "}\n";
        std::cout << out.str();
    } else {
        std::printf("%s: %d frames of %s, dt %.6g s x %d substeps, t = %.4g s\n", std::string(info->name).c_str(),
                    scene.frames, integrator.c_str(), scene.step.dt, scene.step.substeps, s.t);
        const double drift =
            energy.initial != 0.0 ? 100.0 * (energy.final - energy.initial) / std::abs(energy.initial) : 0.0;
        std::printf("  energy    initial %.6g J, final %.6g J (%+.3g%%), range [%.6g, %.6g] J\n", energy.initial,
                    energy.final, drift, energy.min, energy.max);
        if (position_error) {
            std::printf("  accuracy  particle %zu is %.3e m from the closed form\n", scene.reference->particle,
                        *position_error);
        }
        std::printf("  cost      %.0f force evaluations, %.3g ms per step\n", world.force_evaluations(), ms_per_step);
        std::printf("  state     hash %s\n", hash);
        if (exploded_at >= 0) {
            std::printf("%s: exploded at frame %d: the state is no longer finite\n", std::string(info->name).c_str(),
                        exploded_at);
        }
    }
    return exploded_at < 0 ? kExitOk : kExitExploded;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Plausible: a games-physics lab. Scenes run headless; see `plausible list`."};
    app.require_subcommand(1);

    CLI::App* list = app.add_subcommand("list", "List the scenes with their descriptions");

    RunOptions options;
    CLI::App* run_cmd = app.add_subcommand("run", "Run a scene headless and print a summary");
    run_cmd->add_option("scene", options.scene, "Scene name (see `plausible list`)")->required();
    run_cmd->add_option("--frames", options.frames, "Frame steps to run");
    run_cmd->add_option("--integrator", options.integrator, "One of: " + sim::integrator_names());
    run_cmd->add_option("--dt", options.dt, "Frame step, s");
    run_cmd->add_option("--substeps", options.substeps, "Integrator steps per frame step");
    run_cmd->add_flag("--json", options.json, "Print one JSON object");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }

    try {
        if (*list) {
            for (const scenes::SceneInfo& s : scenes::catalog()) {
                std::printf("%-12s %s\n", std::string(s.name).c_str(), std::string(s.description).c_str());
            }
            return kExitOk;
        }
        return run(options);
    } catch (const sim::InputError& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return kExitBadInput;
    }
}
