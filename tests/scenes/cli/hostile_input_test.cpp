// Hostile and unlucky input through the real command (issue 51): output
// names a shell would read as commands, outputs where something other than a
// regular file stands, a disk that fills, --set values of two lines, --shard
// past an int, keys of thousands of parts. Each exits 0 having done what was
// asked, or exits 2 naming the path; nothing is half-written or replaced.
#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const std::string kExe = PLAUSIBLE_EXE;

std::string text_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The names in `dir`, for "nothing else was left there".
std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(NoShell, AVideoGoesToANameAShellWouldRun) {
    const test::TempDir dir("hostile-video");
    const std::vector<std::string> names = {"a';touch PWNED;'b.mp4", "it's.mp4",       "$(touch PWNED) x.mp4",
                                            "new\nline.mp4",         "http:colon.mp4", "-dash.gif"};
    for (const std::string& name : names) {
        const fs::path out = dir.path() / name;
        const test::Ran r = test::run({kExe, "video", "orbit", "--seconds", "0.1", "--size", "64x48", "-o", out});
        EXPECT_EQ(r.status, 0) << name << ": " << r.out;
        EXPECT_TRUE(fs::is_regular_file(out)) << name;
        EXPECT_GT(fs::file_size(out), 100u) << name;
    }
    EXPECT_FALSE(fs::exists("PWNED")) << "a name ran as a command";
    EXPECT_FALSE(fs::exists(dir.path() / "PWNED")) << "a name ran as a command";
    EXPECT_EQ(names_in(dir.path()).size(), names.size()) << "no temporary file or log left";
}

TEST(Outputs, SomethingOtherThanARegularFileIsRefusedNotReplaced) {
    const test::TempDir dir("hostile-outputs");
    const fs::path fifo = dir.path() / "fifo";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
    const fs::path folder = dir.path() / "folder.mp4";
    fs::create_directory(folder);
    const std::vector<std::vector<std::string>> commands = {
        {kExe, "run", "rope", "--frames", "2", "--csv", fifo},
        {kExe, "run", "rope", "--frames", "2", "--record", fifo},
        {kExe, "video", "orbit", "--seconds", "0.1", "--size", "64x48", "-o", folder},
    };
    for (const auto& command : commands) {
        const test::Ran r = test::run(command);
        EXPECT_EQ(r.status, 2) << command.back() << ": " << r.out;
        EXPECT_NE(r.out.find("cannot write " + command.back()), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("only a regular file is replaced"), std::string::npos) << r.out;
    }
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_TRUE(fs::is_directory(folder));
    EXPECT_TRUE(fs::is_empty(folder));
    // A device node (made here, where we may: as root in CI), never a system one.
    std::vector<std::string> left = {"fifo", "folder.mp4"};
    const fs::path device = dir.path() / "full";
    if (mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)) == 0) {
        const test::Ran r = test::run({kExe, "run", "rope", "--frames", "2", "--record", device});
        EXPECT_EQ(r.status, 2) << r.out;
        struct stat s;
        ASSERT_EQ(stat(device.c_str(), &s), 0);
        EXPECT_TRUE(S_ISCHR(s.st_mode)) << "the device node was replaced";
        left.push_back("full");
    }
    EXPECT_EQ(names_in(dir.path()), left) << "no temporary file left";
}

TEST(Outputs, ASymlinksTargetIsWrittenAndTheLinkStays) {
    const test::TempDir dir("hostile-symlink");
    const fs::path target = dir.path() / "real.csv", link = dir.path() / "link.csv";
    std::ofstream(target) << "old\n";
    fs::create_symlink(target, link);
    const test::Ran r = test::run({kExe, "run", "rope", "--frames", "2", "--csv", link});
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(text_of(target).rfind("frame,time,kind,id,x,y,z,vx,vy,vz\n", 0), 0u) << text_of(target);
    EXPECT_EQ(names_in(dir.path()), (std::vector<std::string>{"link.csv", "real.csv"}));
}

// A full disk, as a file size limit stands in for one (prlimit, util-linux).
TEST(Outputs, AFailedWriteExitsTwoAndLeavesNothing) {
    const test::TempDir dir("hostile-full");
    const fs::path csv = dir.path() / "rope.csv", rec = dir.path() / "showcase.rec";
    const fs::path mp4 = dir.path() / "orbit.mp4";
    const std::vector<std::vector<std::string>> commands = {
        {"prlimit", "--fsize=100000", kExe, "run", "rope", "--csv", csv},
        {"prlimit", "--fsize=100000", kExe, "run", "showcase", "--frames", "30", "--record", rec},
        {"prlimit", "--fsize=20000", kExe, "video", "orbit", "--seconds", "2", "--size", "320x240", "-o", mp4},
    };
    for (const auto& command : commands) {
        const test::Ran r = test::run(command);
        EXPECT_EQ(r.status, 2) << command.back() << ": " << r.out;
        EXPECT_NE(r.out.find("cannot write " + command.back()), std::string::npos) << r.out;
    }
    EXPECT_TRUE(fs::is_empty(dir.path())) << "a half-written file or a temporary was left";
    // A PNG: render's frames, into a folder it makes.
    const fs::path pngs = dir.path() / "pngs";
    const test::Ran r = test::run(
        {"prlimit", "--fsize=2000", kExe, "render", "cloth", "--frames", "0", "--size", "320x240", "--out", pngs});
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("cannot write " + (pngs / "cloth_f00000.png").string() + ": File too large"),
              std::string::npos)
        << r.out;
    EXPECT_TRUE(fs::is_empty(pngs)) << "a half-written PNG or a temporary was left";
}

TEST(ExitCodes, PathsThatCannotBeUsedExitTwoNamingThem) {
    const test::TempDir dir("hostile-paths");
    const fs::path file = dir.path() / "a-file";
    std::ofstream(file) << "x\n";
    const fs::path rec_folder = dir.path() / "folder.rec";
    fs::create_directory(rec_folder);
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{kExe, "render", "rope", "--frames", "0", "--size", "64x48", "--out", file / "sub"}, file.string()},
        {{kExe, "check", "rope", "--physics-only", "--report", file / "sub"}, file.string()},
        {{kExe, "run", rec_folder}, rec_folder.string()},
        {{kExe, "video", "orbit", "--seconds", "0.1", "-o", "/proc/x.mp4"}, "/proc/x.mp4"},
    };
    for (const auto& [command, path] : cases) {
        const test::Ran r = test::run(command);
        EXPECT_EQ(r.status, 2) << command[1] << ": " << r.out;
        EXPECT_NE(r.out.find(path), std::string::npos) << "the message names " << path << ": " << r.out;
        EXPECT_EQ(r.out.find("filesystem error"), std::string::npos) << r.out;
    }
}

TEST(ExitCodes, ShardsPastAnIntAreRefused) {
    for (const std::string shard : {"1/99999999999999999999", "9999999999/9999999999", "1/-1", "1/2x", "/2"}) {
        const test::Ran r = test::run({kExe, "check", "--physics-only", "--shard", shard});
        EXPECT_EQ(r.status, 2) << shard << ": " << r.out;
        EXPECT_NE(r.out.find("--shard"), std::string::npos) << r.out;
    }
}

TEST(ExitCodes, SetErrorsNameSetNotTheFile) {
    const test::Ran r = test::run({kExe, "run", "rope", "--set", "nosuch.key=3"});
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("--set nosuch.key=3: unknown key 'nosuch'"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("rope.toml"), std::string::npos) << r.out;
}

TEST(ExitCodes, ABackendThatIsNotHereIsBadInputNotAFailure) {
    const test::TempDir dir("hostile-backend");
    const test::Ran r = test::run(
        {kExe, "render", "rope", "--backend", "gpu", "--frames", "0", "--size", "64x48", "--out", dir.path()});
    EXPECT_TRUE(r.status == 0 || r.status == 2) << "0 with a GPU, 2 without: " << r.status << " " << r.out;
}

TEST(ExitCodes, ASetValueOfTwoLinesIsRefusedNamingSet) {
    const test::Ran r = test::run({kExe, "run", "rope", "--set", "ropes[0].mass=2\nstep.dt = 0.5"});
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("--set ropes[0].mass=2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("more than one line"), std::string::npos) << r.out;
}

TEST(ExitCodes, KeysOfThousandsOfPartsAreRefusedBeforeParsing) {
    const test::TempDir dir("hostile-keys");
    std::string dotted = "a";
    for (int i = 0; i < 35000; ++i) dotted += ".a";
    const fs::path key = dir.path() / "key.toml", header = dir.path() / "header.toml";
    std::ofstream(key) << "description = \"deep\"\n" << dotted << " = 1\n";
    std::ofstream(header) << "description = \"deep\"\n\n[" << dotted << "]\nx = 1\n";
    for (const auto& [file, line] : {std::pair{key, 2}, std::pair{header, 3}}) {
        const test::Ran r = test::run({kExe, "run", file});
        EXPECT_EQ(r.status, 2) << r.out.substr(0, 300);
        EXPECT_NE(r.out.find(file.string() + ":" + std::to_string(line) + ": a dotted key or table header of more"),
                  std::string::npos)
            << r.out.substr(0, 300);
    }
    const test::Ran set = test::run({kExe, "run", "rope", "--frames", "1", "--set", dotted + "=1"});
    EXPECT_EQ(set.status, 2) << set.out.substr(0, 300);
    EXPECT_NE(set.out.find("a key of more than"), std::string::npos) << set.out.substr(0, 300);
}

}  // namespace
