#include "scenes/check/check.h"
#include "scenes/common/output_file.h"

#include "render/font.h"
#include "scenes/draw/run_recorder.h"
#include "scenes/draw/scene_run.h"
#include "scenes/model/recording.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <optional>
#include <tuple>

namespace scenes {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string format_time(double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f s", t);
    return text;
}

// The instruction set this build's physics runs on. State hashes are the same
// bits on every x86-64 CPU (docs/design.md rule 7) but not across
// architectures: another architecture's libm and ODE build round differently
// (Debian's arm64 libode fuses multiply-adds), so a golden records where it
// was made and hashes are compared only on the same architecture.
std::string build_architecture() {
#if defined(__x86_64__)
    return "x86_64";
#elif defined(__aarch64__)
    return "aarch64";
#elif defined(__i386__)
    return "i386";
#elif defined(__riscv) && __riscv_xlen == 64
    return "riscv64";
#elif defined(__powerpc64__)
    return "ppc64";
#else
    return "unknown";
#endif
}

json fingerprint_json(const render::Fingerprint& f) {
    return json{{"backend", f.backend},  {"vendor", f.vendor},     {"renderer", f.renderer},
                {"version", f.version},  {"cpu_simd", f.cpu_simd}, {"gl_threads", f.gl_threads},
                {"summary", f.summary()}};
}

// The thresholds a golden file asks for, or the defaults. Thresholds other
// than the defaults need a "thresholds_reason": a looser metric is a decision
// someone has to be able to read later.
render::GoldenThresholds thresholds_from(const json& golden, const fs::path& file) {
    render::GoldenThresholds t;
    if (!golden.contains("thresholds")) return t;
    try {
        const json& j = golden.at("thresholds");
        t.small_max_d = j.value("small_max_d", t.small_max_d);
        t.small_share = j.value("small_share", t.small_share);
        t.large_share = j.value("large_share", t.large_share);
        render::validate(t);
    } catch (const std::exception& e) {
        throw SceneError(file.string() + ": thresholds: " + e.what());
    }
    const render::GoldenThresholds defaults;
    const bool custom = t.small_max_d != defaults.small_max_d || t.small_share != defaults.small_share ||
                        t.large_share != defaults.large_share;
    const bool has_reason = golden.contains("thresholds_reason") && golden["thresholds_reason"].is_string() &&
                            !golden["thresholds_reason"].get<std::string>().empty();
    if (custom && !has_reason) {
        throw SceneError(file.string() +
                         ": thresholds differ from the defaults (small_max_d 3, small_share 0.05, large_share "
                         "0.0001) but \"thresholds_reason\" is missing: say why this scene needs them");
    }
    return t;
}

void write_golden(const SceneDef& scene, const Filmstrip& strip, const render::Fingerprint& fingerprint,
                  const fs::path& dir, const json& previous) {
    make_output_folder(dir);
    json checkpoints = json::array();
    for (std::size_t i = 0; i < strip.frames.size(); ++i) {
        checkpoints.push_back({{"frame", strip.frames[i]}, {"time", strip.times[i]}, {"state_hash", strip.hashes[i]}});
    }
    const render::GoldenThresholds defaults;
    json thresholds = previous.contains("thresholds") ? previous["thresholds"]
                                                      : json{{"small_max_d", defaults.small_max_d},
                                                             {"small_share", defaults.small_share},
                                                             {"large_share", defaults.large_share}};
    json golden = {{"scene", scene.name},
                   {"integrator", std::string(sim::integrator_info(scene.step.integrator).name)},
                   {"arch", build_architecture()},
                   {"dt", scene.step.dt},
                   {"substeps", scene.step.substeps},
                   {"tile", {strip.image.width > 0 ? 320 : 0, 240}},
                   {"checkpoints", checkpoints},
                   {"thresholds", thresholds},
                   {"fingerprint", fingerprint_json(fingerprint)}};
    if (previous.contains("thresholds_reason")) golden["thresholds_reason"] = previous["thresholds_reason"];
    write_output(dir / (scene.name + ".png"), render::encode_png(strip.image));
    write_output(dir / (scene.name + ".json"), golden.dump(2) + "\n");
    write_output(dir / (scene.name + ".hashes"), format_run_hashes(strip.record));
}

}  // namespace

fs::path default_golden_dir() { return data_dir() / "golden"; }

namespace {

// The filmstrip, or with no renderer its hashes alone (no image, no GL).
Filmstrip run_filmstrip(const SceneDef& scene, render::Renderer* renderer, const FilmstripSettings& settings) {
    Filmstrip strip;
    SceneRun run(scene);
    std::vector<render::Image> tiles;
    std::vector<std::string> labels;
    const render::RenderSettings render_settings{
        .width = settings.width, .height = settings.height, .msaa_samples = settings.msaa};
    const std::vector<SceneObject> objects = scene_objects(scene);
    strip.record.substeps = scene.step.substeps;
    for (const SceneObject& object : objects) strip.record.objects.push_back(object.name);
    std::vector<std::uint64_t> substeps;  // the state hash after each substep of the last frame
    auto keep_frame = [&] {
        FrameRecord f{.hash = run.state_hash(), .substeps = {}};
        for (std::size_t k = 0; k + 1 < substeps.size(); ++k) {
            f.substeps.push_back(static_cast<std::uint16_t>(substeps[k] >> 48));
        }
        strip.record.frames.push_back(std::move(f));
        if (object_grid_frame(run.frame(), scene.checkpoints)) {
            strip.record.object_hashes[run.frame()] = run.object_hashes(objects);
        }
    };
    keep_frame();
    for (int checkpoint : scene.checkpoints) {
        while (run.frame() < checkpoint && !run.verdict().exploded()) {
            run.advance(substeps);
            keep_frame();
        }
        if (renderer != nullptr) {
            tiles.push_back(renderer->render(run.draw_list(settings.width, settings.height), render_settings));
        }
        strip.frames.push_back(run.frame());
        strip.times.push_back(run.time());
        strip.hashes.push_back(run.state_hash_hex());
        if (run.verdict().exploded()) {
            labels.push_back("frame " + std::to_string(run.frame()) + ": EXPLODED");
            break;
        }
        labels.push_back("frame " + std::to_string(run.frame()) + " · " + format_time(run.time()));
    }
    strip.verdict = run.verdict();
    strip.diverged_frame = run.diverged_frame();
    if (renderer == nullptr) return strip;
    // Checkpoints after an explosion: dark tiles, so the strip keeps the
    // golden's layout and the diff shows where the run stopped.
    for (std::size_t i = tiles.size(); i < scene.checkpoints.size(); ++i) {
        render::Image tile = render::make_image(settings.width, settings.height, 3, render::Rgba8{60, 20, 20, 255});
        render::draw_text(tile, render::Font::default_font(), "not reached", 10.0f, 10.0f, 16.0f,
                          render::Rgba8{240, 200, 200, 255});
        tiles.push_back(std::move(tile));
        labels.push_back("frame " + std::to_string(scene.checkpoints[i]) + ": not reached");
    }
    strip.image = render::contact_sheet(tiles, labels, render::Font::default_font());
    return strip;
}

}  // namespace

Filmstrip render_filmstrip(const SceneDef& scene, render::Renderer& renderer, const FilmstripSettings& settings) {
    return run_filmstrip(scene, &renderer, settings);
}

namespace {

// A scene's golden files: the filmstrip PNG and its JSON (checkpoint hashes,
// thresholds, the renderer's fingerprint), read when both are there.
struct Golden {
    fs::path png, json_file, hashes_file;
    bool present = false;
    json previous = json::object();   // the JSON as read; empty when absent
    std::optional<RunHashes> frames;  // golden/<scene>.hashes as read; none when absent
};

Golden read_golden(const fs::path& golden_dir, const std::string& scene) {
    Golden g;
    g.png = golden_dir / (scene + ".png");
    g.json_file = golden_dir / (scene + ".json");
    g.hashes_file = golden_dir / (scene + ".hashes");
    g.present = fs::exists(g.png) && fs::exists(g.json_file);
    if (!g.present) return g;
    try {
        std::ifstream in(g.json_file);
        g.previous = json::parse(in);
    } catch (const json::exception& e) {
        throw SceneError(g.json_file.string() + ": not valid JSON: " + e.what());
    }
    if (fs::exists(g.hashes_file)) {
        std::ifstream in(g.hashes_file, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        g.frames = parse_run_hashes(text, g.hashes_file.string());
    }
    return g;
}

// Where the physics first changed, from the golden's frame-by-frame hashes:
// the frame, its substep and time, and the objects that differ.
void compare_frames(SceneCheck& c, const SceneDef& scene, const Filmstrip& strip, const Golden& golden) {
    c.substeps = scene.step.substeps;
    if (!golden.frames) {
        c.hashes_note = "no " + golden.hashes_file.string() +
                        " (the frame-by-frame hashes): only the checkpoints are compared; `plausible check " +
                        scene.name + " --update missing` writes it";
        return;
    }
    const HashChange change = locate_change(*golden.frames, strip.record);
    if (change.frame < 0) return;
    c.changed_frame = change.frame;
    c.changed_substep = change.substep;
    if (change.ended) {
        c.frames_expected = static_cast<int>(golden.frames->frames.size()) - 1;
        c.frames_actual = static_cast<int>(strip.record.frames.size()) - 1;
    }
    // Frames are of a fixed dt (check never changes it): the end of the substep.
    const double done = change.frame == 0    ? 0.0
                        : change.substep < 0 ? change.frame
                                             : change.frame - 1 + static_cast<double>(change.substep + 1) / c.substeps;
    c.changed_time = done * scene.step.dt;
    c.objects_frame = change.objects_frame;
    c.changed_objects = group_changed(change.objects, scene_objects(scene));
}

// Each checkpoint's state hash against the golden's, and the first that
// differs (a missing or extra checkpoint counts).
void compare_hashes(SceneCheck& c, const Filmstrip& strip, const json& previous) {
    const json expected_checkpoints = previous.value("checkpoints", json::array());
    for (std::size_t i = 0; i < strip.frames.size(); ++i) {
        CheckpointHash h;
        h.frame = strip.frames[i];
        h.actual = strip.hashes[i];
        if (i < expected_checkpoints.size()) {
            const json& e = expected_checkpoints[i];
            h.expected = e.value("frame", -1) == h.frame ? e.value("state_hash", "")
                                                         : "frame " + std::to_string(e.value("frame", -1));
        }
        if (c.first_hash_mismatch < 0 && h.expected != h.actual) c.first_hash_mismatch = static_cast<int>(i);
        c.hashes.push_back(h);
    }
    if (c.first_hash_mismatch < 0 && expected_checkpoints.size() != strip.frames.size()) {
        c.first_hash_mismatch = static_cast<int>(std::min(expected_checkpoints.size(), strip.frames.size()));
    }
}

// Images of a failure go to <report>/<scene>/; paths in the report are
// relative to the report folder.
struct Evidence {
    const fs::path& report_dir;
    SceneCheck& c;

    std::string keep(const std::string& file, const render::Image& image) const {
        make_output_folder(report_dir / c.scene);
        write_output(report_dir / c.scene / file, render::encode_png(image));
        return c.scene + "/" + file;
    }
    // Expected and actual, and where their sizes match, the diff and the three side by side.
    void keep_comparison(const render::Image& expected, const render::Image& actual) const {
        c.expected_png = keep("expected.png", expected);
        c.actual_png = keep("actual.png", actual);
        if (c.image->size_mismatch) return;
        c.diff_png = keep("diff.png", c.image->diff);
        c.side_png =
            keep("side.png", render::side_by_side(expected, actual, c.image->diff, render::Font::default_font()));
    }
};

// The watchdog stopped the run: a failure whatever the golden says; the
// images show where it was.
void judge_exploded(SceneCheck& c, const SceneDef& scene, const Filmstrip& strip, const Golden& golden,
                    const Evidence& evidence) {
    c.status = SceneCheck::Status::exploded;
    c.message = strip.verdict.message(scene.name);
    if (strip.image.pixels.empty()) return;  // physics only: no images
    c.actual_png = evidence.keep("actual.png", strip.image);
    if (!golden.present) return;
    const render::Image expected = render::read_png(golden.png, 3);
    c.expected_png = evidence.keep("expected.png", expected);
    c.image = render::compare_golden(strip.image, expected, thresholds_from(golden.previous, golden.json_file));
    if (c.image->size_mismatch) return;
    c.diff_png = evidence.keep("diff.png", c.image->diff);
    c.side_png = evidence.keep(
        "side.png", render::side_by_side(expected, strip.image, c.image->diff, render::Font::default_font()));
}

// "physics changed at frame 1, substep 2 of 4 (t = 0.004 s): rope", from the
// frame-by-frame hashes; without them, the first checkpoint whose hash differs.
std::string physics_changed(const SceneCheck& c, const Filmstrip& strip) {
    std::string text;
    if (c.frames_expected != c.frames_actual) {
        // Every frame both reached is the same: the scene runs to another last checkpoint.
        text = "the run goes to frame " + std::to_string(c.frames_actual) + " and the golden's to frame " +
               std::to_string(c.frames_expected) + " (its frames or checkpoints changed); every frame both reached " +
               "has the golden's state";
    } else if (c.changed_frame >= 0) {
        text = "physics changed at frame " + std::to_string(c.changed_frame);
        if (c.changed_frame == 0) text += " (the start)";
        if (c.changed_frame > 0 && c.substeps > 1 && c.changed_substep >= 0) {
            text += ", substep " + std::to_string(c.changed_substep + 1) + " of " + std::to_string(c.substeps);
        }
        char t[48];
        std::snprintf(t, sizeof t, " (t = %.4g s)", c.changed_time);
        text += t;
        if (c.objects_frame >= 0) {
            std::string names;
            for (const std::string& name : c.changed_objects) names += (names.empty() ? "" : ", ") + name;
            text += names.empty() ? ": no named object differs" : ": " + names;
            if (c.objects_frame != c.changed_frame) {
                text += " (objects compared at frame " + std::to_string(c.objects_frame) + ", the first kept)";
            }
        }
    }
    const int i = c.first_hash_mismatch;
    if (i >= static_cast<int>(strip.frames.size())) {
        text += (text.empty() ? "" : "; ") + std::string("checkpoint ") + std::to_string(i) + " not reached";
    } else if (i >= 0) {
        const int frame = strip.frames[i];
        text += (text.empty() ? "physics changed at " : "; state hash differs from ") + std::string("checkpoint ") +
                std::to_string(i) + " (frame " + std::to_string(frame) + ")";
        if (c.changed_frame < 0) text += ": state hash differs";
    }
    if (!c.hashes_note.empty()) text += "; " + c.hashes_note;
    return text;
}

// Why the state hashes were not judged: the golden was made on another
// architecture (build_architecture), so only the image can be.
std::string not_comparable(const SceneCheck& c) {
    return "state hashes not compared: the golden was made on " + c.arch_expected + " and this build runs on " +
           c.arch_actual + ", and hashes are not comparable across architectures (judged by the image alone)";
}

// No golden yet: written with --update missing or all, else reported.
void judge_missing(SceneCheck& c, const SceneDef& scene, const Filmstrip& strip, const Golden& golden,
                   const render::Fingerprint& fingerprint, const CheckOptions& options, const fs::path& golden_dir,
                   const Evidence& evidence) {
    if (options.update == UpdateMode::missing || options.update == UpdateMode::all) {
        write_golden(scene, strip, fingerprint, golden_dir, golden.previous);
        c.status = SceneCheck::Status::updated;
        c.message = "golden written: " + golden.png.string();
    } else {
        c.status = SceneCheck::Status::missing;
        c.message = "no golden " + golden.png.string() + ": run `plausible check " + scene.name + " --update missing`";
        c.actual_png = evidence.keep("actual.png", strip.image);
    }
}

// How the golden's renderer differs from this one, empty where it does not:
// another GL_RENDERER (llvmpipe's names its LLVM and vector width) or
// GL_VERSION (Mesa's), each said as "GL_VERSION <the golden's> in the
// golden, <this one's> here", so that a check on another machine says what
// drew what. The backend and the thread count do not change pixels (EGL and
// OSMesa on one Mesa give the same bytes). A golden without a fingerprint
// counts as this renderer's.
std::string another_renderer(const json& golden, const render::Fingerprint& f) {
    if (!golden.contains("fingerprint") || !golden["fingerprint"].is_object()) return "";
    const json& g = golden["fingerprint"];
    std::string differs;
    for (const auto& [key, name, here] :
         {std::tuple{"renderer", "GL_RENDERER", &f.renderer}, std::tuple{"version", "GL_VERSION", &f.version}}) {
        const std::string there = g.value(key, *here);
        if (there == *here) continue;
        differs +=
            (differs.empty() ? "" : "; ") + std::string(name) + " " + there + " in the golden, " + *here + " here";
    }
    return differs;
}

std::string share_text(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%g%%", 100.0 * share);
    return text;
}

// The image against the golden's within its thresholds (another renderer's
// tolerance where another drew it), the state hashes exactly; rewritten with
// --update all (or changed, when it differs).
void judge_against_golden(SceneCheck& c, const SceneDef& scene, const Filmstrip& strip, const Golden& golden,
                          const render::Fingerprint& fingerprint, const CheckOptions& options,
                          const fs::path& golden_dir, const Evidence& evidence) {
    const render::Image expected = render::read_png(golden.png, 3);
    render::GoldenThresholds thresholds = thresholds_from(golden.previous, golden.json_file);
    const std::string renderer_differs = another_renderer(golden.previous, fingerprint);
    const bool another = !renderer_differs.empty();
    if (another) thresholds = render::for_another_renderer(thresholds);
    c.image = render::compare_golden(strip.image, expected, thresholds);
    const bool physics_same = c.first_hash_mismatch < 0 && c.changed_frame < 0;
    const bool pass = c.image->pass && physics_same;
    if (!c.hashes_comparable()) {
        c.message = (c.image->pass ? "image " : "image changed: ") + c.image->summary + "; " + not_comparable(c);
    } else if (physics_same) {
        c.message = c.image->pass ? "image " + c.image->summary + ", state hashes identical"
                                  : "rendering changed, physics identical: " + c.image->summary;
    } else {
        c.message = physics_changed(c, strip) + "; image " + c.image->summary;
    }
    if (another) {
        c.message += "; drawn by another renderer than the golden's (" + renderer_differs +
                     "), so judged with its tolerance: large errors on up to " + share_text(thresholds.large_share);
    } else if (!c.fingerprint_expected.empty() && c.fingerprint_expected != c.fingerprint_actual && !pass) {
        c.message += "; the renderer differs from the golden's (" + c.fingerprint_expected + " in the golden, " +
                     c.fingerprint_actual + " here)";
    }
    if (options.update == UpdateMode::all || (!pass && options.update == UpdateMode::changed)) {
        write_golden(scene, strip, fingerprint, golden_dir, golden.previous);
        c.status = SceneCheck::Status::updated;
        c.message = "golden rewritten (" + c.message + ")";
    } else if (pass && !golden.frames && c.hashes_comparable() && options.update == UpdateMode::missing) {
        // A golden from before the frame-by-frame hashes: what is missing is written, nothing else.
        make_output_folder(golden_dir);
        write_output(golden.hashes_file, format_run_hashes(strip.record));
        c.status = SceneCheck::Status::updated;
        c.message = "frame-by-frame hashes written: " + golden.hashes_file.string() + " (" + c.message + ")";
    } else if (pass) {
        c.status = SceneCheck::Status::pass;
    } else {
        c.status = SceneCheck::Status::fail;
        evidence.keep_comparison(expected, strip.image);
    }
}

// Physics only (no renderer): the state hashes against the golden's, the
// images not compared.
void judge_physics(SceneCheck& c, const SceneDef& scene, const Filmstrip& strip, const Golden& golden) {
    if (!golden.present) {
        c.status = SceneCheck::Status::missing;
        c.message = "no golden " + golden.png.string() + ": run `plausible check " + scene.name + " --update missing`";
        return;
    }
    if (!c.hashes_comparable()) {
        c.status = SceneCheck::Status::error;
        c.message = "a physics-only check cannot judge this scene: " + not_comparable(c) +
                    "; run the full check, which compares the images";
        return;
    }
    if (c.first_hash_mismatch < 0 && c.changed_frame < 0) {
        c.status = SceneCheck::Status::pass;
        c.message = "state hashes identical (physics only: images not compared)";
        return;
    }
    c.status = SceneCheck::Status::fail;
    c.message = physics_changed(c, strip) + " (physics only: images not compared)";
}

// One scene: loaded, its filmstrip rendered, judged. Bad input (the scene
// file, the golden's JSON, the renderer) is the scene's error, not the run's.
// With no renderer, physics only (judge_physics).
SceneCheck check_scene(const std::string& name, const std::vector<Override>& overrides, const CheckOptions& options,
                       render::Renderer* renderer, const render::Fingerprint* fingerprint, const fs::path& golden_dir,
                       const fs::path& report_dir) {
    const auto start = std::chrono::steady_clock::now();
    SceneCheck c;
    c.scene = name;
    c.fingerprint_actual = fingerprint != nullptr ? fingerprint->summary() : "none (physics only)";
    c.arch_actual = build_architecture();
    const Evidence evidence{report_dir, c};
    try {
        const SceneDef scene = load_scene_or_recording(name, overrides);
        c.scene = scene.name;
        const Filmstrip strip = run_filmstrip(scene, renderer, {});
        const Golden golden = read_golden(golden_dir, scene.name);
        c.arch_expected = golden.previous.value("arch", "");
        if (c.hashes_comparable()) compare_hashes(c, strip, golden.previous);
        if (c.hashes_comparable() && golden.present) compare_frames(c, scene, strip, golden);
        if (golden.previous.contains("fingerprint")) {
            c.fingerprint_expected = golden.previous["fingerprint"].value("summary", "");
        }
        if (strip.verdict.exploded()) {
            judge_exploded(c, scene, strip, golden, evidence);
        } else if (renderer == nullptr) {
            judge_physics(c, scene, strip, golden);
        } else if (!golden.present) {
            judge_missing(c, scene, strip, golden, *fingerprint, options, golden_dir, evidence);
        } else {
            judge_against_golden(c, scene, strip, golden, *fingerprint, options, golden_dir, evidence);
        }
        const bool physics_changed = c.changed_frame >= 0 || c.first_hash_mismatch >= 0;
        if ((c.status == SceneCheck::Status::fail && physics_changed && c.hashes_comparable()) ||
            c.status == SceneCheck::Status::exploded) {
            // The evidence a CI job's artifact carries: the actual run, to scrub locally.
            make_output_folder(report_dir / scene.name);
            const int last = scene.checkpoints.empty() ? scene.frames : scene.checkpoints.back();
            write_recording(report_dir / scene.name / "actual.rec", record_scene(scene, last));
            c.actual_recording = scene.name + "/actual.rec";
            c.message += "; the actual run, to scrub: plausible view " + (report_dir / c.actual_recording).string();
        }
        if (strip.diverged_frame >= 0) {
            // A recording given as the scene, replayed here: it parted from what was recorded.
            c.status = SceneCheck::Status::fail;
            c.message = "the recording " + scene.recorded->file.string() + " diverged at frame " +
                        std::to_string(strip.diverged_frame) + "; " + c.message;
        }
    } catch (const sim::InputError& e) {
        c.status = SceneCheck::Status::error;
        c.message = e.what();
    } catch (const render::RenderError& e) {
        c.status = SceneCheck::Status::error;
        c.message = e.what();
    }
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

// Every scene, with a renderer or (both null) physics only.
std::vector<SceneCheck> run_checks(const std::vector<std::string>& names, const std::vector<Override>& overrides,
                                   const CheckOptions& options, render::Renderer* renderer,
                                   const render::Fingerprint* fingerprint) {
    const fs::path golden_dir = options.golden_dir.empty() ? default_golden_dir() : options.golden_dir;
    const fs::path report_dir = options.report_dir.empty() ? fs::path("out/check") : options.report_dir;
    make_output_folder(report_dir);
    std::vector<SceneCheck> results;
    for (const std::string& name : names) {
        results.push_back(check_scene(name, overrides, options, renderer, fingerprint, golden_dir, report_dir));
    }
    write_check_report(report_dir, results, options.shard);
    return results;
}

}  // namespace

std::vector<std::string> shard_of(const std::vector<std::string>& names, int index, int count) {
    if (count < 1 || index < 1 || index > count) {
        throw sim::InputError("--shard " + std::to_string(index) + "/" + std::to_string(count) +
                              ": I/N needs N >= 1 and 1 <= I <= N");
    }
    const std::size_t m = names.size(), i = static_cast<std::size_t>(index), n = static_cast<std::size_t>(count);
    return {names.begin() + static_cast<std::ptrdiff_t>((i - 1) * m / n),
            names.begin() + static_cast<std::ptrdiff_t>(i * m / n)};
}

std::vector<SceneCheck> check_scenes(const std::vector<std::string>& names, const std::vector<Override>& overrides,
                                     const CheckOptions& options, render::Renderer& renderer,
                                     const render::Fingerprint& fingerprint) {
    return run_checks(names, overrides, options, &renderer, &fingerprint);
}

std::vector<SceneCheck> check_physics(const std::vector<std::string>& names, const std::vector<Override>& overrides,
                                      const CheckOptions& options) {
    if (options.update != UpdateMode::none) {
        throw sim::InputError("a physics-only check cannot write goldens (they hold images): drop --update");
    }
    return run_checks(names, overrides, options, nullptr, nullptr);
}

}  // namespace scenes
