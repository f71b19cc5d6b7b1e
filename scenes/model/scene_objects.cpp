// The named objects of a scene (scene.h, SceneObject): what `check` names
// when a state hash differs. Derived from what the loader recorded: the
// bodies' particle ranges, the emitters' ranges and the particles' names,
// the rigid bodies' names and groups.
#include "scenes/model/scene.h"

#include <string_view>

namespace scenes {
namespace {

// "name[3]" -> "name", the group a member of a named group belongs to; a
// plain name is its own.
std::string_view group_of(std::string_view particle_name) {
    const std::size_t bracket = particle_name.rfind('[');
    if (bracket == std::string_view::npos || bracket == 0 || particle_name.back() != ']') return particle_name;
    return particle_name.substr(0, bracket);
}

}  // namespace

std::vector<SceneObject> scene_objects(const SceneDef& scene) {
    std::vector<SceneObject> objects;
    const std::size_t n = scene.model.particles.size();
    std::vector<bool> taken(n, false);
    auto take = [&](std::size_t first, std::size_t count) {
        for (std::size_t i = first; i < first + count && i < n; ++i) taken[i] = true;
    };
    for (const BodyLook& body : scene.bodies) {
        objects.push_back({.name = body.name, .first = body.range.first, .count = body.range.count});
        take(body.range.first, body.range.count);
    }
    for (const sim::Emitter& e : scene.model.emitters) {
        const std::string& member = e.first < scene.particle_names.size() ? scene.particle_names[e.first] : "";
        objects.push_back({.name = std::string(group_of(member)), .first = e.first, .count = e.count});
        take(e.first, e.count);
    }
    // Named particles outside those; a run of one group's members
    // ("drops[0]", "drops[1]", ...) is one object, the group.
    const std::vector<std::string>& names = scene.particle_names;
    auto member = [&](std::size_t i) { return group_of(names[i]) != names[i]; };
    for (std::size_t i = 0; i < names.size() && i < n;) {
        if (taken[i] || names[i].empty()) {
            ++i;
            continue;
        }
        const std::string_view group = group_of(names[i]);
        std::size_t end = i + 1;
        if (member(i)) {
            while (end < names.size() && end < n && !taken[end] && member(end) && group_of(names[end]) == group) ++end;
        }
        objects.push_back({.name = std::string(group), .first = i, .count = end - i});
        i = end;
    }
    for (std::size_t b = 0; b < scene.body_names.size(); ++b) {
        objects.push_back({.name = scene.body_names[b],
                           .group = b < scene.body_groups.size() ? scene.body_groups[b] : "",
                           .rigid = true,
                           .first = b,
                           .count = 1});
    }
    return objects;
}

}  // namespace scenes
