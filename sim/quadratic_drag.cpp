#include "sim/quadratic_drag.h"

#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const QuadraticDrag& drag, std::size_t) {
    if (!(drag.c >= 0.0) || !std::isfinite(drag.c)) {
        throw InputError("quadratic_drag.c must be >= 0 and finite, in N·s²/m² (got " + format_value(drag.c) + ")");
    }
}

void accumulate(const QuadraticDrag& drag, const ForceInput& in, Vec3Span f) {
    const double* vx = in.v.c[0];
    const double* vy = in.v.c[1];
    const double* vz = in.v.c[2];
    for (std::size_t i = 0; i < f.n; ++i) {
        const double scale = drag.c * std::sqrt(vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]);
        f.c[0][i] -= scale * vx[i];
        f.c[1][i] -= scale * vy[i];
        f.c[2][i] -= scale * vz[i];
    }
}

void accumulate_jacobians(const QuadraticDrag& drag, const ForceInput& in, Jacobians& jac) {
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const Vec3 v = in.v.get(i);
        const double speed = v.norm();
        if (speed == 0.0) {
            continue;  // f is flat in v at rest: |v| v has zero derivative there
        }
        const Eigen::Matrix3d block = -drag.c * (speed * Eigen::Matrix3d::Identity() + v * v.transpose() / speed);
        Jacobians::add(jac.dfdv, i, i, block);
    }
}

}  // namespace sim
