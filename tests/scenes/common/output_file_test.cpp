// Outputs (scenes/common/output_file.h): written whole or not at all, only
// over a regular file; a symlink's target is written, the link stays.
#include "scenes/common/output_file.h"

#include "tests/scenes/shell.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>
#include <iterator>

namespace {

namespace fs = std::filesystem;
using scenes::OutputError;

std::string text_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t entries(const fs::path& dir) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// The error's message, or "" when none was thrown.
std::string error_of(const fs::path& path, std::string_view bytes) {
    try {
        scenes::write_output(path, bytes);
    } catch (const OutputError& e) {
        return e.what();
    }
    return "";
}

TEST(OutputFile, WritesNewAndReplacesRegularFilesWhole) {
    const test::TempDir dir("output-file");
    scenes::write_output(dir.path() / "a.txt", "first");
    scenes::write_output(dir.path() / "a.txt", "second");
    EXPECT_EQ(text_of(dir.path() / "a.txt"), "second");
    EXPECT_EQ(entries(dir.path()), 1u) << "no temporary file left";
}

TEST(OutputFile, RefusesWhatIsNotARegularFileAndLeavesItBe) {
    const test::TempDir dir("output-refused");
    const fs::path fifo = dir.path() / "fifo", folder = dir.path() / "folder";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
    fs::create_directory(folder);
    EXPECT_EQ(error_of(fifo, "x"),
              "cannot write " + fifo.string() + ": a FIFO stands there, and only a regular file is replaced");
    EXPECT_EQ(error_of(folder, "x"),
              "cannot write " + folder.string() + ": a folder stands there, and only a regular file is replaced");
    EXPECT_EQ(error_of(dir.path() / "missing" / "a.txt", "x"),
              "cannot write " + (dir.path() / "missing" / "a.txt").string() + ": " + (dir.path() / "missing").string() +
                  " is not a folder");
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_TRUE(fs::is_directory(folder));
    EXPECT_EQ(entries(dir.path()), 2u);
}

TEST(OutputFile, WritesASymlinksTargetAndKeepsTheLink) {
    const test::TempDir dir("output-symlink");
    const fs::path target = dir.path() / "target.txt", link = dir.path() / "link.txt";
    std::ofstream(target) << "old";
    fs::create_symlink(target, link);
    scenes::write_output(link, "new");
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(text_of(target), "new");
    const fs::path dangling = dir.path() / "dangling.txt";
    fs::create_symlink(dir.path() / "nowhere" / "x.txt", dangling);
    EXPECT_NE(error_of(dangling, "x").find("a symlink to nothing that can be written"), std::string::npos);
    EXPECT_EQ(entries(dir.path()), 3u);
}

TEST(OutputFile, UncommittedLeavesNothing) {
    const test::TempDir dir("output-uncommitted");
    {
        scenes::OutputFile out(dir.path() / "a.txt");
        std::ofstream(out.temporary()) << "half";
    }
    EXPECT_EQ(entries(dir.path()), 0u);
}

TEST(OutputFolder, SaysWhichPartIsAFile) {
    const test::TempDir dir("output-folder");
    std::ofstream(dir.path() / "file") << "x";
    try {
        scenes::make_output_folder(dir.path() / "file" / "sub");
        FAIL() << "made a folder under a file";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot make the folder " + (dir.path() / "file" / "sub").string() + ": " +
                                             (dir.path() / "file").string() + " is a file");
    }
    scenes::make_output_folder(dir.path() / "a" / "b");
    EXPECT_TRUE(fs::is_directory(dir.path() / "a" / "b"));
}

}  // namespace
