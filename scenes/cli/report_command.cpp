// `plausible report`: speed against error (scenes/report), written whole to
// one folder.
#include "scenes/cli/commands.h"

#include "scenes/common/progress.h"
#include "scenes/report/report.h"

#include <cstdio>

namespace scenes::cli {

namespace {

struct ReportArgs {
    ReportOptions options;
    std::string out = ReportOptions{}.out.string();
};

int report(ReportArgs& a) {
    a.options.out = a.out;
    a.options.progress = progress_wanted();
    const auto md = write_report(a.options);
    std::printf("report: %s\n", md.string().c_str());
    return kExitOk;
}

}  // namespace

Command add_report(CLI::App& app) {
    auto args = std::make_shared<ReportArgs>();
    CLI::App* cmd = app.add_subcommand(
        "report", "Speed against error: work-precision, orders, energy drift, stability (Markdown, CSV, JSON, PNG)");
    cmd->add_flag("--quick", args->options.quick, "Fewer dt values and timings (CI's run, under 60 s)");
    cmd->add_option("--out", args->out, "Folder written (whole, or not at all)")->capture_default_str();
    return {cmd, [args] { return report(*args); }};
}

}  // namespace scenes::cli
