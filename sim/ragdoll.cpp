#include "sim/ragdoll.h"

#include "sim/error.h"
#include "sim/rotation.h"

#include <cmath>
#include <numeric>
#include <sstream>

namespace sim {

namespace {

// The standing pose, in units of the height H: y up, facing +z, left on +x,
// feet on y = 0. Lengths from Drillis and Contini (upper arm 0.186 H,
// forearm 0.146 H, hand 0.108 H, thigh 0.245 H, shank 0.246 H, foot 0.152 H,
// shoulder height 0.818 H, hip height 0.530 H).
struct Bone {
    const char* name;
    int parent;         // bone index, -1 for the pelvis
    RigidShape shape;   //
    double sx, sy, sz;  // H: box extents; radius, straight length
    double cx, cy, cz;  // H: centre
    bool along_y;       // a capsule turned from ODE's z to the bone's y
};
constexpr double kShoulderX = 0.115, kHipX = 0.05;
constexpr Bone kBones[kRagdollBones] = {
    {"pelvis", -1, RigidShape::box, 0.17, 0.07, 0.10, 0.0, 0.565, 0.0, false},
    {"abdomen", 0, RigidShape::box, 0.15, 0.08, 0.09, 0.0, 0.645, 0.0, false},
    {"chest", 1, RigidShape::box, 0.19, 0.13, 0.11, 0.0, 0.755, 0.0, false},
    {"head", 2, RigidShape::sphere, 0.06, 0.0, 0.0, 0.0, 0.90, 0.0, false},
    {"upper_arm_left", 2, RigidShape::capsule, 0.025, 0.136, 0.0, kShoulderX, 0.707, 0.0, true},
    {"lower_arm_left", 4, RigidShape::capsule, 0.022, 0.102, 0.0, kShoulderX, 0.541, 0.0, true},
    {"hand_left", 5, RigidShape::box, 0.02, 0.09, 0.045, kShoulderX, 0.423, 0.0, false},
    {"upper_arm_right", 2, RigidShape::capsule, 0.025, 0.136, 0.0, -kShoulderX, 0.707, 0.0, true},
    {"lower_arm_right", 7, RigidShape::capsule, 0.022, 0.102, 0.0, -kShoulderX, 0.541, 0.0, true},
    {"hand_right", 8, RigidShape::box, 0.02, 0.09, 0.045, -kShoulderX, 0.423, 0.0, false},
    {"upper_leg_left", 0, RigidShape::capsule, 0.035, 0.175, 0.0, kHipX, 0.4075, 0.0, true},
    {"lower_leg_left", 10, RigidShape::capsule, 0.028, 0.19, 0.0, kHipX, 0.162, 0.0, true},
    {"foot_left", 11, RigidShape::box, 0.05, 0.035, 0.15, kHipX, 0.02, 0.04, false},
    {"upper_leg_right", 0, RigidShape::capsule, 0.035, 0.175, 0.0, -kHipX, 0.4075, 0.0, true},
    {"lower_leg_right", 13, RigidShape::capsule, 0.028, 0.19, 0.0, -kHipX, 0.162, 0.0, true},
    {"foot_right", 14, RigidShape::box, 0.05, 0.035, 0.15, -kHipX, 0.02, 0.04, false},
};

// Each bone's joint to its parent (bone k's joint is joints[k - 1]).
//
// ODE measures a joint angle as minus the child's rotation about the axis
// relative to the parent, so the axes below point along -x, -y and -z: then
// every angle is the child's rotation about +x (flexion: positive tips an
// upward bone forward, a downward bone backward), +z (sideways: positive
// swings a downward bone towards +x) and +y (twist along the bone). Limits
// in rad; a hinge uses [lo, hi] only.
struct JointSpec {
    JointType type;
    double ax, ay, az;  // H: anchor
    double lo, hi;      // about +x
    double lo2, hi2;    // about +z (ball: second swing; universal: second axis)
    double lo3, hi3;    // about +y (ball: twist)
};
constexpr JointSpec kJoints[kRagdollJoints] = {
    {JointType::ball, 0.0, 0.60, 0.0, -0.3, 0.6, -0.3, 0.3, -0.3, 0.3},            // lower spine
    {JointType::ball, 0.0, 0.69, 0.0, -0.3, 0.5, -0.3, 0.3, -0.35, 0.35},          // upper spine
    {JointType::ball, 0.0, 0.83, 0.0, -0.6, 0.8, -0.5, 0.5, -1.0, 1.0},            // neck
    {JointType::ball, kShoulderX, 0.80, 0.0, -2.6, 0.8, -0.3, 1.4, -1.0, 1.0},     // left shoulder
    {JointType::hinge, kShoulderX, 0.614, 0.0, -2.6, 0.0, 1, -1, 1, -1},           // left elbow
    {JointType::universal, kShoulderX, 0.468, 0.0, -1.0, 1.0, -0.4, 0.4, 1, -1},   // left wrist
    {JointType::ball, -kShoulderX, 0.80, 0.0, -2.6, 0.8, -1.4, 0.3, -1.0, 1.0},    // right shoulder
    {JointType::hinge, -kShoulderX, 0.614, 0.0, -2.6, 0.0, 1, -1, 1, -1},          // right elbow
    {JointType::universal, -kShoulderX, 0.468, 0.0, -1.0, 1.0, -0.4, 0.4, 1, -1},  // right wrist
    {JointType::ball, kHipX, 0.53, 0.0, -1.8, 0.35, -0.3, 0.8, -0.5, 0.5},         // left hip
    {JointType::hinge, kHipX, 0.285, 0.0, 0.0, 2.4, 1, -1, 1, -1},                 // left knee
    {JointType::universal, kHipX, 0.039, 0.0, -0.6, 0.6, -0.3, 0.3, 1, -1},        // left ankle
    {JointType::ball, -kHipX, 0.53, 0.0, -1.8, 0.35, -0.8, 0.3, -0.5, 0.5},        // right hip
    {JointType::hinge, -kHipX, 0.285, 0.0, 0.0, 2.4, 1, -1, 1, -1},                // right knee
    {JointType::universal, -kHipX, 0.039, 0.0, -0.6, 0.6, -0.3, 0.3, 1, -1},       // right ankle
};

}  // namespace

std::string_view name(RagdollBone bone) { return kBones[static_cast<std::size_t>(bone)].name; }

void validate(const RagdollDef& d) {
    require_positive(d.height, "ragdoll.height", "m");
    require_positive(d.mass, "ragdoll.mass", "kg");
    require_nonnegative(d.joint_friction, "ragdoll.joint_friction", "N·m");
    if (!d.position.allFinite() || !d.velocity.allFinite() || !d.angular_velocity.allFinite()) {
        throw InputError("ragdoll.position, velocity and angular_velocity must be finite");
    }
    if (!d.orientation.coeffs().allFinite() || std::abs(d.orientation.norm() - 1.0) > 1e-6) {
        throw InputError("ragdoll.orientation must be a unit quaternion");
    }
    for (std::size_t k = 0; k < kRagdollBones; ++k) {
        require_positive(d.mass_fractions[k], "ragdoll.mass_fractions[" + std::string(kBones[k].name) + "]", "");
    }
}

RagdollParts ragdoll_parts(const RagdollDef& d, int first_body) {
    validate(d);
    RagdollParts out;
    const double H = d.height;
    const double fraction_sum = std::accumulate(d.mass_fractions.begin(), d.mass_fractions.end(), 0.0);
    const Eigen::Quaterniond& q = d.orientation;
    const Vec3 pelvis = H * Vec3(kBones[0].cx, kBones[0].cy, kBones[0].cz);
    // Builder frame -> world: about the pelvis centre, then to d.position.
    auto place = [&](const Vec3& p) -> Vec3 { return d.position + q * (H * p - pelvis); };
    const Eigen::Quaterniond z_to_y = rotation_from_z(Vec3::UnitY());
    for (std::size_t k = 0; k < kRagdollBones; ++k) {
        const Bone& bone = kBones[k];
        BodyDef& b = out.bodies[k];
        b.shape = bone.shape;
        b.size = H * Vec3(bone.sx, bone.sy, bone.sz);
        b.mass = d.mass * d.mass_fractions[k] / fraction_sum;
        b.position = place(Vec3(bone.cx, bone.cy, bone.cz));
        b.orientation = bone.along_y ? q * z_to_y : q;
        b.velocity = d.velocity + d.angular_velocity.cross(b.position - d.position);
        b.angular_velocity = d.angular_velocity;
    }
    for (std::size_t k = 0; k < kRagdollJoints; ++k) {
        const JointSpec& s = kJoints[k];
        const Bone& child = kBones[k + 1];
        RigidJoint& rj = out.joints[k];
        rj.a = first_body + child.parent;
        rj.b = first_body + static_cast<int>(k) + 1;
        JointDef& j = rj.joint;
        j.type = s.type;
        j.anchor = place(Vec3(s.ax, s.ay, s.az));
        j.axis = q * Vec3(-1, 0, 0);
        j.axis2 = q * (s.type == JointType::universal ? Vec3(0, 0, -1) : Vec3(0, -1, 0));
        j.lo = s.lo;
        j.hi = s.hi;
        j.lo2 = s.lo2;
        j.hi2 = s.hi2;
        j.lo3 = s.lo3;
        j.hi3 = s.hi3;
        j.motor_velocity = 0.0;
        j.motor_max_force = d.joint_friction;  // friction: a motor holding velocity 0
        const double m_child = out.bodies[k + 1].mass, m_parent = out.bodies[child.parent].mass;
        const double ratio = mass_ratio(m_child, m_parent);
        if (ratio > kSlowMassRatio) {
            std::ostringstream w;
            w.precision(3);
            w << "ragdoll: " << child.name << " (" << m_child << " kg) on " << kBones[child.parent].name << " ("
              << m_parent << " kg): mass ratio " << ratio << ":1 > 10:1; the joint solver will converge slowly";
            out.warnings.push_back(w.str());
        }
    }
    return out;
}

Ragdoll create_ragdoll(RigidWorld& world, const RagdollDef& def) {
    const RagdollParts parts = ragdoll_parts(def);
    Ragdoll r;
    for (std::size_t k = 0; k < kRagdollBones; ++k) r.bodies[k] = world.add_body(parts.bodies[k]);
    for (std::size_t k = 0; k < kRagdollJoints; ++k) {
        JointDef j = parts.joints[k].joint;
        j.a = r.bodies[static_cast<std::size_t>(parts.joints[k].a)];
        j.b = r.bodies[static_cast<std::size_t>(parts.joints[k].b)];
        r.joints[k] = world.add_joint(j);
    }
    r.warnings = parts.warnings;
    return r;
}

void destroy_ragdoll(RigidWorld& world, const Ragdoll& ragdoll) {
    for (const JointId j : ragdoll.joints) world.remove_joint(j);
    for (const BodyId b : ragdoll.bodies) world.remove_body(b);
}

}  // namespace sim
