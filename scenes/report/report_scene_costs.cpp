// Every shipped scene against the frame budget: its physics per 30 FPS frame
// (and per system), a 1280x720 render, and (not in --quick) ffmpeg's H.264
// encoding of its first frames. Its own file: the one stage that renders and
// runs ffmpeg.
#include "scenes/report/report_stages.h"

#include "render/gl_context.h"
#include "render/renderer.h"
#include "scenes/common/child_process.h"
#include "scenes/common/interrupt.h"
#include "scenes/draw/scene_run.h"
#include "scenes/model/scene.h"

#include "sim/error.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

namespace scenes::report {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kVideoWidth = 1280, kVideoHeight = 720;  // px, what `plausible video` makes by default
constexpr int kClipFrames = 30;

// Wall time of ffmpeg encoding `frames` of the clip (cycled) to H.264, yuv420p, as a video would be.
double encode_seconds(const std::vector<render::Image>& clip, int frames, const fs::path& log) {
    const std::vector<std::string> command = {
        "ffmpeg",    "-nostdin",
        "-loglevel", "error",
        "-f",        "rawvideo",
        "-pix_fmt",  clip.front().channels == 4 ? "rgba" : "rgb24",
        "-s",        std::to_string(kVideoWidth) + "x" + std::to_string(kVideoHeight),
        "-r",        "30",
        "-i",        "-",
        "-c:v",      "libx264",
        "-preset",   "medium",
        "-pix_fmt",  "yuv420p",
        "-f",        "null",
        "-"};
    const auto start = Clock::now();
    std::optional<ChildProcess> ffmpeg;
    try {
        ffmpeg.emplace(command, ChildOptions{.pipe_input = true, .errors = log});
    } catch (const std::runtime_error& e) {
        throw sim::InputError(std::string("report: ") + e.what() + " (Debian: apt-get install ffmpeg)");
    }
    bool written = true;
    for (int f = 0; f < frames && written; ++f) {
        const render::Image& image = clip[static_cast<std::size_t>(f) % clip.size()];
        written = ffmpeg->write(image.pixels.data(), image.pixels.size());
    }
    const int status = ffmpeg->wait();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::ifstream said(log);
    std::stringstream text;
    text << said.rdbuf();
    said.close();
    fs::remove(log);
    if (const int signal = child_interrupt(status); signal != 0) throw_interrupted("report", "a test clip", signal);
    check_interrupt("report", "a test clip");  // Ctrl+C reaches ffmpeg too, which stops reading
    if (!written || status != 0) {
        throw sim::InputError("report: ffmpeg failed encoding a test clip (" + describe_status(status) +
                              "): " + text.str());
    }
    return seconds;
}

// ms per frame of encoding, ffmpeg's start-up taken out: (T(n) - T(1)) / (n - 1).
double encode_ms_per_frame(const std::vector<render::Image>& clip, const fs::path& log) {
    const int n = 3 * kClipFrames;
    return 1e3 * (encode_seconds(clip, n, log) - encode_seconds(clip, 1, log)) / (n - 1);
}

// The scene's own frames for `quick` (or all of them), timed whole and per system.
void time_physics(const SceneDef& scene, bool quick, SceneRun& run, SceneCost& c) {
    const int frames = quick ? std::min(scene.frames, 60) : scene.frames;
    const auto start = Clock::now();
    while (run.frame() < frames && run.advance()) {
    }
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    c.frames = std::max(run.frame(), 1);
    c.exploded = run.verdict().exploded();
    c.steps_per_frame = (1.0 / 30.0) / scene.step.dt;
    const double to_ms = 1e3 * c.steps_per_frame / c.frames;  // s over the run -> ms per 30 FPS frame
    const auto& t = run.world().times();                      // sampled frames (World::SystemTimes)
    for (const std::string& system : scene.systems()) {
        const double v = system == "particles"     ? t.particles
                         : system == "constraints" ? t.constraints
                         : system == "collisions"  ? t.collisions
                         : system == "plasticity"  ? t.plasticity
                         : system == "rigid"       ? t.rigid
                         : system == "watchdog"    ? t.watchdog
                                                   : -1.0;
        if (v >= 0.0) c.systems.emplace_back(system, t.ms_per_step(v) * c.steps_per_frame);
    }
    c.physics = wall * to_ms;  // everything advance() does, the systems and the glue between them
}

// Rendering: the last frame a few times (--quick), or the scene's first 30
// frames as a video would show them, each timed; the median. Then (not
// --quick) those frames encoded.
void time_render(const SceneDef& scene, bool quick, const SceneRun& run, render::Renderer& renderer,
                 const fs::path& scratch, SceneCost& c) {
    std::vector<double> renders;
    std::vector<render::Image> clip;
    auto render_now = [&](const SceneRun& at) {
        const auto r0 = Clock::now();
        render::Image image = renderer.render(at.draw_list(kVideoWidth, kVideoHeight),
                                              {.width = kVideoWidth, .height = kVideoHeight, .msaa_samples = 4});
        renders.push_back(1e3 * std::chrono::duration<double>(Clock::now() - r0).count());
        if (image.width != kVideoWidth) throw sim::InputError("report: render of " + c.scene + " failed");
        return image;
    };
    if (quick) {
        for (int k = 0; k < 3; ++k) render_now(run);
    } else {
        SceneRun film(scene);
        for (int f = 0; f < kClipFrames; ++f) {
            clip.push_back(render_now(film));
            if (!film.advance()) break;
        }
    }
    c.render = median(renders);
    if (!clip.empty()) c.encode = encode_ms_per_frame(clip, scratch / "ffmpeg.log");
}

SceneCost scene_cost(const std::string& name, render::Renderer& renderer, bool quick, const fs::path& scratch) {
    const SceneDef scene = load_scene(resolve_scene(name));
    SceneCost c{.scene = name};
    SceneRun run(scene);
    time_physics(scene, quick, run, c);
    time_render(scene, quick, run, renderer, scratch, c);
    return c;
}

}  // namespace

std::vector<SceneCost> measure_scene_costs(bool quick, const fs::path& scratch, Progress& progress) {
    std::vector<SceneCost> out;
    const auto context = render::create_context({});
    render::Renderer renderer(*context);
    for (const std::string& name : catalog()) {
        out.push_back(scene_cost(name, renderer, quick, scratch));
        progress.step("scene " + name);
    }
    return out;
}

const char* budget_verdict(const SceneCost& c) {
    return c.exploded ? "exploded" : c.physics > kPhysicsHigh ? "over" : c.physics > kPhysicsLow ? "within" : "under";
}

}  // namespace scenes::report
