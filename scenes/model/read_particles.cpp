// The loader's particle reader: [[particles]], one particle each, and
// [[groups]], a row of like particles. Its own file because every other
// particle body (rope, cloth, soft body, emitter) comes from a builder and has
// a reader of its own.
#include "scenes/model/scene_builder.h"

namespace scenes::loader {
namespace {

// The keys a particle and a group share: velocity, mass, pinned, radius, color.
void particle_keys(const Section& s, sim::ParticleDef& p, ParticleLook& look, std::size_t index) {
    p.velocity = s.vec3("velocity", sim::Vec3::Zero(), "m/s");
    p.mass = s.positive("mass", 1.0, kHuge, "kg");
    p.pinned = s.boolean("pinned", false);
    if (p.pinned) p.velocity.setZero();
    look.radius = s.positive("radius", 0.1, 100.0, "m");
    p.radius = look.radius;  // what you see is what collides
    look.color = s.color("color", p.pinned ? kPinnedColor : palette(index));
}

void add_particle(SceneBuilder& b, const sim::ParticleDef& p, const ParticleLook& look, const std::string& name) {
    b.scene.model.particles.push_back(p);
    b.scene.looks.push_back(look);
    b.scene.particle_names.push_back(name);
}

void read_single_particles(SceneBuilder& b, const Section& top) {
    for (const Section& s : top.entries("particles", kMaxParticles)) {
        const std::size_t i = b.scene.model.particles.size();
        s.only(keys::particle);
        sim::ParticleDef p;
        ParticleLook look;
        if (s.node("position") == nullptr)
            b.r.fail(&s.table(), s.key_path("position") + " is required: [x, y, z] in m");
        p.position = s.vec3("position", sim::Vec3::Zero(), "m");
        particle_keys(s, p, look, i);
        const std::string name = s.string("name", "", 64);
        b.add_name(s, name, i);
        add_particle(b, p, look, name);
    }
}

// A group's particles are named "<name>[k]" and placed at start + k * spacing.
void read_groups(SceneBuilder& b, const Section& top) {
    for (const Section& s : top.entries("groups", 10'000)) {
        s.only(keys::group);
        const std::size_t count = b.new_particles(s, 1);
        const sim::Vec3 start = s.vec3("start", sim::Vec3::Zero(), "m");
        const sim::Vec3 spacing = s.vec3("spacing", sim::Vec3(0.5, 0, 0), "m");
        const std::string name = s.string("name", "", 64);
        sim::ParticleDef p;
        ParticleLook look;
        particle_keys(s, p, look, b.scene.model.particles.size());
        for (std::size_t k = 0; k < count; ++k) {
            p.position = start + static_cast<double>(k) * spacing;
            const std::string member = name.empty() ? "" : name + "[" + std::to_string(k) + "]";
            b.add_name(s, member, b.scene.model.particles.size());
            add_particle(b, p, look, member);
        }
    }
}

}  // namespace

void read_particles(SceneBuilder& b, const Section& top) {
    read_single_particles(b, top);
    read_groups(b, top);
}

}  // namespace scenes::loader
