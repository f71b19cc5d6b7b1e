// What the rope, cloth and soft-body readers share: the keys of a body's links
// and the names and looks of the particles a builder made. Its own file
// because each of those readers has its own.
#include "scenes/model/scene_builder.h"

#include <algorithm>

namespace scenes::loader {

sim::LinkSettings link_keys(const Section& s, double default_stiffness) {
    sim::LinkSettings l;
    l.kind = s.word("link", "springs", {"springs", "constraints"}) == "constraints"
                 ? sim::LinkSettings::Kind::constraints
                 : sim::LinkSettings::Kind::springs;
    l.stiffness = s.number("stiffness", default_stiffness, 0.0, kHuge, "N/m");
    l.damping = s.number("damping", 0.0, 0.0, kHuge, "N·s/m");
    l.compliance = s.number("compliance", 0.0, 0.0, kHuge, "m/N");
    l.tethers = s.boolean("tethers", true);
    return l;
}

void add_body(SceneBuilder& b, const Section& s, BodyLook::Kind kind, const sim::BodyRange& range,
              const std::string& name, Color color, bool nodes_visible, double node_radius) {
    SceneDef& scene = b.scene;
    for (std::uint32_t k = 0; k < range.count; ++k) {
        const std::size_t i = range.first + k;
        const std::string member = name.empty() ? "" : name + "[" + std::to_string(k) + "]";
        b.add_name(s, member, i);
        scene.particle_names.push_back(member);
        ParticleLook look;
        look.radius = std::max(node_radius, 0.005);
        look.color = scene.model.particles[i].pinned ? kPinnedColor : color;
        look.visible = nodes_visible || scene.model.particles[i].pinned;
        scene.looks.push_back(look);
    }
    BodyLook body;
    body.kind = kind;
    body.name = name;
    body.range = range;
    body.color = color;
    body.strain_colors = s.boolean("strain_colors", false);
    scene.bodies.push_back(std::move(body));
}

sim::BodyRange build_body(const Section& s, const std::function<sim::BodyRange()>& build) {
    try {
        return build();
    } catch (const sim::InputError& e) {
        s.reader().fail(&s.table(), s.path() + ": " + e.what());
    }
}

}  // namespace scenes::loader
