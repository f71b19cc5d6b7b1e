// `plausible video` end to end: physics, rendering at 1280x720 with 4x MSAA,
// read-back and H.264 encoding by the real ffmpeg, for the showcase, the
// cloth, the ragdoll pile and a 3-tile --compare of the orbit. The issue's
// target: >= 20 frames/s on 2 cores. Each iteration writes one second of
// video (30 frames) to a temporary folder; the figure to read is `fps`, with
// the per-frame physics and rendering times beside it (ffmpeg's encoding runs
// in its own threads, overlapping the rendering).
#include "scenes/model/scene.h"
#include "scenes/video/video.h"

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

void video(benchmark::State& state, const std::string& scene_name, std::vector<std::string> compare) {
    const scenes::SceneDef scene = scenes::load_scene(scenes::resolve_scene(scene_name));
    const fs::path dir = fs::temp_directory_path() / ("plausible-bench-video-" + std::to_string(getpid()));
    fs::create_directories(dir);
    scenes::VideoOptions o;
    o.output = dir / (scene_name + ".mp4");
    o.width = static_cast<int>(state.range(0));
    o.height = static_cast<int>(state.range(1));
    o.fps = 30;
    o.seconds = 1.0;
    o.compare = std::move(compare);
    double frames = 0, physics = 0, render = 0;
    for (auto _ : state) {
        const scenes::VideoStats s = scenes::write_video(scene, {}, o);
        frames += s.frames;
        physics += s.physics_ms * s.frames;
        render += s.render_ms * s.frames;
    }
    fs::remove_all(dir);
    state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
    state.counters["physics_ms"] = physics / frames;
    state.counters["render_ms"] = render / frames;
}

BENCHMARK_CAPTURE(video, showcase, "showcase", {})
    ->ArgNames({"w", "h"})
    ->Args({1280, 720})
    ->Args({640, 360})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(video, cloth, "cloth", {})
    ->ArgNames({"w", "h"})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(video, ragdoll_pile, "ragdoll-pile", {})
    ->ArgNames({"w", "h"})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(video, orbit_compare3, "orbit", {"forward_euler", "symplectic_euler", "velocity_verlet"})
    ->ArgNames({"w", "h"})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
