// The shipped scenes: the ordered catalogue (scenes/catalog.txt), where the
// files live, and resolve_scene, which turns a name or a path into a file.
// Its own file because it reads the catalogue, not a scene.
#include "scenes/model/scene.h"
#include "scenes/model/toml_section.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>

namespace scenes {

std::filesystem::path scenes_dir() {
    const char* env = std::getenv("PLAUSIBLE_SCENES_DIR");
    return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                          : std::filesystem::path(PLAUSIBLE_SOURCE_DIR) / "scenes";
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
                     "; or the path of a .toml file)");
}

}  // namespace scenes
