// Hooke springs with damping between pairs of particles, exactly the lecture's
//   f_a = k (|p_b - p_a| - ℓ) (p_b - p_a) / |p_b - p_a|,   f_b = -f_a
// plus a damper along the spring, c ((v_b - v_a) · d̂) d̂ on a (minus on b).
#pragma once

#include "sim/force.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace sim {

// One spring: an index record, nothing points at anything.
struct Spring {
    std::uint32_t i = 0;  // first particle
    std::uint32_t j = 0;  // second particle (!= i)
    double rest = 1.0;    // rest length ℓ, m (>= 0)
    double k = 100.0;     // stiffness, N/m (>= 0)
    double c = 0.0;       // damping along the spring, N·s/m (>= 0)
};

// Plastic springs (the lecture: "dynamically change rest-length in response
// to large compression/stretching"): after each substep of h, a spring whose
// strain s = (|d| - rest) / rest exceeds the yield strain creeps towards its
// current length,
//   rest += creep h (|d| - rest) (1 - yield / |s|),
// and never leaves [rest0 (1 - max_strain), rest0 (1 + max_strain)], rest0
// being the rest length the body was built with. Below the yield it is
// elastic: a dented cube stays dented, a lightly poked one springs back.
struct Plasticity {
    double yield_strain = 0.0;  // strain (0..1) above which rest lengths creep; 0: elastic springs
    double creep = 0.0;         // 1/s, how fast the rest length follows (creep h <= 1)
    double max_strain = 0.5;    // largest permanent change of a rest length, as a fraction of rest0

    bool enabled() const { return yield_strain > 0.0 && creep > 0.0; }
};

// All springs of a system, evaluated in one pass.
struct Springs {
    std::vector<Spring> list;
    Plasticity plasticity;
};

// The plastic update of every spring after a substep of h (see Plasticity),
// with rest0 the built rest lengths (one per spring). Returns the largest
// rest-length change, m.
double apply_plasticity(Springs& springs, const std::vector<double>& rest0, ConstVec3Span x, double h);

// Force on particle i of spring s (particle j gets the opposite), N. Safe at
// zero length: with ℓ = 0 it is k d (no division); with ℓ > 0 and the two
// particles on top of each other there is no direction to push, and it is 0.
Vec3 spring_force(const Spring& s, const Vec3& xi, const Vec3& xj, const Vec3& vi, const Vec3& vj);

void validate(const Springs& springs, std::size_t particle_count);
constexpr bool is_local(const Springs&) { return false; }
// spring_force on plain values: the pull g of spring s on its first particle
// i (the second, j, gets -g), given both particles' positions and dv(k),
// component k of v_j - v_i (read only where the damper needs it); false
// where it has none (ℓ > 0 and the two particles on top of each other).
// Inline, in the loops below and the pairs' paths (sim/pair_forces.h):
// operation for operation spring_force's arithmetic (the same bits). Through
// Vec3 temporaries the cloth's spring loop lost a fifth of its speed; one
// division instead of three (d (1 / |d|)) measured no clear gain.
template <class RelativeVelocity>
[[gnu::always_inline]] inline bool spring_pull(const Spring& s, double xi, double yi, double zi, double xj, double yj,
                                               double zj, const RelativeVelocity& dv, double& gx, double& gy,
                                               double& gz) {
    const double dx = xj - xi, dy = yj - yi, dz = zj - zi;
    if (s.rest == 0.0) {
        gx = s.k * dx, gy = s.k * dy, gz = s.k * dz;
        // Only the damper needs the length (see spring_force).
        const double length = s.c != 0.0 ? std::sqrt(dx * dx + dy * dy + dz * dz) : 0.0;
        if (length > 0.0) {
            const double nx = dx / length, ny = dy / length, nz = dz / length;
            const double damp = s.c * (dv(0) * nx + dv(1) * ny + dv(2) * nz);
            gx += damp * nx, gy += damp * ny, gz += damp * nz;
        }
        return true;
    }
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (length == 0.0) return false;
    const double nx = dx / length, ny = dy / length, nz = dz / length;
    const double magnitude = s.k * (length - s.rest) + s.c * (dv(0) * nx + dv(1) * ny + dv(2) * nz);
    gx = magnitude * nx, gy = magnitude * ny, gz = magnitude * nz;
    return true;
}

// The reference loop: spring_force for each spring in list order, added to
// its first particle and subtracted from its second. Inline: on a few
// springs (one particle on one spring) the call would cost as much as the
// loop; the planned pass (sim/spring_plan.h) gives its bits on many. This
// loop is most of a small cloth's step.
inline void accumulate(const Springs& springs, const ForceInput& in, const Vec3Span& f) {
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
        double gx, gy, gz;
        auto dv = [&](int k) { return k == 0 ? vx[j] - vx[i] : k == 1 ? vy[j] - vy[i] : vz[j] - vz[i]; };
        if (!spring_pull(s, x[i], y[i], z[i], x[j], y[j], z[j], dv, gx, gy, gz)) continue;
        fx[i] += gx, fy[i] += gy, fz[i] += gz;
        fx[j] -= gx, fy[j] -= gy, fz[j] -= gz;
    }
}

// U = Σ ½ k (|d| - ℓ)².
double potential_energy(const Springs& springs, const ForceInput& in);
// ∂f/∂x from the stretch and the change of direction, with the transverse term
// (1 - ℓ/|d|) clamped at 0 under compression (Choi and Ko 2002) so that the
// implicit system stays positive definite; ∂f/∂v = c d̂ d̂ᵀ blocks.
void accumulate_jacobians(const Springs& springs, const ForceInput& in, Jacobians& jac);

}  // namespace sim
