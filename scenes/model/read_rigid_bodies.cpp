// The loader's rigid-body reader: [[bodies]] (one shape, or a compound of
// parts) and [rigid], the ODE world's settings. A scene without them makes no
// ODE world. Ragdolls and joints have their own readers.
#include "scenes/model/scene_builder.h"

#include <cstdio>
#include <numbers>

namespace scenes::loader {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

sim::RigidShape shape_of(const Section& s) {
    const std::string shape = s.word("shape", "box", {"box", "sphere", "capsule", "cylinder"});
    return shape == "sphere"     ? sim::RigidShape::sphere
           : shape == "capsule"  ? sim::RigidShape::capsule
           : shape == "cylinder" ? sim::RigidShape::cylinder
                                 : sim::RigidShape::box;
}

// A box's three extents; a sphere's radius; a capsule's or cylinder's radius
// and length: each within what ODE takes (sim::kMinBodySize .. kMaxBodySize).
sim::Vec3 size_of(const Section& s, sim::RigidShape shape, const sim::Vec3& fallback) {
    const sim::Vec3 size = s.vec3("size", fallback, "m");
    const int used = shape == sim::RigidShape::box ? 3 : shape == sim::RigidShape::sphere ? 1 : 2;
    for (int a = 0; a < used; ++a) {
        if (!(size[a] >= sim::kMinBodySize && size[a] <= sim::kMaxBodySize)) {
            s.fail("size", "needs its first " + std::to_string(used) + " entries within " +
                               sim::format_value(sim::kMinBodySize) + " .. " + sim::format_value(sim::kMaxBodySize) +
                               ", in m (got " + sim::format_value(size[a]) + ")");
        }
    }
    return size;
}

// A compound body's parts (they replace shape and size).
void read_parts(const Section& s, sim::BodyDef& b) {
    const auto parts = s.entries("parts", 64);
    if (!parts.empty() && (s.node("shape") != nullptr || s.node("size") != nullptr))
        s.fail("parts", "replace shape and size: give one or the other");
    for (const Section& ps : parts) {
        ps.only(keys::body_part);
        sim::BodyPart part;
        part.shape = shape_of(ps);
        part.size = size_of(ps, part.shape, part.size);
        part.offset = ps.vec3("offset", part.offset, "m", sim::kMaxBodySize);
        part.orientation = ps.rotation();
        part.density = ps.positive("density", part.density, kHuge, "kg/m³");
        b.parts.push_back(part);
    }
}

sim::BodyDef read_body(const Section& s) {
    s.only(keys::body);
    sim::BodyDef b;
    read_parts(s, b);
    b.shape = shape_of(s);
    if (b.parts.empty()) b.size = size_of(s, b.shape, b.size);
    if (s.node("mass") != nullptr && s.node("density") != nullptr) s.fail("density", "and mass cannot both be given");
    b.mass = s.node("density") != nullptr ? 0.0 : s.number("mass", 1.0, sim::kMinBodyMass, sim::kMaxBodyMass, "kg");
    b.density = s.positive("density", b.density, kHuge, "kg/m³");
    b.position = s.vec3("position", b.position, "m", sim::kMaxBodyReach);
    b.orientation = s.rotation();
    b.velocity = s.vec3("velocity", b.velocity, "m/s");
    b.angular_velocity = s.vec3("angular_velocity", sim::Vec3::Zero(), "deg/s", kMaxSpinDegrees) * kDeg;
    b.com = s.vec3("com", b.com, "m", sim::kMaxBodySize);
    if (b.mass == 0.0) {  // the densities' mass (the parts' own, for a compound), within what ODE takes
        const double mass = sim::mass_of(b);
        if (!(mass >= sim::kMinBodyMass && mass <= sim::kMaxBodyMass)) {
            char text[32];
            std::snprintf(text, sizeof text, "%.3g", mass);
            s.fail(b.parts.empty() ? "density" : "parts", std::string(b.parts.empty() ? "gives" : "give") +
                                                              " a mass of " + text + " kg; a body's must be within " +
                                                              sim::format_value(sim::kMinBodyMass) + " .. " +
                                                              sim::format_value(sim::kMaxBodyMass) + " kg");
        }
    }
    return b;
}

}  // namespace

void read_rigid_bodies(SceneBuilder& b, const Section& top) {
    const auto bodies = top.entries("bodies", 10'000);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        const Section& s = bodies[k];
        const sim::BodyDef body = read_body(s);
        const std::string name = s.string("name", "body" + std::to_string(k), 64);
        if (!b.body_index.emplace(name, static_cast<int>(k)).second)
            s.fail("name", "must be unique: " + quote(name) + " is taken");
        b.scene.model.rigid.bodies.push_back(body);
        b.scene.body_names.push_back(name);
        b.scene.body_groups.emplace_back();
        b.scene.body_colors.push_back(s.color("color", palette(k + 2)));
    }
}

void read_rigid_settings(SceneBuilder& b, const Section& top) {
    const toml::table* t = top.subtable("rigid");
    if (t == nullptr) return;
    const Section s(b.r, *t, "rigid");
    s.only(keys::rigid);
    sim::RigidSettings& rs = b.scene.model.rigid.settings;
    rs.quickstep = s.boolean("quickstep", rs.quickstep);
    rs.iterations = static_cast<int>(s.integer("iterations", rs.iterations, 1, 10'000));
    rs.friction = s.number("friction", rs.friction, 0.0, 1e6, "(Coulomb μ)");
    rs.restitution = s.number("restitution", rs.restitution, 0.0, 1.0, "(0 .. 1)");
    rs.bounce_velocity = s.number("bounce_velocity", rs.bounce_velocity, 0.0, kHuge, "m/s");
    rs.joint_erp = s.number("joint_erp", rs.joint_erp, 0.0, 1.0, "(0 .. 1)");
    rs.joint_cfm = s.number("joint_cfm", rs.joint_cfm, 0.0, kHuge, "(ODE's CFM)");
    rs.contact_erp = s.number("contact_erp", rs.contact_erp, 0.0, 1.0, "(0 .. 1)");
    rs.contact_cfm = s.number("contact_cfm", rs.contact_cfm, 0.0, kHuge, "(ODE's CFM)");
    rs.gravity = s.vec3("gravity", rs.gravity, "m/s²");
    rs.ground = s.boolean("ground", rs.ground);
    rs.ground_height = s.number("ground_height", rs.ground_height, -1e5, 1e5, "m");
    rs.seed = s.seed("seed");
    rs.sleep = s.boolean("sleep", rs.sleep);
    rs.sleep_speed = s.positive("sleep_speed", rs.sleep_speed, kHuge, "m/s");
    // A rest of more than 11.6 days before sleeping means never, which
    // `sleep = false` says (1e300 s once overflowed the sleep counter and put
    // every body to sleep at its first step): refused, naming that key.
    rs.sleep_time = s.positive("sleep_time", rs.sleep_time, kHuge, "s");
    if (rs.sleep_time > kMaxSleepTime) {
        s.fail("sleep_time", "must be > 0 and at most " + sim::format_value(kMaxSleepTime) +
                                 ", in s (11.6 days; a longer rest means never: say sleep = false) (got " +
                                 sim::format_value(rs.sleep_time) + ")");
    }
    rs.self_collision = s.boolean("self_collision", rs.self_collision);
    rs.articulated = s.boolean("articulated", rs.articulated);
    rs.speculative_stops = s.boolean("speculative_stops", rs.speculative_stops);
    rs.position_iterations = static_cast<int>(s.integer("position_iterations", rs.position_iterations, 0, 100));
    rs.position_slop = s.number("position_slop", rs.position_slop, 0.0, 1.0, "m");
}

void refuse_rigid_step_too_small(SceneBuilder& b, const Section& top) {
    const sim::StepSettings& step = b.scene.step;
    const toml::table* t = top.subtable("step");
    if (b.scene.model.rigid.empty() || t == nullptr || step.dt / step.substeps >= sim::kMinRigidStep) return;
    Section(b.r, *t, "step")
        .fail("dt", "/ substeps must be at least " + sim::format_value(sim::kMinRigidStep) +
                        " s with rigid bodies: ODE divides by the step (got " +
                        sim::format_value(step.dt / step.substeps) + ")");
}

}  // namespace scenes::loader
