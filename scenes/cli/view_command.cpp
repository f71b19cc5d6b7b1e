// `plausible view SCENE`: the scene in a window (scenes/view); prints where
// it was left. Exit 1 when the watchdog stopped it, 2 without a display.
#include "scenes/cli/commands.h"

#include "scenes/view/frame_budget.h"
#include "scenes/view/view.h"

#include <cstdio>

namespace scenes::cli {

namespace {

struct ViewArgs {
    SceneOptions scene;
    ViewOptions options;
    std::string size = "1280x720", screenshot;
    bool no_panel = false;
};

// --verbose: a running frame part by part, the renderer pass by pass.
void print_parts(const ViewFrameParts& f) {
    const render::Renderer::PassTimes& p = f.passes;
    std::printf(
        "view: a running frame, the mean of %d, ms: %.2f swap to swap; physics %.2f, draw list %.2f, rendering "
        "%.2f (prepare %.2f, shadow %.2f, ground %.2f, opaque %.2f, impostors %.2f, translucent %.2f, trails "
        "%.2f, overlays %.2f, MSAA resolve %.2f; each pass waiting for the renderer), blit %.2f, panel %.2f, "
        "swap %.2f\n",
        f.frames, f.frame, f.physics, f.draw_list, p.total(), p.prepare, p.shadow, p.ground, p.opaque, p.impostors,
        p.translucent, p.trails, p.overlays, p.resolve, f.blit, f.panel, f.swap);
}

// --verbose: the running frames' spread, against the budget a frame keeps to.
void print_spread(const FrameSpread& s) {
    if (s.frames == 0) return;
    std::printf(
        "view: running frames, swap to swap, ms: median %.1f, 95th percentile %.1f, worst %.1f; %d of %d over "
        "the %.0f ms budget\n",
        s.median, s.p95, s.worst, s.over_budget, s.frames, view::FrameBudget::kBudgetMs);
}

int view(ViewArgs& a) {
    const auto [w, h] = parse_size(a.size);
    a.options.panel = !a.no_panel;
    a.options.width = w;
    a.options.height = h;
    a.options.screenshot = a.screenshot;
    const SceneDef scene = a.scene.load();
    const ViewResult v = run_viewer(scene, a.scene.overrides(), a.options);
    // Where running frames were drawn on fewer pixels (dynamic resolution), by how much.
    char scales[64] = "";
    if (v.running_scale_min > 0.0f && v.running_scale_min < 1.0f) {
        std::snprintf(scales, sizeof scales, ", running frames drawn at %.0f-%.0f%%", 100.0f * v.running_scale_min,
                      100.0f * v.running_scale_max);
    }
    std::printf("view: %s, frame %d, t = %.4f s, state %s%s%s%s\n", scene.name.c_str(), v.frame, v.time,
                v.state_hash.c_str(), v.exploded ? " (exploded)" : "", scales,
                a.screenshot.empty() ? "" : (", screenshot " + a.screenshot).c_str());
    if (a.options.verbose) {
        print_parts(v.parts);
        print_spread(v.spread);
    }
    const int replay = report_replay(scene, v.diverged_frame, v.frame);
    return v.exploded ? kExitFailed : replay;
}

}  // namespace

Command add_view(CLI::App& app) {
    auto args = std::make_shared<ViewArgs>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Run a scene in a window: pause, step, step back, drag things, change integrator and dt live");
    cmd->add_option("scene", args->scene.scene,
                    "Scene name, .toml path or recording (run --record; a regular file of at most 128 MiB)")
        ->required();
    args->scene.add_to(cmd);
    cmd->add_option("--size", args->size, "Window size WIDTHxHEIGHT, px")->capture_default_str();
    cmd->add_option("--msaa", args->options.msaa_samples,
                    "MSAA samples, 0 (off, as the goldens) .. 8; -1: 4 when still, off while running")
        ->capture_default_str();
    cmd->add_option("--render-scale", args->options.render_scale,
                    "Draw a running scene at this fraction of the window's pixels per side, 0.375 .. 1; -1: chosen "
                    "frame by frame to keep a frame within 25 ms (still frames are drawn whole, and so are "
                    "--exit-after's)")
        ->capture_default_str();
    cmd->add_flag("--no-panel", args->no_panel, "Hide the control panel (H shows it)");
    cmd->add_flag("--paused", args->options.paused, "Start paused (Space resumes, Right steps)");
    cmd->add_option("--exit-after", args->options.exit_after,
                    "Show N frames, one scene step each (no wall clock), then exit");
    cmd->add_option("--screenshot", args->screenshot, "Save the window's last frame as this PNG on exit");
    cmd->add_option("--input", args->options.input,
                    "Play this script of key, text and mouse events, each at a drawn frame (lines like '3 key "
                    "Right', '5 move @Scene parameters', '6 press left'; see docs/commands.md); the "
                    "scene then steps once per drawn frame while running. A regular file of at most 16 MiB");
    cmd->add_flag("--verbose", args->options.verbose,
                  "Time each running frame part by part (physics, draw list, each render pass, blit, panel, swap) "
                  "and print the means on exit, then the running frames' spread swap to swap (median, 95th percentile, "
                  "worst, how many over the 25 ms budget); each pass then waits for the renderer: a little slower");
    return {cmd, [args] { return view(*args); }};
}

}  // namespace scenes::cli
