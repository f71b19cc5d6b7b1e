// The mutation sweep (issue 51): every numeric value of every shipped scene,
// array elements included, replaced by extremes and multiplied by large and
// small factors, each variant loaded with the --set mechanism and run for
// --frames frames as `plausible run` runs it (load_scene, then SceneRun), in
// a forked child under a CPU, wall-clock and address-space limit. A child may
// exit 0 (ran), 1 (the watchdog stopped it) or 2 (refused: InputError);
// anything else is a finding: a signal (ODE's assertions abort), another
// exception, a run past its limit. Each finding is printed as scene and --set.
//   usage: mutation_sweep SCENE_DIR [--every K] [--jobs J] [--frames N]
//                         [--seconds S] [--memory-mb M] [--only SCENE]
// --every K runs variants 0, K, 2K, ... of the whole list (K prime to the
// 13 mutations, so every mutation and every scene is still covered).
#include "scenes/draw/scene_run.h"
#include "scenes/model/scene.h"

#include <toml++/toml.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// What a numeric value becomes: replaced by `value`, or multiplied by it.
struct Mutation {
    const char* name;
    bool multiply;
    double value;
};
constexpr Mutation kMutations[] = {
    {"0", false, 0.0},       {"1e-300", false, 1e-300}, {"-1e-300", false, -1e-300}, {"1e-100", false, 1e-100},
    {"1e100", false, 1e100}, {"1e300", false, 1e300},   {"-1e300", false, -1e300},   {"1e9", false, 1e9},
    {"-1e9", false, -1e9},   {"x-1", true, -1.0},       {"x1e-3", true, 1e-3},       {"x1e3", true, 1e3},
    {"x1e6", true, 1e6},
};
constexpr std::size_t kMutationCount = std::size(kMutations);

struct Variant {
    std::size_t scene;  // index into the scene list
    std::string key;    // --set KEY
    std::string value;  // --set VALUE (TOML)
    std::size_t mutation;
};

// A float as a TOML float literal (always with '.' or an exponent).
std::string float_literal(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    std::string s = text;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
}

// An integer node keeps integer form where the result is a whole number;
// past int64 it is clamped to the largest (a user's 1e300 in an integer key).
std::string mutated(const toml::node& node, const Mutation& m) {
    const double x = *node.value<double>();
    const double v = m.multiply ? x * m.value : m.value;
    if (!node.is_integer() || v != std::trunc(v)) return float_literal(v);
    if (v >= 9.2e18) return std::to_string(LLONG_MAX);
    if (v <= -9.2e18) return std::to_string(LLONG_MIN);
    return std::to_string(static_cast<long long>(v));
}

// Every numeric leaf under `node`, as the --set key that names it.
void walk(const toml::node& node, const std::string& path,
          std::vector<std::pair<std::string, const toml::node*>>& out) {
    if (const toml::table* t = node.as_table()) {
        for (auto&& [k, v] : *t) walk(v, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()), out);
    } else if (const toml::array* a = node.as_array()) {
        for (std::size_t i = 0; i < a->size(); ++i) {
            const toml::node& e = *a->get(i);
            if (e.is_array()) continue;  // an array of arrays: --set cannot name its elements
            walk(e, path + "[" + std::to_string(i) + "]", out);
        }
    } else if (node.is_integer() || node.is_floating_point()) {
        out.emplace_back(path, &node);
    }
}

// Per variant. CPU: the loader refuses work over about a second a frame, so
// twice that; the wall clock (a child that blocks) five times the CPU's.
struct Limits {
    int frames = 30;
    int seconds = 60;              // s of CPU
    std::size_t memory_mb = 4096;  // MiB of address space, beyond what the child starts with
};

// The address space this process holds now, bytes (/proc/self/statm's first
// field): under AddressSanitizer that is terabytes of reserved shadow, so a
// limit counts from here, not from zero.
rlim_t address_space_now() {
    unsigned long pages = 0;
    if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%lu", &pages) != 1) pages = 0;
        std::fclose(f);
    }
    return static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE));
}

// The child: the variant through the command's path. Exit codes as `plausible run`'s.
[[noreturn]] void run_child(const fs::path& file, const Variant& v, const Limits& limits) {
    const rlim_t bytes = address_space_now() + (static_cast<rlim_t>(limits.memory_mb) << 20);
    const rlimit as{bytes, bytes};
    const rlimit cpu{static_cast<rlim_t>(limits.seconds), static_cast<rlim_t>(limits.seconds) + 1};
    setrlimit(RLIMIT_AS, &as);
    setrlimit(RLIMIT_CPU, &cpu);
    alarm(static_cast<unsigned>(limits.seconds) * 5);
    int code = 0;
    try {
        const std::vector<scenes::Override> overrides{{v.key, v.value}, {"frames", std::to_string(limits.frames)}};
        const scenes::SceneDef scene = scenes::load_scene(file, overrides);
        scenes::SceneRun run(scene);
        double energy = run.world().energy();
        while (run.frame() < scene.frames && run.advance()) energy += run.world().energy();
        code = run.verdict().exploded() ? 1 : 0;
        (void)energy;
    } catch (const sim::InputError& e) {
        code = 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "exception: %s\n", e.what());
        code = 3;
    }
    std::fflush(stderr);
    std::_Exit(code);
}

// The last line of what a child wrote to stderr (its memfd).
std::string last_line(int fd) {
    std::string text;
    char buffer[4096];
    const off_t size = lseek(fd, 0, SEEK_END);
    const off_t from = std::max<off_t>(0, size - static_cast<off_t>(sizeof buffer));
    const ssize_t n = pread(fd, buffer, sizeof buffer, from);
    if (n > 0) text.assign(buffer, static_cast<std::size_t>(n));
    while (!text.empty() && text.back() == '\n') text.pop_back();
    if (const auto nl = text.rfind('\n'); nl != std::string::npos) text = text.substr(nl + 1);
    return text;
}

struct Running {
    std::size_t variant;
    int fd;
    std::chrono::steady_clock::time_point start;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: %s SCENE_DIR [--every K] [--jobs J] [--frames N] [--seconds S] [--memory-mb M] "
                     "[--only SCENE]\n",
                     argv[0]);
        return 2;
    }
    const fs::path dir = argv[1];
    if (!fs::is_directory(dir)) {
        std::fprintf(stderr, "mutation_sweep: %s is not a folder of scenes\n", argv[1]);
        return 2;
    }
    std::size_t every = 1, jobs = 1;
    std::string only;
    Limits limits;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string option = argv[i], value = argv[i + 1];
        if (option == "--every")
            every = std::max(1ul, std::stoul(value));
        else if (option == "--jobs")
            jobs = std::max(1ul, std::stoul(value));
        else if (option == "--frames")
            limits.frames = std::stoi(value);
        else if (option == "--seconds")
            limits.seconds = std::stoi(value);
        else if (option == "--memory-mb")
            limits.memory_mb = std::stoul(value);
        else if (option == "--only")
            only = value;
        else {
            std::fprintf(stderr, "mutation_sweep: unknown option %s\n", option.c_str());
            return 2;
        }
    }

    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() == ".toml" && (only.empty() || entry.path().stem() == only))
            files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::fprintf(stderr, "mutation_sweep: no scenes in %s\n", dir.c_str());
        return 2;
    }

    // Every variant in a fixed order: scene, value, mutation.
    std::vector<Variant> all;
    for (std::size_t s = 0; s < files.size(); ++s) {
        const toml::table root = toml::parse_file(files[s].string());
        std::vector<std::pair<std::string, const toml::node*>> leaves;
        walk(root, "", leaves);
        for (const auto& [key, node] : leaves) {
            for (std::size_t m = 0; m < kMutationCount; ++m) all.push_back({s, key, mutated(*node, kMutations[m]), m});
        }
    }
    std::vector<std::size_t> chosen;
    for (std::size_t v = 0; v < all.size(); v += every) chosen.push_back(v);

    const auto t0 = std::chrono::steady_clock::now();
    std::map<pid_t, Running> running;
    std::size_t next = 0, findings = 0;
    std::size_t outcomes[3] = {0, 0, 0};  // ran, exploded, refused
    std::vector<std::size_t> per_scene(files.size()), per_mutation(kMutationCount);
    std::fflush(nullptr);
    while (next < chosen.size() || !running.empty()) {
        while (next < chosen.size() && running.size() < jobs) {
            const std::size_t v = chosen[next++];
            const int fd = memfd_create("mutation_sweep", 0);
            const pid_t pid = fork();
            if (pid < 0) {
                std::perror("mutation_sweep: fork");
                return 2;
            }
            if (pid == 0) {
                const int null = open("/dev/null", O_WRONLY);
                dup2(null, 1);
                dup2(fd, 2);
                run_child(files[all[v].scene], all[v], limits);
            }
            running[pid] = {v, fd, std::chrono::steady_clock::now()};
        }
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) {
            std::perror("mutation_sweep: waitpid");
            return 2;
        }
        const Running r = running.at(pid);
        running.erase(pid);
        const Variant& v = all[r.variant];
        ++per_scene[v.scene];
        ++per_mutation[v.mutation];
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
        std::string what;
        if (WIFEXITED(status) && WEXITSTATUS(status) <= 2) {
            ++outcomes[WEXITSTATUS(status)];
        } else if (WIFSIGNALED(status)) {
            const int sig = WTERMSIG(status);
            what = sig == SIGXCPU || sig == SIGALRM
                       ? "over its time limit (" + std::to_string(limits.seconds) + " s of CPU)"
                       : "killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
        } else {
            what = "exit " + std::to_string(WEXITSTATUS(status));
        }
        if (!what.empty()) {
            ++findings;
            std::printf("FINDING %s --set '%s=%s': %s after %.1f s; stderr: %s\n", files[v.scene].filename().c_str(),
                        v.key.c_str(), v.value.c_str(), what.c_str(), seconds, last_line(r.fd).c_str());
            std::fflush(stdout);
        }
        close(r.fd);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // Coverage: a subset that missed a scene or a mutation says so.
    bool covered = true;
    for (std::size_t s = 0; s < files.size(); ++s) {
        if (per_scene[s] == 0) std::printf("NOT COVERED: scene %s\n", files[s].filename().c_str()), covered = false;
    }
    for (std::size_t m = 0; m < kMutationCount; ++m) {
        if (per_mutation[m] == 0) std::printf("NOT COVERED: mutation %s\n", kMutations[m].name), covered = false;
    }
    std::printf(
        "mutation sweep: %zu of %zu variants (every %zu; %zu scenes, %zu mutations, %d frames each) in %.1f s: "
        "%zu ran, %zu exploded, %zu refused, %zu findings\n",
        chosen.size(), all.size(), every, files.size(), kMutationCount, limits.frames, seconds, outcomes[0],
        outcomes[1], outcomes[2], findings);
    return findings == 0 && covered ? 0 : 1;
}
