// A shell command from a test (the real `plausible` command, end to end):
// what it printed, stdout and stderr together, and its exit status.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace test {

struct Ran {
    int status = -1;  // exit status; -1: it did not exit normally
    std::string out;  // stdout and stderr
};

inline Ran shell(const std::string& command) {
    Ran r;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (p == nullptr) return r;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, n);
    const int status = pclose(p);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

}  // namespace test
