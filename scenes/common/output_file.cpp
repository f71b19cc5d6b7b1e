#include "scenes/common/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace scenes {

namespace fs = std::filesystem;

namespace {

OutputError cannot_write(const fs::path& path, const std::string& reason) {
    return OutputError("cannot write " + path.string() + ": " + reason);
}

const char* kind_of(fs::file_type type) {
    switch (type) {
        case fs::file_type::directory:
            return "a folder";
        case fs::file_type::fifo:
            return "a FIFO";
        case fs::file_type::character:
            return "a character device";
        case fs::file_type::block:
            return "a block device";
        case fs::file_type::socket:
            return "a socket";
        default:
            return "not a regular file";
    }
}

}  // namespace

fs::path output_target(const fs::path& path) {
    if (path.empty()) throw OutputError("cannot write an empty path");
    std::error_code ec;
    fs::path target = path;
    if (fs::is_symlink(fs::symlink_status(path, ec))) {
        target = fs::canonical(path, ec);
        if (ec) throw cannot_write(path, "a symlink to nothing that can be written (" + ec.message() + ")");
    }
    const fs::file_status status = fs::status(target, ec);
    if (fs::exists(status) && !fs::is_regular_file(status)) {
        throw cannot_write(path,
                           std::string(kind_of(status.type())) + " stands there, and only a regular file is replaced");
    }
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(folder, ec)) throw cannot_write(path, folder.string() + " is not a folder");
    return target;
}

OutputFile::OutputFile(const fs::path& path)
    : path_(path), target_(output_target(path)), temporary_(target_.string() + ".tmp-" + std::to_string(getpid())) {
    // Made now, empty: a folder we may not write (root may, except in /proc) fails before the work.
    const int fd = open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw error(std::strerror(errno));
    close(fd);
}

OutputFile::~OutputFile() {
    if (committed_) return;
    std::error_code ignored;
    fs::remove(temporary_, ignored);
}

void OutputFile::commit() {
    std::error_code ec;
    fs::rename(temporary_, target_, ec);
    if (ec) throw error(ec.message());
    committed_ = true;
}

OutputError OutputFile::error(const std::string& reason) const { return cannot_write(path_, reason); }

void write_output(const fs::path& path, std::string_view bytes) {
    OutputFile out(path);
    std::FILE* file = std::fopen(out.temporary().c_str(), "wb");
    if (file == nullptr) throw out.error(std::strerror(errno));
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    const int write_errno = errno;
    const bool closed = std::fclose(file) == 0;
    if (!written || !closed) throw out.error(std::strerror(written ? errno : write_errno));
    out.commit();
}

void check_output(const fs::path& path) {
    const OutputFile probe(path);  // made and, uncommitted, removed
}

void make_output_folder(const fs::path& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) return;
    fs::create_directories(path, ec);
    if (!ec && fs::is_directory(path)) return;
    // The first part of the path that is not a folder says why.
    fs::path part;
    for (const fs::path& piece : path) {
        part /= piece;
        const fs::file_status s = fs::status(part, ec);
        if (fs::exists(s) && !fs::is_directory(s)) {
            throw OutputError("cannot make the folder " + path.string() + ": " + part.string() + " is " +
                              (fs::is_regular_file(s) ? "a file" : kind_of(s.type())));
        }
    }
    throw OutputError("cannot make the folder " + path.string() + ": " +
                      (ec ? ec.message() : std::string("it is not a folder")));
}

}  // namespace scenes
