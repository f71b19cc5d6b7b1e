// The shipped scenes: the ordered catalogue (scenes/catalog.txt), where the
// files live (data_dir: the source tree or the installed share/plausible),
// and resolve_scene, which turns a name or a path into a file.
// Its own file because it reads the catalogue, not a scene.
#include "scenes/model/scene.h"
#include "scenes/model/toml_section.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>

namespace scenes {

namespace fs = std::filesystem;

namespace {

// Whether `path` lies inside `dir` (both absolute).
bool is_within(const fs::path& path, const fs::path& dir) {
    const fs::path rel = path.lexically_relative(dir);
    return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

// One decision, by where the running executable is (/proc/self/exe, links
// resolved): inside the build tree it was built in, the source tree it was
// built from (so that an edited scene or a re-blessed golden is seen without
// installing); anywhere else, the installed layout beside it
// (<prefix>/bin/plausible -> <prefix>/share/plausible). An installed or
// copied command never falls back to the source tree: it may be gone, or a
// different version.
fs::path data_dir() {
    std::error_code error;
    const fs::path exe = fs::read_symlink("/proc/self/exe", error);
    if (error) throw SceneError("cannot tell where this executable is (/proc/self/exe: " + error.message() + ")");
    const bool in_build_tree = is_within(exe, fs::weakly_canonical(PLAUSIBLE_BINARY_DIR, error));
    const fs::path dir = in_build_tree ? fs::path(PLAUSIBLE_SOURCE_DIR)
                                       : (exe.parent_path() / PLAUSIBLE_DATA_FROM_BIN).lexically_normal();
    if (!fs::exists(dir / "scenes" / "catalog.txt")) {
        throw SceneError("the shipped scenes and goldens are not where " + exe.string() + " looks for them: no " +
                         (dir / "scenes" / "catalog.txt").string() +
                         (in_build_tree ? " (the source tree this build was made from)"
                                        : " (install with `cmake --install BUILD --prefix PREFIX`, which puts them "
                                          "there)") +
                         "; PLAUSIBLE_SCENES_DIR=DIR reads scenes from DIR instead, check --golden DIR goldens");
    }
    return dir;
}

fs::path scenes_dir() {
    const char* env = std::getenv("PLAUSIBLE_SCENES_DIR");
    return env != nullptr && *env != '\0' ? fs::path(env) : data_dir() / "scenes";
}

std::vector<std::string> catalog() {
    std::vector<std::string> names;
    std::ifstream in(scenes_dir() / "catalog.txt");
    if (!in) throw SceneError((scenes_dir() / "catalog.txt").string() + ": the scene catalogue cannot be read");
    std::string line;
    while (std::getline(in, line)) {
        line = line.substr(0, line.find('#'));
        line.erase(0, line.find_first_not_of(" \t"));
        line.erase(line.find_last_not_of(" \t\r") + 1);
        if (!line.empty()) names.push_back(line);
    }
    return names;
}

std::filesystem::path resolve_scene(const std::string& name_or_path) {
    const auto names = catalog();
    if (std::find(names.begin(), names.end(), name_or_path) != names.end()) {
        return scenes_dir() / (name_or_path + ".toml");
    }
    if (name_or_path.ends_with(".toml")) {
        if (!std::filesystem::exists(name_or_path)) throw SceneError(name_or_path + ": no such scene file");
        return name_or_path;
    }
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw SceneError("unknown scene " + loader::quote(name_or_path) + " (scenes: " + list +
                     "; or the path of a .toml file, or of a recording)");
}

}  // namespace scenes
