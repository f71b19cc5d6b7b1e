// The loader's joint reader: [[joints]] between two rigid bodies (or a body
// and the world), with limits and motors; and the warning about jointed mass
// ratios the iterative solver handles badly.
#include "scenes/model/scene_builder.h"

#include <numbers>
#include <sstream>

namespace scenes::loader {
namespace {

sim::JointType joint_type(const Section& s) {
    const std::string type = s.word("type", "ball", {"ball", "hinge", "universal", "slider", "fixed"});
    return type == "hinge"       ? sim::JointType::hinge
           : type == "universal" ? sim::JointType::universal
           : type == "slider"    ? sim::JointType::slider
           : type == "fixed"     ? sim::JointType::fixed
                                 : sim::JointType::ball;
}

// The body a key names (a rigid body, or a ragdoll's "<name>.<bone>").
int body_named(const SceneBuilder& b, const Section& s, std::string_view key) {
    const std::string name = s.string(key, "");
    const auto it = b.body_index.find(name);
    if (it == b.body_index.end()) s.fail(key, "names no body (got " + quote(name) + ")");
    return it->second;
}

// Limits, stops and the motor: in degrees (deg/s, N·m) for turning joints, in m
// (m/s, N) for sliders; stored in radians and metres.
void read_limits_and_motor(const Section& s, sim::JointDef& joint) {
    const bool angular = joint.type != sim::JointType::slider;
    const double scale = angular ? std::numbers::pi / 180.0 : 1.0;
    auto limits = [&](const char* lo_key, const char* hi_key, double& lo, double& hi) {
        if (s.node(lo_key) == nullptr && s.node(hi_key) == nullptr) return;
        lo = s.number(lo_key, -1e300, -1e6, 1e6, angular ? "degrees" : "m") * scale;
        hi = s.number(hi_key, 1e300, -1e6, 1e6, angular ? "degrees" : "m") * scale;
        if (lo > hi) s.fail(hi_key, std::string("must be >= ") + lo_key);
    };
    limits("lo", "hi", joint.lo, joint.hi);
    limits("lo2", "hi2", joint.lo2, joint.hi2);
    limits("lo3", "hi3", joint.lo3, joint.hi3);
    joint.stop_stiffness = s.number("stop_stiffness", 0.0, 0.0, kHuge, angular ? "N·m/rad" : "N/m");
    joint.stop_damping = s.number("stop_damping", 0.0, 0.0, kHuge, angular ? "N·m·s/rad" : "N·s/m");
    joint.motor_velocity = s.number("motor_velocity", 0.0, -1e6, 1e6, angular ? "deg/s" : "m/s") * scale;
    joint.motor_max_force = s.number("motor_max_force", 0.0, 0.0, sim::kMaxJointForce, angular ? "N·m" : "N");
}

sim::RigidJoint read_joint(const SceneBuilder& b, const Section& s) {
    s.only(keys::joint);
    sim::RigidJoint j;
    j.joint.type = joint_type(s);
    if (s.node("a") == nullptr) s.fail("a", "is required: a body name");
    j.a = body_named(b, s, "a");
    j.b = s.node("b") != nullptr ? body_named(b, s, "b") : -1;
    if (j.a == j.b) s.fail("b", "must be another body than a");
    j.joint.anchor = s.vec3("anchor", j.joint.anchor, "m");
    j.joint.axis = s.direction("axis", j.joint.axis);
    j.joint.axis2 = s.direction("axis2", j.joint.axis2);
    read_limits_and_motor(s, j.joint);
    return j;
}

}  // namespace

void read_joints(SceneBuilder& b, const Section& top) {
    for (const Section& s : top.entries("joints", 10'000)) {
        b.scene.model.rigid.joints.push_back(read_joint(b, s));
        b.joint_nodes.push_back(&s.table());
    }
}

// Jointed mass ratios above 10:1 converge slowly in the iterative solver: warn
// (ODE's exact solver, quickstep = false, does not care).
void warn_jointed_mass_ratios(SceneBuilder& b) {
    const sim::RigidModel& m = b.scene.model.rigid;
    for (std::size_t k = 0; m.settings.quickstep && k < m.joints.size(); ++k) {
        const sim::RigidJoint& j = m.joints[k];
        if (j.b < 0) continue;
        const auto ja = static_cast<std::size_t>(j.a), jb = static_cast<std::size_t>(j.b);
        const double ma = sim::mass_of(m.bodies[ja]), mb = sim::mass_of(m.bodies[jb]);
        const double ratio = sim::mass_ratio(ma, mb);
        if (ratio <= sim::kSlowMassRatio) continue;
        std::ostringstream w;
        w.precision(3);
        w << b.r.where(b.joint_nodes[k]) << ": " << b.scene.body_names[ja] << " (" << ma << " kg) and "
          << b.scene.body_names[jb] << " (" << mb << " kg) are jointed with a mass ratio of " << ratio
          << ":1, over 10:1: the iterative solver converges slowly (the joint stretches); "
             "raise rigid.iterations, use the exact solver (rigid.quickstep = false) or even out the masses";
        b.scene.warnings.push_back(w.str());
    }
}

}  // namespace scenes::loader
