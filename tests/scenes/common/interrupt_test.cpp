// Ctrl+C and SIGTERM during the commands that write through a temporary file
// (video, report, run --csv), through the real command: it says so, leaves
// nothing behind (neither the output nor the temporary) and ends by the
// signal, so that a shell loop around it stops. Signalled alone, or with its
// whole process group as a terminal's Ctrl+C does (ffmpeg and gnuplot get it
// too). And the scope itself: the signal caught inside, the previous
// handlers back outside.
#include "scenes/common/interrupt.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;

// The handler installed for `signal` now.
void (*handler(int signal))(int) {
    struct sigaction now;
    sigaction(signal, nullptr, &now);
    return now.sa_handler;
}

TEST(InterruptScope, CatchesTheSignalInsideAndRestoresThePreviousHandlers) {
    // Markers to see come back: SIGINT ignored, SIGTERM at its default.
    std::signal(SIGINT, SIG_IGN);
    {
        const scenes::InterruptScope scope;
        EXPECT_NE(handler(SIGINT), SIG_IGN);
        EXPECT_NE(handler(SIGTERM), SIG_DFL);
        EXPECT_EQ(scenes::interrupt_signal(), 0);
    }
    EXPECT_EQ(handler(SIGINT), SIG_IGN) << "restored without a signal";
    EXPECT_EQ(handler(SIGTERM), SIG_DFL) << "restored without a signal";
    {
        const scenes::InterruptScope scope;
        EXPECT_NO_THROW(scenes::check_interrupt("test", "step 1"));
        ASSERT_EQ(::raise(SIGINT), 0);  // caught: the test goes on
        ASSERT_EQ(::raise(SIGTERM), 0);
        EXPECT_EQ(scenes::interrupt_signal(), SIGINT) << "the first signal is the one kept";
        try {
            scenes::check_interrupt("test", "step 2");
            ADD_FAILURE() << "no Interrupted after SIGINT";
        } catch (const scenes::Interrupted& e) {
            EXPECT_EQ(e.signal(), SIGINT);
            EXPECT_STREQ(e.what(), "test: interrupted by SIGINT (Ctrl+C) at step 2; nothing written");
        }
    }
    EXPECT_EQ(handler(SIGINT), SIG_IGN) << "restored after a signal";
    EXPECT_EQ(handler(SIGTERM), SIG_DFL) << "restored after a signal";
    EXPECT_EQ(scenes::interrupt_signal(), 0) << "forgotten with the scope";
    EXPECT_NO_THROW(scenes::check_interrupt("test", "after the scope"));
    std::signal(SIGINT, SIG_DFL);
}

TEST(InterruptScope, ChildInterruptReadsRealChildStatuses) {
    EXPECT_EQ(scenes::child_interrupt(std::system("kill -INT $$")), SIGINT) << "killed by SIGINT";
    EXPECT_EQ(scenes::child_interrupt(std::system("kill -TERM $$")), SIGTERM) << "killed by SIGTERM";
    EXPECT_EQ(scenes::child_interrupt(std::system("exit 130")), SIGINT) << "a shell's 128 + SIGINT";
    EXPECT_EQ(scenes::child_interrupt(std::system("exit 0")), 0);
    EXPECT_EQ(scenes::child_interrupt(std::system("exit 1")), 0);
    EXPECT_EQ(scenes::child_interrupt(std::system("kill -KILL $$")), 0) << "SIGKILL is no interrupt";
}

class Interrupt : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("plausible-interrupt-test-" + std::to_string(getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "out");
    }
    void TearDown() override { fs::remove_all(dir_); }

    struct Ended {
        int signal = 0;   // the signal that ended it, 0 if it exited
        int status = -1;  // its exit status if it exited
        std::string err;  // what it wrote on stderr
    };
    // Runs `plausible args...` (output in out/) in a process group of its
    // own, waits until `ready()` (at most 600 s: the report's plots come
    // after 30 s here, minutes in the sanitizer build), sends `signal` to the
    // command alone or (`group`) to its whole group, and waits for the end
    // (SIGKILL after 120 s more: a test failure, not a hang).
    Ended interrupt(const std::vector<std::string>& args, int signal, bool group, const std::function<bool()>& ready) {
        std::vector<std::string> argv_s{PLAUSIBLE_EXE};
        argv_s.insert(argv_s.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (std::string& a : argv_s) argv.push_back(a.data());
        argv.push_back(nullptr);
        const std::string err_path = (dir_ / "stderr.txt").string();
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawnattr_t attributes;
        posix_spawnattr_init(&attributes);
        posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
        posix_spawnattr_setpgroup(&attributes, 0);
        pid_t pid = 0;
        const int spawned = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        posix_spawnattr_destroy(&attributes);
        EXPECT_EQ(spawned, 0) << "cannot start " << PLAUSIBLE_EXE;
        if (spawned != 0) return {};
        int status = 0;
        bool ended = false, seen = false;
        auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(600);
        while (!seen && !ended && std::chrono::steady_clock::now() < deadline) {
            seen = ready();
            ended = waitpid(pid, &status, WNOHANG) == pid;
            if (!seen && !ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        EXPECT_TRUE(seen) << (ended ? "the command ended before it was ready" : "not ready in 600 s");
        if (!ended) {
            ::kill(group ? -pid : pid, signal);
            deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
            while (!ended && std::chrono::steady_clock::now() < deadline) {
                ended = waitpid(pid, &status, WNOHANG) == pid;
                if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
            EXPECT_TRUE(ended) << "still running 120 s after the signal";
            if (!ended) {
                ::kill(-pid, SIGKILL);
                waitpid(pid, &status, 0);
            }
        }
        std::ifstream in(err_path);
        std::stringstream err;
        err << in.rdbuf();
        std::printf("%s", err.str().c_str());
        return {WIFSIGNALED(status) ? WTERMSIG(status) : 0, WIFEXITED(status) ? WEXITSTATUS(status) : -1, err.str()};
    }
    // The command's temporary showed in out/ (the output comes only at the
    // end, renamed from it).
    std::function<bool()> temporary_shows() const {
        return [out = dir_ / "out"] { return !fs::is_empty(out); };
    }
    // Nothing left in out/: no output, no temporary.
    void expect_nothing_written() const {
        for (const auto& entry : fs::directory_iterator(dir_ / "out")) ADD_FAILURE() << "left behind: " << entry.path();
    }
    std::string out(const std::string& name) const { return (dir_ / "out" / name).string(); }

    fs::path dir_;
};

// Ctrl+C to the command alone, then to its process group as a terminal
// sends it (ffmpeg stops reading too: the broken pipe is an interrupt).
TEST_F(Interrupt, CtrlCDuringAVideoEndsItByTheSignalAndLeavesNoFile) {
    for (const bool group : {false, true}) {
        SCOPED_TRACE(group ? "to the process group" : "to the command alone");
        const Ended e = interrupt({"video", "cloth", "--size", "320x180", "--seconds", "600", "-o", out("cloth.mp4")},
                                  SIGINT, group, temporary_shows());
        EXPECT_EQ(e.signal, SIGINT) << "exit status " << e.status;
        EXPECT_NE(e.err.find("video: interrupted by SIGINT (Ctrl+C) at "), std::string::npos) << e.err;
        expect_nothing_written();
    }
}

TEST_F(Interrupt, SigtermDuringAReportEndsItByTheSignalAndLeavesNoFolder) {
    const Ended e = interrupt({"report", "--quick", "--out", out("report")}, SIGTERM, false, temporary_shows());
    EXPECT_EQ(e.signal, SIGTERM) << "exit status " << e.status;
    EXPECT_NE(e.err.find("report: interrupted by SIGTERM"), std::string::npos) << e.err;
    expect_nothing_written();
}

// The report's plots come last, from gnuplot, in our process group: a
// Ctrl+C reaches both, and the command learns of it from gnuplot's status or
// its own handler, whichever comes first (not "gnuplot failed", exit 2).
TEST_F(Interrupt, CtrlCToTheReportsProcessGroupWhilePlottingLeavesNoFolder) {
    const fs::path out_dir = dir_ / "out";
    const Ended e = interrupt({"report", "--quick", "--out", out("report")}, SIGINT, true, [out_dir] {
        for (const auto& entry : fs::directory_iterator(out_dir)) {
            if (!entry.is_directory()) continue;
            for (const auto& file : fs::directory_iterator(entry.path())) {
                if (file.path().extension() == ".png") return true;  // the first plot is out
            }
        }
        return false;
    });
    EXPECT_EQ(e.signal, SIGINT) << "exit status " << e.status;
    EXPECT_NE(e.err.find("report: interrupted by SIGINT (Ctrl+C)"), std::string::npos) << e.err;
    expect_nothing_written();
}

TEST_F(Interrupt, CtrlCDuringARunWithCsvEndsItByTheSignalAndLeavesNoCsv) {
    const Ended e = interrupt({"run", "showcase", "--frames", "1000000", "--csv", out("showcase.csv")}, SIGINT, false,
                              temporary_shows());
    EXPECT_EQ(e.signal, SIGINT) << "exit status " << e.status;
    EXPECT_NE(e.err.find("run --csv: interrupted by SIGINT (Ctrl+C) at frame"), std::string::npos) << e.err;
    expect_nothing_written();
}

}  // namespace
