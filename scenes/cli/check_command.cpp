// `plausible check [SCENE...]`: every scene's checkpoints against its golden
// images and state hashes (scenes/check), one line per scene and a summary.
// Exit 1 when one failed, 2 on errors only.
#include "scenes/cli/commands.h"

#include "render/renderer.h"
#include "scenes/check/check.h"
#include "scenes/check/check_report.h"
#include "scenes/common/output_file.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <utility>

namespace scenes::cli {

namespace {

struct CheckArgs {
    std::vector<std::string> scenes;
    SceneOptions options;  // --set and the step shorthands, applied to every scene
    std::string update = "none";
    std::string report = "out/check";
    std::string golden;   // empty: the shipped goldens (default_golden_dir)
    std::string backend;  // set by add_backend_option: render::default_backend()
    bool physics_only = false;
    std::string shard;  // "I/N"; empty: every scene
    std::string junit;  // a JUnit XML file to write; empty: none
};

// "I/N" -> (I, N), each all digits and within an int (no wrap); the range
// is shard_of's to check.
std::pair<int, int> parse_shard(const std::string& text) {
    const auto fail = [&] {
        return sim::InputError("--shard must be I/N, the I-th of N parts, e.g. 2/4, each at most " +
                               std::to_string(std::numeric_limits<int>::max()) + " (got '" + text + "')");
    };
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos) throw fail();
    const auto number = [&](std::size_t from, std::size_t to) {
        int n = 0;
        const auto [end, error] = std::from_chars(text.data() + from, text.data() + to, n);
        if (from == to || error != std::errc() || end != text.data() + to) throw fail();
        return n;
    };
    return {number(0, slash), number(slash + 1, text.size())};
}

UpdateMode parse_update(const std::string& text) {
    if (text == "none") return UpdateMode::none;
    if (text == "missing") return UpdateMode::missing;
    if (text == "changed") return UpdateMode::changed;
    if (text == "all") return UpdateMode::all;
    throw sim::InputError("--update must be none, missing, changed or all (got '" + text + "')");
}

int check(const CheckArgs& a) {
    CheckOptions o;
    o.update = parse_update(a.update);
    const auto overrides = a.options.overrides();
    if (o.update != UpdateMode::none && !overrides.empty()) {
        throw sim::InputError(
            "--update with --set would bless a scene that is not the one in its file: drop one of them");
    }
    // The backend, decided once (auto lists the EGL devices); physics alone draws nothing.
    const render::Backend backend = a.physics_only ? render::default_backend() : parse_backend(a.backend);
    // The shipped goldens are llvmpipe's: a GPU's frame is judged against
    // them with another renderer's tolerance, never written as one of them.
    if (o.update != UpdateMode::none && a.golden.empty() && !a.physics_only && backend == render::Backend::gpu) {
        throw sim::InputError("--update with --backend " + a.backend +
                              " would bless a GPU's frames: the shipped goldens are llvmpipe's (" +
                              std::string(render::backend_name(render::default_backend())) +
                              "), and a GPU's frame is judged against them with another renderer's tolerance; "
                              "drop --backend, or write your own goldens with --golden DIR");
    }
    o.report_dir = a.report;
    if (!a.junit.empty()) check_output(a.junit);  // a bad path is said before any scene runs
    if (!a.golden.empty()) {
        // A folder that is not there holds no goldens: say so once, not "no
        // golden" per scene. --update creates it.
        if (o.update == UpdateMode::none && !std::filesystem::is_directory(a.golden)) {
            throw sim::InputError("--golden " + a.golden + ": no such folder (--update missing writes goldens there)");
        }
        o.golden_dir = a.golden;
    }
    std::vector<std::string> names = a.scenes.empty() ? catalog() : a.scenes;
    if (!a.shard.empty()) {
        const auto [index, count] = parse_shard(a.shard);
        o.shard = {.index = index, .count = count, .of = static_cast<int>(names.size())};
        names = shard_of(names, index, count);
    }
    std::vector<SceneCheck> results;
    if (a.physics_only) {
        results = check_physics(names, overrides, o);
    } else {
        const auto context = render::create_context({.backend = backend});
        render::Renderer renderer(*context);
        results = check_scenes(names, overrides, o, renderer, context->fingerprint());
    }
    int passed = 0, failed = 0, errors = 0;
    int width = 0;  // the longest scene name, so that the verdicts line up
    for (const SceneCheck& c : results) width = std::max(width, static_cast<int>(c.scene.size()));
    for (const SceneCheck& c : results) {
        const bool ok = c.status == SceneCheck::Status::pass || c.status == SceneCheck::Status::updated;
        passed += ok ? 1 : 0;
        errors += c.status == SceneCheck::Status::error ? 1 : 0;
        failed += !ok && c.status != SceneCheck::Status::error ? 1 : 0;
        std::printf("%-*s %-8s %s (%.1f s)\n", width, c.scene.c_str(), status_name(c.status), c.message.c_str(),
                    c.seconds);
    }
    if (!a.junit.empty()) write_junit(a.junit, results, o.shard, a.report);
    if (o.shard.count > 0) {
        std::printf("shard %d of %d: %zu of the %d scenes\n", o.shard.index, o.shard.count, results.size(), o.shard.of);
    }
    std::printf("%d passed, %d failed, %d errors; report: %s\n", passed, failed, errors,
                (std::filesystem::path(a.report) / "index.html").c_str());
    return failed > 0 ? kExitFailed : errors > 0 ? kExitBadInput : kExitOk;
}

}  // namespace

Command add_check(CLI::App& app) {
    auto args = std::make_shared<CheckArgs>();
    CLI::App* cmd = app.add_subcommand("check", "Compare scenes' checkpoint frames with their golden images");
    cmd->add_option("scenes", args->scenes,
                    "Scenes to check (default: all): names, .toml paths or recordings (run --record; at most 128 MiB)");
    args->options.add_to(cmd);
    cmd->add_option("--update", args->update, "Write goldens: none, missing, changed or all")->capture_default_str();
    cmd->add_option("--golden", args->golden,
                    "Folder of goldens to compare with, and to write with --update (your own scenes' goldens "
                    "outside the project); default: the shipped goldens");
    cmd->add_option("--report", args->report, "Folder for the report (index.html, report.json, images)")
        ->capture_default_str();
    add_backend_option(cmd, &args->backend);
    cmd->add_option("--shard", args->shard,
                    "Check only the I-th of N equal parts of the scenes, I/N (e.g. 2/4: a CI matrix of 4 machines); "
                    "the report covers that part alone");
    cmd->add_option("--junit", args->junit,
                    "Also write the check as JUnit XML to this file: one testcase per scene, a failure carrying the "
                    "verdict line and the paths of its evidence");
    cmd->add_flag("--physics-only", args->physics_only,
                  "Compare state hashes only: nothing rendered, no GL (fast; e.g. under an emulated CPU)");
    return {cmd, [args] { return check(*args); }};
}

}  // namespace scenes::cli
