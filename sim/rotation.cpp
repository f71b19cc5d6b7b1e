#include "sim/rotation.h"

namespace sim {

Eigen::Quaterniond rotation_from_z(const Vec3& direction) {
    return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), direction);
}

}  // namespace sim
