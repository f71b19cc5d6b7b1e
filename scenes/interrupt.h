// Ctrl+C (SIGINT) and SIGTERM during a command that writes through a
// temporary file (video, report, run --csv): instead of dying with the
// temporary left behind, the command stops at its next check, removes what
// it started and exits 128 + the signal (130 for Ctrl+C) with nothing
// written. A second signal ends the process at once, as usual. Outside an
// InterruptScope the signals keep their default action.
#pragma once

#include <signal.h>

#include <stdexcept>
#include <string>

namespace scenes {

// Thrown by check_interrupt(); `signal()` is the signal that came.
class Interrupted : public std::runtime_error {
public:
    Interrupted(const std::string& what, int signal) : std::runtime_error(what), signal_(signal) {}
    int signal() const { return signal_; }
    int exit_code() const { return 128 + signal_; }

private:
    int signal_;
};

// While one lives, SIGINT and SIGTERM are caught (and remembered) instead of
// ending the process; the previous handlers come back when it goes.
class InterruptScope {
public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;

private:
    struct sigaction previous_int_, previous_term_;
};

// The signal caught inside the current scope, 0 if none.
int interrupt_signal();

// Throws Interrupted if a signal came: "<command>: interrupted by SIGINT
// (Ctrl+C) at <where>; nothing written" (command "video", where "frame 12").
void check_interrupt(const std::string& command, const std::string& where);

}  // namespace scenes
