// Ctrl+C and SIGTERM during the commands that write through a temporary file
// (video, report, run --csv), through the real command: it exits 128 + the
// signal, says so, and leaves nothing behind, neither the output nor the
// temporary. And the scope itself: the signal is caught inside, the previous
// handler is back outside.
#include "scenes/interrupt.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;

TEST(InterruptScope, CatchesTheSignalInsideAndRestoresTheHandlerOutside) {
    {
        const scenes::InterruptScope scope;
        EXPECT_EQ(scenes::interrupt_signal(), 0);
        EXPECT_NO_THROW(scenes::check_interrupt("test", "step 1"));
        ASSERT_EQ(::raise(SIGINT), 0);  // caught: the test goes on
        EXPECT_EQ(scenes::interrupt_signal(), SIGINT);
        try {
            scenes::check_interrupt("test", "step 2");
            ADD_FAILURE() << "no Interrupted after SIGINT";
        } catch (const scenes::Interrupted& e) {
            EXPECT_EQ(e.exit_code(), 130);
            EXPECT_STREQ(e.what(), "test: interrupted by SIGINT (Ctrl+C) at step 2; nothing written");
        }
    }
    struct sigaction now;
    ASSERT_EQ(sigaction(SIGINT, nullptr, &now), 0);
    EXPECT_EQ(now.sa_handler, SIG_DFL) << "the default action is back";
    const scenes::InterruptScope again;
    EXPECT_EQ(scenes::interrupt_signal(), 0) << "a new scope starts clean";
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
        int status = -1;  // exit status, -1 if it did not exit
        std::string err;  // what it wrote on stderr
    };
    // Runs `plausible args...` with its output in out/, waits until its
    // temporary file or folder shows there (the output comes only at the end,
    // renamed from it), sends
    // `signal` to the command alone (not to ffmpeg), and waits for the end.
    Ended interrupt(const std::vector<std::string>& args, int signal) {
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
        pid_t pid = 0;
        const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        EXPECT_EQ(spawned, 0) << "cannot start " << PLAUSIBLE_EXE;
        if (spawned != 0) return {};
        bool seen = false;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (!seen && std::chrono::steady_clock::now() < deadline) {
            seen = !fs::is_empty(dir_ / "out");
            if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        EXPECT_TRUE(seen) << "no temporary file showed in 60 s";
        ::kill(pid, signal);
        int status = 0;
        waitpid(pid, &status, 0);
        std::ifstream in(err_path);
        std::stringstream err;
        err << in.rdbuf();
        std::printf("%s", err.str().c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, err.str()};
    }
    // Nothing left in out/: no output, no temporary.
    void expect_nothing_written() const {
        for (const auto& entry : fs::directory_iterator(dir_ / "out")) ADD_FAILURE() << "left behind: " << entry.path();
    }
    fs::path out(const std::string& name) const { return dir_ / "out" / name; }

    fs::path dir_;
};

TEST_F(Interrupt, CtrlCDuringAVideoExits130AndLeavesNoFile) {
    const Ended e =
        interrupt({"video", "cloth", "-o", out("cloth.mp4").string(), "--size", "320x180", "--seconds", "600"}, SIGINT);
    EXPECT_EQ(e.status, 130);
    EXPECT_NE(e.err.find("video: interrupted by SIGINT (Ctrl+C) at frame"), std::string::npos) << e.err;
    expect_nothing_written();
}

TEST_F(Interrupt, SigtermDuringAReportExits143AndLeavesNoFolder) {
    const Ended e = interrupt({"report", "--quick", "--out", out("report").string()}, SIGTERM);
    EXPECT_EQ(e.status, 143);
    EXPECT_NE(e.err.find("report: interrupted by SIGTERM"), std::string::npos) << e.err;
    expect_nothing_written();
}

TEST_F(Interrupt, CtrlCDuringARunWithCsvExits130AndLeavesNoCsv) {
    const Ended e =
        interrupt({"run", "showcase", "--frames", "1000000", "--csv", out("showcase.csv").string()}, SIGINT);
    EXPECT_EQ(e.status, 130);
    EXPECT_NE(e.err.find("run --csv: interrupted by SIGINT (Ctrl+C) at frame"), std::string::npos) << e.err;
    expect_nothing_written();
}

}  // namespace
