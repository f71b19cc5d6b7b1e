// The loader's rope reader: [[ropes]], a line of particles from start to end
// joined by springs or constraints (sim::add_rope builds it).
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

void read_ropes(SceneBuilder& b, const Section& top) {
    const auto ropes = top.entries("ropes", 10'000);
    for (std::size_t k = 0; k < ropes.size(); ++k) {
        const Section& s = ropes[k];
        s.only(keys::rope);
        sim::RopeDef d;
        d.start = s.vec3("start", d.start, "m");
        d.end = s.vec3("end", d.end, "m");
        if ((d.end - d.start).norm() == 0.0) s.fail("end", "must differ from start");
        d.segments = static_cast<int>(s.integer("segments", d.segments, 1, 4096));
        d.mass = s.positive("mass", d.mass, kHuge, "kg");
        d.radius = s.positive("radius", d.radius, 100.0, "m");
        d.pin_start = s.boolean("pin_start", d.pin_start);
        d.pin_end = s.boolean("pin_end", d.pin_end);
        d.links = link_keys(s, 1000.0);
        const Color color = s.color("color", palette(b.scene.bodies.size()));
        const auto range = build_body(s, [&] { return sim::add_rope(b.scene.model, d); });
        const std::string name = s.string("name", "rope" + std::to_string(k), 64);
        add_body(b, s, BodyLook::Kind::rope, range, name, color, true, d.radius);
        // An explosion of this rope freezes it and the run goes on.
        if (s.boolean("contain_explosion", false)) {
            b.scene.watchdog.contain.push_back({name, range.first, range.count});
            b.contained_ropes.push_back(s);
        }
    }
}

}  // namespace scenes::loader
