// Ctrl+C (SIGINT) and SIGTERM during a command that writes through a
// temporary file (video, report, run --csv): instead of dying with the
// temporary left behind, the command stops at its next check, removes what
// it started, says so, and then ends by the same signal (main() re-raises
// it), so that a shell sees an interrupted command (status 130 or 143) and a
// loop around it stops too. A second signal ends the process at once
// (SA_RESETHAND): for a user who will not wait for the clean-up. Outside an
// InterruptScope the signals keep their previous handlers.
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

private:
    int signal_;
};

// While one lives, SIGINT and SIGTERM are caught (the first one remembered)
// instead of ending the process; the previous handlers come back, and the
// remembered signal is forgotten, when it goes.
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

// Throws that Interrupted for `signal`.
[[noreturn]] void throw_interrupted(const std::string& command, const std::string& where, int signal);

// The signal (SIGINT or SIGTERM) that ended a child process, from its wait
// status: killed by it, or an exit status of 128 + it. 0 otherwise. (A
// Ctrl+C in a terminal reaches the child too: this is how it shows there.)
int child_interrupt(int status);

}  // namespace scenes
