// The `plausible` command's subcommands (docs/design.md, "The command"). Each
// lives in its own file: it declares its options on the command line and
// returns what runs it once the line is parsed. plausible.cpp lists them in
// order and maps errors to exit codes.
#pragma once

#include "render/gl_context.h"
#include "scenes/model/scene.h"

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace scenes::cli {

// Exit codes: 0 ok, 1 a check failed or a simulation exploded, 2 bad input.
constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitBadInput = 2;

// A subcommand: its parser (true once given) and what runs it.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Command add_list(CLI::App& app);
Command add_run(CLI::App& app);
Command add_render(CLI::App& app);
Command add_check(CLI::App& app);
Command add_video(CLI::App& app);
Command add_view(CLI::App& app);
Command add_report(CLI::App& app);

// What every scene-taking subcommand accepts: the scene, --set overrides and
// the step shorthands --integrator, --dt, --substeps and --frames (each a
// --set of its key).
struct SceneOptions {
    std::string scene;
    std::vector<std::string> sets;
    std::optional<std::string> integrator;
    std::optional<double> dt;
    std::optional<int> substeps;
    std::optional<int> frames;

    // `frames`: false where the subcommand's --frames means something else
    // (render: the frames to draw).
    void add_to(CLI::App* app, bool frames = true);
    std::vector<Override> overrides() const;
    SceneDef load() const;  // a scene or a recording (recording.h); prints the scene's warnings to stderr
};

// After a run of a scene from a recording (SceneDef::recorded): prints
// whether every frame reached had the recorded state hash or where it
// diverged, and returns kExitFailed for a divergence (kExitOk otherwise, and
// for a scene that is not a recording).
int report_replay(const SceneDef& scene, int diverged_frame, int frames_reached);

// "1 frame", "2 frames": n and the word, plural unless n is 1.
std::string counted(long long n, const std::string& word);

// "WIDTHxHEIGHT" within 16x16 .. 8192x8192 px.
std::pair<int, int> parse_size(const std::string& text);
// An off-screen backend this build has (render::backends(): osmesa where the
// build found OSMesa, egl and gpu always; a window is not an off-screen
// backend), or auto: render::fastest_backend().
render::Backend parse_backend(const std::string& text);
// --backend, set to render::default_backend() (the goldens' llvmpipe), or to
// auto when `fastest` (videos), its help listing the backends this build
// has; --backend list prints them with the EGL devices found, and exits 0.
void add_backend_option(CLI::App* app, std::string* backend, bool fastest = false);

}  // namespace scenes::cli
