// Hooke springs with damping between pairs of particles, exactly the lecture's
//   f_a = k (|p_b - p_a| - ℓ) (p_b - p_a) / |p_b - p_a|,   f_b = -f_a
// plus a damper along the spring, c ((v_b - v_a) · d̂) d̂ on a (minus on b).
#pragma once

#include "sim/force.h"

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

// All springs of a system, evaluated in one pass.
struct Springs {
    std::vector<Spring> list;
};

// Force on particle i of spring s (particle j gets the opposite), N. Safe at
// zero length: with ℓ = 0 it is k d (no division); with ℓ > 0 and the two
// particles on top of each other there is no direction to push, and it is 0.
Vec3 spring_force(const Spring& s, const Vec3& xi, const Vec3& xj, const Vec3& vi, const Vec3& vj);

void validate(const Springs& springs, std::size_t particle_count);
constexpr bool is_local(const Springs&) { return false; }
void accumulate(const Springs& springs, const ForceInput& in, Vec3Span f);
// U = Σ ½ k (|d| - ℓ)².
double potential_energy(const Springs& springs, const ForceInput& in);
// ∂f/∂x from the stretch and the change of direction, with the transverse term
// (1 - ℓ/|d|) clamped at 0 under compression (Choi and Ko 2002) so that the
// implicit system stays positive definite; ∂f/∂v = c d̂ d̂ᵀ blocks.
void accumulate_jacobians(const Springs& springs, const ForceInput& in, Jacobians& jac);

}  // namespace sim
