#include "sim/newton_gravity.h"

#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const NewtonGravity& gravity, std::size_t) {
    if (!(gravity.G > 0.0) || !std::isfinite(gravity.G)) {
        throw InputError("newton_gravity.G must be > 0 and finite, in m³/(kg·s²) (got " + format_value(gravity.G) +
                         ")");
    }
    if (!(gravity.softening >= 0.0) || !std::isfinite(gravity.softening)) {
        throw InputError("newton_gravity.softening must be >= 0 and finite, in m (got " +
                         format_value(gravity.softening) + ")");
    }
}

void accumulate(const NewtonGravity& gravity, const ForceInput& in, Vec3Span f) {
    const double eps2 = gravity.softening * gravity.softening;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const Vec3 xi = in.x.get(i);
        for (std::size_t j = i + 1; j < in.x.n; ++j) {
            const Vec3 d = in.x.get(j) - xi;
            const double s2 = d.squaredNorm() + eps2;
            if (s2 == 0.0) {
                continue;  // two unsoftened particles at one point: no direction
            }
            const Vec3 fij = (gravity.G * in.mass[i] * in.mass[j] / (s2 * std::sqrt(s2))) * d;
            f.add(i, fij);
            f.add(j, -fij);
        }
    }
}

double potential_energy(const NewtonGravity& gravity, const ForceInput& in) {
    const double eps2 = gravity.softening * gravity.softening;
    double u = 0.0;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        for (std::size_t j = i + 1; j < in.x.n; ++j) {
            if (in.inv_mass[i] == 0.0 && in.inv_mass[j] == 0.0) {
                continue;
            }
            const double s2 = (in.x.get(j) - in.x.get(i)).squaredNorm() + eps2;
            if (s2 > 0.0) {
                u -= gravity.G * in.mass[i] * in.mass[j] / std::sqrt(s2);
            }
        }
    }
    return u;
}

void accumulate_jacobians(const NewtonGravity& gravity, const ForceInput& in, Jacobians& jac) {
    const double eps2 = gravity.softening * gravity.softening;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        for (std::size_t j = i + 1; j < in.x.n; ++j) {
            const Vec3 d = in.x.get(j) - in.x.get(i);
            const double s2 = d.squaredNorm() + eps2;
            if (s2 == 0.0) {
                continue;
            }
            const double s = std::sqrt(s2);
            const double gm = gravity.G * in.mass[i] * in.mass[j];
            const Eigen::Matrix3d k =
                gm * (Eigen::Matrix3d::Identity() / (s2 * s) - 3.0 * d * d.transpose() / (s2 * s2 * s));
            Jacobians::add(jac.dfdx, i, j, k);
            Jacobians::add(jac.dfdx, j, i, k);
            Jacobians::add(jac.dfdx, i, i, -k);
            Jacobians::add(jac.dfdx, j, j, -k);
        }
    }
}

}  // namespace sim
