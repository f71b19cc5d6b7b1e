#include "sim/constraints.h"

#include "sim/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace sim {

void validate(const Constraints& constraints, std::size_t particle_count) {
    if (constraints.iterations < 1 || constraints.iterations > 10'000) {
        throw InputError("constraints.iterations must be within 1 .. 10000 (got " +
                         std::to_string(constraints.iterations) + ")");
    }
    for (std::size_t k = 0; k < constraints.distance.size(); ++k) {
        const DistanceConstraint& c = constraints.distance[k];
        const std::string name = "constraints.distance[" + std::to_string(k) + "]";
        if (c.i >= particle_count || c.j >= particle_count) {
            throw InputError(name + " joins particles " + std::to_string(c.i) + " and " + std::to_string(c.j) +
                             ", but there are only " + std::to_string(particle_count));
        }
        if (c.i == c.j) throw InputError(name + " joins particle " + std::to_string(c.i) + " to itself");
        if (!(c.rest >= 0.0) || !std::isfinite(c.rest)) {
            throw InputError(name + ".rest must be >= 0 and finite, in m (got " + format_value(c.rest) + ")");
        }
        if (!(c.compliance >= 0.0) || !std::isfinite(c.compliance)) {
            throw InputError(name + ".compliance must be >= 0 and finite, in m/N (got " + format_value(c.compliance) +
                             ")");
        }
    }
    for (std::size_t k = 0; k < constraints.tethers.size(); ++k) {
        const Tether& t = constraints.tethers[k];
        const std::string name = "constraints.tethers[" + std::to_string(k) + "]";
        if (t.particle >= particle_count || t.anchor >= particle_count || t.particle == t.anchor) {
            throw InputError(name + " ties particle " + std::to_string(t.particle) + " to " + std::to_string(t.anchor) +
                             ": two different particles of the " + std::to_string(particle_count) + " are needed");
        }
        if (!(t.max_distance >= 0.0) || !std::isfinite(t.max_distance)) {
            throw InputError(name + ".max_distance must be >= 0 and finite, in m (got " + format_value(t.max_distance) +
                             ")");
        }
    }
}

void project(const Constraints& constraints, Vec3Span x, const double* inv_mass, double h,
             std::vector<double>& lambda) {
    const auto& list = constraints.distance;
    lambda.assign(list.size(), 0.0);
    const double inv_h2 = 1.0 / (h * h);
    for (int sweep = 0; sweep < constraints.iterations; ++sweep) {
        for (std::size_t k = 0; k < list.size(); ++k) {
            const DistanceConstraint& c = list[k];
            const double wi = inv_mass[c.i], wj = inv_mass[c.j];
            const double alpha = c.compliance * inv_h2;  // α̃, 1/kg
            const double w = wi + wj + alpha;
            if (w == 0.0) continue;  // both pinned and rigid: nothing can move
            const Vec3 d = x.get(c.i) - x.get(c.j);
            const double length = d.norm();
            // Coincident particles have no direction to push along: skip
            // rather than divide by zero (the next step usually separates them).
            if (length < 1e-12) continue;
            const Vec3 n = d / length;
            const double C = length - c.rest;
            const double dlambda = (-C - alpha * lambda[k]) / w;
            lambda[k] += dlambda;
            x.add(c.i, (wi * dlambda) * n);
            x.add(c.j, (-wj * dlambda) * n);
        }
        for (const Tether& t : constraints.tethers) {
            const double wi = inv_mass[t.particle], wa = inv_mass[t.anchor];
            if (wi == 0.0) continue;
            const Vec3 d = x.get(t.particle) - x.get(t.anchor);
            const double length = d.norm();
            if (length <= t.max_distance) continue;  // one-sided: slack is free
            const double excess = length - t.max_distance;
            const Vec3 n = d / length;
            x.add(t.particle, (-excess * wi / (wi + wa)) * n);
            x.add(t.anchor, (excess * wa / (wi + wa)) * n);
        }
    }
}

double potential_energy(const Constraints& constraints, ConstVec3Span x) {
    double u = 0.0;
    for (const DistanceConstraint& c : constraints.distance) {
        if (c.compliance > 0.0) {
            const double C = (x.get(c.i) - x.get(c.j)).norm() - c.rest;
            u += 0.5 * C * C / c.compliance;
        }
    }
    return u;
}

double max_strain(const Constraints& constraints, ConstVec3Span x) {
    double worst = 0.0;
    for (const DistanceConstraint& c : constraints.distance) {
        if (c.rest > 0.0) {
            worst = std::max(worst, std::abs((x.get(c.i) - x.get(c.j)).norm() - c.rest) / c.rest);
        }
    }
    return worst;
}

}  // namespace sim
