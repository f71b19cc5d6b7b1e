// The options every scene-taking subcommand shares, and the parsers of the
// values several of them take (--size, --backend).
#include "scenes/cli/commands.h"

#include "scenes/model/recording.h"
#include "sim/error.h"

#include <algorithm>
#include <cstdio>

namespace scenes::cli {

void SceneOptions::add_to(CLI::App* app, bool with_frames) {
    app->add_option("--set", sets, "Override a scene parameter, KEY=VALUE (e.g. step.dt=0.01); repeatable");
    app->add_option("--integrator", integrator, "Integrator (shorthand for --set step.integrator=NAME)");
    app->add_option("--dt", dt, "Frame step, s (shorthand for --set step.dt=S)");
    app->add_option("--substeps", substeps, "Integrator steps per frame step (--set step.substeps=N)");
    if (with_frames) app->add_option("--frames", frames, "Frame steps to run (--set frames=N)");
}

std::vector<Override> SceneOptions::overrides() const {
    std::vector<Override> out;
    for (const std::string& s : sets) out.push_back(parse_override(s));
    if (integrator) out.push_back({"step.integrator", "\"" + *integrator + "\""});
    if (dt) out.push_back({"step.dt", sim::format_value(*dt)});
    if (substeps) out.push_back({"step.substeps", std::to_string(*substeps)});
    if (frames) out.push_back({"frames", std::to_string(*frames)});
    return out;
}

SceneDef SceneOptions::load() const {
    SceneDef def = load_scene_or_recording(scene, overrides());
    for (const std::string& w : def.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return def;
}

int report_replay(const SceneDef& scene, int diverged_frame, int frames_reached) {
    if (!scene.recorded) return kExitOk;
    const std::string file = scene.recorded->file.string();
    const int recorded = static_cast<int>(scene.recorded->hashes.size()) - 1;
    if (diverged_frame >= 0) {
        std::printf("recording %s: DIVERGED at frame %d (t = %.4g s): the state hash differs from the recorded one\n",
                    file.c_str(), diverged_frame, diverged_frame * scene.step.dt);
        return kExitFailed;
    }
    std::printf("recording %s: replayed, frames 0 .. %d of its %d identical to the recorded state hashes\n",
                file.c_str(), std::min(frames_reached, recorded), recorded);
    return kExitOk;
}

std::string counted(long long n, const std::string& word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

std::pair<int, int> parse_size(const std::string& text) {
    int w = 0, h = 0;
    char end = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &end) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192) {
        throw sim::InputError("--size must be WIDTHxHEIGHT within 16x16 .. 8192x8192 px (got '" + text + "')");
    }
    return {w, h};
}

render::Backend parse_backend(const std::string& text) {
    if (text == "auto") return render::fastest_backend();
    const auto b = render::backend_from_name(text);
    const std::string built = render::offscreen_backend_names();
    if (!b || !render::backend_info(*b).offscreen) {
        throw sim::InputError("--backend must be an off-screen backend of this build: " + built +
                              ", auto or list (got '" + text + "')");
    }
    if (!render::backend_info(*b).built) {
        throw sim::InputError("--backend " + text +
                              ": not in this build (its library was not found when it was "
                              "configured); this build has: " +
                              built);
    }
    return *b;
}

void add_backend_option(CLI::App* app, std::string* backend, bool fastest) {
    *backend = fastest ? "auto" : std::string(render::backend_name(render::default_backend()));
    std::string help = "Off-screen GL backend; this build has: ";
    const char* separator = "";
    for (const render::BackendInfo& info : render::backends()) {
        if (!info.offscreen || !info.built) continue;
        help += separator + std::string(info.name) + " (" + std::string(info.about) + ")";
        separator = ", ";
    }
    help += "; auto: gpu where a hardware device is found, else " +
            std::string(render::backend_name(render::default_backend())) +
            "; list: print the backends and the EGL devices found, and exit";
    // list: when the option is parsed, before a missing scene is reported
    // (CLI11 2.6 checks required arguments before running the callbacks).
    app->add_option("--backend", *backend, help)
        ->capture_default_str()
        ->trigger_on_parse()
        ->each([](const std::string& value) {
            if (value != "list") return;
            std::printf("%s", render::describe_backends().c_str());
            throw CLI::Success();
        });
}

}  // namespace scenes::cli
