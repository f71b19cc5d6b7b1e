// A progress bar with ETA on stderr, for the long commands (run, report, video):
// one line rewritten in place, a newline when done. Off, it only counts.
// Each step is also where a long command notices Ctrl+C (scenes/interrupt.h).
#pragma once

#include "scenes/common/interrupt.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <type_traits>
#include <utility>

namespace scenes {

class Progress {
public:
    // `label` starts the line ("report", "video"); `total` steps make 100%.
    Progress(std::string label, bool on, int total)
        : label_(std::move(label)), on_(on), total_(total), start_(Clock::now()) {}

    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    // Stopped early (an error, Ctrl+C): the message that follows starts a line.
    ~Progress() {
        if (on_ && done_ < total_) std::fprintf(stderr, "\n");
    }

    // One step done; `what` says which (shown, cut to 28 characters): a
    // string, or a callable that makes one, called only where the line is
    // drawn or a signal came (a run's frames are a few hundred ns each: a
    // label made every frame would be a tenth of that). Throws Interrupted if
    // a signal came inside an InterruptScope. The line is redrawn at most
    // every kRedraw, and at the last step: drawn every step, a terminal run
    // of a bead took 15 times as long as through a pipe (8.3 s against 0.56
    // for 2e6 frames).
    template <class What>
    void step(const What& what) {
        ++done_;
        if (interrupt_signal() != 0) check_interrupt(label_, "the end of " + text(what));
        if (!on_) return;
        const Clock::time_point now = Clock::now();
        if (done_ != total_ && done_ > 1 && now - drawn_ < kRedraw) return;
        drawn_ = now;
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double eta = done_ > 0 ? elapsed / done_ * (total_ - done_) : 0.0;
        const int width = 30, filled = total_ > 0 ? std::clamp(width * done_ / total_, 0, width) : width;
        std::fprintf(stderr, "\r%s [%s%s] %3d%%  ETA %3.0f s  %-28.28s", label_.c_str(),
                     std::string(filled, '#').c_str(), std::string(width - filled, '-').c_str(),
                     total_ > 0 ? std::min(100, 100 * done_ / total_) : 100, std::max(eta, 0.0), text(what).c_str());
        if (done_ == total_) std::fprintf(stderr, "\n");
    }
    int done() const { return done_; }

private:
    using Clock = std::chrono::steady_clock;
    static constexpr std::chrono::milliseconds kRedraw{100};

    template <class What>
    static std::string text(const What& what) {
        if constexpr (std::is_invocable_v<const What&>) {
            return what();
        } else {
            return std::string(what);
        }
    }

    std::string label_;
    bool on_;
    int total_;
    int done_ = 0;
    Clock::time_point start_, drawn_;
};

// On when stderr is a terminal and CI is not set to true.
bool progress_wanted();

}  // namespace scenes
