// A humanoid ragdoll from a height and a mass: 16 bodies with anatomical
// mass fractions, 15 joints with anatomical limits.
//
// Proportions (as fractions of the height H) follow Drillis and Contini's
// segment lengths; mass fractions follow Winter's anthropometric table
// (Biomechanics and Motor Control of Human Movement, table 4.1), with the
// trunk split into pelvis, abdomen and chest. Standing, the figure faces +z
// with its left on +x, feet on the plane y = 0 of the builder's frame.
//
// Joints: spine (two), neck, shoulders and hips are ball joints with swing
// and twist limits; elbows and knees are hinges that bend one way; wrists and
// ankles are universal joints. Joints turn freely by default (as Bullet's and
// Jolt's ragdoll samples); joint_friction gives every joint axis a friction
// torque (a motor at velocity 0), a stiffer, more tired-looking body at the
// cost of one more solver row per axis (about 12% of a pile's step).
//
// A Ragdoll is a plain struct of ids: create it in a RigidWorld, destroy it
// there. A RigidModel holds bodies and joints only: ragdoll_parts lists a
// ragdoll's as a RigidModel would (the scene loader adds them so).
#pragma once

#include "sim/rigid.h"

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace sim {

enum class RagdollBone {
    pelvis,
    abdomen,
    chest,
    head,
    upper_arm_left,
    lower_arm_left,
    hand_left,
    upper_arm_right,
    lower_arm_right,
    hand_right,
    upper_leg_left,
    lower_leg_left,
    foot_left,
    upper_leg_right,
    lower_leg_right,
    foot_right,
};
inline constexpr std::size_t kRagdollBones = 16;
inline constexpr std::size_t kRagdollJoints = 15;

std::string_view name(RagdollBone bone);

// Where the ragdoll starts: its pelvis at `position` in the builder's
// standing pose turned by `orientation`, every body with the same velocity.
struct RagdollDef {
    double height = 1.8;                                              // m (> 0)
    double mass = 75.0;                                               // kg (> 0)
    Vec3 position = Vec3(0.0, 1.0, 0.0);                              // m, of the pelvis centre
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // of the standing pose
    Vec3 velocity = Vec3::Zero();                                     // m/s
    Vec3 angular_velocity = Vec3::Zero();                             // rad/s, about the pelvis
    double joint_friction = 0.0;                                      // N·m per joint axis (>= 0)
    // Each bone's share of the mass, indexed by RagdollBone (Winter's table
    // by default; normalised by their sum, so any positive weights do).
    std::array<double, kRagdollBones> mass_fractions = {0.142, 0.139, 0.216, 0.081,  0.028,  0.016, 0.006,  0.028,
                                                        0.016, 0.006, 0.100, 0.0465, 0.0145, 0.100, 0.0465, 0.0145};
};

// Throws InputError naming the field ("ragdoll.height must be > 0 ...").
void validate(const RagdollDef& def);

struct Ragdoll {
    std::array<BodyId, kRagdollBones> bodies{};    // indexed by RagdollBone
    std::array<JointId, kRagdollJoints> joints{};  // child bone k + 1's joint to its parent
    std::vector<std::string> warnings;             // as RagdollParts::warnings
    BodyId body(RagdollBone bone) const { return bodies[static_cast<std::size_t>(bone)]; }
};

// The bodies and joints of a ragdoll as a RigidModel would list them (body
// indices from `first_body`): what create_ragdoll adds, for callers that
// build descriptions rather than worlds.
struct RagdollParts {
    std::array<BodyDef, kRagdollBones> bodies;
    std::array<RigidJoint, kRagdollJoints> joints;
    // Jointed pairs heavier than 10:1 (a heavy helmet on a light neck): the
    // iterative solver converges slowly on them. One line per pair, e.g.
    // "ragdoll: head (12 kg) on chest (1 kg): mass ratio 12:1 > 10:1".
    std::vector<std::string> warnings;
};
RagdollParts ragdoll_parts(const RagdollDef& def, int first_body = 0);

Ragdoll create_ragdoll(RigidWorld& world, const RagdollDef& def);  // validates (InputError)
void destroy_ragdoll(RigidWorld& world, const Ragdoll& ragdoll);

}  // namespace sim
