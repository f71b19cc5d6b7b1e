#include "sim/buoyancy.h"

#include "sim/error.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace sim {

namespace {

constexpr double kPi = std::numbers::pi;

// Calls f(block index) for each particle the generator acts on in the block
// [first, first + n); `particles` holds global indices.
template <typename F>
void for_each_particle(const Buoyancy& b, const ForceInput& in, F&& f) {
    if (b.particles.empty()) {
        for (std::size_t i = 0; i < in.x.n; ++i) f(i);
    } else {
        for (std::uint32_t p : b.particles) {
            if (p >= in.first && p - in.first < in.x.n) f(p - in.first);
        }
    }
}

double depth(const Buoyancy& b, double y) { return b.surface_height - (y - b.radius); }  // unclamped, m

}  // namespace

double cap_volume(double r, double h) { return kPi * h * h * (3.0 * r - h) / 3.0; }

void validate(const Buoyancy& b, std::size_t particle_count) {
    require_positive(b.fluid_density, "buoyancy.fluid_density", "kg/m³");
    require_positive(b.gravity, "buoyancy.gravity", "m/s²");
    require_positive(b.radius, "buoyancy.radius", "m");
    if (!std::isfinite(b.surface_height)) {
        throw InputError("buoyancy.surface_height must be finite, in m (got " + format_value(b.surface_height) + ")");
    }
    require_nonnegative(b.drag, "buoyancy.drag", "N·s/m");
    for (std::size_t k = 0; k < b.particles.size(); ++k) {
        if (b.particles[k] >= particle_count) {
            throw InputError("buoyancy.particles[" + std::to_string(k) + "] is particle " +
                             std::to_string(b.particles[k]) + ", but there are only " + std::to_string(particle_count));
        }
    }
}

void accumulate(const Buoyancy& b, const ForceInput& in, Vec3Span f) {
    const double r = b.radius, full = 4.0 / 3.0 * kPi * r * r * r;
    for_each_particle(b, in, [&](std::size_t i) {
        const double h = std::clamp(depth(b, in.x.c[1][i]), 0.0, 2.0 * r);
        if (h == 0.0) return;
        const double volume = cap_volume(r, h);
        f.c[1][i] += b.fluid_density * b.gravity * volume;
        const double drag = b.drag * volume / full;
        for (int k = 0; k < 3; ++k) f.c[k][i] -= drag * in.v.c[k][i];
    });
}

double potential_energy(const Buoyancy& b, const ForceInput& in) {
    const double r = b.radius, rho_g = b.fluid_density * b.gravity;
    double u = 0.0;
    for_each_particle(b, in, [&](std::size_t i) {
        if (in.inv_mass[i] == 0.0) return;  // a pinned particle's is constant
        const double d = depth(b, in.x.c[1][i]);
        if (d <= 0.0) return;
        if (d <= 2.0 * r) {
            u += rho_g * kPi * (r * d * d * d - d * d * d * d / 4.0) / 3.0;
        } else {
            u += rho_g * (4.0 * kPi * r * r * r * r / 3.0 + 4.0 / 3.0 * kPi * r * r * r * (d - 2.0 * r));
        }
    });
    return u;
}

void accumulate_jacobians(const Buoyancy& b, const ForceInput& in, Jacobians& jac) {
    const double r = b.radius, full = 4.0 / 3.0 * kPi * r * r * r;
    for_each_particle(b, in, [&](std::size_t i) {
        const double d = depth(b, in.x.c[1][i]);
        if (d <= 0.0) return;
        const double h = std::min(d, 2.0 * r);
        // dV/dh while partly submerged (0 once under), and dh/dy = -1.
        const double dv_dh = d < 2.0 * r ? kPi * h * (2.0 * r - h) : 0.0;
        Eigen::Matrix3d dfdx = Eigen::Matrix3d::Zero();
        dfdx(1, 1) = -b.fluid_density * b.gravity * dv_dh;
        // Drag -drag (V / V_full) v: its dependence on y through V.
        for (int k = 0; k < 3; ++k) dfdx(k, 1) += b.drag * in.v.c[k][i] * dv_dh / full;
        Jacobians::add(jac.dfdx, i, i, dfdx);
        const double frac = cap_volume(r, h) / full;
        Jacobians::add(jac.dfdv, i, i, Eigen::Matrix3d(-b.drag * frac * Eigen::Matrix3d::Identity()));
    });
}

}  // namespace sim
