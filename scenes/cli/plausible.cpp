// The `plausible` command (docs/design.md, "The command"): its subcommands in
// the order --help lists them, each in its own file (commands.h), and the
// mapping of errors to exit codes: 0 ok, 1 a check failed or a simulation
// exploded, 2 bad input. Ctrl+C (SIGTERM) during a video, report or run
// --csv: nothing written, and the command ends by that signal (a shell shows
// 130, 143), see scenes/common/interrupt.h.
#include "render/error.h"
#include "scenes/cli/commands.h"
#include "scenes/common/interrupt.h"
#include "scenes/common/output_file.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>

namespace scenes::cli {

// `plausible list`: the catalogue in order, each scene with its one sentence.
Command add_list(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("list", "List the scenes with their descriptions");
    return {cmd, [] {
                const std::vector<std::string> names = catalog();
                int width = 0;  // the longest name, so that the descriptions line up
                for (const std::string& name : names) width = std::max(width, static_cast<int>(name.size()));
                for (const std::string& name : names) {
                    const SceneDef scene = load_scene(scenes_dir() / (name + ".toml"));
                    std::printf("%-*s %s\n", width, name.c_str(), scene.description.c_str());
                }
                return kExitOk;
            }};
}

namespace {

// Runs the command that was given, its errors as exit codes.
int run_guarded(const Command& command) {
    try {
        return command.run();
    } catch (const Interrupted& e) {
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
    } catch (const OutputError& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::filesystem::filesystem_error& e) {
        // A path given (or made from one given) that cannot be used: bad input.
        std::fprintf(stderr, "plausible: error: cannot use %s: %s\n", e.path1().c_str(), e.code().message().c_str());
        return kExitBadInput;
    } catch (const render::RenderError& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        // Asked for what cannot be had here (a size, a display, a GPU): bad input; the driver's refusal: a failure.
        return e.kind() == render::ErrorKind::gl ? kExitFailed : kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "plausible: error: %s\n", e.what());
        return kExitFailed;
    }
}

}  // namespace

}  // namespace scenes::cli

int main(int argc, char** argv) {
    using namespace scenes::cli;
    CLI::App app{"Plausible: a games-physics lab. Scenes run headless; see `plausible list`."};
    app.set_version_flag("--version", "plausible " PLAUSIBLE_VERSION);
    app.require_subcommand(1);
    const std::string exit_codes =
        "Exit codes: 0 ok; 1 a check failed, a simulation exploded or a recording diverged; 2 bad input (usage, a "
        "scene file or value, a path that cannot be read or written, no display or GPU); 130 or 143 interrupted "
        "(Ctrl+C, SIGTERM), nothing written.";
    app.footer(exit_codes);
    std::signal(SIGXFSZ, SIG_IGN);  // a file size limit: a failed write (exit 2, named), not a killed process
    const Command commands[] = {add_list(app),  add_run(app),  add_render(app), add_check(app),
                                add_video(app), add_view(app), add_report(app)};
    for (const Command& command : commands) command.app->footer(exit_codes);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }
    for (const Command& command : commands) {
        if (*command.app) return run_guarded(command);
    }
    return kExitBadInput;  // (require_subcommand: not reached)
}
