// The loader's reader of what keeps particles apart and in place:
// [constraints] (the solver's sweeps), [collisions] (restitution, friction,
// particle-particle) and [[colliders]], static shapes for particles and rigid
// bodies alike.
#include "scenes/model/scene_builder.h"

namespace scenes::loader {
namespace {

// One collider; its keys depend on its shape.
sim::Collider read_collider(const Section& s, const std::string& shape) {
    if (shape == "plane") {
        s.only(keys::plane_collider);
        const sim::Vec3 n = s.direction("normal", sim::Vec3::UnitY());
        return sim::PlaneCollider{n, s.number("offset", 0.0, -1e6, 1e6, "m")};
    }
    if (shape == "sphere") {
        s.only(keys::sphere_collider);
        return sim::SphereCollider{s.vec3("center", sim::Vec3::Zero(), "m"), s.positive("radius", 1.0, 1e6, "m")};
    }
    if (shape == "box") {
        s.only(keys::box_collider);
        sim::BoxCollider b;
        b.center = s.vec3("center", b.center, "m");
        b.half_extents = s.lengths("half_extents", b.half_extents, "must be three lengths > 0, in m");
        b.rotation = s.rotation().toRotationMatrix();
        return b;
    }
    s.only(keys::capsule_collider);
    return sim::CapsuleCollider{s.vec3("a", sim::Vec3::Zero(), "m"), s.vec3("b", sim::Vec3::UnitY(), "m"),
                                s.positive("radius", 0.25, 1e6, "m")};
}

}  // namespace

void read_constraints(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("constraints");
    if (t == nullptr) return;
    const Section s(b.r, *t, "constraints");
    s.only(keys::constraints);
    b.scene.model.constraints.iterations = static_cast<int>(s.integer("iterations", 1, 1, 1000));
}

void read_collisions(SceneBuilder& b, const Section& top) {
    sim::Collisions& c = b.scene.model.collisions;
    if (const toml::table* t = top.subtable("collisions")) {
        const Section s(b.r, *t, "collisions");
        s.only(keys::collisions);
        c.restitution = s.number("restitution", c.restitution, 0.0, 1.0, "(0 .. 1)");
        c.friction = s.number("friction", c.friction, 0.0, 100.0, "(Coulomb μ)");
        c.rest_speed = s.number("rest_speed", c.rest_speed, 0.0, kHuge, "m/s");
        c.particle_particle = s.boolean("particles", false);
    }
    for (const Section& s : top.entries("colliders", 10'000)) {
        const std::string shape = s.word("shape", "", {"plane", "sphere", "box", "capsule"});
        Color color = s.color("color", Color{0.6f, 0.62f, 0.66f, 1});
        color.a = s.boolean("visible", true) ? 1.0f : 0.0f;  // planes at the ground are not drawn twice
        c.colliders.push_back(read_collider(s, shape));
        b.scene.collider_colors.push_back(color);
    }
}

}  // namespace scenes::loader
