// A progress bar with ETA on stderr, for the long commands (run, report, video):
// one line rewritten in place, a newline when done. Off, it only counts.
// Each step is also where a long command notices Ctrl+C (scenes/interrupt.h).
#pragma once

#include "scenes/common/interrupt.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

namespace scenes {

class Progress {
public:
    // `label` starts the line ("report", "video"); `total` steps make 100%.
    Progress(std::string label, bool on, int total)
        : label_(std::move(label)), on_(on), total_(total), start_(std::chrono::steady_clock::now()) {}

    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    // Stopped early (an error, Ctrl+C): the message that follows starts a line.
    ~Progress() {
        if (on_ && done_ < total_) std::fprintf(stderr, "\n");
    }

    // One step done; `what` says which (shown, cut to 28 characters). Throws
    // Interrupted if a signal came inside an InterruptScope.
    void step(const std::string& what) {
        ++done_;
        if (interrupt_signal() != 0) check_interrupt(label_, "the end of " + what);
        if (!on_) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const double eta = done_ > 0 ? elapsed / done_ * (total_ - done_) : 0.0;
        const int width = 30, filled = total_ > 0 ? std::clamp(width * done_ / total_, 0, width) : width;
        std::fprintf(stderr, "\r%s [%s%s] %3d%%  ETA %3.0f s  %-28.28s", label_.c_str(),
                     std::string(filled, '#').c_str(), std::string(width - filled, '-').c_str(),
                     total_ > 0 ? std::min(100, 100 * done_ / total_) : 100, std::max(eta, 0.0), what.c_str());
        if (done_ == total_) std::fprintf(stderr, "\n");
    }
    int done() const { return done_; }

private:
    std::string label_;
    bool on_;
    int total_;
    int done_ = 0;
    std::chrono::steady_clock::time_point start_;
};

// On when stderr is a terminal and CI is not set to true.
bool progress_wanted();

}  // namespace scenes
