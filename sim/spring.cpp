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

void accumulate(const Springs& springs, const ForceInput& in, const Vec3Span& f) {
    // spring_force, written out over the raw component arrays: this loop is
    // most of a cloth step (24k springs on a 64 x 64 cloth), and going
    // through Vec3 temporaries cost it a fifth of its speed. The arithmetic
    // is spring_force's, operation for operation (the same bits). One
    // division instead of three (d (1 / |d|)) measured no clear gain.
    const double* __restrict x = in.x.c[0];
    const double* __restrict y = in.x.c[1];
    const double* __restrict z = in.x.c[2];
    const double* __restrict vx = in.v.c[0];
    const double* __restrict vy = in.v.c[1];
    const double* __restrict vz = in.v.c[2];
    double* __restrict fx = f.c[0];
    double* __restrict fy = f.c[1];
    double* __restrict fz = f.c[2];
    for (const Spring& s : springs.list) {
        const std::uint32_t i = s.i, j = s.j;
        const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
        double gx, gy, gz;
        if (s.rest == 0.0) {
            gx = s.k * dx, gy = s.k * dy, gz = s.k * dz;
            // Only the damper needs the length (see spring_force).
            const double length = s.c != 0.0 ? std::sqrt(dx * dx + dy * dy + dz * dz) : 0.0;
            if (length > 0.0) {
                const double nx = dx / length, ny = dy / length, nz = dz / length;
                const double damp = s.c * ((vx[j] - vx[i]) * nx + (vy[j] - vy[i]) * ny + (vz[j] - vz[i]) * nz);
                gx += damp * nx, gy += damp * ny, gz += damp * nz;
            }
        } else {
            const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
            if (length == 0.0) continue;
            const double nx = dx / length, ny = dy / length, nz = dz / length;
            const double magnitude =
                s.k * (length - s.rest) + s.c * ((vx[j] - vx[i]) * nx + (vy[j] - vy[i]) * ny + (vz[j] - vz[i]) * nz);
            gx = magnitude * nx, gy = magnitude * ny, gz = magnitude * nz;
        }
        fx[i] += gx, fy[i] += gy, fz[i] += gz;
        fx[j] -= gx, fy[j] -= gy, fz[j] -= gz;
    }
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
