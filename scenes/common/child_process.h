// A program the commands start (ffmpeg, gnuplot): an argument vector handed
// to posix_spawnp, never a shell line, so no path or name from the user is
// ever read as a command. Its input a pipe or nothing, its errors a file.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace scenes {

struct ChildOptions {
    bool pipe_input = false;          // its standard input a pipe we write; else `input`
    std::filesystem::path input;      // its standard input from this file; empty: /dev/null
    bool quiet = false;               // its standard output to /dev/null; else ours
    std::filesystem::path errors;     // its standard error into this file; empty: ours
    std::filesystem::path directory;  // where it runs; empty: where we do
};

class ChildProcess {
public:
    // Starts argv[0], looked up on PATH. Throws std::runtime_error naming the
    // program when it cannot be started (not installed, say).
    ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options);
    // Unwaited (an error, an interrupt): its input closed, then waited for.
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    // Writes all `size` bytes to its input; false when it stopped reading
    // (SIGPIPE is ignored while a child's input is open: a dead child shows
    // as a failed write, not as our death).
    bool write(const void* bytes, std::size_t size);
    // Asks for a pipe of `bytes` (fewer turns of the two processes a large
    // frame); where it is refused, the pipe stays as it is.
    void set_pipe_size(int bytes);
    // Closes its input and waits for it: the wait status (as waitpid's).
    int wait();

private:
    pid_t pid_ = -1;
    int input_ = -1;  // the write end of its input pipe, -1 when none or closed
};

// Whether `program` is an executable file on PATH (no shell's `command -v`).
bool on_path(const std::string& program);

// A wait status in words: "exit status 3", "killed by signal 9".
std::string describe_status(int status);

}  // namespace scenes
