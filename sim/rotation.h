// The rotation that turns +Z onto a direction, which emitters, chains,
// capsules and the ragdoll's bones all need.
#pragma once

#include "sim/vec3_array.h"

#include <Eigen/Geometry>

namespace sim {

// The shortest rotation taking +Z onto `direction` (a unit vector; for -Z,
// a half turn about an axis orthogonal to Z): Eigen's
// Quaterniond::FromTwoVectors, called in this one place. Its case for
// opposite vectors instantiates a JacobiSVD, about 5 s of compile time in
// every file that instantiates it (issue 19's build budget).
Eigen::Quaterniond rotation_from_z(const Vec3& direction);

}  // namespace sim
