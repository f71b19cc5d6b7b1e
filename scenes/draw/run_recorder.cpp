#include "scenes/draw/run_recorder.h"

#include "sim/error.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace scenes {
namespace {

std::string mib(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
    return text;
}

}  // namespace

RunRecorder::RunRecorder(const SceneRun& run, int frames) {
    const SceneDef& scene = run.scene();
    rec_.scene_name = scene.name;
    rec_.scene_file = scene.file.string();
    rec_.scene_text = scene.text;
    rec_.overrides = scene.overrides;
    rec_.step = scene.step;
    // K from the size of a state (the first); frame() thins the states if
    // later ones are larger, so they stay within max(budget, the first).
    const std::size_t first = snapshot_bytes(run.world().snapshot());
    rec_.every = recording_interval(frames, first);
    const std::uint64_t most = recording_bytes_without_states(rec_, frames) + std::max(kRecordingStatesBytes, first);
    if (most > kMaxRecordingBytes) {
        throw sim::InputError("--record: " + std::to_string(frames) + " frames of " + scene.name +
                              " could make a recording of " + mib(most) + " (8 bytes a frame, the scene's text, " +
                              "states within " + mib(std::max(kRecordingStatesBytes, first)) +
                              "), more than a recording may hold (" + mib(kMaxRecordingBytes) +
                              "): record fewer frames");
    }
}

void RunRecorder::frame(const SceneRun& run) {
    rec_.hashes.push_back(run.state_hash());
    rec_.frames = run.frame();
    if (run.frame() % rec_.every != 0) return;
    rec_.states.emplace_back(run.frame(), run.world().snapshot());
    state_bytes_ += snapshot_bytes(rec_.states.back().second);
    // Over budget (states grew: an emitter): keep every other one, K doubled.
    while (state_bytes_ > kRecordingStatesBytes && rec_.states.size() > 1) {
        rec_.every *= 2;
        std::erase_if(rec_.states, [&](const auto& s) { return s.first % rec_.every != 0; });
        state_bytes_ = 0;
        for (const auto& s : rec_.states) state_bytes_ += snapshot_bytes(s.second);
    }
}

Recording record_scene(const SceneDef& scene, int frames) {
    SceneRun run(scene);
    RunRecorder recorder(run, frames);
    recorder.frame(run);
    while (run.frame() < frames && run.advance()) recorder.frame(run);
    // The frame the watchdog stopped in (advance returned false after it).
    if (static_cast<int>(recorder.recording().hashes.size()) == run.frame()) recorder.frame(run);
    return recorder.recording();
}

}  // namespace scenes
