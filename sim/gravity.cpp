#include "sim/gravity.h"

#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const UniformGravity& gravity, std::size_t) {
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(gravity.g[k])) {
            throw InputError("gravity.g must be finite, in m/s² (got " + format_value(gravity.g[k]) + ")");
        }
    }
}

void accumulate(const UniformGravity& gravity, const ForceInput& in, Vec3Span f) {
    for (int k = 0; k < 3; ++k) {
        const double gk = gravity.g[k];
        double* fk = f.c[k];
        for (std::size_t i = 0; i < f.n; ++i) {
            fk[i] += in.mass[i] * gk;
        }
    }
}

double potential_energy(const UniformGravity& gravity, const ForceInput& in) {
    double u = 0.0;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        if (in.inv_mass[i] != 0.0) {
            u -= in.mass[i] * gravity.g.dot(in.x.get(i));
        }
    }
    return u;
}

}  // namespace sim
