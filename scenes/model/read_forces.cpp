// The loader's force reader: [forces] and its sub-tables, each a force
// generator of the physics core: gravity, drags, Newtonian gravity, springs
// (drawn as rods), wind, buoyancy, shock waves and keyed control forces.
// Their order in model.forces is the order below, whatever the file's.
#include "scenes/model/scene_builder.h"

#include <algorithm>

namespace scenes::loader {
namespace {

void read_gravity_and_drag(SceneBuilder& b, const Section& f) {
    std::vector<sim::ForceDef>& forces = b.scene.model.forces;
    if (const toml::table* t = f.subtable("gravity")) {
        const Section s(b.r, *t, "forces.gravity");
        s.only(keys::gravity);
        forces.push_back(sim::UniformGravity{s.vec3("g", sim::Vec3(0, -9.81, 0), "m/s²", 1e6)});
    }
    if (const toml::table* t = f.subtable("drag")) {
        const Section s(b.r, *t, "forces.drag");
        s.only(keys::drag);
        forces.push_back(sim::LinearDrag{s.number("c", 0.1, 0.0, kHuge, "N·s/m")});
    }
    if (const toml::table* t = f.subtable("quadratic_drag")) {
        const Section s(b.r, *t, "forces.quadratic_drag");
        s.only(keys::drag);
        forces.push_back(sim::QuadraticDrag{s.number("c", 0.01, 0.0, kHuge, "N·s²/m²")});
    }
    if (const toml::table* t = f.subtable("newton_gravity")) {
        const Section s(b.r, *t, "forces.newton_gravity");
        s.only(keys::newton_gravity);
        forces.push_back(sim::NewtonGravity{s.positive("G", 6.674e-11, kHuge, "m³/(kg·s²)"),
                                            s.number("softening", 0.0, 0.0, kHuge, "m")});
    }
}

// All [[forces.springs]] make one Springs force; its rest length defaults to the initial distance.
void read_springs(SceneBuilder& b, const Section& f) {
    const auto springs = f.entries("springs", kMaxSprings);
    if (springs.empty()) return;
    const std::vector<sim::ParticleDef>& particles = b.scene.model.particles;
    sim::Springs list;
    for (const Section& s : springs) {
        s.only(keys::spring);
        sim::Spring spring;
        const std::size_t pa = b.particle_ref(s, "a"), pb = b.particle_ref(s, "b");
        if (pa == pb) s.fail("b", "must be another particle than a (both are particle " + std::to_string(pa) + ")");
        spring.i = static_cast<std::uint32_t>(pa);
        spring.j = static_cast<std::uint32_t>(pb);
        const double initial = (particles[pa].position - particles[pb].position).norm();
        spring.rest = s.number("rest_length", initial, 0.0, kHuge, "m");
        spring.k = s.number("stiffness", 100.0, 0.0, kHuge, "N/m");
        spring.c = s.number("damping", 0.0, 0.0, kHuge, "N·s/m");
        list.list.push_back(spring);
    }
    b.scene.drawn_springs.push_back(b.scene.model.forces.size());
    b.scene.model.forces.push_back(std::move(list));
}

// The wind pushes on particles (as spheres of `radius`) and on the surface
// triangles of the cloths and soft bodies it names.
void read_wind(SceneBuilder& b, const Section& f) {
    const toml::table* t = f.subtable("wind");
    if (t == nullptr) return;
    const Section s(b.r, *t, "forces.wind");
    s.only(keys::wind);
    sim::Wind w;
    w.velocity = s.vec3("velocity", w.velocity, "m/s");
    w.air_density = s.number("air_density", w.air_density, 0.0, 1e5, "kg/m³");
    w.drag_coefficient = s.number("drag_coefficient", w.drag_coefficient, 0.0, 100.0, "(C_d)");
    w.gust_strength = s.number("gust_strength", w.gust_strength, 0.0, 1e4, "m/s");
    // Gusts faster than a millisecond are noise no step resolves (and a
    // period of 1e-300 s put t / period beyond any gust index).
    w.gust_period = s.number("gust_period", w.gust_period, 1e-3, 1e6, "s");
    w.seed = s.seed("seed");
    w.radius = s.number("radius", w.radius, 0.0, 100.0, "m");
    w.particles = b.particle_list(s, "particles");
    if (const toml::node* n = s.node("bodies")) {
        const toml::array* a = n->as_array();
        if (a == nullptr) s.fail("bodies", "must be an array of cloth or soft-body names");
        for (std::size_t k = 0; k < a->size(); ++k) {
            const auto name = a->get(k)->value<std::string>();
            const auto body = std::find_if(b.scene.bodies.begin(), b.scene.bodies.end(), [&](const BodyLook& look) {
                return name && look.name == *name && !look.range.surface.empty();
            });
            if (body == b.scene.bodies.end()) {
                b.r.fail(a->get(k), "forces.wind.bodies[" + std::to_string(k) + "] names no cloth or soft body (got " +
                                        describe(*a->get(k)) + ")");
            }
            for (const auto& tri : body->range.surface) w.triangles.push_back(tri);
        }
    }
    b.scene.model.forces.push_back(std::move(w));
}

// Buoyancy takes its g from [forces.gravity] (read before it) and shows the water.
void read_buoyancy(SceneBuilder& b, const Section& f) {
    const sim::UniformGravity* gravity_force = b.find_force<sim::UniformGravity>();
    const double g = gravity_force != nullptr ? gravity_force->g.norm() : 0.0;  // m/s² (a copy: forces grow below)
    for (const Section& s : f.entries("buoyancy", 64)) {
        s.only(keys::buoyancy);
        sim::Buoyancy by;
        by.surface_height = s.number("surface_height", by.surface_height, -1e5, 1e5, "m");
        by.fluid_density = s.positive("fluid_density", by.fluid_density, 1e6, "kg/m³");
        by.radius = s.positive("radius", by.radius, 100.0, "m");
        by.drag = s.number("drag", by.drag, 0.0, kHuge, "N·s/m");
        by.particles = b.particle_list(s, "particles");
        if (g == 0.0) s.fail("surface_height", "needs [forces.gravity]: buoyancy is the weight of the water displaced");
        by.gravity = g;
        b.scene.view.water = true;
        b.scene.view.water_height = by.surface_height;
        b.scene.model.forces.push_back(std::move(by));
    }
}

void read_shock_waves(SceneBuilder& b, const Section& f) {
    for (const Section& s : f.entries("shock_waves", 64)) {
        s.only(keys::shock_wave);
        sim::ShockWave w;
        w.center = s.vec3("center", w.center, "m");
        w.start_time = s.number("start_time", w.start_time, 0.0, 1e6, "s");
        w.speed = s.positive("speed", w.speed, 1e5, "m/s");
        w.thickness = s.positive("thickness", w.thickness, 1e4, "m");
        w.strength = s.number("strength", w.strength, 0.0, kHuge, "N");
        w.reference_distance = s.positive("reference_distance", w.reference_distance, 1e4, "m");
        w.max_radius = s.number("max_radius", w.max_radius, 0.0, 1e6, "m");
        b.scene.model.forces.push_back(w);
    }
}

// All [[forces.control]] keys make one ControlForces force.
void read_control(SceneBuilder& b, const Section& f) {
    const auto entries = f.entries("control", 10'000);
    if (entries.empty()) return;
    sim::ControlForces c;
    for (const Section& s : entries) {
        s.only(keys::control);
        sim::ControlKey key;
        key.start = s.number("start", 0.0, 0.0, 1e6, "s");
        key.end = s.number("end", key.start + 1.0, 0.0, 1e6, "s");
        if (!(key.end > key.start)) s.fail("end", "must be after start (got " + sim::format_value(key.end) + ")");
        key.particles = b.particle_list(s, "particles");
        if (key.particles.empty()) s.fail("particles", "is required: the particles the key pushes");
        key.force = s.vec3("force", sim::Vec3::Zero(), "N");
        c.keys.push_back(std::move(key));
    }
    b.scene.model.forces.push_back(std::move(c));
}

}  // namespace

void read_forces(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("forces");
    if (t == nullptr) return;
    const Section f(b.r, *t, "forces");
    f.only(keys::forces);
    read_gravity_and_drag(b, f);
    read_springs(b, f);
    read_wind(b, f);
    read_buoyancy(b, f);
    read_shock_waves(b, f);
    read_control(b, f);
}

}  // namespace scenes::loader
