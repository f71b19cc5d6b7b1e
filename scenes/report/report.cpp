// write_report: the report's stages in order (measure → analyse → write the
// tables → plot → write report.md), what --quick changes, and the folder
// written whole or not at all (a temporary folder renamed to --out at the
// end, removed on an error or Ctrl+C). The stages are in report_*.cpp, listed
// in report_stages.h.
#include "scenes/report/report.h"

#include "scenes/common/child_process.h"
#include "scenes/common/interrupt.h"
#include "scenes/common/progress.h"
#include "scenes/model/scene.h"
#include "scenes/report/report_stages.h"

#include "sim/error.h"
#include "sim/integrators.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <numbers>

namespace scenes {
namespace {

namespace fs = std::filesystem;
using namespace scenes::report;

Settings settings_for(bool quick) {
    constexpr double pi = std::numbers::pi;
    return {.quick = quick,
            .dt_count = quick ? 6 : 8,
            .timing = {.repetitions = quick ? 1 : 5, .min_seconds = quick ? 0.005 : 0.02},
            .batch = {.copies = 1000, .min_seconds = quick ? 0.02 : 0.1, .repetitions = quick ? 3 : 5},
            .drift_oscillator = quick ? 200.0 * pi : 400.0 * pi,
            .drift_kepler = (quick ? 10.0 : 20.0) * 2.0 * pi,
            .stiff_bisections = quick ? 14 : 30,
            .map_bisections = quick ? 8 : 16,
            .growth = growth_timing(quick),
            .rigid = quick ? RigidSpan{.substeps = {1, 4, 16}, .seconds = 5.0, .repetitions = 1} : RigidSpan{}};
}

// The steps the progress bar counts, one per progress.step() in the measuring stages.
int progress_steps(const std::vector<Problem>& problems) {
    const std::size_t methods = sim::kIntegrators.size();
    const auto peer_problems =
        std::count_if(problems.begin(), problems.end(), [](const Problem& p) { return peer_knows(p.name); });
    return static_cast<int>(problems.size() * methods                  // work-precision sweeps
                            + static_cast<std::size_t>(peer_problems)  // peers
                            + problems.size()                          // frame substeps
                            + 2 * methods                              // energy drift
                            + methods                                  // stiff spring limits
                            + hard_cases().size() + 1 + 1              // stability map, ragdoll, small steps
                            + catalog().size()                         // scene costs
                            + growth_system_count()                    // how cost grows
                            + rigid_series_count());                   // rigid bodies
}

// Every measurement, in the order the progress bar counts them. `scratch`:
// a folder for ffmpeg's messages.
Measurements measure(const Settings& settings, bool show_progress, const fs::path& scratch) {
    Measurements m;
    m.problems = problems();
    Progress progress("report", show_progress, progress_steps(m.problems));
    m.sweeps = measure_sweeps(m.problems, settings, progress);
    m.peers = measure_peers(m.problems, settings, progress);
    m.frames = measure_frames(m.problems, settings, progress);
    m.drifts = measure_drift(settings, progress);
    m.limits = measure_stiff_spring(settings, progress);
    m.map = measure_stability_map(settings, progress);
    m.small_steps = measure_small_steps(progress);
    m.costs = measure_scene_costs(settings.quick, scratch, progress);
    m.growth = measure_growth(settings.growth, [&](const std::string& s) { progress.step("growth " + s); });
    m.rigid = measure_rigid(settings.rigid, progress);
    return m;
}

// The folder the report is written into before it becomes --out: beside it,
// so that the rename stays on one file system. Throws sim::InputError when
// --out holds something that is not a report, or cannot be written.
fs::path temporary_folder(const fs::path& out) {
    if (fs::exists(out) && !fs::is_directory(out)) {
        throw sim::InputError("report: --out " + out.string() + " is not a folder: choose another path");
    }
    if (fs::exists(out) && !fs::is_empty(out) && !fs::exists(out / "report.md")) {
        throw sim::InputError("report: --out " + out.string() +
                              " exists and holds no report: choose another directory");
    }
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    std::error_code ec;
    fs::create_directories(parent, ec);
    const fs::path tmp = parent / (".report-" + std::to_string(getpid()));
    fs::remove_all(tmp, ec);
    if (!fs::create_directories(tmp, ec) || ec) throw sim::InputError("report: cannot write --out " + out.string());
    return tmp;
}

// The finished report replaces --out whole.
void publish(const fs::path& tmp, const fs::path& out) {
    std::error_code ec;
    fs::remove_all(out, ec);
    fs::rename(tmp, out, ec);
    if (ec) throw sim::InputError("report: cannot write --out " + out.string() + ": " + ec.message());
}

}  // namespace

fs::path write_report(const ReportOptions& options) {
    if (!on_path("gnuplot")) {
        throw sim::InputError(
            "report: gnuplot is not installed (Debian: apt-get install gnuplot-nox; `make test` does it)");
    }
    const InterruptScope interrupts;  // Ctrl+C: stop after the step under way, remove the folder
    // "out/report/" names the folder "out/report" (its parent is "out", where
    // the temporary folder goes); "." and ".." name what they stand for.
    fs::path out = fs::absolute(options.out).lexically_normal();
    if (!out.has_filename()) out = out.parent_path();
    const fs::path tmp = temporary_folder(out);
    try {
        const Settings settings = settings_for(options.quick);
        const Measurements m = measure(settings, options.progress, tmp);
        const Findings f = analyse(m);
        write_tables(tmp, settings, m, f);
        draw_plots(tmp, m);
        write_markdown(tmp, settings, m, f);
        check_interrupt("report", "the plots");
        publish(tmp, out);
    } catch (...) {
        std::error_code ec;
        fs::remove_all(tmp, ec);
        throw;
    }
    return options.out / "report.md";  // as the user named it
}

}  // namespace scenes
