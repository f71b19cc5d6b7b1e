// A reduced-coordinate step (Featherstone's articulated-body algorithm) for a tree of rigid
// bodies hanging from the world by hinges and ball joints, state in and out in maximal coordinates.
// Why: ODE loses the heavy top and a falling chain (docs/studies/rigid-closed-forms.md §2, §4, §8).
//
// Every body is written back root down, so each joint's anchors coincide exactly; input off its joints
// (a body ODE stepped) is projected: a child's position and velocity are rebuilt from its parent's
// and its own spin, and a hinge keeps only the spin along its axis.
#pragma once

#include "sim/vec3_array.h"

#include <Eigen/Geometry>

#include <vector>

namespace sim {

enum class ArticulatedJointType { hinge, ball };

// One body and the joint to its parent. A hinge's axis is fixed in the child
// as given; in the parent it stays where the input's relative orientation puts it.
struct ArticulatedLink {
    int parent = -1;  // index of the parent link (lower than this one's); -1: the world, fixed
    ArticulatedJointType joint = ArticulatedJointType::ball;
    // m, the joint in the parent's body frame (origin at its centre of mass); in the world frame for -1
    Vec3 anchor_in_parent = Vec3::Zero();
    Vec3 anchor_in_child = Vec3::Zero();  // m, the joint in this body's frame
    Vec3 axis_in_child = Vec3::UnitZ();   // hinge axis in this body's frame (unit)
    double mass = 1.0;                    // kg (> 0)
    // kg·m², about the centre of mass, body frame (symmetric, positive definite)
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();
};

// One body's state, as BodyState's first four fields.
struct LinkState {
    Vec3 position = Vec3::Zero();                                     // m, centre of mass
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body to world
    Vec3 velocity = Vec3::Zero();                                     // m/s, of the centre of mass
    Vec3 angular_velocity = Vec3::Zero();                             // rad/s, world frame
};

// Throws InputError naming the link and field: a parent not lower than its
// child, a mass or inertia not positive, a hinge axis not unit, anything not finite.
void validate(const std::vector<ArticulatedLink>& links);

// Advances `state` (one entry per link, parents first) by h under uniform
// gravity: RK4 on the joints' rotations (on the rotation group) and spins, in
// substeps that turn no joint more than 0.3 rad, the accelerations from the
// articulated-body algorithm. InputError for bad links or state, h <= 0.
void articulated_step(const std::vector<ArticulatedLink>& links, std::vector<LinkState>& state, const Vec3& gravity,
                      double h);

}  // namespace sim
