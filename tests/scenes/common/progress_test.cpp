// The progress bar (scenes/common/progress.h) through the real command: `run`
// draws it on stderr when stderr is a terminal (script(1) gives it one), and
// says nothing of it through a pipe, where a log would fill with bars.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

namespace {

// What `command` writes to stdout.
std::string output(const std::string& command) {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    if (!pipe) return "";
    std::string out;
    std::array<char, 4096> buffer{};
    while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe.get())) out.append(buffer.data(), n);
    return out;
}

TEST(Progress, RunShowsABarOnATerminalAndNotThroughAPipe) {
    // CI=true turns the bar off (progress_wanted), and make test sets it.
    const std::string run = std::string("env -u CI ") + PLAUSIBLE_EXE + " run orbit";
    const std::string terminal = output("script -qec '" + run + "' /dev/null");
    EXPECT_NE(terminal.find("run [##############################] 100%"), std::string::npos) << terminal;
    EXPECT_NE(terminal.find("orbit: 600 frames"), std::string::npos) << "the summary follows\n" << terminal;
    const std::string piped = output(run + " 2>&1");
    EXPECT_EQ(piped.find("run ["), std::string::npos) << piped;
    EXPECT_NE(piped.find("orbit: 600 frames"), std::string::npos) << piped;
}

// A long run redraws its line a few times a second, not every frame: drawn
// every frame, a terminal run of a bead took 15 times as long as through a
// pipe. 200,000 frames take a few tenths of a second here.
TEST(Progress, ALongRunRedrawsItsLineAFewTimesASecond) {
    const std::string run = std::string("env -u CI ") + PLAUSIBLE_EXE + " run oscillator --frames 200000";
    const std::string terminal = output("script -qec '" + run + "' /dev/null");
    EXPECT_NE(terminal.find("run [##############################] 100%"), std::string::npos) << terminal;
    std::size_t lines = 0;  // each drawing starts with a carriage return
    for (char c : terminal) lines += c == '\r' ? 1 : 0;
    EXPECT_GE(lines, 2u) << "the first frame and the last at least";
    EXPECT_LT(lines, 1000u) << "at most one a 0.1 s, and the last: 200,000 frames would be 200,000 drawings";
}

}  // namespace
