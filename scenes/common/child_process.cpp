#include "scenes/common/child_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace scenes {

namespace {

// posix_spawn's two attribute objects, destroyed on every way out.
struct SpawnSetup {
    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attributes;
    SpawnSetup() {
        posix_spawn_file_actions_init(&actions);
        posix_spawnattr_init(&attributes);
    }
    ~SpawnSetup() {
        posix_spawn_file_actions_destroy(&actions);
        posix_spawnattr_destroy(&attributes);
    }
    SpawnSetup(const SpawnSetup&) = delete;
    SpawnSetup& operator=(const SpawnSetup&) = delete;
};

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options) {
    if (argv.empty()) throw std::invalid_argument("ChildProcess: no program");
    SpawnSetup setup;
    int pipe_ends[2] = {-1, -1};
    if (options.pipe_input) {
        if (pipe2(pipe_ends, O_CLOEXEC) != 0) throw std::runtime_error("cannot start " + argv[0] + ": no pipe");
        posix_spawn_file_actions_adddup2(&setup.actions, pipe_ends[0], 0);
        std::signal(SIGPIPE, SIG_IGN);
    } else {
        const char* from = options.input.empty() ? "/dev/null" : options.input.c_str();
        posix_spawn_file_actions_addopen(&setup.actions, 0, from, O_RDONLY, 0);
    }
    if (options.quiet) posix_spawn_file_actions_addopen(&setup.actions, 1, "/dev/null", O_WRONLY, 0);
    if (!options.errors.empty()) {
        posix_spawn_file_actions_addopen(&setup.actions, 2, options.errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    if (!options.directory.empty()) posix_spawn_file_actions_addchdir_np(&setup.actions, options.directory.c_str());
    // The child gets SIGPIPE's default back (we may ignore it).
    sigset_t defaults;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGPIPE);
    posix_spawnattr_setsigdefault(&setup.attributes, &defaults);
    posix_spawnattr_setflags(&setup.attributes, POSIX_SPAWN_SETSIGDEF);

    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int error = posix_spawnp(&pid_, args[0], &setup.actions, &setup.attributes, args.data(), environ);
    if (options.pipe_input) close(pipe_ends[0]);
    if (error != 0) {
        if (options.pipe_input) close(pipe_ends[1]);
        pid_ = -1;
        throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(error));
    }
    input_ = options.pipe_input ? pipe_ends[1] : -1;
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0) wait();
}

bool ChildProcess::write(const void* bytes, std::size_t size) {
    const char* at = static_cast<const char*>(bytes);
    while (size > 0 && input_ >= 0) {
        const ssize_t n = ::write(input_, at, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += n;
        size -= static_cast<std::size_t>(n);
    }
    return size == 0;
}

void ChildProcess::set_pipe_size(int bytes) {
    if (input_ >= 0) fcntl(input_, F_SETPIPE_SZ, bytes);
}

int ChildProcess::wait() {
    if (input_ >= 0) close(input_), input_ = -1;
    int status = -1;
    while (pid_ > 0 && waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    return status;
}

bool on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
        const std::string file = dir + "/" + program;
        struct stat s;
        if (stat(file.c_str(), &s) == 0 && S_ISREG(s.st_mode) && access(file.c_str(), X_OK) == 0) return true;
        start = end + 1;
    }
    return false;
}

std::string describe_status(int status) {
    if (status == -1) return "no status";
    if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
    return "status " + std::to_string(status);
}

}  // namespace scenes
