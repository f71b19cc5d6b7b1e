// Child programs (scenes/common/child_process.h): started from an argument
// vector, so an argument reaches the program byte for byte, whatever a shell
// would have made of it.
#include "scenes/common/child_process.h"

#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <fstream>
#include <iterator>

namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ChildProcess, AnArgumentArrivesAsItIs) {
    const test::TempDir dir("child-args");
    const fs::path said = dir.path() / "said";
    const std::string hostile = "a';touch PWNED;'b $(touch PWNED) \"\n-x";
    const int status = scenes::ChildProcess({"sh", "-c", "printf %s \"$1\" >&2", "sh", hostile},
                                            {.errors = said, .directory = dir.path()})
                           .wait();
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << scenes::describe_status(status);
    EXPECT_EQ(text_of(said), hostile);
    EXPECT_FALSE(fs::exists(dir.path() / "PWNED"));
}

TEST(ChildProcess, ItsInputIsThePipeWeWrite) {
    const test::TempDir dir("child-pipe");
    const fs::path said = dir.path() / "said";
    scenes::ChildProcess cat({"sh", "-c", "cat >&2"}, {.pipe_input = true, .errors = said});
    ASSERT_TRUE(cat.write("frames", 6));
    EXPECT_EQ(cat.wait(), 0);
    EXPECT_EQ(text_of(said), "frames");
}

TEST(ChildProcess, ItsExitStatusAndAMissingProgramAreSaid) {
    const int status = scenes::ChildProcess({"sh", "-c", "exit 3"}, {}).wait();
    EXPECT_EQ(scenes::describe_status(status), "exit status 3");
    try {
        scenes::ChildProcess({"no-such-program-of-ours", "x"}, {});
        FAIL() << "started a program that is not there";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "cannot start no-such-program-of-ours: No such file or directory");
    }
    EXPECT_TRUE(scenes::on_path("sh"));
    EXPECT_FALSE(scenes::on_path("no-such-program-of-ours"));
}

TEST(ChildProcess, AWriteToAChildThatStoppedReadingFails) {
    scenes::ChildProcess done({"true"}, {.pipe_input = true});
    std::string frame(1 << 22, 'x');  // more than any pipe holds
    EXPECT_FALSE(done.write(frame.data(), frame.size()));
    EXPECT_EQ(done.wait(), 0);
}

}  // namespace
