#include "scenes/interrupt.h"

#include <csignal>
#include <cstring>

namespace scenes {

namespace {

// The one file-level variable: a signal handler may do no more than set a
// flag of this type, and it has nowhere else to put it.
volatile std::sig_atomic_t caught = 0;

extern "C" void on_signal(int signal) { caught = signal; }

}  // namespace

InterruptScope::InterruptScope() {
    caught = 0;
    struct sigaction action;
    std::memset(&action, 0, sizeof action);
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    // SA_RESETHAND: the second Ctrl+C gets the default action (the process
    // ends) for a user who does not want to wait for the clean-up;
    // SA_RESTART: a write under way finishes instead of failing with EINTR.
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
}

InterruptScope::~InterruptScope() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
}

int interrupt_signal() { return caught; }

void check_interrupt(const std::string& command, const std::string& where) {
    const int signal = caught;
    if (signal == 0) return;
    throw Interrupted(command + ": interrupted by " + (signal == SIGINT ? "SIGINT (Ctrl+C)" : "SIGTERM") + " at " +
                          where + "; nothing written",
                      signal);
}

}  // namespace scenes
