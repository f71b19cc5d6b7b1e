// The scene file's sections and the dotted list of every key (see scene_keys.h).
#include "scenes/model/scene_keys.h"

#include <algorithm>

namespace scenes {

const std::vector<keys::SectionKeys>& keys::sections() {
    static const std::vector<SectionKeys> all = {
        {"", {top}},
        {"step", {step}},
        {"particles", {particle}},
        {"groups", {group}},
        {"ropes", {rope}},
        {"cloths", {cloth}},
        {"soft_bodies", {soft_body}},
        {"emitters", {emitter}},
        {"forces", {forces}},
        {"forces.gravity", {gravity}},
        {"forces.drag", {drag}},
        {"forces.quadratic_drag", {drag}},
        {"forces.newton_gravity", {newton_gravity}},
        {"forces.springs", {spring}},
        {"forces.wind", {wind}},
        {"forces.buoyancy", {buoyancy}},
        {"forces.shock_waves", {shock_wave}},
        {"forces.control", {control}},
        {"constraints", {constraints}},
        {"collisions", {collisions}},
        {"colliders", {plane_collider, sphere_collider, box_collider, capsule_collider}},
        {"rigid", {rigid}},
        {"bodies", {body}},
        {"bodies.parts", {body_part}},
        {"ragdolls", {ragdoll}},
        {"chains", {chain}},
        {"joints", {joint}},
        {"watchdog", {watchdog}},
        {"camera", {camera}},
        {"view", {view}},
        {"ghosts", {ghost}},
    };
    return all;
}

std::vector<std::string> scene_keys() {
    const auto& sections = keys::sections();
    auto is_section = [&](const std::string& path) {
        return std::any_of(sections.begin(), sections.end(), [&](const auto& s) { return s.path == path; });
    };
    std::vector<std::string> out;
    for (const keys::SectionKeys& section : sections) {
        for (keys::Table table : section.tables) {
            for (std::string_view key : table) {
                std::string path =
                    section.path.empty() ? std::string(key) : std::string(section.path) + "." + std::string(key);
                if (is_section(path) || std::find(out.begin(), out.end(), path) != out.end()) continue;
                out.push_back(std::move(path));
            }
        }
    }
    return out;
}

}  // namespace scenes
