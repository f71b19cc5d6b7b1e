#include "scenes/draw/run_recorder.h"

namespace scenes {

RunRecorder::RunRecorder(const SceneDef& scene, int frames) : frames_(frames) {
    rec_.scene_name = scene.name;
    rec_.scene_file = scene.file.string();
    rec_.scene_text = scene.text;
    rec_.overrides = scene.overrides;
    rec_.step = scene.step;
}

void RunRecorder::frame(const SceneRun& run) {
    rec_.hashes.push_back(run.state_hash());
    rec_.frames = run.frame();
    // K from the size of a state (the first): the states stay within a few MB.
    if (run.frame() == 0) rec_.every = recording_interval(frames_, snapshot_bytes(run.world().snapshot()));
    if (run.frame() % rec_.every == 0) rec_.states.emplace_back(run.frame(), run.world().snapshot());
}

Recording record_scene(const SceneDef& scene, int frames) {
    SceneRun run(scene);
    RunRecorder recorder(scene, frames);
    recorder.frame(run);
    while (run.frame() < frames && run.advance()) recorder.frame(run);
    // The frame the watchdog stopped in (advance returned false after it).
    if (static_cast<int>(recorder.recording().hashes.size()) == run.frame()) recorder.frame(run);
    return recorder.recording();
}

}  // namespace scenes
