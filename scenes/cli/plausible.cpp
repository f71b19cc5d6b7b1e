// The `plausible` command (DESIGN.md, "The command"). Exit codes: 0 ok,
// 1 a check failed or a simulation exploded, 2 bad input. Ctrl+C (SIGTERM)
// during a video, report or run --csv: nothing written, and the command ends
// by that signal (a shell shows 130, 143), see scenes/interrupt.h.
#include "render/font.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "scenes/check/check.h"
#include "scenes/common/interrupt.h"
#include "scenes/common/progress.h"
#include "scenes/report/report.h"
#include "scenes/model/scene.h"
#include "scenes/draw/scene_run.h"
#include "scenes/video/video.h"
#include "scenes/view/view.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <string>

namespace {

namespace fs = std::filesystem;

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitBadInput = 2;

// What every scene-taking subcommand accepts.
struct SceneOptions {
    std::string scene;
    std::vector<std::string> sets;
    std::optional<std::string> integrator;
    std::optional<double> dt;
    std::optional<int> substeps;
    std::optional<int> frames;

    void add_to(CLI::App* app, bool shorthands) {
        app->add_option("--set", sets, "Override a scene parameter, KEY=VALUE (e.g. step.dt=0.01); repeatable");
        if (!shorthands) return;
        app->add_option("--integrator", integrator, "Integrator (shorthand for --set step.integrator=NAME)");
        app->add_option("--dt", dt, "Frame step, s (shorthand for --set step.dt=S)");
        app->add_option("--substeps", substeps, "Integrator steps per frame step (--set step.substeps=N)");
        app->add_option("--frames", frames, "Frame steps to run (--set frames=N)");
    }
    std::vector<scenes::Override> overrides() const {
        std::vector<scenes::Override> out;
        for (const std::string& s : sets) out.push_back(scenes::parse_override(s));
        if (integrator) out.push_back({"step.integrator", "\"" + *integrator + "\""});
        if (dt) out.push_back({"step.dt", sim::format_value(*dt)});
        if (substeps) out.push_back({"step.substeps", std::to_string(*substeps)});
        if (frames) out.push_back({"frames", std::to_string(*frames)});
        return out;
    }
    scenes::SceneDef load() const {
        scenes::SceneDef def = scenes::load_scene(scenes::resolve_scene(scene), overrides());
        for (const std::string& w : def.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        return def;
    }
};

double finite_or_nan(double v) { return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN(); }
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// --- list -------------------------------------------------------------------------

int list_scenes() {
    for (const std::string& name : scenes::catalog()) {
        const scenes::SceneDef scene = scenes::load_scene(scenes::scenes_dir() / (name + ".toml"));
        std::printf("%-12s %s\n", name.c_str(), scene.description.c_str());
    }
    return kExitOk;
}

// --- run ----------------------------------------------------------------------------

struct RunOutput {
    std::optional<std::string> csv;
    bool json = false;
};

int run_scene(const SceneOptions& options, const RunOutput& output) {
    const scenes::SceneDef scene = options.load();
    scenes::SceneRun run(scene);
    std::ofstream csv;
    std::string csv_temp;
    // Ctrl+C while the CSV is being written: stop at the next frame and
    // remove it (a run without --csv writes nothing and keeps the default).
    std::optional<scenes::InterruptScope> interrupts;
    if (output.csv) {
        interrupts.emplace();
        csv_temp = *output.csv + ".tmp-" + std::to_string(getpid());
        csv.open(csv_temp, std::ios::binary);
        if (!csv) throw sim::InputError("--csv: cannot write " + *output.csv);
        csv << "frame,time,kind,id,x,y,z,vx,vy,vz\n";
        csv.precision(17);
    }
    auto write_rows = [&](const scenes::SceneRun& run) {
        if (!csv.is_open()) return;
        const sim::ParticleState& s = run.world().state();
        for (std::size_t i = 0; i < s.size(); ++i) {
            const sim::Vec3 x = s.x.get(i), v = s.v.get(i);
            csv << run.frame() << ',' << s.t << ",particle," << i << ',' << x.x() << ',' << x.y() << ',' << x.z() << ','
                << v.x() << ',' << v.y() << ',' << v.z() << '\n';
        }
        if (const sim::RigidWorld* rigid = run.world().rigid()) {
            const auto bodies = rigid->body_states();
            for (std::size_t k = 0; k < bodies.size(); ++k) {
                const sim::Vec3 x = bodies[k].position, v = bodies[k].velocity;
                csv << run.frame() << ',' << s.t << ",body," << k << ',' << x.x() << ',' << x.y() << ',' << x.z() << ','
                    << v.x() << ',' << v.y() << ',' << v.z() << '\n';
            }
        }
    };

    const double e0 = run.world().energy();
    double e_min = e0, e_max = e0;
    try {
        write_rows(run);
        while (run.frame() < scene.frames && run.advance()) {
            const double e = run.world().energy();
            e_min = std::min(e_min, e), e_max = std::max(e_max, e);
            write_rows(run);
            if (scenes::interrupt_signal() != 0)
                scenes::check_interrupt("run --csv", "frame " + std::to_string(run.frame()));
        }
        if (run.verdict().exploded()) {
            write_rows(run);
            const double e = run.world().energy();
            e_min = std::min(e_min, e), e_max = std::max(e_max, e);
        }
        if (csv.is_open()) scenes::check_interrupt("run --csv", "the last frame");
    } catch (...) {
        if (csv.is_open()) {
            csv.close();
            std::error_code error;
            fs::remove(csv_temp, error);
        }
        throw;
    }
    if (csv.is_open()) {
        csv.close();
        std::error_code error;
        fs::rename(csv_temp, *output.csv, error);
        if (error) {
            fs::remove(csv_temp, error);
            throw sim::InputError("--csv: cannot write " + *output.csv);
        }
    }
    const sim::World& world = run.world();
    const double e1 = world.energy();
    const std::string integrator(sim::integrator_info(scene.step.integrator).name);
    const auto& times = world.times();
    auto ms = [&](double seconds) { return times.ms_per_step(seconds); };
    // Per system the scene built (DESIGN.md: ms_per_step has one entry per system and the total), measured
    // on the sampled frames (World::SystemTimes); the total is the whole step, the glue between systems included.
    nlohmann::json per_system = nlohmann::json::object();
    for (const std::string& system : scene.systems()) {
        const double v = system == "particles"     ? ms(times.particles)
                         : system == "constraints" ? ms(times.constraints)
                         : system == "collisions"  ? ms(times.collisions)
                         : system == "plasticity"  ? ms(times.plasticity)
                         : system == "rigid"       ? ms(times.rigid)
                         : system == "watchdog"    ? ms(times.watchdog)
                                                   : -1.0;
        if (v < 0.0) continue;  // springs: inside the particles' force evaluations
        per_system[system] = v;
    }
    per_system["total"] = ms(times.total);
    std::optional<double> error;
    if (!scene.ghosts.empty()) {
        const scenes::Ghost& g = scene.ghosts.front();
        const sim::Vec3 x = g.body >= 0 ? world.rigid()->state({static_cast<std::uint32_t>(g.body), 0}).position
                                        : world.state().x.get(g.particle);
        error = (x - g.exact(run.time()).x).norm();
    }
    const sim::Verdict& verdict = run.verdict();

    if (output.json) {
        nlohmann::json j;
        j["scene"] = scene.name;
        j["integrator"] = integrator;
        j["dt"] = scene.step.dt;
        j["substeps"] = scene.step.substeps;
        j["steps"] = world.steps();
        j["frames"] = run.frame();
        j["sim_time"] = number(run.time());
        j["systems"] = scene.systems();
        j["state_hash"] = run.state_hash_hex();
        j["energy"] = {{"initial", number(e0)}, {"final", number(e1)}, {"min", number(e_min)}, {"max", number(e_max)}};
        if (verdict.exploded()) {
            j["verdict"] = {{"status", "exploded"},
                            {"frame", verdict.frame},
                            {"quantity", verdict.quantity},
                            {"index", verdict.index},
                            {"value", number(verdict.value)},
                            {"limit", number(verdict.limit)},
                            {"message", verdict.message(scene.name)}};
        } else {
            j["verdict"] = {{"status", "ok"}};
        }
        j["ms_per_step"] = per_system;
        nlohmann::json contained = nlohmann::json::array();
        for (const auto& c : world.contained()) {
            contained.push_back({{"name", c.name},
                                 {"frame", c.verdict.frame},
                                 {"quantity", c.verdict.quantity},
                                 {"index", c.verdict.index},
                                 {"value", number(c.verdict.value)},
                                 {"message", c.verdict.message(scene.name + ": " + c.name)}});
        }
        if (!contained.empty()) j["contained"] = contained;
        j["force_evaluations"] = world.force_evaluations();
        if (error) j["position_error"] = number(*error);
        if (world.rigid() != nullptr) j["solver_messages"] = world.rigid()->solver_messages();
        std::cout << j.dump() << "\n";
    } else {
        std::printf("%s: %d frames of %s, dt %s x %d substeps, t = %.4g s\n", scene.name.c_str(), run.frame(),
                    integrator.c_str(), scenes::format_dt(scene.step.dt).c_str(), scene.step.substeps, run.time());
        const double drift = e0 != 0.0 ? 100.0 * (e1 - e0) / std::abs(e0) : 0.0;
        std::printf("  energy    initial %.6g J, final %.6g J (%+.3g%%), range [%.6g, %.6g] J\n", e0, finite_or_nan(e1),
                    drift, e_min, e_max);
        if (error) {
            const scenes::Ghost& g = scene.ghosts.front();
            const std::string& who = g.body >= 0
                                         ? scene.body_names[static_cast<std::size_t>(g.body)] + "'s centre of mass"
                                         : scene.particle_names[g.particle];
            std::printf("  accuracy  %s is %.3e m from the %s closed form\n", who.c_str(), *error, g.solution.c_str());
        }
        std::printf("  cost      %.0f force evaluations, %.3g ms per step (", world.force_evaluations(),
                    ms(times.total));
        bool first = true;
        for (const auto& [system, v] : per_system.items()) {
            if (system == "total") continue;
            std::printf("%s%s %.3g", first ? "" : ", ", system.c_str(), v.get<double>());
            first = false;
        }
        std::printf(")\n");
        for (const auto& c : world.contained()) {
            std::printf("  contained %s (frozen; the run went on)\n",
                        c.verdict.message(scene.name + ": " + c.name).c_str());
        }
        if (world.rigid() != nullptr) {
            for (const std::string& said : world.rigid()->solver_messages())
                std::printf("  ODE said  %s\n", said.c_str());
        }
        std::printf("  state     hash %s\n", run.state_hash_hex().c_str());
        if (verdict.exploded()) std::printf("%s\n", verdict.message(scene.name).c_str());
    }
    return verdict.exploded() ? kExitFailed : kExitOk;
}

// --- render -------------------------------------------------------------------------

struct RenderOptions {
    std::string frames;  // "0,30,60"; empty: the scene's checkpoints
    std::string size = "640x480";
    std::string out = "out/render";
    std::string backend = "osmesa";
    int msaa = 4;
};

std::pair<int, int> parse_size(const std::string& text) {
    int w = 0, h = 0;
    char end = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &end) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192) {
        throw sim::InputError("--size must be WIDTHxHEIGHT within 16x16 .. 8192x8192 px (got '" + text + "')");
    }
    return {w, h};
}

render::Backend parse_backend(const std::string& text) {
    const auto b = render::backend_from_name(text);
    if (!b || *b == render::Backend::glfw)
        throw sim::InputError("--backend must be osmesa or egl (got '" + text + "')");
    return *b;
}

int render_scene(const SceneOptions& options, const RenderOptions& r) {
    scenes::SceneDef scene = options.load();
    const auto [w, h] = parse_size(r.size);
    const render::Backend backend = parse_backend(r.backend);
    if (r.msaa != 0 && r.msaa != 1 && r.msaa != 2 && r.msaa != 4 && r.msaa != 8) {
        throw sim::InputError("--msaa must be 0, 1, 2, 4 or 8 (got " + std::to_string(r.msaa) + ")");
    }
    std::vector<int> frames;
    if (r.frames.empty()) {
        frames = scene.checkpoints;
    } else {
        std::stringstream list(r.frames);
        std::string item;
        while (std::getline(list, item, ',')) {
            char* end = nullptr;
            const long f = std::strtol(item.c_str(), &end, 10);
            if (item.empty() || *end != '\0' || f < 0 || f > scene.frames || (!frames.empty() && f <= frames.back())) {
                throw sim::InputError("--frames must be ascending frame numbers within 0 .. " +
                                      std::to_string(scene.frames) + ", comma-separated (got '" + item + "' in '" +
                                      r.frames + "')");
            }
            frames.push_back(static_cast<int>(f));
        }
    }
    // The contact sheet: one row while it stays under 8192 px, else rows of
    // as many frames as fit that width; refused up front (nothing written)
    // when the rows would pass the 16384 px an image may have.
    render::SheetOptions sheet_options;
    sheet_options.label_size = std::max(14.0f, static_cast<float>(h) / 28.0f);  // px, readable beside large frames
    const int n = static_cast<int>(frames.size());
    const int per_row = std::max(1, 8192 / (w + sheet_options.padding));
    sheet_options.columns = n <= per_row ? 0 : per_row;
    const int row_h = h + 2 * static_cast<int>(sheet_options.label_size) + 2 * sheet_options.padding;  // px, with label
    const int max_frames = per_row * std::max(1, 16384 / row_h);
    if (n > max_frames) {
        throw sim::InputError("--frames: " + std::to_string(n) + " frames of " + r.size +
                              " do not fit one contact sheet (at most " + std::to_string(max_frames) +
                              "); ask for fewer frames or a smaller --size, or use `plausible video`");
    }
    fs::create_directories(r.out);
    const auto context = render::create_context({.backend = backend});
    render::Renderer renderer(*context);
    scenes::SceneRun run(scene);
    std::vector<render::Image> tiles;
    std::vector<std::string> labels;
    char name[64];
    for (int f : frames) {
        while (run.frame() < f && run.advance()) {
        }
        tiles.push_back(renderer.render(run.draw_list(w, h), {.width = w, .height = h, .msaa_samples = r.msaa}));
        std::snprintf(name, sizeof name, "_f%05d.png", run.frame());
        const fs::path png = fs::path(r.out) / (scene.name + name);
        render::write_png(png, tiles.back());
        std::printf("%s\n", png.c_str());
        labels.push_back("frame " + std::to_string(run.frame()));
        if (run.verdict().exploded()) break;
    }
    const fs::path sheet = fs::path(r.out) / (scene.name + "_sheet.png");
    render::write_png(sheet, render::contact_sheet(tiles, labels, render::Font::default_font(), sheet_options));
    std::printf("%s\n", sheet.c_str());
    if (run.verdict().exploded()) {
        std::printf("%s\n", run.verdict().message(scene.name).c_str());
        return kExitFailed;
    }
    return kExitOk;
}

// --- check --------------------------------------------------------------------------

struct CheckArgs {
    std::vector<std::string> scenes;
    std::string update = "none";
    std::string report = "out/check";
    std::string backend = "osmesa";
};

int check(const CheckArgs& a, const SceneOptions& options) {
    scenes::CheckOptions o;
    if (a.update == "none")
        o.update = scenes::UpdateMode::none;
    else if (a.update == "missing")
        o.update = scenes::UpdateMode::missing;
    else if (a.update == "changed")
        o.update = scenes::UpdateMode::changed;
    else if (a.update == "all")
        o.update = scenes::UpdateMode::all;
    else
        throw sim::InputError("--update must be none, missing, changed or all (got '" + a.update + "')");
    const auto overrides = options.overrides();
    if (o.update != scenes::UpdateMode::none && !overrides.empty()) {
        throw sim::InputError(
            "--update with --set would bless a scene that is not the one in its file: drop one of them");
    }
    o.report_dir = a.report;
    const std::vector<std::string> names = a.scenes.empty() ? scenes::catalog() : a.scenes;
    const auto context = render::create_context({.backend = parse_backend(a.backend)});
    render::Renderer renderer(*context);
    const auto results = scenes::check_scenes(names, overrides, o, renderer, context->fingerprint());
    int passed = 0, failed = 0, errors = 0;
    for (const scenes::SceneCheck& c : results) {
        const bool ok = c.status == scenes::SceneCheck::Status::pass || c.status == scenes::SceneCheck::Status::updated;
        passed += ok ? 1 : 0;
        errors += c.status == scenes::SceneCheck::Status::error ? 1 : 0;
        failed += !ok && c.status != scenes::SceneCheck::Status::error ? 1 : 0;
        std::printf("%-12s %-8s %s (%.1f s)\n", c.scene.c_str(), scenes::status_name(c.status), c.message.c_str(),
                    c.seconds);
    }
    std::printf("%d passed, %d failed, %d errors; report: %s\n", passed, failed, errors,
                (fs::path(a.report) / "index.html").c_str());
    return failed > 0 ? kExitFailed : errors > 0 ? kExitBadInput : kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Plausible: a games-physics lab. Scenes run headless; see `plausible list`."};
    app.require_subcommand(1);

    CLI::App* list = app.add_subcommand("list", "List the scenes with their descriptions");

    SceneOptions run_options;
    RunOutput run_output;
    CLI::App* run = app.add_subcommand("run", "Run a scene headless and print a summary");
    run->add_option("scene", run_options.scene, "Scene name (see `plausible list`) or path of a .toml file")
        ->required();
    run_options.add_to(run, true);
    run->add_option("--csv", run_output.csv, "Write frame,time,kind,id,x,y,z,vx,vy,vz per object per frame");
    run->add_flag("--json", run_output.json,
                  "Print one JSON object. ms_per_step: the whole step (total) and each system, timed on a sample "
                  "of frames (every frame at first, then enough to keep the clocks under 1% of the step; a step "
                  "under a microsecond reads longer than it runs, the clock reads stopping its overlap with the "
                  "next: bench_sim times those)");

    SceneOptions render_options;
    RenderOptions render_args;
    CLI::App* render_cmd = app.add_subcommand("render", "Render frames of a scene to PNG, and a contact sheet");
    render_cmd->add_option("scene", render_options.scene, "Scene name or .toml path")->required();
    render_options.add_to(render_cmd, false);
    render_cmd->add_option("--frames", render_args.frames, "Frames to render, e.g. 0,30,60 (default: the checkpoints)");
    render_cmd->add_option("--size", render_args.size, "Image size WIDTHxHEIGHT, px")->capture_default_str();
    render_cmd->add_option("--out", render_args.out, "Output folder")->capture_default_str();
    render_cmd->add_option("--backend", render_args.backend, "osmesa or egl")->capture_default_str();
    render_cmd->add_option("--msaa", render_args.msaa, "MSAA samples (0 off)")->capture_default_str();

    CheckArgs check_args;
    SceneOptions check_options;
    CLI::App* check_cmd = app.add_subcommand("check", "Compare scenes' checkpoint frames with their golden images");
    check_cmd->add_option("scenes", check_args.scenes, "Scenes to check (default: all)");
    check_options.add_to(check_cmd, true);
    check_cmd->add_option("--update", check_args.update, "Write goldens: none, missing, changed or all")
        ->capture_default_str();
    check_cmd->add_option("--report", check_args.report, "Folder for the report (index.html, report.json, images)")
        ->capture_default_str();
    check_cmd->add_option("--backend", check_args.backend, "osmesa or egl")->capture_default_str();

    SceneOptions video_scene;
    scenes::VideoOptions video_options;
    std::string video_out, video_size = "1280x720", video_compare;
    CLI::App* video_cmd = app.add_subcommand("video", "Render a scene to MP4 (H.264) or GIF through ffmpeg");
    video_cmd->add_option("scene", video_scene.scene, "Scene name or .toml path")->required();
    video_scene.add_to(video_cmd, true);
    video_cmd->add_option("-o,--output", video_out, "FILE.mp4 or FILE.gif (written whole or not at all)")->required();
    video_cmd->add_option("--size", video_size, "Width x height, even, px")->capture_default_str();
    video_cmd->add_option("--fps", video_options.fps, "Video frames per second (physics keeps its own dt)")
        ->capture_default_str();
    video_cmd->add_option("--seconds", video_options.seconds, "Simulated seconds (default: the scene's length)");
    video_cmd->add_option(
        "--compare", video_compare,
        "Tiles side by side in lock step, comma-separated: integrators (forward_euler,symplectic_euler) or "
        "--set variants (step.substeps=1,step.substeps=8)");
    video_cmd->add_flag("!--no-caption", video_options.caption,
                        "No description across the bottom for the first seconds");

    SceneOptions view_scene;
    scenes::ViewOptions view_options;
    std::string view_size = "1280x720", view_screenshot;
    CLI::App* view_cmd = app.add_subcommand(
        "view", "Run a scene in a window: pause, step, step back, drag things, change integrator and dt live");
    view_cmd->add_option("scene", view_scene.scene, "Scene name or .toml path")->required();
    view_scene.add_to(view_cmd, true);
    view_cmd->add_option("--size", view_size, "Window size WIDTHxHEIGHT, px")->capture_default_str();
    view_cmd
        ->add_option("--msaa", view_options.msaa_samples,
                     "MSAA samples, 0 (off, as the goldens) .. 8; -1: 4 when still, off while running")
        ->capture_default_str();
    view_cmd->add_flag("!--no-panel", view_options.panel, "Hide the control panel (H shows it)");
    view_cmd->add_flag("--paused", view_options.paused, "Start paused (Space resumes, Right steps)");
    view_cmd->add_option("--exit-after", view_options.exit_after,
                         "Show N frames, one scene step each (no wall clock), then exit");
    view_cmd->add_option("--screenshot", view_screenshot, "Save the window's last frame as this PNG on exit");

    scenes::ReportOptions report_options;
    std::string report_out = report_options.out.string();
    CLI::App* report_cmd = app.add_subcommand(
        "report", "Speed against error: work-precision, orders, energy drift, stability (Markdown, CSV, JSON, PNG)");
    report_cmd->add_flag("--quick", report_options.quick, "Fewer dt values and timings (CI's run, under 60 s)");
    report_cmd->add_option("--out", report_out, "Folder written (whole, or not at all)")->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }

    try {
        if (*list) return list_scenes();
        if (*run) return run_scene(run_options, run_output);
        if (*render_cmd) return render_scene(render_options, render_args);
        if (*video_cmd) {
            const auto [w, h] = parse_size(video_size);
            video_options.width = w;
            video_options.height = h;
            video_options.output = video_out;
            std::stringstream names(video_compare);
            for (std::string name; std::getline(names, name, ',');) video_options.compare.push_back(name);
            video_options.progress = scenes::progress_wanted();
            const scenes::SceneDef scene = video_scene.load();
            const scenes::VideoStats v = scenes::write_video(scene, video_scene.overrides(), video_options);
            std::printf("video: %s (%d frames; per frame: physics %.2f ms, rendering %.1f ms; %.1f frames/s in all)\n",
                        video_out.c_str(), v.frames, v.physics_ms, v.render_ms, v.frames / v.seconds);
            return kExitOk;
        }
        if (*view_cmd) {
            const auto [w, h] = parse_size(view_size);
            view_options.width = w;
            view_options.height = h;
            view_options.screenshot = view_screenshot;
            const scenes::SceneDef scene = view_scene.load();
            const scenes::ViewResult v = scenes::run_viewer(scene, view_scene.overrides(), view_options);
            std::printf("view: %s, frame %d, t = %.4f s, state %s%s%s\n", scene.name.c_str(), v.frame, v.time,
                        v.state_hash.c_str(), v.exploded ? " (exploded)" : "",
                        view_screenshot.empty() ? "" : (", screenshot " + view_screenshot).c_str());
            return v.exploded ? kExitFailed : kExitOk;
        }
        if (*report_cmd) {
            report_options.out = report_out;
            report_options.progress = scenes::progress_wanted();
            const auto md = scenes::write_report(report_options);
            std::printf("report: %s\n", md.string().c_str());
            return kExitOk;
        }
        return check(check_args, check_options);
    } catch (const scenes::Interrupted& e) {
        // Cleaned up (the scopes that wrote are gone): end by the signal, as
        // without the handler, so that a shell loop around us stops too.
        std::fprintf(stderr, "plausible: %s\n", e.what());
        std::fflush(stderr);
        std::signal(e.signal(), SIG_DFL);
        std::raise(e.signal());
        return 128 + e.signal();
    } catch (const sim::InputError& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return kExitBadInput;
    } catch (const render::RenderError& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return e.kind() == render::ErrorKind::bad_input || e.kind() == render::ErrorKind::no_display ? kExitBadInput
                                                                                                     : kExitFailed;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return kExitFailed;
    }
}
