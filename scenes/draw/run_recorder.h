// A run kept as a recording (scenes/model/recording.h) as it goes: `run
// --record` feeds it each frame, and `check` records the actual run of a
// scene whose physics changed, for the CI's evidence.
#pragma once

#include "scenes/draw/scene_run.h"
#include "scenes/model/recording.h"

namespace scenes {

class RunRecorder {
public:
    // `run` at frame 0; `frames`: the frames it will take (for how often to
    // store a state). InputError, before anything runs, when the recording
    // could be larger than kMaxRecordingBytes.
    RunRecorder(const SceneRun& run, int frames);
    // After each frame the run reaches, frame 0 first.
    void frame(const SceneRun& run);
    // The recording so far, to the frame the run is at.
    const Recording& recording() const { return rec_; }

private:
    Recording rec_;
    std::size_t state_bytes_ = 0;  // the stored states' sections
};

// The scene run from frame 0 to `frames` (or the watchdog's stop), recorded.
Recording record_scene(const SceneDef& scene, int frames);

}  // namespace scenes
