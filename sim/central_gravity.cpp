#include "sim/central_gravity.h"

#include "sim/error.h"

#include <cmath>

namespace sim {

void validate(const CentralGravity& gravity, std::size_t) {
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(gravity.center[k])) {
            throw InputError("central_gravity.center must be finite, in m (got " + format_value(gravity.center[k]) +
                             ")");
        }
    }
    if (!(gravity.mu > 0.0) || !std::isfinite(gravity.mu)) {
        throw InputError("central_gravity.mu must be > 0 and finite, in m³/s² (got " + format_value(gravity.mu) + ")");
    }
}

namespace {

// The force loop: plain pointers and scalars, __restrict on the parameters
// (GCC ignores it on local pointers, and then gives up vectorising for the
// number of overlaps it would have to test), as the field pass has it. Its
// square root and division are most of a Kepler step.
void central_loop(const double* __restrict x, const double* __restrict y, const double* __restrict z,
                  const double* __restrict m, double* __restrict fx, double* __restrict fy, double* __restrict fz,
                  std::size_t n, double cx, double cy, double cz, double mu) {
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = x[i] - cx, dy = y[i] - cy, dz = z[i] - cz;
        const double r2 = dx * dx + dy * dy + dz * dz;
        // -m μ / r³; at the centre (r = 0) no force: r² is replaced by 1
        // there and the result multiplied by 0, arithmetic rather than a
        // branch or a select (GCC vectorises neither around a division).
        // Elsewhere the factor is 1, which changes no bit.
        const double centre = static_cast<double>(r2 == 0.0);
        const double safe = r2 + centre;
        const double s = (1.0 - centre) * (-m[i] * mu / (safe * std::sqrt(safe)));
        fx[i] += s * dx;
        fy[i] += s * dy;
        fz[i] += s * dz;
    }
}

}  // namespace

void accumulate(const CentralGravity& gravity, const ForceInput& in, Vec3Span f) {
    central_loop(in.x.c[0], in.x.c[1], in.x.c[2], in.mass, f.c[0], f.c[1], f.c[2], f.n, gravity.center.x(),
                 gravity.center.y(), gravity.center.z(), gravity.mu);
}

double potential_energy(const CentralGravity& gravity, const ForceInput& in) {
    double u = 0.0;
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const double r = (in.x.get(i) - gravity.center).norm();
        if (in.inv_mass[i] != 0.0 && r > 0.0) {
            u -= in.mass[i] * gravity.mu / r;
        }
    }
    return u;
}

void accumulate_jacobians(const CentralGravity& gravity, const ForceInput& in, Jacobians& jac) {
    for (std::size_t i = 0; i < in.x.n; ++i) {
        const Vec3 d = in.x.get(i) - gravity.center;
        const double r2 = d.squaredNorm();
        if (r2 == 0.0) {
            continue;
        }
        const double r = std::sqrt(r2);
        const Eigen::Matrix3d k = -in.mass[i] * gravity.mu *
                                  (Eigen::Matrix3d::Identity() / (r2 * r) - 3.0 * d * d.transpose() / (r2 * r2 * r));
        Jacobians::add(jac.dfdx, i, i, k);
    }
}

}  // namespace sim
