// `plausible video`: a scene rendered to MP4 (H.264) or GIF by piping raw
// frames to the ffmpeg command. Physics and frame rate are independent (the
// lecture: render at 30 FPS, step physics at 60 Hz): frame k shows the state
// at the last physics step not after k / fps, the usual fixed-step
// accumulator. --compare runs the same scene under several integrators (or
// --set variants) in lock step, side by side in tiles labelled by their HUD.
#pragma once

#include "render/renderer.h"
#include "scenes/model/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace scenes {

struct VideoOptions {
    std::filesystem::path output;      // .mp4 or .gif
    int width = 1280, height = 720;    // px, even
    int fps = 30;                      // frames per second of video, 1 .. 120
    double seconds = 0.0;              // of simulated time; 0: the scene's length
    std::vector<std::string> compare;  // one tile each: an integrator name or a --set variant KEY=VALUE
    bool progress = false;             // a progress bar with frames/s and ETA on stderr
    bool caption = true;               // the scene's description across the bottom for the first seconds
    bool verbose = false;              // time each frame pass by pass (VideoStats::passes; a little slower)
    // The GL backend; none: render::create_fastest_context() (a GPU where EGL finds one that works, else llvmpipe).
    std::optional<render::Backend> backend;
};

struct VideoStats {
    int frames = 0;
    // Per frame, all tiles: drawing and reading back (the calling thread), and
    // stepping and building the draw lists (the stepping thread). The two
    // overlap: a frame takes about the larger, not their sum.
    double render_ms = 0.0;
    double physics_ms = 0.0;
    double seconds = 0.0;                // wall time of the whole video
    int last_frame = 0;                  // the scene frame the video ends on
    int diverged_frame = -1;             // a recording's: the first frame whose state differs from it; -1: none
    double encode_ms = 0.0;              // per frame: waiting for room in the encoder's queue
    render::Renderer::PassTimes passes;  // per frame, all tiles, ms (options.verbose; else zero)
    std::string renderer;                // what drew the frames: the context's fingerprint, one line
};

// Writes options.output whole or not at all. Throws sim::InputError for bad
// options (odd size, unknown integrator, an unwritable path, a wrong
// extension), std::runtime_error when ffmpeg fails or goes away.
VideoStats write_video(const SceneDef& scene, const std::vector<Override>& overrides, const VideoOptions& options);

// The ffmpeg arguments that encode raw frames (rgb24, or rgba for 4
// channels) from its standard input into `output` as options say:
// write_video's, and bench_video's reference (ffmpeg alone on the same frames).
std::vector<std::string> ffmpeg_arguments(const VideoOptions& options, int channels,
                                          const std::filesystem::path& output);

}  // namespace scenes
