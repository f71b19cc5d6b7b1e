#include "scenes/common/interrupt.h"

#include <sys/wait.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace scenes {

namespace {

// The one file-level variable: a signal handler has nowhere else to put what
// it saw. A lock-free atomic, not a volatile sig_atomic_t, because the
// handler may run on any thread (llvmpipe's included) and be read on
// another.
std::atomic<int> caught{0};
static_assert(std::atomic<int>::is_always_lock_free, "a signal handler may only touch lock-free atomics");

// Keeps the first signal: a SIGTERM after a Ctrl+C does not change the story.
extern "C" void on_signal(int signal) {
    int none = 0;
    caught.compare_exchange_strong(none, signal);
}

}  // namespace

InterruptScope::InterruptScope() {
    caught = 0;
    struct sigaction action;
    std::memset(&action, 0, sizeof action);
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    // SA_RESETHAND: the second Ctrl+C gets the default action (the process
    // ends); SA_RESTART: a write under way finishes instead of failing with
    // EINTR.
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
}

InterruptScope::~InterruptScope() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
    caught = 0;
}

int interrupt_signal() { return caught; }

void throw_interrupted(const std::string& command, const std::string& where, int signal) {
    throw Interrupted(command + ": interrupted by " + (signal == SIGINT ? "SIGINT (Ctrl+C)" : "SIGTERM") + " at " +
                          where + "; nothing written",
                      signal);
}

void check_interrupt(const std::string& command, const std::string& where) {
    if (const int signal = caught; signal != 0) throw_interrupted(command, where, signal);
}

int child_interrupt(int status) {
    if (status == -1) return 0;
    if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM)) return WTERMSIG(status);
    if (WIFEXITED(status) && (WEXITSTATUS(status) == 128 + SIGINT || WEXITSTATUS(status) == 128 + SIGTERM))
        return WEXITSTATUS(status) - 128;
    return 0;
}

}  // namespace scenes
