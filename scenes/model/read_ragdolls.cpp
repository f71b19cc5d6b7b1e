// The loader's ragdoll reader: [[ragdolls]], a human figure of rigid bones and
// joints (sim::ragdoll_parts builds it); its bones are named "<name>.<bone>"
// so that joints and ghosts can name them.
#include "scenes/model/scene_builder.h"

#include "sim/ragdoll.h"

#include <numbers>

namespace scenes::loader {
namespace {

// A ragdoll's bones in shades of its colour, so that limbs read apart from
// the trunk: forearms, shins and the head lighter, hands and feet darker.
Color bone_color(Color c, sim::RagdollBone bone) {
    using B = sim::RagdollBone;
    auto mix = [&](float target, float amount) {
        return Color{c.r + (target - c.r) * amount, c.g + (target - c.g) * amount, c.b + (target - c.b) * amount, c.a};
    };
    switch (bone) {
        case B::head:
        case B::lower_arm_left:
        case B::lower_arm_right:
        case B::lower_leg_left:
        case B::lower_leg_right:
            return mix(1.0f, 0.3f);
        case B::hand_left:
        case B::hand_right:
        case B::foot_left:
        case B::foot_right:
            return mix(0.0f, 0.35f);
        default:
            return c;
    }
}

sim::RagdollDef read_ragdoll(const Section& s) {
    s.only(keys::ragdoll);
    sim::RagdollDef d;
    d.height = s.positive("height", d.height, 100.0, "m");
    d.mass = s.positive("mass", d.mass, kHuge, "kg");
    d.position = s.vec3("position", d.position, "m", sim::kMaxBodyReach);
    d.orientation = s.rotation();
    d.velocity = s.vec3("velocity", d.velocity, "m/s");
    d.angular_velocity =
        s.vec3("angular_velocity", sim::Vec3::Zero(), "deg/s", kMaxSpinDegrees) * (std::numbers::pi / 180.0);
    d.joint_friction = s.number("joint_friction", d.joint_friction, 0.0, sim::kMaxJointForce, "N·m");
    return d;
}

// Each bone within what ODE takes: where it is follows position, its sizes
// height, its mass mass.
void refuse_bone_ode_cannot_take(const Section& s, const sim::BodyDef& body, sim::RagdollBone bone) {
    if (!(body.position.cwiseAbs().maxCoeff() <= sim::kMaxBodyReach)) {
        s.fail("position", "puts the " + std::string(sim::name(bone)) + " beyond +-" +
                               sim::format_value(sim::kMaxBodyReach) + " m, past what ODE can place");
    }
    double mass = 0.0;
    try {
        mass = sim::mass_of(body);
    } catch (const sim::InputError& e) {
        s.fail("height", "makes the " + std::string(sim::name(bone)) + " too small or too large for ODE: " + e.what());
    }
    if (!(mass >= sim::kMinBodyMass && mass <= sim::kMaxBodyMass)) {
        s.fail("mass", "gives the " + std::string(sim::name(bone)) + " " + sim::format_value(mass) +
                           " kg; each bone's mass must be within " + sim::format_value(sim::kMinBodyMass) + " .. " +
                           sim::format_value(sim::kMaxBodyMass) + " kg");
    }
}

}  // namespace

void read_ragdolls(SceneBuilder& b, const Section& top) {
    sim::RigidModel& m = b.scene.model.rigid;
    const auto ragdolls = top.entries("ragdolls", 1'000);
    for (std::size_t k = 0; k < ragdolls.size(); ++k) {
        const Section& s = ragdolls[k];
        const sim::RagdollDef d = read_ragdoll(s);
        const std::string name = s.string("name", "ragdoll" + std::to_string(k), 64);
        const Color color = s.color("color", palette(k + 5));
        const sim::RagdollParts made = sim::ragdoll_parts(d, static_cast<int>(m.bodies.size()));
        for (std::size_t i = 0; i < made.bodies.size(); ++i) {
            const auto bone = static_cast<sim::RagdollBone>(i);
            refuse_bone_ode_cannot_take(s, made.bodies[i], bone);
            const std::string bone_name = name + "." + std::string(sim::name(bone));
            if (!b.body_index.emplace(bone_name, static_cast<int>(m.bodies.size())).second)
                s.fail("name", "must be unique: " + quote(bone_name) + " is taken");
            m.bodies.push_back(made.bodies[i]);
            b.scene.body_names.push_back(bone_name);
            b.scene.body_groups.push_back(name);
            b.scene.body_colors.push_back(bone_color(color, bone));
        }
        m.joints.insert(m.joints.end(), made.joints.begin(), made.joints.end());
        b.joint_nodes.insert(b.joint_nodes.end(), made.joints.size(), &s.table());
    }
}

}  // namespace scenes::loader
