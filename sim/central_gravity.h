// Gravity of a fixed attractor (a planet or a sun that does not move, the
// centre of a test-particle orbit): every particle falls towards one point,
//   f_i = -m_i μ d_i / |d_i|³,   d_i = x_i - center,   μ = G M,
// and never towards the other particles, so that particle i's force depends
// on particle i alone (local: evaluated block by block, O(n)). NewtonGravity
// is the all-pairs law, O(n²), for bodies that attract each other; this is
// the same law about a pinned mass M with the particles' own attraction left
// out, what a swarm of test particles (1000 independent Kepler orbits) needs.
#pragma once

#include "sim/force.h"

namespace sim {

struct CentralGravity {
    Vec3 center = Vec3::Zero();  // the attractor's position, m
    double mu = 3.986e14;        // G M, m³/s² (> 0); the default is the Earth's
};

void validate(const CentralGravity& gravity, std::size_t particle_count);
constexpr bool is_local(const CentralGravity&) { return true; }
// A particle at the centre itself has no direction to fall in: no force.
void accumulate(const CentralGravity& gravity, const ForceInput& in, Vec3Span f);
// The same, in the pinned build (wide = false) or the AVX2 one (the same
// bits; accumulate above takes it where the CPU has it).
void accumulate(const CentralGravity& gravity, const ForceInput& in, Vec3Span f, bool wide);
// The last generator and the step's M⁻¹ in one pass: a = (a + f) · (1/m),
// a holding the other forces, N (or, from_zero, nothing yet: a = (+0 + f) ·
// (1/m)). The operations of a zero pass, accumulate and a multiply by the
// inverse mass, per particle, so their bits.
void to_acceleration(const CentralGravity& gravity, const ForceInput& in, Vec3Span a, bool from_zero, bool wide);
// U = -Σ m_i μ / |d_i| over moving particles (a pinned one's is constant: left out).
double potential_energy(const CentralGravity& gravity, const ForceInput& in);
// ∂f_i/∂x_i = -m_i μ (I/r³ - 3 d dᵀ/r⁵), r = |d_i| (no coupling between
// particles); ∂f/∂v = 0.
void accumulate_jacobians(const CentralGravity& gravity, const ForceInput& in, Jacobians& jac);

}  // namespace sim
