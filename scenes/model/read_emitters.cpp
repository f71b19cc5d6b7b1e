// The loader's emitter reader: [[emitters]], a fountain of `count` particles
// born at `rate` per second into a cone (sim::Emitter). Every particle exists
// from the start, parked and pinned until it is born, so the arrays never grow.
#include "scenes/model/scene_builder.h"

namespace scenes::loader {

void read_emitters(SceneBuilder& b, const Section& top) {
    SceneDef& scene = b.scene;
    const auto emitters = top.entries("emitters", 100);
    for (std::size_t k = 0; k < emitters.size(); ++k) {
        const Section& s = emitters[k];
        s.only(keys::emitter);
        sim::Emitter e;
        const std::size_t count = b.new_particles(s, 1000);
        e.first = static_cast<std::uint32_t>(scene.model.particles.size());
        e.count = static_cast<std::uint32_t>(count);
        e.position = s.vec3("position", e.position, "m");
        e.direction = s.direction("direction", e.direction);
        e.cone = s.number("cone", e.cone, 0.0, 180.0, "degrees");
        e.speed = s.positive("speed", e.speed, 1e4, "m/s");
        e.speed_jitter = s.number("speed_jitter", e.speed_jitter, 0.0, 1.0, "(a fraction)");
        e.rate = s.positive("rate", e.rate, 1e7, "particles/s");
        e.seed = s.seed("seed");
        sim::ParticleDef p;
        p.mass = s.positive("mass", 0.01, kHuge, "kg");
        p.radius = s.positive("radius", 0.02, 100.0, "m");
        p.pinned = true;  // parked until born
        p.position = sim::parked_position(e);
        ParticleLook look;
        look.radius = p.radius;
        look.color = s.color("color", Color{0.25f, 0.55f, 0.95f, 1});
        const std::string name = s.string("name", "emitter" + std::to_string(k), 64);
        for (std::uint32_t i = 0; i < e.count; ++i) {
            const std::string member = name + "[" + std::to_string(i) + "]";
            b.add_name(s, member, scene.model.particles.size());
            scene.particle_names.push_back(member);
            scene.model.particles.push_back(p);
            scene.looks.push_back(look);
        }
        scene.model.emitters.push_back(e);
    }
}

}  // namespace scenes::loader
