// scene_parameters: the numbers of a scene file a person may want to turn
// (the viewer's sliders), as --set keys. Its own file because it reads the
// file's TOML tree as it is, not the scene the readers built.
#include "scenes/model/scene.h"

#include <toml++/toml.h>

#include <cstdlib>

namespace scenes {
namespace {

// Numeric leaves under `node`, depth first in file order, as --set keys.
void collect_parameters(const toml::node& node, const std::string& key, std::vector<Parameter>& out) {
    if (const toml::table* t = node.as_table()) {
        for (const auto& [k, v] : *t)
            collect_parameters(v, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), out);
    } else if (const toml::array* a = node.as_array()) {
        // Arrays of tables ([[forces.springs]]) are walked; arrays of numbers are vectors, not sliders.
        for (std::size_t i = 0; i < a->size(); ++i) {
            if ((*a)[i].is_table()) collect_parameters((*a)[i], key + "[" + std::to_string(i) + "]", out);
        }
    } else if (const auto* f = node.as_floating_point()) {
        out.push_back({key, f->get(), false});
    } else if (const auto* n = node.as_integer()) {
        out.push_back({key, static_cast<double>(n->get()), true});
    }
}

// Pictures, timing and the watchdog are not physics parameters; step settings have their own controls.
bool is_physics(const Parameter& p) {
    const std::string head = p.key.substr(0, p.key.find_first_of(".["));
    return !(head == "camera" || head == "view" || head == "step" || head == "watchdog" || head == "frames" ||
             head == "checkpoints" || p.key.find("color") != std::string::npos ||
             p.key.find("seed") != std::string::npos);
}

}  // namespace

std::vector<Parameter> scene_parameters(const SceneDef& scene, const std::vector<Override>& overrides) {
    toml::table root;
    try {
        root = toml::parse_file(scene.file.string());
    } catch (const toml::parse_error&) {
        return {};  // the scene loaded from this file once; a file edited since is simply not offered
    }
    std::vector<Parameter> all, out;
    collect_parameters(root, "", all);
    for (const Parameter& p : all) {
        if (is_physics(p)) out.push_back(p);
    }
    // The values this run uses: the last --set of a key wins, as in the loader.
    for (const Override& o : overrides) {
        for (Parameter& p : out) {
            if (p.key != o.key) continue;
            char* end = nullptr;
            const double v = std::strtod(o.value.c_str(), &end);
            if (end != o.value.c_str() && *end == '\0') p.value = v;
        }
    }
    return out;
}

}  // namespace scenes
