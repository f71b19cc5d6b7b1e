// The loader's cloth reader: [[cloths]], a grid of nx by ny particles over the
// parallelogram corner + [0, 1] u + [0, 1] v, with structural, shear and bend
// links (sim::add_cloth builds it). Its nodes are drawn as the cloth's mesh.
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

void read_cloths(SceneBuilder& b, const Section& top) {
    const auto cloths = top.entries("cloths", 1'000);
    for (std::size_t k = 0; k < cloths.size(); ++k) {
        const Section& s = cloths[k];
        s.only(keys::cloth);
        sim::ClothDef d;
        d.corner = s.vec3("corner", d.corner, "m");
        d.u = s.vec3("u", d.u, "m");
        d.v = s.vec3("v", d.v, "m");
        if (d.u.cross(d.v).norm() < 1e-12) s.fail("v", "must be non-zero and not parallel to u");
        d.nx = static_cast<int>(s.integer("nx", d.nx, 2, 1024));
        d.ny = static_cast<int>(s.integer("ny", d.ny, 2, 1024));
        d.mass = s.positive("mass", d.mass, kHuge, "kg");
        d.radius = s.number("radius", d.radius, 0.0, 100.0, "m");
        d.shear = s.number("shear", d.shear, 0.0, 1e6, "(a factor)");
        d.bend = s.number("bend", d.bend, 0.0, 1e6, "(a factor)");
        const std::string pins = s.word("pins", "corners", {"none", "corners", "edge", "all"});
        d.pins = pins == "none"   ? sim::ClothDef::Pins::none
                 : pins == "edge" ? sim::ClothDef::Pins::edge
                 : pins == "all"  ? sim::ClothDef::Pins::all
                                  : sim::ClothDef::Pins::corners;
        d.links = link_keys(s, 1000.0);
        const Color color = s.color("color", Color{0.75f, 0.2f, 0.2f, 1});
        // sim::add_cloth's links: structural, two shear a cell, bend two apart.
        const std::size_t nx = static_cast<std::size_t>(d.nx), ny = static_cast<std::size_t>(d.ny);
        refuse_links_ahead(b, s,
                           (nx - 1) * ny + nx * (ny - 1) + (d.shear > 0.0 ? 2 * (nx - 1) * (ny - 1) : 0) +
                               (d.bend > 0.0 ? (nx - 2) * ny + nx * (ny - 2) : 0),
                           nx * ny);
        const auto range = build_body(s, [&] { return sim::add_cloth(b.scene.model, d); });
        add_body(b, s, BodyLook::Kind::cloth, range, s.string("name", "cloth" + std::to_string(k), 64), color, false,
                 d.radius);
    }
}

}  // namespace scenes::loader
