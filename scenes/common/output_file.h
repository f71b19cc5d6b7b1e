// Where the commands' outputs go (CSV, recordings, PNG, MP4, reports), so
// that nothing is half-written and nothing but a regular file is replaced.
// A path where nothing or a regular file stands is written whole into a
// temporary file beside it, then renamed over it; a symlink, the same for
// the file it points to (the link stays); anything else (a folder, a FIFO,
// a device) is refused. Errors are OutputError, exit 2 in the command.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace scenes {

// An output that cannot be written: "cannot write <path>: <reason>".
class OutputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The file that writing `path` replaces: `path`, or where its symlinks end.
// Throws OutputError when something other than a regular file stands there,
// or its folder is missing or cannot be written.
std::filesystem::path output_target(const std::filesystem::path& path);

// One output under way: the temporary file beside its target (made empty
// at once), written by us or by another program (ffmpeg), renamed into
// place by commit(); removed if never committed.
class OutputFile {
public:
    explicit OutputFile(const std::filesystem::path& path);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    const std::filesystem::path& path() const { return path_; }  // as given, for messages
    const std::filesystem::path& temporary() const { return temporary_; }
    // Renames the temporary file over the target. Throws OutputError.
    void commit();
    // An OutputError for this output: "cannot write <path>: <reason>".
    OutputError error(const std::string& reason) const;

private:
    std::filesystem::path path_, target_, temporary_;
    bool committed_ = false;
};

// Writes `bytes` to `path` as above; a failed write (the disk full) throws
// OutputError, and what stood at `path` is as it was.
void write_output(const std::filesystem::path& path, std::string_view bytes);

// Whether `path` can be written, found out as writing would (its temporary
// file made and removed), before the work that makes it. Throws OutputError.
void check_output(const std::filesystem::path& path);

// Makes the folder `path` (and its parents) for outputs. Throws OutputError
// naming it when something else stands there or it cannot be made.
void make_output_folder(const std::filesystem::path& path);

}  // namespace scenes
