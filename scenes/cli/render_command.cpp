// `plausible render SCENE`: chosen frames of a scene as PNG files, and a
// contact sheet of them all.
#include "scenes/cli/commands.h"
#include "scenes/common/output_file.h"

#include "render/font.h"
#include "render/renderer.h"
#include "scenes/draw/scene_run.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace scenes::cli {

namespace {

namespace fs = std::filesystem;

struct RenderArgs {
    SceneOptions scene;
    std::string frames;  // "0,30,60"; empty: the scene's checkpoints
    std::string size = "640x480";
    std::string out = "out/render";
    std::string backend;  // set by add_backend_option: render::default_backend()
    int msaa = 4;
};

// --frames "0,30,60": ascending frame numbers within the scene's length.
std::vector<int> parse_frames(const std::string& text, const SceneDef& scene) {
    if (text.empty()) return scene.checkpoints;
    std::vector<int> frames;
    std::stringstream list(text);
    std::string item;
    while (std::getline(list, item, ',')) {
        char* end = nullptr;
        const long f = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || f < 0 || f > scene.frames || (!frames.empty() && f <= frames.back())) {
            throw sim::InputError("--frames must be ascending frame numbers within 0 .. " +
                                  std::to_string(scene.frames) + ", comma-separated (got '" + item + "' in '" + text +
                                  "')");
        }
        frames.push_back(static_cast<int>(f));
    }
    return frames;
}

// The contact sheet: one row while it stays under 8192 px, else rows of as
// many frames as fit that width; refused up front (nothing written) when the
// rows would pass the 16384 px an image may have.
render::SheetOptions sheet_layout(int frames, int w, int h, const std::string& size) {
    render::SheetOptions sheet;
    sheet.label_size = std::max(14.0f, static_cast<float>(h) / 28.0f);  // px, readable beside large frames
    const int per_row = std::max(1, 8192 / (w + sheet.padding));
    sheet.columns = frames <= per_row ? 0 : per_row;
    const int row_h = h + 2 * static_cast<int>(sheet.label_size) + 2 * sheet.padding;  // px, with label
    const int max_frames = per_row * std::max(1, 16384 / row_h);
    if (frames > max_frames) {
        throw sim::InputError("--frames: " + std::to_string(frames) + " frames of " + size +
                              " do not fit one contact sheet (at most " + std::to_string(max_frames) +
                              "); ask for fewer frames or a smaller --size, or use `plausible video`");
    }
    return sheet;
}

int render_scene(const RenderArgs& r) {
    const SceneDef scene = r.scene.load();
    const auto [w, h] = parse_size(r.size);
    const render::Backend backend = parse_backend(r.backend);
    if (!render::supported_msaa_samples(r.msaa)) {
        throw sim::InputError("--msaa must be 0, 1, 2, 4 or 8 (got " + std::to_string(r.msaa) + ")");
    }
    const std::vector<int> frames = parse_frames(r.frames, scene);
    const render::SheetOptions sheet_options = sheet_layout(static_cast<int>(frames.size()), w, h, r.size);
    make_output_folder(r.out);
    const auto context = render::create_context({.backend = backend});
    render::Renderer renderer(*context);
    SceneRun run(scene);
    std::vector<render::Image> tiles;
    std::vector<std::string> labels;
    char name[64];
    for (int f : frames) {
        while (run.frame() < f && run.advance()) {
        }
        tiles.push_back(renderer.render(run.draw_list(w, h), {.width = w, .height = h, .msaa_samples = r.msaa}));
        std::snprintf(name, sizeof name, "_f%05d.png", run.frame());
        const fs::path png = fs::path(r.out) / (scene.name + name);
        write_output(png, render::encode_png(tiles.back()));
        std::printf("%s\n", png.c_str());
        labels.push_back("frame " + std::to_string(run.frame()));
        if (run.verdict().exploded()) break;
    }
    const fs::path sheet = fs::path(r.out) / (scene.name + "_sheet.png");
    write_output(sheet,
                 render::encode_png(render::contact_sheet(tiles, labels, render::Font::default_font(), sheet_options)));
    std::printf("%s\n", sheet.c_str());
    const int replay = report_replay(scene, run.diverged_frame(), run.frame());
    if (run.verdict().exploded()) {
        std::printf("%s\n", run.verdict().message(scene.name).c_str());
        return kExitFailed;
    }
    return replay;
}

}  // namespace

Command add_render(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render frames of a scene to PNG, and a contact sheet");
    cmd->add_option("scene", args->scene.scene,
                    "Scene name, .toml path or recording (run --record; a regular file of at most 128 MiB)")
        ->required();
    args->scene.add_to(cmd, false);  // --frames here: the frames to draw
    cmd->add_option("--frames", args->frames,
                    "Frames to render, e.g. 0,30,60 (default: the checkpoints; the scene runs to the last)");
    cmd->add_option("--size", args->size, "Image size WIDTHxHEIGHT, px")->capture_default_str();
    cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
    add_backend_option(cmd, &args->backend);
    cmd->add_option("--msaa", args->msaa, "MSAA samples (0 off)")->capture_default_str();
    return {cmd, [args] { return render_scene(*args); }};
}

}  // namespace scenes::cli
