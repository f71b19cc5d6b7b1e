// `plausible video SCENE -o FILE`: the scene (or several variants side by
// side) as an MP4 or GIF through ffmpeg (scenes/video).
#include "scenes/cli/commands.h"

#include "scenes/common/progress.h"
#include "scenes/video/video.h"

#include <cstdio>
#include <sstream>

namespace scenes::cli {

namespace {

struct VideoArgs {
    SceneOptions scene;
    VideoOptions options;
    std::string out, size = "1280x720", compare, backend;
    bool no_caption = false;
};

int video(VideoArgs& a) {
    const auto [w, h] = parse_size(a.size);
    a.options.width = w;
    a.options.height = h;
    a.options.caption = !a.no_caption;
    a.options.output = a.out;
    // auto: write_video takes the fastest context, llvmpipe where a listed GPU cannot be used.
    if (a.backend != "auto") a.options.backend = parse_backend(a.backend);
    std::stringstream names(a.compare);
    for (std::string name; std::getline(names, name, ',');) a.options.compare.push_back(name);
    a.options.progress = progress_wanted();
    const SceneDef scene = a.scene.load();
    const VideoStats v = write_video(scene, a.scene.overrides(), a.options);
    std::printf("video: %s (%s; per frame: physics %.2f ms, rendering %.1f ms; %.1f frames/s in all)\n", a.out.c_str(),
                counted(v.frames, "frame").c_str(), v.physics_ms, v.render_ms, v.frames / v.seconds);
    std::printf("video: drawn by %s\n", v.renderer.c_str());
    if (a.options.verbose) {
        const render::Renderer::PassTimes& p = v.passes;
        std::printf(
            "video: per frame, pass by pass (ms, each pass waiting for the renderer): prepare %.2f, shadow "
            "%.2f, ground %.2f, opaque %.2f, impostors %.2f, translucent %.2f, trails %.2f, overlays %.2f, "
            "MSAA resolve %.2f, read-back %.2f; encoder wait %.2f\n",
            p.prepare, p.shadow, p.ground, p.opaque, p.impostors, p.translucent, p.trails, p.overlays, p.resolve,
            p.read_back, v.encode_ms);
    }
    return report_replay(scene, v.diverged_frame, v.last_frame);
}

}  // namespace

Command add_video(CLI::App& app) {
    auto args = std::make_shared<VideoArgs>();
    CLI::App* cmd = app.add_subcommand("video", "Render a scene to MP4 (H.264) or GIF through ffmpeg");
    cmd->add_option("scene", args->scene.scene,
                    "Scene name, .toml path or recording (run --record; a regular file of at most 128 MiB)")
        ->required();
    args->scene.add_to(cmd);
    cmd->add_option("-o,--output", args->out, "FILE.mp4 or FILE.gif (written whole or not at all)")->required();
    cmd->add_option("--size", args->size, "Width x height, even, px")->capture_default_str();
    cmd->add_option("--fps", args->options.fps, "Video frames per second (physics keeps its own dt)")
        ->capture_default_str();
    cmd->add_option("--seconds", args->options.seconds, "Simulated seconds (default: the scene's length)");
    cmd->add_option("--compare", args->compare,
                    "Tiles side by side in lock step, comma-separated: integrators (forward_euler,symplectic_euler) "
                    "or --set variants (step.substeps=1,step.substeps=8)");
    add_backend_option(cmd, &args->backend, /*fastest=*/true);
    cmd->add_flag("--no-caption", args->no_caption, "No description across the bottom for the first seconds");
    cmd->add_flag("--verbose", args->options.verbose,
                  "Time each frame pass by pass (shadow, opaque, impostors, overlays, MSAA resolve, read-back) and "
                  "the wait for the encoder, and print them (each pass then waits for the renderer: a little slower)");
    return {cmd, [args] { return video(*args); }};
}

}  // namespace scenes::cli
