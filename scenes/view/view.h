// `plausible view`: a scene in a GLFW window on the same renderer as the
// pictures, to poke at. Keys (also buttons in the panel):
//   Space pause/resume   Right or . one step   Left or , one step back
//   R reset   [ ] slower/faster   I next integrator   H panel   P screenshot (view-SCENE-FRAME.png)
//   C camera back to the scene's   Q or Esc quit
// Mouse: left-drag a particle or a body (a spring pulls it to the cursor),
// left-drag elsewhere or right-drag to orbit, middle-drag to pan, wheel to
// zoom. The Dear ImGui panel has the step settings, sliders for the scene
// file's numbers (changing one rebuilds the scene) and live plots of the
// energy and of each system's time per frame.
//
// Stepping back restores stored states (the lecture: to go back in time
// accurately, store states; Euler does not run backwards), so a frame shown
// again has the same bits as the first time.
#pragma once

#include "render/renderer.h"
#include "scenes/model/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace scenes {

struct ViewOptions {
    int width = 1280, height = 720;  // px, the window
    // 0 (as the goldens), 1, 2, 4 or 8; -1: 4x when still (paused, scripted),
    // off while the scene runs, so that a heavy scene stays interactive
    // (4x MSAA costs llvmpipe about 40% more per frame).
    int msaa_samples = -1;
    // The fraction of the window's pixels per side a frame is drawn at while
    // the scene runs, 0.375 .. 1; -1: chosen frame by frame to keep a frame
    // within 25 ms (view/frame_budget.h). Still frames are drawn whole, and
    // so are --exit-after's (one step each, as the goldens draw them).
    double render_scale = -1.0;
    bool panel = true;                 // the Dear ImGui panel (H toggles it)
    bool paused = false;               // start paused
    int exit_after = 0;                // > 0: show this many frames, one scene step each (no wall clock), then exit
    std::filesystem::path screenshot;  // the window's last frame as PNG, on exit (and P's target)
    // A script of key, text and mouse events by drawn frame (view/input_script.h);
    // while one drives it, a running scene steps once per drawn frame.
    std::filesystem::path input;
    // Time each running frame part by part (ViewResult::parts), the renderer
    // pass by pass (each pass then waits for it: a little slower).
    bool verbose = false;
};

// A running frame's parts, ms, the mean over the frames drawn running.
struct ViewFrameParts {
    int frames = 0;                      // drawn running
    double physics = 0.0;                // the scene's steps (Viewer::update) and the history kept for stepping back
    double draw_list = 0.0;              // the scene turned into a DrawList
    render::Renderer::PassTimes passes;  // Renderer::draw, pass by pass
    double blit = 0.0;                   // the frame stretched into the window, and the overlays over it when scaled
    double panel = 0.0;                  // the Dear ImGui panel
    double swap = 0.0;                   // the buffer swap: the copy to the display (with vsync, the wait for it)
    double frame = 0.0;                  // the whole frame, swap to swap
};

// The running frames' whole times (swap to swap), ms: every frame drawn
// running, with or without --verbose (whose waits for the renderer add a
// little to each).
struct FrameSpread {
    int frames = 0;
    double median = 0.0, p95 = 0.0, worst = 0.0;  // ms
    int over_budget = 0;                          // frames over view::FrameBudget::kBudgetMs
};

struct ViewResult {
    int frame = 0;      // the scene frame shown last
    double time = 0.0;  // s, its simulated time
    bool exploded = false;
    std::string state_hash;   // hex, as `run --json` prints it: the same frame gives the same bits
    int diverged_frame = -1;  // a recording's: the first frame whose state differed from it; -1: none
    // The scales running frames were drawn at (RenderSettings::scale), lowest
    // and highest; 0 when no frame was drawn running.
    float running_scale_min = 0.0f, running_scale_max = 0.0f;
    ViewFrameParts parts;  // options.verbose; else zero
    FrameSpread spread;
};

// Opens the window and runs until it is closed (or after exit_after frames).
// Throws render::RenderError(no_display) without a display, with a message
// that says how to get a picture instead; sim::InputError for bad options.
ViewResult run_viewer(const SceneDef& scene, const std::vector<Override>& overrides, const ViewOptions& options);

}  // namespace scenes
