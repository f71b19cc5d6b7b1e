#include "sim/linear_drag.h"

#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const LinearDrag& drag, std::size_t) {
    if (!(drag.c >= 0.0) || !std::isfinite(drag.c)) {
        throw InputError("linear_drag.c must be >= 0 and finite, in N·s/m (got " + format_value(drag.c) + ")");
    }
}

void accumulate(const LinearDrag& drag, const ForceInput& in, Vec3Span f) {
    for (int k = 0; k < 3; ++k) {
        const double* vk = in.v.c[k];
        double* fk = f.c[k];
        for (std::size_t i = 0; i < f.n; ++i) {
            fk[i] -= drag.c * vk[i];
        }
    }
}

void accumulate_jacobians(const LinearDrag& drag, const ForceInput& in, Jacobians& jac) {
    const Eigen::Matrix3d block = -drag.c * Eigen::Matrix3d::Identity();
    for (std::size_t i = 0; i < in.x.n; ++i) {
        Jacobians::add(jac.dfdv, i, i, block);
    }
}

}  // namespace sim
