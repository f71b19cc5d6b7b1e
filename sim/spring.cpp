#include "sim/spring.h"

#include "sim/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace sim {

Vec3 spring_force(const Spring& s, const Vec3& xi, const Vec3& xj, const Vec3& vi, const Vec3& vj) {
    const Vec3 d = xj - xi;
    if (s.rest == 0.0) {
        // k (|d| - 0) d / |d| = k d; the damper needs a direction. Without a
        // damper no length is needed: the linear spring is k d, no square root
        // and no division (the damper's term would add a zero, which changes
        // no sum: forces are summed from +0).
        Vec3 f = s.k * d;
        const double length = s.c != 0.0 ? d.norm() : 0.0;
        if (length > 0.0) {
            const Vec3 n = d / length;
            f += s.c * (vj - vi).dot(n) * n;
        }
        return f;
    }
    const double length = d.norm();
    if (length == 0.0) {
        return Vec3::Zero();
    }
    const Vec3 n = d / length;
    return (s.k * (length - s.rest) + s.c * (vj - vi).dot(n)) * n;
}

void validate(const Springs& springs, std::size_t particle_count) {
    const Plasticity& p = springs.plasticity;
    if (!(p.yield_strain >= 0.0 && p.yield_strain < 1.0)) {
        throw InputError("springs.plasticity.yield_strain must be within 0 .. 1 (got " + format_value(p.yield_strain) +
                         ")");
    }
    if (!(p.creep >= 0.0) || !std::isfinite(p.creep)) {
        throw InputError("springs.plasticity.creep must be >= 0 and finite, in 1/s (got " + format_value(p.creep) +
                         ")");
    }
    if (!(p.max_strain >= 0.0 && p.max_strain < 1.0)) {
        throw InputError("springs.plasticity.max_strain must be within 0 .. 1 (got " + format_value(p.max_strain) +
                         ")");
    }
    for (std::size_t index = 0; index < springs.list.size(); ++index) {
        const Spring& s = springs.list[index];
        const std::string name = "springs[" + std::to_string(index) + "]";
        if (s.i >= particle_count || s.j >= particle_count) {
            throw InputError(name + " joins particles " + std::to_string(s.i) + " and " + std::to_string(s.j) +
                             ", but there are only " + std::to_string(particle_count));
        }
        if (s.i == s.j) {
            throw InputError(name + " joins particle " + std::to_string(s.i) + " to itself");
        }
        if (!(s.k >= 0.0) || !std::isfinite(s.k)) {
            throw InputError(name + ".k must be >= 0 and finite, in N/m (got " + format_value(s.k) + ")");
        }
        if (!(s.rest >= 0.0) || !std::isfinite(s.rest)) {
            throw InputError(name + ".rest must be >= 0 and finite, in m (got " + format_value(s.rest) + ")");
        }
        if (!(s.c >= 0.0) || !std::isfinite(s.c)) {
            throw InputError(name + ".c must be >= 0 and finite, in N·s/m (got " + format_value(s.c) + ")");
        }
    }
}

double apply_plasticity(Springs& springs, const std::vector<double>& rest0, ConstVec3Span x, double h) {
    const Plasticity& p = springs.plasticity;
    if (!p.enabled()) return 0.0;
    const double rate = std::min(1.0, p.creep * h);
    double largest = 0.0;
    for (std::size_t k = 0; k < springs.list.size(); ++k) {
        Spring& s = springs.list[k];
        if (s.rest <= 0.0) continue;  // zero-length springs have no strain to yield
        const double length = (x.get(s.j) - x.get(s.i)).norm();
        const double strain = (length - s.rest) / s.rest;
        if (std::abs(strain) <= p.yield_strain) continue;
        const double before = s.rest;
        s.rest += rate * (length - s.rest) * (1.0 - p.yield_strain / std::abs(strain));
        s.rest = std::clamp(s.rest, rest0[k] * (1.0 - p.max_strain), rest0[k] * (1.0 + p.max_strain));
        largest = std::max(largest, std::abs(s.rest - before));
    }
    return largest;
}

double potential_energy(const Springs& springs, const ForceInput& in) {
    double u = 0.0;
    for (const Spring& s : springs.list) {
        const double stretch = (in.x.get(s.j) - in.x.get(s.i)).norm() - s.rest;
        u += 0.5 * s.k * stretch * stretch;
    }
    return u;
}

void accumulate_jacobians(const Springs& springs, const ForceInput& in, Jacobians& jac) {
    const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
    for (const Spring& s : springs.list) {
        const Vec3 d = in.x.get(s.j) - in.x.get(s.i);
        const double length = d.norm();
        Eigen::Matrix3d kx;                            // ∂f_i/∂x_j
        Eigen::Matrix3d kv = Eigen::Matrix3d::Zero();  // ∂f_i/∂v_j
        if (length == 0.0) {
            kx = s.rest == 0.0 ? Eigen::Matrix3d(s.k * identity) : Eigen::Matrix3d::Zero();
        } else {
            const Vec3 n = d / length;
            const Eigen::Matrix3d nn = n * n.transpose();
            const double transverse = std::max(0.0, 1.0 - s.rest / length);
            kx = s.k * (nn + transverse * (identity - nn));
            kv = s.c * nn;
        }
        Jacobians::add(jac.dfdx, s.i, s.j, kx);
        Jacobians::add(jac.dfdx, s.j, s.i, kx);
        Jacobians::add(jac.dfdx, s.i, s.i, -kx);
        Jacobians::add(jac.dfdx, s.j, s.j, -kx);
        Jacobians::add(jac.dfdv, s.i, s.j, kv);
        Jacobians::add(jac.dfdv, s.j, s.i, kv);
        Jacobians::add(jac.dfdv, s.i, s.i, -kv);
        Jacobians::add(jac.dfdv, s.j, s.j, -kv);
    }
}

}  // namespace sim
