// What the rope, cloth and soft-body readers share: the keys of a body's links
// and the names and looks of the particles a builder made. Its own file
// because each of those readers has its own.
#include "scenes/model/scene_builder.h"

#include <algorithm>
#include <cmath>

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

namespace {

// What a link costs to hold, bytes, with its share of the nodes (a cloth has
// six links a node with shear and bend): a 300² cloth (537,000 links) runs in
// 243 MB, a 600² one (2.15 million) in 804 MB: 350 bytes a link more. A
// 1000² cloth, 6 million links, took 2.1 GB.
constexpr double kLinkBytes = 350.0;

// Every link in the scene so far: springs, distance constraints and tethers.
std::size_t links_in(const sim::ParticleModel& model) {
    std::size_t links = model.constraints.distance.size() + model.constraints.tethers.size();
    for (const sim::ForceDef& f : model.forces) {
        if (const auto* springs = std::get_if<sim::Springs>(&f)) links += springs->list.size();
    }
    return links;
}

// A body's links grow with its nodes times the neighbours each is linked to
// (a cloth with shear and bend: 6 a node; a soft body: 13), so a file of a
// few lines can ask for more than [[forces.springs]] may list: the same
// limit for all of them together.
void refuse_links(const Section& s, const std::string& verb, std::size_t body_links, std::size_t nodes,
                  std::size_t links) {
    if (links <= kMaxSprings) return;
    s.reader().fail(&s.table(), s.path() + " " + verb + " " + std::to_string(body_links) + " links on " +
                                    std::to_string(nodes) + " nodes, " + std::to_string(links) +
                                    " in the scene with the bodies before it (springs, constraints and tethers), "
                                    "about " +
                                    sim::format_value(std::round(links * kLinkBytes / 1e8) / 10.0) + " GB at " +
                                    sim::format_value(kLinkBytes) + " bytes a link; at most " +
                                    std::to_string(kMaxSprings) +
                                    " links in a scene, so that a run cannot run out of memory: fewer nodes, or "
                                    "fewer links a node (a cloth's shear and bend)");
}

}  // namespace

void refuse_links_ahead(const SceneBuilder& b, const Section& s, std::size_t body_links, std::size_t nodes) {
    refuse_links(s, "would make", body_links, nodes, links_in(b.scene.model) + body_links);
}

void add_body(SceneBuilder& b, const Section& s, BodyLook::Kind kind, const sim::BodyRange& range,
              const std::string& name, Color color, bool nodes_visible, double node_radius) {
    refuse_links(s, "makes", range.links.size(), range.count, links_in(b.scene.model));  // tethers included
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
